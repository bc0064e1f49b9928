// The trimmed-face field of a closed triangle mesh (paper 004, sec. 5.1;
// FORMULAS.md "From boundary representation to a solid function").
//
// Triangle i with vertices a, b, c (outward orientation), outward unit
// normal n:
//   h_i = n . (a - p)                 signed distance to its plane, > 0 inside
//   s_j = m_j . (p - v_j)             one per edge v_j -> v_k, m_j = n x (v_k - v_j)
//                                     normalized: the plane through the edge
//                                     perpendicular to the face, > 0 on the
//                                     triangle's side
//   t_i = s_0 AND s_1 AND s_2         the triangle extruded along n; R0 (or any
//                                     normalized system) keeps |grad t| = 1 on
//                                     its sides away from their meeting lines
//   w_i = trim_smooth(h_i, t_i)       >= 0, zero exactly on the triangle
//   w   = r_conjunction_n(w_0, ..., w_{n-1})   (balanced tree, soup order)
// The edge planes are perpendicular to the face, so h_i and t_i already
// meet orthogonally; orthogonalize (optional) then only renormalizes t_i.
#include "mesh_internal.hpp"

#include <sage/trimming.hpp>

#include <cmath>

namespace sage::geometry::mesh {

namespace {

using V3 = std::array<double, 3>;

V3 sub(const Point& a, const Point& b) { return {a.x() - b.x(), a.y() - b.y(), a.z() - b.z()}; }
V3 cross(const V3& u, const V3& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
V3 unit(const V3& v) {
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}
double dot(const V3& u, const Point& p) { return u[0] * p.x() + u[1] * p.y() + u[2] * p.z(); }

}  // namespace

Expr brep_distance(const std::vector<Point>& points, const std::vector<Triangle>& triangles, const RSystem& glue_system,
                   const RSystem& trim_system, bool orthogonalize) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  // g . p + c as an expression.
  auto linear = [&](const V3& g, double c) { return x * g[0] + y * g[1] + z * g[2] + c; };
  std::vector<Expr> faces;
  faces.reserve(triangles.size());
  for (const Triangle& tri : triangles) {
    const Point &a = points[tri[0]], &b = points[tri[1]], &c = points[tri[2]];
    const V3 n = unit(cross(sub(b, a), sub(c, a)));
    const Expr h = linear({-n[0], -n[1], -n[2]}, dot(n, a));
    std::vector<Expr> sides;
    for (int j = 0; j < 3; ++j) {
      const Point &from = points[tri[j]], &to = points[tri[(j + 1) % 3]];
      const V3 m = unit(cross(n, sub(to, from)));
      sides.push_back(linear(m, -dot(m, from)));
    }
    Expr t = r_conjunction_n(std::move(sides), trim_system);
    if (orthogonalize) t = sage::orthogonalize(h, t, 3);
    faces.push_back(trim_smooth(h, t));
  }
  return r_conjunction_n(std::move(faces), glue_system);
}

}  // namespace sage::geometry::mesh
