#pragma once
// PointClassifier: point membership classification as a node of the
// expression graph (paper 004, sec. 5.1: the solid function of a B-rep is
// xi(p) * w with xi = +1 inside, 0 on the boundary, -1 outside).
//
// xi is piecewise constant, so its tuple is a constant (all derivatives 0)
// and its symbolic derivative is 0. Its interval over a box is what
// classify_box proves; the default, [-1, 1], proves nothing. Geometry code
// (polygons, meshes) implements it with exact predicates.
//
// Ownership: expressions and tapes share the classifier (shared_ptr); it
// must be safe to call from several threads at once.

#include <sage/scalars/interval.hpp>

namespace sage {

class PointClassifier {
 public:
  virtual ~PointClassifier() = default;
  /// +1 inside, 0 on the boundary, -1 outside; p has dimension() entries.
  virtual double classify(const double* p) const = 0;
  /// An enclosure of classify over the box (dimension() intervals).
  virtual Interval classify_box(const Interval* /*box*/) const { return {-1.0, 1.0}; }
  virtual int dimension() const = 0;
};

}  // namespace sage
