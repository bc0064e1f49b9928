#pragma once
// Helpers for manufactured-solution studies: pick an exact solution u, and
// the source term and boundary data follow. (The tests' and benchmarks'
// problems built on them are in tests/support/solver_fixtures.hpp.)

#include <sage/expression/derivative.hpp>
#include <sage/expression/expression.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/solver/problem.hpp>

#include <array>
#include <functional>

namespace sage::solver {

/// f = -div(k grad u), by symbolic differentiation.
inline Expr manufactured_source(const Expr& u, const Expr& k, int dimension) {
  Expr f = 0.0;
  for (int a = 0; a < dimension; ++a) f = f - derivative(k * derivative(u, a), a);
  return f;
}

/// u(x / s) with s = (1 + |x|^2) / 2: equal to u on the unit sphere (circle),
/// smooth, built from u's values along rays only, so not u itself inside.
/// Dirichlet data for the unit disk and ball that leave omega Phi work to do.
inline Expr unit_sphere_extension(const std::function<Expr(const std::array<Expr, 3>&)>& u, int dimension) {
  Expr r2 = 0.0;
  for (int a = 0; a < dimension; ++a) r2 = r2 + square(Expr::var(a));
  const Expr s = (1.0 + r2) * 0.5;
  std::array<Expr, 3> p{Expr(0.0), Expr(0.0), Expr(0.0)};
  for (int a = 0; a < dimension; ++a) p[a] = Expr::var(a) / s;
  return u(p);
}

}  // namespace sage::solver
