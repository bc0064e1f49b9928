// Nitsche's method for Dirichlet conditions (the weak route, poisson.hpp):
// its consistency (a solution in the spline space comes back to round-off)
// and the size of its penalty sigma = c (n + 1)^2 / h, c = 4. The errors
// hardly tell the size: c = 40 instead of 4 raises the L2 error by 5% to
// 66% and the H1 error by at most 24% (measured on an off-centre disk and a
// quadrilateral, degrees 2 and 3, h = 0.1 and 0.05), while the condition
// number grows 6 to 10 times. What tells it is coercivity: the system is
// positive definite only from some c* on, and c = 4 must keep a margin over
// c* without being an order of magnitude beyond it.
#include "manufactured.hpp"

#include <sage/scalars/rfunction.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace sage::solver {
namespace {

using namespace manufactured;

/// A quadrilateral with no edge on the grid's lattice and no right angle,
/// as the R0-conjunction of its edges (corners anticlockwise).
Expr quadrilateral() {
  const std::array<std::array<double, 2>, 4> corner{{{-0.9, -0.7}, {0.8, -0.9}, {1.0, 0.6}, {-0.6, 0.95}}};
  Expr field;
  for (int e = 0; e < 4; ++e) {
    const auto& p = corner[e];
    const auto& q = corner[(e + 1) % 4];
    const double length = std::hypot(q[0] - p[0], q[1] - p[1]);
    const Expr edge = halfspace({p[0], p[1], 0}, {(q[1] - p[1]) / length, -(q[0] - p[0]) / length, 0}, 2);
    field = e == 0 ? edge : r_and(field, edge, RSystem::r0());
  }
  return field;
}

PoissonProblem dirichlet_on(const Expr& domain, const Expr& k, const Expr& exact, std::array<double, 3> min,
                            std::array<double, 3> max) {
  return conductivity_problem(domain, k, exact, exact, min, max);
}

TEST(NitschePatchTest, SplineSpaceSolutionIsReproducedWeakly) {
  // u of coordinate degree 2 lies in the WEB space of degree n >= 2 (the
  // extension keeps such polynomials), and Nitsche's symmetric form is
  // consistent: with u, a(u, v) - l(v) = (k grad u, grad v) - <k dn u, v>
  // - (f, v), zero by the divergence theorem. Polygonal edges and Gauss
  // rules of 2n + 2 nodes integrate every term exactly (along a slanted
  // edge a product of two B-splines and k has degree 4n + 2), so what is
  // left is round-off: for k = 1 and for a polynomial k, whatever the
  // penalty (above coercivity). Degree 1 cannot hold x y^2 and must fail.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr u = 1.0 + x - 2.0 * y + x * square(y) + 0.5 * square(x) * y - 0.3 * square(x) * square(y);
  for (const Expr& k : {Expr(1.0), 1.0 + 0.5 * square(x) + 0.25 * square(y) + 0.1 * x * y}) {
    const PoissonProblem problem = dirichlet_on(quadrilateral(), k, u, {-1, -1, 0}, {1, 1, 0});
    for (const int degree : {2, 3})
      for (const double factor : {1.0, 8.0}) {
        SolverOptions options;
        options.degree = degree;
        options.cell_width = 0.15;
        options.quadrature_points = 2 * degree + 2;
        options.nitsche_penalty = factor * nitsche_penalty(0.0, degree);
        options.linear_solver = LinearSolverKind::Direct;
        options.estimate_condition = false;
        const SolveReport report = solve_poisson<2>(problem, options).report;
        std::printf("  k %s, degree %d, penalty %g: L2 %.2e  H1 %.2e\n", k.is_constant() ? "1" : "polynomial", degree,
                    *report.nitsche_penalty, *report.l2_error, *report.h1_error);
        EXPECT_EQ(report.dirichlet_route, "weak (Nitsche)");
        EXPECT_LT(*report.l2_error, 1e-12) << "degree " << degree << ", penalty " << *report.nitsche_penalty;
        EXPECT_LT(*report.h1_error, 1e-11) << "degree " << degree << ", penalty " << *report.nitsche_penalty;
      }
    SolverOptions options;
    options.degree = 1;
    options.cell_width = 0.15;
    options.estimate_condition = false;
    EXPECT_GT(*solve_poisson<2>(problem, options).report.l2_error, 1e-4);
  }
}

/// The triangle with a `degrees` angle at (-0.83, 0.11), opening along the
/// direction 0.2 rad from the x axis, closed 1.6 from its apex: sharp
/// corners inside cells, edges at general angles to the grid.
Expr wedge(double degrees) {
  const double apex[2] = {-0.83, 0.11}, direction = 0.2, half = 0.5 * degrees * kPi / 180, length = 1.6;
  const double a = direction + half, b = direction - half;
  const Expr upper = halfspace({apex[0], apex[1], 0}, {-std::sin(a), std::cos(a), 0}, 2);
  const Expr lower = halfspace({apex[0], apex[1], 0}, {std::sin(b), -std::cos(b), 0}, 2);
  const Expr end = halfspace({apex[0] + length * std::cos(direction), apex[1] + length * std::sin(direction), 0},
                             {std::cos(direction), std::sin(direction), 0}, 2);
  return r_and(r_and(upper, lower, RSystem::r0()), end, RSystem::r0());
}

/// Whether the system matrix with Nitsche's penalty `penalty` / h is
/// positive definite: the direct solve checks the diagonal and LDLT's
/// pivots, and refuses an indefinite matrix ("... not positive definite").
bool definite(const PoissonProblem& problem, int degree, double h, double penalty) {
  SolverOptions options;
  options.degree = degree;
  options.cell_width = h;
  options.nitsche_penalty = penalty;
  options.linear_solver = LinearSolverKind::Direct;
  options.estimate_condition = false;
  try {
    solve_poisson<2>(problem, options);
    return true;
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("positive definite") == std::string::npos) throw;
    return false;
  }
}

TEST(NitschePenalty, DefaultKeepsAMarginOverCoercivityOnAThinWedge) {
  // The symmetric method is coercive when sigma exceeds an inverse-trace
  // constant, ||dn v||^2 on a cell's boundary piece <= C (n + 1)^2 / h
  // ||grad v||^2 on the cell, which the WEB extension keeps bounded in cut
  // cells whatever the cut. The matrix A0 + sigma P (P >= 0) is positive
  // definite exactly from a threshold c* (n + 1)^2 / h on, c* independent of
  // h, and largest where the domain is thin: a 10 degree wedge (measured
  // 0.64 to 0.71 at degree 2, 0.81 to 0.88 at degree 3). So:
  //   - the default is 4 (n + 1)^2 / h (solver_options.hpp, method.md);
  //   - it keeps a margin of 2 over c*, and is less than 12 times c*;
  //   - c* is the same at h = 0.1, 0.05 and 0.025 within a factor 1.5.
  // A penalty ten times too large or too small, or one that scales as
  // 1/h^2 (c* would then fall in proportion to h), fails this. c* by
  // bisection, definiteness being monotone in sigma.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr u = exp(0.5 * x) * sin(1.3 * y + 0.4) + x * square(y);
  const PoissonProblem problem = dirichlet_on(wedge(10.0), Expr(1.0), u, {-1, -1, 0}, {1, 1, 0});
  for (const int degree : {2, 3}) {
    const double scale = (degree + 1) * (degree + 1), standard = nitsche_penalty(0.0, degree);
    EXPECT_EQ(standard, 4.0 * scale);
    std::vector<double> thresholds;
    for (const double h : {0.1, 0.05, 0.025}) {
      ASSERT_TRUE(definite(problem, degree, h, standard)) << "the default penalty, degree " << degree << ", h " << h;
      double lo = standard / 100, hi = standard;  // indefinite at lo (checked), definite at hi
      ASSERT_FALSE(definite(problem, degree, h, lo)) << "degree " << degree << ", h " << h;
      for (int step = 0; step < 7; ++step) {
        const double mid = std::sqrt(lo * hi);
        (definite(problem, degree, h, mid) ? hi : lo) = mid;
      }
      const double threshold = hi / scale;  // c*, within a factor 1.04 (100^(1/128))
      std::printf("  degree %d, h = %-6.3g: definite from c = %.3f on (default %.0f)\n", degree, h, threshold,
                  standard / scale);
      EXPECT_LE(2 * threshold, standard / scale) << "degree " << degree << ", h " << h;
      EXPECT_GE(12 * threshold, standard / scale) << "degree " << degree << ", h " << h;
      thresholds.push_back(threshold);
    }
    const auto [least, most] = std::minmax_element(thresholds.begin(), thresholds.end());
    EXPECT_LE(*most, 1.5 * *least) << "degree " << degree << ": c* depends on h";
  }
}

}  // namespace
}  // namespace sage::solver
