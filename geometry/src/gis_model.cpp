// Placeholder replaced by the GIS work in progress (same session).
#include <sage/geometry/gis_model.hpp>

namespace sage::geometry {

bool is_gis_path(const std::string&) { return false; }

Model load_gis(const std::string& path, const LoadOptions&) {
  throw ModelError(path + ": GIS data is not supported yet");
}

}  // namespace sage::geometry
