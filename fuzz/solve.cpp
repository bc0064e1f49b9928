// Fuzzes a problem file through a solve on a tiny grid: read_problem_file
// (as problem.cpp, in the scratch folder), then solve_poisson<D> or
// solve_elasticity<D> with 4 to 16 cells across the box in 2D, 3 to 5 in
// 3D, degree 1 or 2 (2 for the Robin structure), a linear solver and a
// basis picked by a hash of the input (deterministic), the file's Robin
// route, and a memory limit of 256 MB. A std::exception
// (bad problem, grid too coarse, no convergence) is an answer; a crash, a
// sanitizer report, a hang or huge memory is a finding.
#include "fuzz_targets.hpp"

#include <sage/problems/problem_file.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <algorithm>
#include <variant>

namespace sage::fuzz {

namespace {

std::uint32_t fnv1a(const std::uint8_t* data, std::size_t size) {
  std::uint32_t h = 2166136261u;
  for (std::size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 16777619u;
  return h;
}

template <int D>
void solve_in(const problems::ProblemFile& file, const solver::SolverOptions& options) {
  if (const auto* elasticity = std::get_if<solver::ElasticityProblem>(&file.physics))
    (void)solver::solve_elasticity<D>(*elasticity, options);
  else
    (void)solver::solve_poisson<D>(std::get<solver::PoissonProblem>(file.physics), options);
}

}  // namespace

void solve(const std::uint8_t* data, std::size_t size) {
  setup();
  if (size > 16 * 1024) return;
  if (!domain_stays_in_scratch(std::string(reinterpret_cast<const char*>(data), size))) return;
  const std::string path = write_scratch("problems/input.json", data, size);
  const std::uint32_t hash = fnv1a(data, size);
  static const solver::LinearSolverKind kSolvers[] = {
      solver::LinearSolverKind::Automatic, solver::LinearSolverKind::Direct,
      solver::LinearSolverKind::ConjugateGradient, solver::LinearSolverKind::JacobiConjugateGradient,
      solver::LinearSolverKind::Schwarz};
  try {
    const problems::ProblemFile file = problems::read_problem_file(path);
    const solver::ProblemDomain& domain = file.domain();
    solver::SolverOptions options;
    // The Robin structure needs degree 2.
    options.robin = file.robin.value_or(solver::RobinRoute::Weak);
    options.degree = options.robin == solver::RobinRoute::Structure ? 2 : 1 + static_cast<int>(hash & 1);
    options.linear_solver = kSolvers[(hash >> 1) % 5];
    options.basis = hash & 8 ? solver::BasisKind::Weighted : solver::BasisKind::Web;
    options.estimate_condition = false;
    options.memory_limit_mb = 256;
    const int cells =
        domain.dimension == 2 ? 4 + static_cast<int>((hash >> 4) % 13) : 3 + static_cast<int>((hash >> 4) % 3);
    options.cell_width = domain.longest_side() / cells;
    if (domain.dimension == 2)
      solve_in<2>(file, options);
    else
      solve_in<3>(file, options);
  } catch (const std::exception& e) {
    rejected(e);
  }
}

}  // namespace sage::fuzz
