// The literals of the exact CAD field (cad_literals.hpp): OCCT's analytic
// surfaces as sage's normalized primitives.
#include "cad_literals.hpp"

#include "cad_internal.hpp"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <gp_Torus.hxx>

namespace sage::geometry::cad {

namespace {

Vec3 point(const gp_Pnt& p, double scale) { return {p.X() / scale, p.Y() / scale, p.Z() / scale}; }
Vec3 direction(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }

}  // namespace

std::optional<Literal> literal_of(const TopoDS_Face& face, std::size_t index, double scale, std::string& why_not) {
  const BRepAdaptor_Surface surface(face);
  Literal l;
  l.face = index;
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      const gp_Pln p = surface.Plane();
      l.kind = "plane", l.origin = point(p.Location(), scale), l.axis = direction(p.Axis().Direction());
      l.field = halfspace(l.origin, l.axis, 3);
      return l;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder c = surface.Cylinder();
      l.kind = "cylinder", l.origin = point(c.Location(), scale), l.axis = direction(c.Axis().Direction());
      l.radius = c.Radius() / scale;
      l.field = cylinder(l.origin, l.axis, l.radius);
      return l;
    }
    case GeomAbs_Sphere: {
      const gp_Sphere s = surface.Sphere();
      l.kind = "sphere", l.origin = point(s.Location(), scale), l.radius = s.Radius() / scale;
      l.field = ball(l.origin, l.radius, 3);
      return l;
    }
    case GeomAbs_Cone: {
      // OCCT's conical surface has both nappes; the primitive has one, the face's.
      const gp_Cone c = surface.Cone();
      l.kind = "cone", l.origin = point(c.Apex(), scale), l.axis = direction(c.Axis().Direction());
      const double u = 0.5 * (surface.FirstUParameter() + surface.LastUParameter());
      const double v = 0.5 * (surface.FirstVParameter() + surface.LastVParameter());
      if (dot(minus(point(surface.Value(u, v), scale), l.origin), l.axis) < 0)
        for (double& a : l.axis) a = -a;
      l.angle = std::abs(c.SemiAngle());
      l.field = cone(l.origin, l.axis, l.angle);
      return l;
    }
    case GeomAbs_Torus: {
      const gp_Torus t = surface.Torus();
      if (t.MajorRadius() <= t.MinorRadius()) {
        why_not = "face " + std::to_string(index) + " is a self-intersecting torus";
        return std::nullopt;
      }
      l.kind = "torus", l.origin = point(t.Location(), scale), l.axis = direction(t.Axis().Direction());
      l.radius = t.MajorRadius() / scale, l.minor = t.MinorRadius() / scale;
      l.field = torus(l.origin, l.axis, l.radius, l.minor);
      return l;
    }
    default: break;
  }
  why_not = "face " + std::to_string(index) + " is not a plane, cylinder, cone, sphere or torus (" +
            describe_surface(face, scale).surface + ")";
  return std::nullopt;
}

std::size_t add_distinct(std::vector<Literal>& literals, Literal l, double length) {
  for (std::size_t k = 0; k < literals.size(); ++k)
    if (literals[k].same_surface(l, length)) return k;
  literals.push_back(std::move(l));
  return literals.size() - 1;
}

namespace {

Literal separating_plane(const Vec3& origin, Vec3 normal) {
  const double n = norm(normal);
  for (double& x : normal) x /= n;
  Literal l;
  l.kind = "plane", l.separator = true, l.origin = origin, l.axis = normal;
  l.field = halfspace(origin, normal, 3);
  return l;
}

}  // namespace

void add_bounding_planes(std::vector<Literal>& literals, const TopoDS_Face& face, double scale, double length) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(face, box, false, false);
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  for (std::size_t a = 0; a < 3; ++a)
    for (double c : {lo[a], hi[a]}) {
      Vec3 origin{0, 0, 0}, normal{0, 0, 0};
      origin[a] = c / scale, normal[a] = 1;
      add_distinct(literals, separating_plane(origin, normal), length);
    }
}

void add_fillet_separators(std::vector<Literal>& literals, const TopoDS_Face& face, double scale, double length) {
  const BRepAdaptor_Surface surface(face);
  if (surface.GetType() == GeomAbs_Cylinder) {
    // A fillet in any direction: the plane through its two straight edges
    // (the chord of its arc), and the planes through the axis and each.
    const gp_Cylinder c = surface.Cylinder();
    const Vec3 axis = direction(c.Axis().Direction()), on_axis = point(c.Location(), scale);
    std::vector<Vec3> lines;  // a point of each straight edge
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
      const BRepAdaptor_Curve curve(TopoDS::Edge(e.Current()));
      if (curve.GetType() == GeomAbs_Line)
        lines.push_back(point(curve.Value(0.5 * (curve.FirstParameter() + curve.LastParameter())), scale));
    }
    for (const Vec3& q : lines) {
      const Vec3 radial = cross(axis, minus(q, on_axis));
      if (norm(radial) > length) add_distinct(literals, separating_plane(q, radial), length);
    }
    if (lines.size() == 2) {
      const Vec3 chord = cross(axis, minus(lines[1], lines[0]));
      if (norm(chord) > length) add_distinct(literals, separating_plane(lines[0], chord), length);
    }
  } else if (surface.GetType() == GeomAbs_Torus) {
    // A fillet around a boss: the cylinder through the tube's centre circle
    // and the plane of that circle.
    const gp_Torus t = surface.Torus();
    const Vec3 axis = direction(t.Axis().Direction()), centre = point(t.Location(), scale);
    add_distinct(literals, separating_plane(centre, axis), length);
    Literal l;
    l.kind = "cylinder", l.separator = true, l.origin = centre, l.axis = axis, l.radius = t.MajorRadius() / scale;
    l.field = cylinder(centre, axis, l.radius);
    add_distinct(literals, std::move(l), length);
  }
}

}  // namespace sage::geometry::cad
