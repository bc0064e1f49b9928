#pragma once
// Far mesh faces in single precision.
//
// A mesh's trimmed-face field is an R0 tree over its faces (mesh_field.cpp),
// each face one fused run (trimmed_face.hpp), about 5 ns per face and
// point in doubles with the gradient: every face is evaluated at every
// point, and nearly all of them are far. A cluster of faces (a subtree of
// the tree: contiguous in the tape, read only through its root) that lies
// farther from a batch's points than the larger of the two boxes' sizes is
// evaluated here in single precision, in coordinates relative to the
// batch's centre, at about 3 times the speed (whole sampling runs).
//
// Why the field stays within reach of the doubles: R0 is positively
// homogeneous of degree 1, so over any cut of the tree w = sum_C a_C V_C
// with a_C = dw/dV_C >= 0 (Euler's theorem); relative errors of at most
// delta in every cluster value V_C move w by at most delta w, to first
// order. Far from its faces, a cluster's value is computed from plane
// values whose rounding (relative to the box sizes, by the local
// coordinates) is small against the distance, through operations
// that do not cancel (square roots of sums of squares, and R0 of values
// >= 0 written without cancellation): delta is a few single-precision
// roundings (measured on real meshes: at most 1, mesh_test.cpp). Lanes
// where a value or partial is not finite (an R0 corner, overflow) send the
// whole cluster back to the doubles.

#include <sage/tape/trimmed_face.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sage {

/// An axis-aligned box.
struct Box3 {
  std::array<double, 3> lo{}, hi{};
};

/// Whether `tape` has enough fused mesh faces (3D, at least 1,024) for far
/// faces to pay: sage field's default for such tapes.
bool far_faces_pay(const Tape& tape);

class FarFaces {
 public:
  /// What a step of BatchEvaluator's program is, as far as clusters care:
  /// a fused face (writing `out`), an R0 of reads[0] and reads[1] (`sign`
  /// -1 for a conjunction), or anything else (reading `reads`).
  struct Step {
    enum class Kind : std::uint8_t { Face, Glue, Other };
    Kind kind = Kind::Other;
    const TrimmedFace* face = nullptr;
    double sign = -1;
    std::uint32_t out = 0;
    std::array<std::uint32_t, 3> reads{};
    int read_count = 0;
  };

  /// Finds the clusters of `steps`; `results` are the registers read after
  /// the last step.
  void build(const std::vector<Step>& steps, const std::vector<std::uint32_t>& results);

  bool empty() const { return clusters_.empty(); }
  std::size_t cluster_count() const { return clusters_.size(); }

  /// The largest cluster whose first step is `step` and that lies far from
  /// `box`, or -1.
  int far_cluster_at(std::size_t step, const Box3& box) const;

  /// The cluster's last step (its root) and the register it writes.
  std::size_t last_step(int cluster) const { return clusters_[static_cast<std::size_t>(cluster)].last; }
  std::uint32_t output(int cluster) const { return clusters_[static_cast<std::size_t>(cluster)].out; }

  /// The cluster's value (and, with gradient != nullptr, its partials in
  /// gradient[0..2][l]) at (x[l], y[l], z[l]), l < count <= kMaxLanes, in
  /// single precision around `centre`. False if some lane's value or
  /// partial is not finite (nothing is then to be used).
  bool evaluate(int cluster, const std::array<double, 3>& centre, const double* x, const double* y, const double* z,
                std::size_t count, double* value, const std::array<double*, 3>* gradient) const;

  static constexpr std::size_t kMaxLanes = 128;

 private:
  struct FloatFace {
    std::array<std::array<double, 3>, 4> gradient{};  // of h, then the trimming's three planes
    std::array<double, 4> offset{};                   // their values at the origin
    std::array<std::array<float, 3>, 4> single{};     // the gradients in single precision
    // The first and second R0's signs, h's factor inside the fourth power,
    // and the trimming's weights of its root and of t.
    std::array<float, 5> constants{};
  };
  struct Op {
    std::int32_t face = -1;  // >= 0: push the face's value; else R0 of the top two
    float sign = -1;
  };
  struct Cluster {
    std::size_t first = 0, last = 0;  // steps
    std::uint32_t out = 0;            // the root's register
    Box3 box;
    double size = 0;      // the box's diagonal
    int smaller = -1;     // the largest cluster inside this one with the same first step
    std::size_t ops = 0;  // program_[ops .. ops + count)
    std::size_t op_count = 0;
  };
  std::vector<FloatFace> faces_;
  std::vector<Op> program_;  // by step: a face or a glue
  std::vector<Cluster> clusters_;
  std::vector<int> largest_at_;  // by step: the largest cluster starting there, or -1
};

}  // namespace sage
