// describe_surface: what `sage info` says of a CAD face and what face
// queries match: the surface type and its parameters (OCCT's
// BRepAdaptor_Surface), the area and centroid (BRepGProp).
#include "cad_internal.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <gp_Torus.hxx>

#include <cmath>

namespace sage::geometry::cad {

namespace {

std::array<double, 3> direction(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }

std::array<double, 3> point(const gp_Pnt& p, double scale) { return {p.X() / scale, p.Y() / scale, p.Z() / scale}; }

std::string surface_name(GeomAbs_SurfaceType type) {
  switch (type) {
    case GeomAbs_Plane: return "plane";
    case GeomAbs_Cylinder: return "cylinder";
    case GeomAbs_Cone: return "cone";
    case GeomAbs_Sphere: return "sphere";
    case GeomAbs_Torus: return "torus";
    case GeomAbs_BezierSurface: return "bezier";
    case GeomAbs_BSplineSurface: return "bspline";
    case GeomAbs_SurfaceOfRevolution: return "revolution";
    case GeomAbs_SurfaceOfExtrusion: return "extrusion";
    case GeomAbs_OffsetSurface: return "offset";
    default: return "other";
  }
}

}  // namespace

ModelFace describe_surface(const TopoDS_Face& face, double scale) {
  ModelFace out;
  const BRepAdaptor_Surface surface(face);  // with the face's location
  out.surface = surface_name(surface.GetType());
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      gp_Dir n = surface.Plane().Axis().Direction();
      if (face.Orientation() == TopAbs_REVERSED) n.Reverse();  // faces of a solid are oriented outward
      out.normal = direction(n);
      break;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder c = surface.Cylinder();
      out.axis = direction(c.Axis().Direction());
      out.center = point(c.Location(), scale);
      out.radius = c.Radius() / scale;
      break;
    }
    case GeomAbs_Cone: {
      const gp_Cone c = surface.Cone();
      out.axis = direction(c.Axis().Direction());
      out.center = point(c.Location(), scale);
      out.radius = c.RefRadius() / scale;
      out.half_angle = std::abs(c.SemiAngle()) * 180 / M_PI;
      break;
    }
    case GeomAbs_Sphere: {
      const gp_Sphere s = surface.Sphere();
      out.center = point(s.Location(), scale);
      out.radius = s.Radius() / scale;
      break;
    }
    case GeomAbs_Torus: {
      const gp_Torus t = surface.Torus();
      out.axis = direction(t.Axis().Direction());
      out.center = point(t.Location(), scale);
      out.radius = t.MajorRadius() / scale;
      out.minor_radius = t.MinorRadius() / scale;
      break;
    }
    default: break;
  }
  GProp_GProps properties;
  BRepGProp::SurfaceProperties(face, properties);
  out.area = properties.Mass() / (scale * scale);
  out.centroid = point(properties.CentreOfMass(), scale);
  return out;
}

}  // namespace sage::geometry::cad
