// Placeholder replaced by the mesh work in progress (same session).
#include <sage/geometry/mesh_model.hpp>

namespace sage::geometry {

bool is_mesh_path(const std::string& path) {
  for (const char* ext : {".off", ".stl", ".obj", ".ply"})
    if (path.size() >= 4 && path.compare(path.size() - 4, 4, ext) == 0) return true;
  return false;
}

Model load_mesh(const std::string& path, const LoadOptions&) {
  throw ModelError(path + ": triangle meshes are not supported yet");
}

}  // namespace sage::geometry
