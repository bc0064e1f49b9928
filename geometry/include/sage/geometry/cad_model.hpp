#pragma once
// CAD solids (STEP, IGES, OCCT's BREP) read with OpenCASCADE: checked,
// sewn where safe, tessellated within a stated chordal deflection and
// handed to the mesh path (mesh_model.hpp), each triangle keeping its face.
// Faces become boundary parts: by number ("face:12", "faces": [3, 4]), by
// the file's names, or by a query such as "cylinder radius 4".

#include <sage/geometry/model.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace sage::geometry {

/// True for .step, .stp, .iges, .igs and .brep (any case).
bool is_cad_path(const std::string& path);

/// False when sage was built without OpenCASCADE (-DSAGE_WITH_CAD=OFF):
/// load_cad then refuses every file, saying so.
bool cad_available();

/// "OpenCASCADE 7.6.3", or "" without it: for `sage --version`.
std::string cad_library();

/// Reads a CAD file: its solids (options.solid picks one; several are
/// united), checked with BRepCheck_Analyzer (ShapeFix where it fails);
/// faces without a solid are sewn into closed shells when that leaves no
/// free edge. Coordinates are in the file's length unit (model.unit), the
/// tessellation's deflection options.deflection (default 1e-3 of the
/// bounding box's diagonal). Throws ModelError naming the file and the
/// entity (no solid, an open shell, an unreadable unit, a face that cannot
/// be tessellated).
Model load_cad(const std::string& path, const LoadOptions& options);

/// One line of `sage info`'s face listing: "12  cylinder  radius 4, axis
/// (0, 0, 1) through (10, 0, 0)  area 251.3  centroid (...)".
std::string describe_face(const Model& model, std::size_t face);

/// The faces (numbered from 1) a problem file's part names: a face name
/// from the file, or a query of a surface type (plane, cylinder, cone,
/// sphere, torus, bspline, ..., or "any") followed by any of
/// "radius R", "normal X Y Z", "axis X Y Z" (either sense), "center X Y Z"
/// and "colour #rrggbb": "cylinder radius 4", "plane normal 0 0 1",
/// "any colour #ff0000". Lengths match
/// within 1e-6 of the model's size, directions within 1e-6 radians.
/// Throws std::invalid_argument saying what matched nothing, with the
/// values the model has.
std::vector<std::size_t> faces_matching(const Model& model, const std::string& query);

/// A selector for boundary parts (solver/problem.hpp): zero on the given
/// faces, positive elsewhere. Tessellated models: the trimmed-triangle
/// distance of mesh_internal.hpp's brep_distance, over those faces'
/// triangles only. Exact models: zero on each face's exact surface near
/// its triangles.
/// Throws std::invalid_argument for a face the model does not have.
Expr faces_selector(const Model& model, const std::vector<std::size_t>& faces);

}  // namespace sage::geometry
