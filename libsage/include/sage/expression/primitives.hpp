#pragma once
// Normalized primitives (paper 004, sec. 3.3): each is >= 0 inside, 0 on its
// boundary, < 0 outside, and normalized to first order (|grad| = 1 on the
// boundary). Points and directions are given in 3 components; 2D
// primitives read the first two. Directions need not be unit vectors.
//
// | primitive       | field                                      | dims |
// |-----------------|--------------------------------------------|------|
// | halfspace       | -n.(p - p0) / |n|  (n the OUTWARD normal)  | 2, 3 |
// | ball (disk)     | (r^2 - |p - c|^2) / (2 r)                  | 2, 3 |
// | cylinder        | (r^2 - rho^2) / (2 r), rho = distance to   | 3    |
// |                 | the axis (infinite)                        |      |
// | capped cylinder | cylinder AND two end halfspaces            | 3    |
// | cone            | h sin(a) - rho cos(a): the signed distance | 3    |
// |                 | near the surface; apex, axis into the      |      |
// |                 | cone, half-angle a; one nappe, infinite    |      |
// | torus           | (r^2 - (rho - R)^2 - h^2) / (2 r)          | 3    |
// | ellipsoid       | normalize(1 - sum ((p_i - c_i) / a_i)^2)   | 2, 3 |
// | box             | AND of the 2 dim face halfspaces           | 2, 3 |
//
// rho = sqrt(|q|^2 - h^2) with q = p - apex/centre and h = q.u is not
// differentiable on the axis, which lies inside the cone and outside a
// torus with R > r: away from the boundary, as paper 004 allows.
// Every function throws std::invalid_argument on a bad parameter
// (non-positive radius, zero direction, ...), saying which.

#include <sage/expression/expression.hpp>
#include <sage/scalars/rfunction.hpp>

#include <array>

namespace sage {

using Vec3 = std::array<double, 3>;

Expr halfspace(const Vec3& point, const Vec3& outward_normal, int dimension);
Expr ball(const Vec3& center, double radius, int dimension);
Expr cylinder(const Vec3& axis_point, const Vec3& axis_direction, double radius);
Expr capped_cylinder(const Vec3& base_center, const Vec3& axis_direction, double radius, double height,
                     const RSystem& system);
Expr cone(const Vec3& apex, const Vec3& axis_direction, double half_angle);
Expr torus(const Vec3& center, const Vec3& axis_direction, double major_radius, double minor_radius);
Expr ellipsoid(const Vec3& center, const Vec3& semi_axes, int dimension);
Expr box(const Vec3& min_corner, const Vec3& max_corner, int dimension, const RSystem& system);

/// The coordinate expressions (x, y, z) minus a point, first `dimension` used.
std::array<Expr, 3> offset_coordinates(const Vec3& origin, int dimension);

}  // namespace sage
