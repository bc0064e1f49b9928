// load_cad for builds without OpenCASCADE (-DSAGE_WITH_CAD=OFF).
#include <sage/geometry/cad_model.hpp>

namespace sage::geometry {

bool cad_available() { return false; }

std::string cad_library() { return {}; }

Model load_cad(const std::string& path, const LoadOptions&) {
  throw ModelError(path +
                   ": this sage was built without OpenCASCADE (-DSAGE_WITH_CAD=OFF) and reads no CAD file; "
                   "rebuild it with OpenCASCADE (scripts/install-deps.sh installs it), or export the solid as "
                   "STL");
}

}  // namespace sage::geometry
