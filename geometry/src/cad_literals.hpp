#pragma once
// Internal to the exact CAD field (cad_csg.cpp): the literals, one per
// distinct surface of the solid's faces (plane, cylinder, cone, sphere,
// torus) plus separating planes, each a normalized primitive.

#include <sage/expression/expression.hpp>
#include <sage/expression/primitives.hpp>

#include <TopoDS_Face.hxx>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace sage::geometry::cad {

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// A surface that bounds the solid or separates its cells: its normalized
/// primitive (> 0 on one side) and what identifies it among the others.
struct Literal {
  std::string kind;  // plane, cylinder, cone, sphere, torus
  Vec3 origin{}, axis{};
  double radius = 0, minor = 0, angle = 0;
  std::size_t face = 0;    // the first face on it (from 1); 0 for separators
  bool separator = false;  // a separating surface (add_separators), not a face's
  Expr field;

  bool same_surface(const Literal& o, double length) const {
    if (kind != o.kind) return false;
    const bool parallel = norm(cross(axis, o.axis)) < 1e-9;
    const Vec3 d = minus(o.origin, origin);
    if (kind == "plane") return parallel && std::abs(dot(axis, d)) < length;
    if (kind == "sphere") return norm(d) < length && std::abs(radius - o.radius) < length;
    if (kind == "cylinder") return parallel && norm(cross(axis, d)) < length && std::abs(radius - o.radius) < length;
    // Cones share apex, axis sense and angle; tori centre, axis and radii.
    const bool same_axis = kind == "cone" ? dot(axis, o.axis) > 0 : true;
    return parallel && same_axis && norm(d) < length && std::abs(radius - o.radius) < length &&
           std::abs(minor - o.minor) < length && std::abs(angle - o.angle) < 1e-9;
  }
};

/// The literal of face `index`'s surface (lengths divided by `scale`, the
/// millimetres per model unit), or nothing and why.
std::optional<Literal> literal_of(const TopoDS_Face& face, std::size_t index, double scale, std::string& why_not);

/// Adds `l` unless a literal on the same surface (within `length`) is
/// there already; the index of the literal on that surface.
std::size_t add_distinct(std::vector<Literal>& literals, Literal l, double length);

/// Adds the six planes of a curved face's bounding box (separators of a
/// fillet along a coordinate axis).
void add_bounding_planes(std::vector<Literal>& literals, const TopoDS_Face& face, double scale, double length);

/// Adds the separators of a fillet in any direction: for a cylinder the
/// planes through its straight edges (radial, and the chord of its arc),
/// for a torus the cylinder and the plane of its centre circle.
void add_fillet_separators(std::vector<Literal>& literals, const TopoDS_Face& face, double scale, double length);

}  // namespace sage::geometry::cad
