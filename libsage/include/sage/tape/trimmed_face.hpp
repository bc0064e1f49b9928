#pragma once
// A mesh face's trimmed field, a tape run fused into one kernel.
//
// A triangle of a mesh's trimmed-face field (mesh_field.cpp) is up to 27
// instructions: four planes (affine functions of x, y, z: its own plane h
// and its three side planes s0, s1, s2), h^2, the trimming t = (s0 AND s1) AND s2 as two
// R0 nodes, and the smooth trimming of h by t (smooth_trim.hpp). Run as
// the smaller fused runs, every face made a pass over memory per piece and
// component, and the interpreter decoded each piece: fandisk's 12,946
// faces cost 32 cycles per face and point. Here the whole face is found
// once per tape (find_trimmed_face) and computed lane by lane in
// registers, each piece with its own arithmetic in its own order
// (lane_steps.hpp): the same bits as the instructions. The planes'
// partials are the same at every finite point (1 and 0 seeded through the
// forms' arithmetic), so they are computed once per run; lanes with a
// coordinate that is not finite, and lanes where an R0 or the trimming
// takes another branch, run the operators.
//
// The run reads x, y and z only, so its intermediate results may live in
// any registers: every one must be read by the run alone.

#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/linear_form.hpp>
#include <sage/tape/smooth_trim.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace sage {

/// A plane of a face: an affine function of the variables, as the tape
/// writes it (terms with a zero coefficient are left out, a coefficient
/// of 1 or -1 is no product), then + d if has_offset.
struct FacePlane {
  enum class Kind : std::uint8_t {
    Variable,    // a
    Negated,     // -a
    Scaled,      // a p (a Scale)
    TwoTerms,    // a p + b q (an Axpby)
    ThreeTerms,  // a p + b q + c k (a linear form)
  };
  Kind kind = Kind::ThreeTerms;
  LinearForm form;                   // p, q, k and d, as the kind reads them
  std::array<int, 3> variables{};    // which variable (0 = x) a, b and c are
  std::array<double, 3> partials{};  // at a finite point
};

/// The arithmetic of a fused face.
struct TrimmedFace {
  /// planes[0] is h; planes[1] and planes[2] are the first R0's arguments,
  /// in order; planes[3] is the second R0's other argument.
  std::array<FacePlane, 4> planes{};
  double first_sign = -1, second_sign = -1;  // -1 conjunction, +1 disjunction
  bool trimming_first = true;                // the first R0 is the second's first argument
  SmoothTrim trim;
};

/// A run found in a tape: its arithmetic, the register it writes and how
/// many instructions it stands for.
struct TrimmedFaceRun {
  TrimmedFace face;
  std::uint32_t out = 0;
  std::size_t length = 0;
};

/// The run starting at instruction `first`, if any. `is_constant` and
/// `constant_value` by register, as BatchEvaluator keeps them.
std::optional<TrimmedFaceRun> find_trimmed_face(const Tape& tape, std::size_t first,
                                                const std::vector<char>& is_constant,
                                                const std::vector<double>& constant_value);

/// out[l] = the run's result at the point (x[l], y[l], z[l]), l < count,
/// for x, y, z seeded as variables.
void trimmed_face_lanes(const TrimmedFace& face, ConstFirstOrderLanes<3> x, ConstFirstOrderLanes<3> y,
                        ConstFirstOrderLanes<3> z, FirstOrderLanes<3> out, std::size_t count);
void trimmed_face_values(const TrimmedFace& face, const double* x, const double* y, const double* z, double* out,
                         std::size_t count);

}  // namespace sage
