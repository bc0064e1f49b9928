#pragma once
// Closed triangle meshes (OFF, STL, OBJ, PLY) to fields: validation with
// CGAL, trimmed-face B-rep fields signed by point membership, and
// well-formed CSG where the polyhedron allows it.

#include <sage/geometry/model.hpp>

#include <string>

namespace sage::geometry {

/// Reads and validates a mesh and builds its field (options.method: "csg"
/// or "brep"). Throws ModelError naming the file and the face or vertex.
Model load_mesh(const std::string& path, const LoadOptions& options);

/// Throws ModelError naming the file unless options.method is csg or brep.
void check_mesh_method(const std::string& path, const LoadOptions& options);

/// True for the extensions load_mesh reads.
bool is_mesh_path(const std::string& path);

}  // namespace sage::geometry
