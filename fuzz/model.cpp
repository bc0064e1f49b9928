// Fuzzes the JSON CSG model reader: sage::geometry::parse_model on the
// input text, then the model's field compiled to a tape and evaluated at a
// few points and over a box. ModelError (or another std::exception) is the
// answer to bad input; anything else is a finding.
#include "fuzz_targets.hpp"

#include <sage/geometry/csg_model.hpp>

namespace sage::fuzz {

void model(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return;
  try {
    const geometry::Model m = geometry::parse_model(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    evaluate(m.field, m.dimension);
  } catch (const std::exception& e) {
    rejected(e);
  }
}

}  // namespace sage::fuzz
