// Fuzzes the formula parser: sage::parse_formula on the input text in 2D
// and in 3D, each parsed expression compiled to a tape and evaluated at a
// few points (doubles) and over a box (intervals). FormulaError (or
// another std::exception) is the answer to bad input; anything else is a
// finding.
#include "fuzz_targets.hpp"

#include <sage/expression/formula.hpp>

namespace sage::fuzz {

void formula(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return;
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const int dimension : {2, 3}) {
    try {
      evaluate(parse_formula(text, dimension), dimension);
    } catch (const std::exception& e) {
      rejected(e);
    }
  }
}

}  // namespace sage::fuzz
