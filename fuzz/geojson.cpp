// Fuzzes GIS polygons through GDAL: sage::geometry::load_model on the input
// written to the scratch folder as input.geojson (GDAL restricted to its
// JSON drivers, no network: fuzz_support.cpp), then the field evaluated.
// The input's size modulo 4 picks the options: csg, brep, csg with the
// well-formedness certificate, brep with repair. ModelError (or another
// std::exception) is the answer to bad input; anything else is a finding.
//
// Open bug, skipped: the certificate (well_formedness.cpp) spends its whole
// budget of 1e6 interval boxes on a sliver with a far vertex, 85 to 100 s
// an input under the sanitizers, and its verdict differs between builds
// (GCC and libgomp: "NOT well-formed", in 0.2 to 2 s; clang and libomp:
// "gave up after 1000001 boxes"; task order or rounding, not isolated):
// fuzz/regressions/geojson/certify_*. So the certificate is left out unless
// SAGE_FUZZ_KNOWN_BUGS is set.
#include "fuzz_targets.hpp"

#include <sage/geometry/model.hpp>

namespace sage::fuzz {

void geojson(const std::uint8_t* data, std::size_t size) {
  setup();
  if (size > 64 * 1024) return;
  geometry::LoadOptions options;
  options.method = size % 2 ? "brep" : "csg";
  options.certify = size % 4 == 2 && !skip_known_bugs();
  options.repair = size % 4 == 3;
  const std::string path = write_scratch("input.geojson", data, size);
  try {
    const geometry::Model m = geometry::load_model(path, options);
    evaluate(m.field, m.dimension);
  } catch (const std::exception& e) {
    rejected(e);
  }
}

}  // namespace sage::fuzz
