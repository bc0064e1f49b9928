#pragma once
// Internal to the CAD part of sage_geometry (built with OpenCASCADE):
//   read_cad_solid   cad_reader.cpp    file -> checked solid, unit, notes
//   load_cad         cad_model.cpp     tessellation -> mesh::Soup -> Model
//   describe_surface cad_surfaces.cpp  a face's surface type and parameters
//   exact_csg        cad_csg.cpp       the exact field of analytic faces

#include <sage/expression/triangle_surface.hpp>
#include <sage/geometry/model.hpp>

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sage::geometry::cad {

/// A solid read from a CAD file, in OCCT's millimetres.
struct CadSolid {
  TopoDS_Shape shape;          // one solid, or a compound of disjoint solids
  std::string format;          // "STEP", "IGES", "BREP"
  std::string unit = "model";  // the file's length unit
  double millimetres_per_unit = 1;
  std::vector<std::string> notes;
  /// Faces the file names (STEP's ADVANCED_FACE names), as read; faces
  /// that repair or union rebuilt lose theirs.
  std::vector<std::pair<TopoDS_Shape, std::string>> face_names;
  /// Colours the file gives faces ("#rrggbb"), from styles on the faces or
  /// on a solid or shell holding them; a later entry for a face wins.
  std::vector<std::pair<TopoDS_Shape, std::string>> face_colours;
  /// Solids the file names (STEP's MANIFOLD_SOLID_BREP names).
  std::vector<std::pair<TopoDS_Shape, std::string>> solid_names;
};

/// Reads, checks and selects (options.solid) or unites the solids of a
/// CAD file. Throws ModelError naming the file and the entity.
CadSolid read_cad_solid(const std::string& path, const LoadOptions& options);

/// The face's surface type and parameters (lengths divided by `scale`,
/// the millimetres per model unit), its area and centroid.
ModelFace describe_surface(const TopoDS_Face& face, double scale);

/// The solid's exact field (cad_csg.cpp): a Boolean formula over the
/// normalized primitives of its faces' surfaces, checked against the
/// solid. Faces must be planes, cylinders, cones, spheres or tori.
struct ExactCsg {
  Expr field;
  std::vector<Expr> face_surfaces;  // face i + 1's surface, zero on it
  std::vector<std::string> notes;
};

/// The exact field, or nothing and `why_not`. `tessellation` (in model
/// units, within `deflection` of the faces; triangle i on face
/// triangle_faces[i], from 1) supplies points near and on the faces, and
/// point membership away from the curved ones.
std::optional<ExactCsg> exact_csg(const CadSolid& solid, const TriangleSurface& tessellation,
                                  const std::vector<std::size_t>& triangle_faces, double deflection,
                                  const RSystem& system, std::string& why_not);

}  // namespace sage::geometry::cad
