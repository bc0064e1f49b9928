#include <sage/expression/normalize.hpp>
#include <sage/expression/primitives.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sage {

namespace {
void require_positive(double v, const char* what) {
  if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(std::string(what) + " must be a positive number");
}

Vec3 unit(const Vec3& v, int dimension, const char* what) {
  double n = 0;
  for (int i = 0; i < dimension; ++i) n += v[i] * v[i];
  n = std::sqrt(n);
  if (!(n > 0) || !std::isfinite(n)) throw std::invalid_argument(std::string(what) + " must be a non-zero vector");
  Vec3 u{0, 0, 0};
  for (int i = 0; i < dimension; ++i) u[i] = v[i] / n;
  return u;
}

void require_dimension(int dimension) {
  if (dimension != 2 && dimension != 3) throw std::invalid_argument("dimension must be 2 or 3");
}

Expr dot(const std::array<Expr, 3>& q, const Vec3& u, int dimension) {
  Expr s = 0.0;
  for (int i = 0; i < dimension; ++i) s += q[i] * u[i];
  return s;
}

Expr norm_squared(const std::array<Expr, 3>& q, int dimension) {
  Expr s = 0.0;
  for (int i = 0; i < dimension; ++i) s += square(q[i]);
  return s;
}

// Axial coordinate h and squared distance to the axis rho^2 of p, as
// |q x u|^2: a sum of squares, with no cancellation of |q|^2 - h^2, and
// for an axis along a coordinate axis exactly the other two coordinates'
// squares (products with u's zero components fold away), so interval
// bounds see that it does not depend on the axial coordinate.
struct Axial {
  Expr h, rho_squared;
};
Axial axial(const Vec3& origin, const Vec3& direction, const char* what) {
  const Vec3 u = unit(direction, 3, what);
  const auto q = offset_coordinates(origin, 3);
  Expr rho_squared = 0.0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    rho_squared += square(q[j] * u[k] - q[k] * u[j]);
  }
  return {dot(q, u, 3), rho_squared};
}
}  // namespace

std::array<Expr, 3> offset_coordinates(const Vec3& origin, int dimension) {
  std::array<Expr, 3> q{0.0, 0.0, 0.0};
  for (int i = 0; i < dimension; ++i) q[i] = Expr::var(i) - origin[i];
  return q;
}

Expr halfspace(const Vec3& point, const Vec3& outward_normal, int dimension) {
  require_dimension(dimension);
  const Vec3 n = unit(outward_normal, dimension, "normal");
  return -dot(offset_coordinates(point, dimension), n, dimension);
}

Expr ball(const Vec3& center, double radius, int dimension) {
  require_dimension(dimension);
  require_positive(radius, "radius");
  return (radius * radius - norm_squared(offset_coordinates(center, dimension), dimension)) / (2.0 * radius);
}

Expr cylinder(const Vec3& axis_point, const Vec3& axis_direction, double radius) {
  require_positive(radius, "radius");
  const Axial a = axial(axis_point, axis_direction, "axis");
  return (radius * radius - a.rho_squared) / (2.0 * radius);
}

Expr capped_cylinder(const Vec3& base_center, const Vec3& axis_direction, double radius, double height,
                     const RSystem& system) {
  require_positive(height, "height");
  const Vec3 u = unit(axis_direction, 3, "axis");
  const Vec3 top{base_center[0] + height * u[0], base_center[1] + height * u[1], base_center[2] + height * u[2]};
  const Expr slab = r_and(halfspace(base_center, {-u[0], -u[1], -u[2]}, 3), halfspace(top, u, 3), system);
  return r_and(cylinder(base_center, u, radius), slab, system);
}

Expr cone(const Vec3& apex, const Vec3& axis_direction, double half_angle) {
  if (!(half_angle > 0 && half_angle < M_PI / 2))
    throw std::invalid_argument("half_angle must lie strictly between 0 and pi/2 radians");
  const Axial a = axial(apex, axis_direction, "axis");
  return a.h * std::sin(half_angle) - sqrt(a.rho_squared) * std::cos(half_angle);
}

Expr torus(const Vec3& center, const Vec3& axis_direction, double major_radius, double minor_radius) {
  require_positive(major_radius, "major_radius");
  require_positive(minor_radius, "minor_radius");
  const Axial a = axial(center, axis_direction, "axis");
  const double r = minor_radius;
  return (r * r - square(sqrt(a.rho_squared) - major_radius) - square(a.h)) / (2.0 * r);
}

Expr ellipsoid(const Vec3& center, const Vec3& semi_axes, int dimension) {
  require_dimension(dimension);
  const auto q = offset_coordinates(center, dimension);
  Expr f = 1.0;
  for (int i = 0; i < dimension; ++i) {
    require_positive(semi_axes[i], "semi_axes");
    f = f - square(q[i] * (1.0 / semi_axes[i]));
  }
  return normalize(f, dimension);
}

Expr box(const Vec3& min_corner, const Vec3& max_corner, int dimension, const RSystem& system) {
  require_dimension(dimension);
  std::vector<Expr> faces;
  for (int i = 0; i < dimension; ++i) {
    if (!(max_corner[i] > min_corner[i])) throw std::invalid_argument("box: max must exceed min in every coordinate");
    Vec3 n{0, 0, 0};
    n[i] = -1;
    faces.push_back(halfspace(min_corner, n, dimension));
    n[i] = 1;
    faces.push_back(halfspace(max_corner, n, dimension));
  }
  return r_conjunction_n(faces, system);
}

}  // namespace sage
