#pragma once
// Manufactured solutions for the solver tests: the source term is
// f = -div(k grad u) (manufactured.hpp of the library), so every test
// states only its exact solution, its domain and its boundary data; and
// refinement studies with observed rates.

#include <sage/expression/derivative.hpp>
#include <sage/expression/expression.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>

#include <solver_fixtures.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace sage::solver::manufactured {

constexpr double kPi = 3.14159265358979323846;

/// A problem with Dirichlet data on the whole boundary.
inline PoissonProblem dirichlet_problem(int dimension, const Expr& domain, const Expr& exact, const Expr& extension,
                                        std::array<double, 3> min, std::array<double, 3> max) {
  PoissonProblem p;
  p.domain.dimension = dimension;
  p.domain.field = domain;
  p.domain.min = min;
  p.domain.max = max;
  p.source = manufactured_source(exact, p.conductivity, dimension);
  p.exact = exact;
  p.dirichlet_extension = extension;
  return p;
}

/// -div(k grad u) = f in 2D, u = `boundary_value` on the whole boundary
/// (the rest), k and the exact solution given.
inline PoissonProblem conductivity_problem(const Expr& domain, const Expr& k, const Expr& exact,
                                           const Expr& boundary_value, std::array<double, 3> min,
                                           std::array<double, 3> max) {
  PoissonProblem p;
  p.domain.dimension = 2;
  p.domain.field = domain;
  p.domain.min = min;
  p.domain.max = max;
  p.conductivity = k;
  p.source = manufactured_source(exact, k, 2);
  p.exact = exact;
  p.rest.value = boundary_value;
  return p;
}

struct RefinementRun {
  double h;
  SolveReport report;
};

/// Solves on cell widths h, and returns the reports.
template <int D>
std::vector<RefinementRun> refine(const PoissonProblem& problem, SolverOptions options,
                                  const std::vector<double>& widths) {
  std::vector<RefinementRun> runs;
  for (double h : widths) {
    options.cell_width = h;
    runs.push_back({h, solve_poisson<D>(problem, options).report});
  }
  return runs;
}

/// Observed rate of the last refinement step for an error picked by `error`.
inline double last_rate(const std::vector<RefinementRun>& runs, double (*error)(const SolveReport&)) {
  const RefinementRun& a = runs[runs.size() - 2];
  const RefinementRun& b = runs.back();
  return std::log(error(a.report) / error(b.report)) / std::log(a.h / b.h);
}
inline double l2(const SolveReport& r) { return *r.l2_error; }
inline double h1(const SolveReport& r) { return *r.h1_error; }

}  // namespace sage::solver::manufactured
