// Fuzzes the mesh readers and what follows them (validation, CSG or brep
// field): sage::geometry::load_mesh on the input less its first byte,
// written to the scratch folder. The first byte picks the format and the
// options: bits 0-1 OFF, STL (ASCII or binary), OBJ, PLY; bit 2 brep
// instead of csg; bit 3 repair. So '0' to '3' are OFF, STL, OBJ and PLY
// with the defaults. Then the field is evaluated. ModelError (or another
// std::exception) is the answer to bad input; anything else is a finding.
// OFF and PLY go through sage's readers (geometry/src/off_ply_reader.hpp),
// STL and OBJ through CGAL's. fuzz/regressions/mesh/ holds seven inputs
// that crashed, hung or took gigabytes in CGAL 5.5's OFF and PLY readers,
// which sage used until then: each is now an error naming the place.
#include "fuzz_targets.hpp"

#include <sage/geometry/mesh_model.hpp>

namespace sage::fuzz {

void mesh(const std::uint8_t* data, std::size_t size) {
  setup();
  if (size < 1 || size > 64 * 1024) return;
  const int format = data[0] & 3;
  static const char* const kNames[] = {"input.off", "input.stl", "input.obj", "input.ply"};
  geometry::LoadOptions options;
  options.method = data[0] & 4 ? "brep" : "csg";
  options.repair = (data[0] & 8) != 0;
  const std::string path = write_scratch(kNames[format], data + 1, size - 1);
  try {
    const geometry::Model m = geometry::load_mesh(path, options);
    evaluate(m.field, m.dimension);
  } catch (const std::exception& e) {
    rejected(e);
  }
}

}  // namespace sage::fuzz
