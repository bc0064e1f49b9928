#include <sage/geometry/csg_model.hpp>
#include <sage/geometry/gis_model.hpp>
#include <sage/geometry/mesh_model.hpp>
#include <sage/geometry/model.hpp>

namespace sage::geometry {

Model load_model(const std::string& path, const LoadOptions& options) {
  if (is_mesh_path(path)) return load_mesh(path, options);
  if (is_gis_path(path)) return load_gis(path, options);
  ModelOptions model_options;
  model_options.rfunction = options.rfunction;
  return read_model(path, model_options);
}

}  // namespace sage::geometry
