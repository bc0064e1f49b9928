#pragma once
// Trimming (paper 004, sec. 4; FORMULAS.md): a distance-like field of an
// unbounded curve or surface h = 0 (h normalized) restricted to the region
// t >= 0 (t normalized, built with R-functions).
//
// All trimmed fields here are >= 0 everywhere and 0 exactly on the trimmed
// entity: distances, not solids. Glue them with R-conjunction and a point
// membership sign to get a solid (sec. 5.1).
//
//  - simple:      sqrt(-((-h^2) AND t))  with the given R-function system;
//                 normalized on both sides away from the border, its
//                 derivative blows up near the border point from outside.
//  - normalized:  sqrt(h^2 + ((|t| - t) / 2)^2)                     (C1)
//                 exactly the Euclidean distance for the half-line y = 0,
//                 x >= 0 (h = y, t = x).
//  - smooth:      sqrt(h^2 + ((sqrt(t^2 + h^4 / s^2) - t) / 2)^2)
//                 smooth away from the entity, equal to the C1 form to
//                 first order near it. The length s (1 by default, as in
//                 the paper) makes h^4 / s^2 a length squared like t^2, so
//                 the field does not depend on the unit of length when s
//                 scales with the entity; segment_field uses s = L.
//  - orthogonalize: replaces t by normalize(t - h (grad h . grad t)); on
//                 h = 0 it equals t's zero set and its gradient there is
//                 orthogonal to grad h, which restores |grad| = 1 near the
//                 border point when h = 0 and t = 0 meet at an angle.

#include <sage/expression/expression.hpp>
#include <sage/scalars/rfunction.hpp>

namespace sage {

enum class TrimMethod { Simple, Normalized, Smooth };

/// Parses "simple", "normalized", "smooth"; throws std::invalid_argument.
TrimMethod parse_trim_method(const std::string& text);

Expr trim_simple(const Expr& h, const Expr& t, const RSystem& system);
Expr trim_normalized(const Expr& h, const Expr& t);
/// Throws std::invalid_argument unless scale is positive and finite.
Expr trim_smooth(const Expr& h, const Expr& t, double scale = 1.0);

/// t made orthogonal to h = 0 and normalized (see above).
Expr orthogonalize(const Expr& h, const Expr& t, int dimension);

/// Signed distance to the line through a and b, positive left of a -> b
/// (2D), as one Axpby and one Offset: n . (p - a), n the unit left normal.
Expr line_halfplane(const std::array<double, 2>& a, const std::array<double, 2>& b);

/// Distance-like field of the segment from a to b (2D): h is the signed
/// distance to the line through a and b, t = ((L/2)^2 - |p - c|^2) / L;
/// smooth trimming with s = L.
Expr segment_field(const std::array<double, 2>& a, const std::array<double, 2>& b, TrimMethod method,
                   const RSystem& system = RSystem::r0());

/// Distance-like field of the triangle a, b, c (3D; paper 004, sec. 5.1):
/// h = n . (a - p), n the unit normal of (b - a) x (c - a), so h > 0 on
/// the side n points away from; each side j -> k gives the plane through
/// it perpendicular to the triangle, m . (p - v_j) with m = n x (v_k -
/// v_j) normalized, > 0 on the triangle's side; t is their conjunction in
/// `system` (the triangle extruded along n), made orthogonal to h if asked;
/// smooth trimming with s = 1. Zero exactly on the triangle.
Expr triangle_field(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                    const RSystem& system = RSystem::r0(), bool orthogonal = false);

}  // namespace sage
