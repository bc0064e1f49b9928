#pragma once
// A certificate that a polygon field has no zeros away from the boundary
// (the definition of a well-formed CSG translation, paper 004 sec. 3.1),
// by interval arithmetic over an adaptive covering of the bounds: every
// box either has an interval of omega that excludes 0, or is at most
// `band` wide and meets an edge once grown by `band` (so it lies within
// 3 sqrt(2) band of the boundary: Certificate::band). A box that meets no edge
// but where omega changes sign between sample points proves a spurious
// zero: the field is then reported NOT well-formed.

#include <sage/expression/expression.hpp>
#include <sage/geometry/model.hpp>
#include <sage/geometry/polygon.hpp>

#include <string>

namespace sage::geometry {

struct Certificate {
  bool certified = false;
  std::size_t boxes = 0;  // boxes evaluated
  double band = 0;        // zeros may remain only this close to an edge
  std::string text;       // one line for `sage info`
};

/// Tries to certify `field` (2D) over `bounds`; gives up after `budget`
/// boxes (then certified = false and the text says so).
Certificate certify_no_spurious_zeros(const Expr& field, const PolygonSet& polygons, const Bounds& bounds, double band,
                                      std::size_t budget = 1'000'000);

}  // namespace sage::geometry
