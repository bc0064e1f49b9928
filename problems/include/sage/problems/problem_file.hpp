#pragma once
// Problem files for `sage solve` and library users (schema in README.md,
// "Solving boundary value problems"): a domain (inline JSON CSG model or the path of any
// model sage reads), the data of -div(k grad u) = f or, with "physics":
// "elasticity", of linear elasticity as formulas, boundary conditions on
// named parts, and an optional exact solution.

#include <sage/geometry/model.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/problem.hpp>
#include <sage/solver/trial_structure.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <variant>

namespace sage::problems {

/// Bad problem file: the message names the file, the JSON pointer (or
/// line:column for malformed JSON) and what is wrong.
class ProblemError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The physics of a problem file: "physics": "poisson" (the default) or "elasticity".
using Physics = std::variant<solver::PoissonProblem, solver::ElasticityProblem>;

struct ProblemFile {
  geometry::Model model;
  Physics physics;
  std::string exact_formula;                // empty when none
  std::optional<solver::RobinRoute> robin;  // "robin": "weak" | "structure"; --robin overrides
  std::optional<double> deflection;         // "deflection": a CAD domain's, as the file gives it

  /// The domain (from the model and "bounds"), as the physics holds it.
  const solver::ProblemDomain& domain() const {
    return std::visit([](const auto& problem) -> const solver::ProblemDomain& { return problem.domain; }, physics);
  }
};

/// Reads a problem file; a domain given as a path is read with
/// `domain_options` (a CAD domain's "deflection" key applies unless they
/// set one). Throws ProblemError (and geometry::ModelError for a domain
/// model that cannot be read).
ProblemFile read_problem_file(const std::string& path, const geometry::LoadOptions& domain_options = {});

}  // namespace sage::problems
