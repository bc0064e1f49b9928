// Rvachev's solution structure for Robin and Neumann parts
// (trial_structure.hpp): the trial functions satisfy the condition
// identically, whatever the spline coefficients; rates on the square with a
// Robin hole beside the weak route; and the problems it refuses.
//
// With the global weight W the structure converges one order below the
// weak route: grad u contains W times second derivatives of the splines,
// which degree-n splines approximate to O(h^(n-1)) only. The solver cuts W
// off at a distance band ~ h^(2/3) from the structured parts (poisson.hpp,
// robin_band) and adds Rvachev's second function there, which absorbs the
// Robin defect that P alone could only follow with a layer: the rates are
// optimal and the errors those of the weak route (`solve_bench robin`
// prints both routes and both weights).
#include "manufactured.hpp"

#include <sage/scalars/rfunction.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <gtest/gtest.h>

#include <random>

namespace sage::solver {
namespace {

using namespace manufactured;

double value_at(const Expr& e, const double* x) {
  Tape tape(e, 2);
  Evaluator<double> eval(tape);
  return eval.at({x[0], x[1], 0.0});
}

TEST(RobinStructure, SatisfiesTheConditionForAnyCoefficients) {
  // Non-constant k and beta: the structure divides by k; any sign slip or a
  // missing factor shows as a residual of order one.
  const Expr x = Expr::x(), y = Expr::y();
  const PoissonProblem problem = square_with_robin_hole(1.0 + 0.5 * square(x), 1.0 + square(y));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coefficient(-1.0, 1.0);
  for (int degree : {2, 3}) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = 0.2;
    options.robin = RobinRoute::Structure;
    options.estimate_condition = false;
    PoissonSolution<2> solution = solve_poisson<2>(problem, options);
    for (Eigen::Index i = 0; i < solution.spline_coefficients.size(); ++i)
      solution.spline_coefficients[i] = coefficient(random);
    ASSERT_EQ(solution.second_coefficients.size(), solution.spline_coefficients.size());  // the second function
    for (Eigen::Index i = 0; i < solution.second_coefficients.size(); ++i)
      solution.second_coefficients[i] = 10 * coefficient(random);
    PoissonSolution<2>::Probe probe(solution);
    const BoundaryPart& robin = problem.parts[1];
    double worst = 0.0, size = 0.0;
    for (int k = 0; k < 97; ++k) {
      const double angle = 2 * kPi * k / 97 + 0.01;
      const double p[2] = {0.4 * std::cos(angle), 0.4 * std::sin(angle)};
      double grad[2];
      const double u = probe.at(p, grad);
      const double du_dn = -(p[0] * grad[0] + p[1] * grad[1]) / 0.4;
      const double k_value = value_at(problem.conductivity, p);
      const double residual = k_value * du_dn + value_at(robin.beta, p) * u - value_at(robin.flux, p);
      worst = std::max(worst, std::abs(residual));
      size = std::max(size, std::abs(k_value * du_dn) + std::abs(u));
    }
    std::printf(
        "  degree %d, random coefficients: |k du/dn + beta u - h| <= %.2e on the hole (|u| + |k du/dn| "
        "up to %.2f)\n",
        degree, worst, size);
    EXPECT_GT(size, 0.5);  // the coefficients do reach the boundary
    EXPECT_LT(worst, 1e-11);
    // And the Dirichlet part keeps u = 0 (on the square's edges).
    for (double t : {-0.9, -0.3, 0.2, 0.75}) {
      const double q[2] = {1.0, t}, r[2] = {t, -1.0};
      EXPECT_NEAR(probe.at(q), 0.0, 1e-12);
      EXPECT_NEAR(probe.at(r), 0.0, 1e-12);
    }
  }
  // The weak route's trial functions do not: the same random coefficients
  // leave an O(1) residual (the test can tell the two apart).
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.2;
  options.estimate_condition = false;
  PoissonSolution<2> weak = solve_poisson<2>(problem, options);
  for (Eigen::Index i = 0; i < weak.spline_coefficients.size(); ++i) weak.spline_coefficients[i] = coefficient(random);
  PoissonSolution<2>::Probe probe(weak);
  double worst = 0.0;
  for (int k = 0; k < 16; ++k) {
    const double angle = 2 * kPi * k / 16;
    const double p[2] = {0.4 * std::cos(angle), 0.4 * std::sin(angle)};
    double grad[2];
    const double u = probe.at(p, grad);
    const double du_dn = -(p[0] * grad[0] + p[1] * grad[1]) / 0.4;
    worst = std::max(worst, std::abs(value_at(problem.conductivity, p) * du_dn +
                                     value_at(problem.parts[1].beta, p) * u - value_at(problem.parts[1].flux, p)));
  }
  EXPECT_GT(worst, 1e-2);
}

void print_runs(const char* route, const std::vector<RefinementRun>& runs) {
  for (const RefinementRun& r : runs)
    std::printf("  %-9s h = %-6.3g unknowns %-6zu L2 %.3e  H1 %.3e\n", route, r.h, r.report.unknowns, l2(r.report),
                h1(r.report));
  std::printf("  %-9s rates: L2 %.2f  H1 %.2f\n", route, last_rate(runs, l2), last_rate(runs, h1));
}

TEST(RobinStructure, RatesBesideTheWeakRoute) {
  // Both routes at their optimal rates, n + 1 in L2 and n in H1, less 0.3,
  // and the structure's errors within twice the weak route's at the finest
  // width (without the second function they were 440 to 26,000 times).
  const PoissonProblem problem = square_with_robin_hole(1.0, 1.0);
  const std::vector<double> widths{0.05, 0.025, 0.0125};
  for (int n : {2, 3}) {
    SolverOptions options;
    options.degree = n;
    options.estimate_condition = false;
    const auto weak = refine<2>(problem, options, widths);
    options.robin = RobinRoute::Structure;
    const auto structure = refine<2>(problem, options, widths);
    std::printf("  degree %d\n", n);
    print_runs("weak", weak);
    print_runs("structure", structure);
    EXPECT_GE(last_rate(weak, l2), n + 1 - 0.3);
    EXPECT_GE(last_rate(weak, h1), n - 0.3);
    EXPECT_GE(last_rate(structure, l2), n + 1 - 0.3);
    EXPECT_GE(last_rate(structure, h1), n - 0.3);
    EXPECT_LT(l2(structure.back().report), 2 * l2(weak.back().report));
    EXPECT_LT(h1(structure.back().report), 2 * h1(weak.back().report));
    EXPECT_GT(structure.back().report.second_unknowns, 0u);
    if (n == 3) {
      // The global W (robin_band 0, no second function) leaves W D1(Phi)
      // of size O(1) inside and loses an order.
      options.cell_width = 0.025;
      options.robin_band = 0.0;
      const SolveReport global = solve_poisson<2>(problem, options).report;
      const SolveReport& cut = structure[1].report;
      std::printf("  global W  h = 0.025  L2 %.3e  H1 %.3e\n", l2(global), h1(global));
      EXPECT_EQ(global.second_unknowns, 0u);
      EXPECT_LT(l2(cut), 1e-3 * l2(global));
      EXPECT_LT(h1(cut), 1e-3 * h1(global));
    }
  }
}

TEST(RobinStructure, CutOffKeepsTheWeightNormalized) {
  // W = x cut at band 0.5: psi(0) = 0 and psi'(0) = 1 (so the structure's
  // condition is unchanged), zero from the band on, and the derivative is
  // continuous across the band's edge (it is C^(power - 1)).
  const Expr x = Expr::x();
  const Expr cut = localized_weight(x, x, 0.5, 8);
  const Expr slope = derivative(cut, 0);
  auto at = [](const Expr& e, double t) {
    const double p[2] = {t, 0.0};
    return value_at(e, p);
  };
  EXPECT_NEAR(at(cut, 0.0), 0.0, 1e-15);
  EXPECT_NEAR(at(slope, 0.0), 1.0, 1e-15);
  EXPECT_NEAR(at(cut, 0.1), 0.1 * std::pow(0.8, 8), 1e-15);
  EXPECT_EQ(at(cut, 0.5), 0.0);
  EXPECT_EQ(at(cut, 0.7), 0.0);
  EXPECT_EQ(at(slope, 0.7), 0.0);
  EXPECT_LT(std::abs(at(slope, 0.5 - 1e-3)), 1e-15);
  // Finite differences agree with the symbolic slope inside the band.
  const double e = 1e-6;
  EXPECT_NEAR((at(cut, 0.2 + e) - at(cut, 0.2 - e)) / (2 * e), at(slope, 0.2), 1e-8);
  // Without a band the weight is W itself.
  EXPECT_EQ(localized_weight(x, x, 0.0, 8).id(), x.id());
}

TEST(RobinStructure, RefusesWhatItCannotPose) {
  SolverOptions options;
  options.cell_width = 0.2;
  options.robin = RobinRoute::Structure;
  options.estimate_condition = false;
  PoissonProblem problem = square_with_robin_hole(1.0, 1.0);
  options.degree = 1;  // no second derivatives
  EXPECT_THROW(solve_poisson<2>(problem, options), std::invalid_argument);
  options.degree = 2;
  options.cell_width = 0.17;  // edges off the cell faces, so the surface rule has points there
  // A Robin part that meets the Dirichlet part: the right edge of the square.
  const Expr x = Expr::x(), y = Expr::y();
  PoissonProblem edge;
  edge.domain.dimension = 2;
  edge.domain.field = box({-1, -1, 0}, {1, 1, 0}, 2, RSystem::r0());
  edge.domain.min = {-1, -1, 0};
  edge.domain.max = {1, 1, 0};
  edge.source = 1.0;
  edge.parts = {{"others", (1.0 + x) * (1.0 - square(y)), BoundaryKind::Dirichlet, 0.0},
                {"right", 1.0 - x, BoundaryKind::Robin, 0.0, 1.0, 0.0}};
  edge.rest = edge.parts[1];
  EXPECT_THROW(solve_poisson<2>(edge, options), std::invalid_argument);
  // The weak route poses both.
  options.robin = RobinRoute::Weak;
  EXPECT_NO_THROW(solve_poisson<2>(edge, options));
  // A selector whose zero line crosses the domain: the structure would
  // impose the condition along it.
  options.robin = RobinRoute::Structure;
  PoissonProblem crossing = square_with_robin_hole(1.0, 1.0);
  crossing.parts[1].selector = crossing.parts[1].selector * (x - 0.7);
  EXPECT_THROW(solve_poisson<2>(crossing, options), std::invalid_argument);
}

TEST(RobinStructure, RouteNames) {
  EXPECT_EQ(parse_robin_route("weak"), RobinRoute::Weak);
  EXPECT_EQ(parse_robin_route("structure"), RobinRoute::Structure);
  EXPECT_THROW(parse_robin_route("strong"), std::invalid_argument);
}

}  // namespace
}  // namespace sage::solver
