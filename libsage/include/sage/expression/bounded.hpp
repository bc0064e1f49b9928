#pragma once
// Bounded ("soft object") primitives and their Boolean composition with a
// smooth transition by arcs of ellipses (paper 001; FORMULAS.md, "Bounded
// composition operators").
//
// A bounded potential lies in [0, 1], is 0 outside the primitive's
// support, and its surface is the iso-value C (1/2 for bounded_potential).
// An operator G(X, Y) combines potentials X = f1, Y = f2 >= 0 and returns
// a potential again. Union, with theta the angle of (X, Y) from the X axis
// and 0 < theta1 < 45 deg < theta2 < 90 deg:
//
//     theta <= theta1: G = X            theta >= theta2: G = Y
//     otherwise G = c, the level whose quarter ellipse passes through
//     (X, Y): centre (c cot theta2, c tan theta1), semi-axes
//     c (1 - cot theta2) and c (1 - tan theta1).
//
// The level curves are homothetic, so c solves a quadratic
// A c^2 - 2 B c + D = 0 in closed form, taking the root on the far arc
// (union) or the near arc (intersection). At the zone borders the arc is
// tangent to the straight iso-lines and G is homogeneous of degree 1, so the
// gradient is continuous (G1): G = X where Y = 0, G = Y where X = 0 and
// G(0, 0) = 0. Intersection mirrors it (G = Y below theta1, X above
// theta2, the arc with centre (c cot theta1, c tan theta2)); difference is
// intersection with 2C - f2.
//
// Profile: control points p_i shape the transition. Each gives P_i =
// (f1(p_i), f2(p_i)) and the factor C / G(P_i); the arc value is multiplied
// by m, a clamped cubic spline through (theta1, 1), those factors and
// (theta2, 1) with zero slope at both ends, so G1 is kept and the level-C
// surface passes through every p_i. m is a function of
// u = Y / (X + Y) = tan(theta) / (1 + tan(theta)), a monotone function of
// theta, which needs no arctangent.
//
// Intervals: the zone steps give [0, 1] weights wherever a box straddles
// a border, and outside both supports (X = Y = 0, widened by outward
// rounding) the arc's quotient is the whole line; the loose enclosure made
// ray casting visit every leaf along every ray. So G is clamped between
// linear bounds that are exact over boxes: lines tangent to the level
// curve on one side and its chords on the other (16 each). Pointwise the
// clamp changes nothing (the bounds touch G only where they are tangent
// to it); over a box the enclosure is at most the bounds' range, which
// shrinks with the box. The profile is written without steps, in the
// truncated power basis, for the same reason.
//
// Sharp transition (BoundedTransition::sharp; the paper's appendix is
// unreadable, this is our own family): the level-C curve is the corner
// max(X, Y) = C (union) or min(X, Y) = C (intersection) and the field is
// G1 everywhere else. Union: in corner coordinates P = (c - X) / a,
// Q = (c - Y) / b, a = 1 - cot theta2, b = 1 - tan theta1, the smooth arc of
// level c is N(P, Q) = P + Q + sqrt(2 P Q) = rho with rho = c. The sharp
// arcs take rho = (1 - c / C) s(X, Y) for c <= C, with s = alpha X + beta Y
// the chord gauge (s = 1 at (1, tan theta1) and (cot theta2, 1)), and
// rho = c - C for c >= C (the smooth union homothetic about (C, C)). rho
// is linear in c in both, so c is again the root of a quadratic; rho -> 0
// at c = C shrinks the arc to the corner. The arc meets X = c at a tangent
// point inside the zone (angle >= theta1; -> theta1 as c -> 0), below it
// G = X; along N = rho, dPsi/dc > 0 for Psi = N - rho, so the arcs do not
// cross and the root is unique, and at the tangent points the gradient
// tends to (1, 0) (N_P -> infinity), so G is G1 except at (C, C).
// 0 <= dG/dX, dG/dY <= 1, which gives the interval bound
// max(X, Y) <= G <= min(X + (Y - Yt(X))+, Y + (X - Xt(Y))+), exact where
// the zone steps switch (Yt: the tangent point of level X). Intersection:
// X Y / U(X, Y) with U the sharp union (min = X Y / max): G = Y where U = X,
// X where U = Y, level C on min(X, Y) = C, G1 where U is, monotone with
// slopes in [0, 1]. The profile does not apply (refused): it would move the
// level-C curve off the corner.

#include <sage/expression/expression.hpp>
#include <sage/expression/primitives.hpp>

#include <vector>

namespace sage {

/// A potential in [0, 1] from a field omega (>= 0 inside) and a support
/// half-width w: P(t) = (1 + t)^2 (2 - t) / 4 with t = omega / w clamped to
/// [-1, 1]. P = 1/2 on omega = 0, 0 where omega <= -w, 1 where omega >= w,
/// C1 everywhere. Throws std::invalid_argument for w <= 0.
Expr bounded_potential(const Expr& omega, double width);

struct BoundedTransition {
  double theta1 = M_PI / 8;      // radians, in (0, pi/4)
  double theta2 = 3 * M_PI / 8;  // radians, in (pi/4, pi/2)
  double iso = 0.5;              // C, in (0, 1)
  /// Profile control points in model space; each must map to an angle
  /// strictly between theta1 and theta2.
  std::vector<Vec3> profile_points;
  /// Sharp transition: the level-C curve is the corner of f1 = C and
  /// f2 = C (see above); no profile points then.
  bool sharp = false;
};

enum class BoundedOp { Union, Intersection, Difference };

/// G(f1, f2) for potentials f1, f2 in `dimension` variables (needed to
/// evaluate them at profile points). Throws std::invalid_argument for bad
/// angles, iso-value or profile points, saying which.
Expr bounded_compose(BoundedOp op, const Expr& f1, const Expr& f2, const BoundedTransition& transition, int dimension);

/// Potential -> field: G - C, >= 0 inside the composed object.
inline Expr iso_field(const Expr& potential, double iso) { return potential - iso; }

}  // namespace sage
