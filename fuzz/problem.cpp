// Fuzzes the problem-file reader: sage::problems::read_problem_file on the
// input written to the scratch folder (problems/input.json beside a models/
// folder, so "../models/plate_with_holes.json" resolves), then the domain
// field evaluated. A "domain" path leaving the scratch folder is skipped.
// ProblemError, ModelError (or another std::exception) is the answer to
// bad input; anything else is a finding.
#include "fuzz_targets.hpp"

#include <sage/problems/problem_file.hpp>

namespace sage::fuzz {

void problem(const std::uint8_t* data, std::size_t size) {
  setup();
  if (size > 64 * 1024) return;
  if (!domain_stays_in_scratch(std::string(reinterpret_cast<const char*>(data), size))) return;
  const std::string path = write_scratch("problems/input.json", data, size);
  try {
    const problems::ProblemFile file = problems::read_problem_file(path);
    evaluate(file.domain().field, file.domain().dimension);
  } catch (const std::exception& e) {
    rejected(e);
  }
}

}  // namespace sage::fuzz
