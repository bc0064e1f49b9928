#pragma once
// Manufactured solutions for the solver tests: the source term is
// f = -div(k grad u), computed by symbolic differentiation, so every test
// states only its exact solution, its domain and its boundary data.

#include <sage/derivative.hpp>
#include <sage/expression.hpp>
#include <sage/primitives.hpp>
#include <sage/solver/poisson.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace sage::solver::manufactured {

constexpr double kPi = 3.14159265358979323846;

/// f = -div(k grad u).
inline Expr source_for(const Expr& u, const Expr& k, int dimension) {
  Expr f = 0.0;
  for (int a = 0; a < dimension; ++a) f = f - derivative(k * derivative(u, a), a);
  return f;
}

/// A problem with Dirichlet data on the whole boundary.
inline PoissonProblem dirichlet_problem(int dimension, const Expr& domain, const Expr& exact, const Expr& extension,
                                        std::array<double, 3> min, std::array<double, 3> max) {
  PoissonProblem p;
  p.dimension = dimension;
  p.domain = domain;
  p.min = min;
  p.max = max;
  p.source = source_for(exact, p.conductivity, dimension);
  p.exact = exact;
  p.dirichlet_extension = extension;
  return p;
}

/// u(x / s) with s = (1 + |x|^2) / 2: equal to u on the unit sphere, smooth,
/// and built from u's values on rays only, so not u itself inside.
inline Expr radial_extension(const std::function<Expr(const std::array<Expr, 3>&)>& u, int dimension) {
  Expr r2 = 0.0;
  for (int a = 0; a < dimension; ++a) r2 = r2 + square(Expr::var(a));
  const Expr s = (1.0 + r2) * 0.5;
  std::array<Expr, 3> p{Expr(0.0), Expr(0.0), Expr(0.0)};
  for (int a = 0; a < dimension; ++a) p[a] = Expr::var(a) / s;
  return u(p);
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
