#pragma once
// Internal to the exact CAD field (cad_csg.cpp): sample points, their
// membership in the exact solid, and their literals' sign vectors.

#include "cad_literals.hpp"
#include "sign_cover.hpp"

#include <sage/expression/triangle_surface.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <TopoDS_Shape.hxx>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace sage::geometry::cad {

/// Membership in the exact solid: +1 inside, -1 outside, 0 on it (within
/// `tolerance` mm). Farther than `margin` from the curved faces' triangles
/// (which lie within the deflection of their faces), CGAL's exact point
/// membership in the tessellation answers; OpenCASCADE's classifier, many
/// times slower, answers nearer.
class Membership {
 public:
  Membership(const TopoDS_Shape& shape, double scale, double tolerance, const TriangleSurface& tessellation,
             const TriangleSurface& curved, double margin);
  ~Membership();

  /// Whether `p` is farther than `margin` from every triangle, so surely
  /// not on the solid's boundary.
  bool off_boundary(const Vec3& p) const;
  int operator()(const Vec3& p);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The literals' signs at a point; empty where one is too close to zero
/// to tell.
class SignsAt {
 public:
  SignsAt(const std::vector<Literal>& literals, double zero) : zero_(zero), count_(literals.size()) {
    std::vector<Expr> roots;
    for (const Literal& l : literals) roots.push_back(l.field);
    tape_ = std::make_unique<Tape>(roots, 3);
    eval_ = std::make_unique<Evaluator<double>>(*tape_);
  }

  SignVector operator()(const Vec3& p) {
    eval_->evaluate(p.data());
    SignVector v((count_ + 63) / 64, 0);
    for (std::size_t l = 0; l < count_; ++l) {
      const double value = eval_->result(l);
      if (std::abs(value) <= zero_) return {};
      if (value > 0) v[l / 64] |= std::uint64_t{1} << (l % 64);
    }
    return v;
  }

 private:
  double zero_;
  std::size_t count_;
  std::unique_ptr<Tape> tape_;
  std::unique_ptr<Evaluator<double>> eval_;
};

struct Sample {
  Vec3 p;
  int side;  // +1 inside, -1 outside
};

/// Points of a jittered n^3 grid over the box (none for n = 0) and on both
/// sides of the triangles (at `offsets` along their normals; of at most
/// about `max_triangles`, evenly spread), classified; points on the
/// solid's boundary are left out.
std::vector<Sample> samples(const Vec3& lo, const Vec3& hi, int n, const TriangleSurface& surface,
                            const std::vector<double>& offsets, std::size_t max_triangles, std::uint32_t seed,
                            Membership& membership);

/// Sorts samples into the inside and outside sign vectors; a vector seen
/// on both sides is returned in `conflict` (its first point).
void sign_vectors(const std::vector<Sample>& points, SignsAt& signs, std::vector<SignVector>& inside,
                  std::vector<SignVector>& outside, std::optional<Vec3>& conflict);

}  // namespace sage::geometry::cad
