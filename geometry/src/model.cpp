#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/csg_model.hpp>
#include <sage/geometry/gis_model.hpp>
#include <sage/geometry/mesh_model.hpp>
#include <sage/geometry/model.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace sage::geometry {

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

Model load_model(const std::string& path, const LoadOptions& options) {
  if (is_mesh_path(path)) return load_mesh(path, options);
  if (is_cad_path(path)) return load_cad(path, options);
  if (is_gis_path(path)) return load_gis(path, options);
  const std::string ext = lowercase_extension(path);
  if (!ext.empty() && ext != ".json")
    throw ModelError(path + ": unknown file type '" + ext +
                     "': sage reads JSON models (.json), GIS polygons (.geojson, .shp, .gpkg, .gml, .kml, .fgb, "
                     ".sqlite, .tab, .mif), meshes (.off, .stl, .obj, .ply) and CAD solids (.step, .stp, .iges, .igs, "
                     ".brep)");
  ModelOptions model_options;
  model_options.rfunction = options.rfunction;
  return read_model(path, model_options);
}

}  // namespace sage::geometry
