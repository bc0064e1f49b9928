// Convergence rates of the meshfree Poisson solver on the manufactured
// problems of issue 4. Rates are measured from the last of a few uniform
// refinements; the Dirichlet data are never the exact solution (so the
// structure omega * Phi + g~ has work to do).
#include "manufactured.hpp"

#include <sage/scalars/rfunction.hpp>

#include <gtest/gtest.h>

namespace sage::solver {
namespace {

using namespace manufactured;

std::array<Expr, 3> coordinates() { return {Expr::x(), Expr::y(), Expr::z()}; }

Expr disk_solution(const std::array<Expr, 3>& p) { return cos(kPi * p[0]) * sin(kPi * p[1]) + p[0]; }

PoissonProblem disk_problem() {
  return dirichlet_problem(2, ball({0, 0, 0}, 1.0, 2), disk_solution(coordinates()),
                           unit_sphere_extension(disk_solution, 2), {-1, -1, 0}, {1, 1, 0});
}

void expect_rates(const std::vector<RefinementRun>& runs, double l2_rate, double h1_rate) {
  for (const RefinementRun& r : runs)
    std::printf("  h = %-8.4g unknowns %-7zu L2 %.3e  H1 %.3e  cond %.3g\n", r.h, r.report.unknowns, l2(r.report),
                h1(r.report), r.report.condition);
  const double l2_observed = last_rate(runs, l2), h1_observed = last_rate(runs, h1);
  std::printf("  rates: L2 %.2f  H1 %.2f\n", l2_observed, h1_observed);
  EXPECT_GE(l2_observed, l2_rate);
  EXPECT_GE(h1_observed, h1_rate);
}

TEST(PoissonConvergence, DiskQuadratic) {
  SolverOptions options;
  options.degree = 2;
  expect_rates(refine<2>(disk_problem(), options, {0.25, 0.125, 0.0625}), 3 - 0.3, 2 - 0.3);
}

TEST(PoissonConvergence, DiskCubic) {
  SolverOptions options;
  options.degree = 3;
  expect_rates(refine<2>(disk_problem(), options, {0.25, 0.125, 0.0625}), 4 - 0.3, 3 - 0.3);
}

TEST(PoissonConvergence, DiskCubicWeightedBasisAgreesWithWeb) {
  // Same space up to the outer B-splines: errors of the same size (both
  // by the Dirichlet structure, the weighted basis' route).
  SolverOptions options;
  options.degree = 3;
  options.cell_width = 0.125;
  options.dirichlet = DirichletRoute::Structure;
  options.basis = BasisKind::Weighted;
  const auto weighted = solve_poisson<2>(disk_problem(), options).report;
  options.basis = BasisKind::Web;
  const auto web = solve_poisson<2>(disk_problem(), options).report;
  EXPECT_LT(web.unknowns, weighted.unknowns);
  EXPECT_LT(*web.l2_error, 3 * *weighted.l2_error);
  EXPECT_LT(*weighted.l2_error, 3 * *web.l2_error);
}

/// u = r^(2/3) sin(2 theta / 3), theta from the edge x = 0, y > 0 of the
/// L-shape (-1,1)^2 minus [0,1]^2, written without atan2: in the frame
/// turned to the bisector of the domain's angle, u = r^(2/3) cos(2 psi/3)
/// with psi in (-3pi/4, 3pi/4); c = cos(psi/3) solves 4c^3 - 3c = cos psi
/// on (cos(pi/4), 1], found by Newton from c = 1 (monotone convergence).
Expr l_shape_solution(const std::array<Expr, 3>& p) {
  const double s = std::sqrt(0.5);
  const Expr along = -(p[0] + p[1]) * s;  // towards the bisector direction (-1, -1)
  const Expr r2 = square(p[0]) + square(p[1]);
  const Expr cos_psi = along / sqrt(r2);
  Expr c = 1.0;
  for (int k = 0; k < 8; ++k) c = c - (4.0 * pow_int(c, 3) - 3.0 * c - cos_psi) / (12.0 * square(c) - 3.0);
  return pow_real(r2, 1.0 / 3.0) * (2.0 * square(c) - 1.0);
}

TEST(PoissonConvergence, LShapeSingularSolution) {
  const RSystem r0 = RSystem::r0();
  const Expr domain = r_and(box({-1, -1, 0}, {1, 1, 0}, 2, r0), -box({0, 0, 0}, {1, 1, 0}, 2, r0), r0);
  const Expr x = Expr::x(), y = Expr::y();
  const Expr exact = l_shape_solution(coordinates());
  // g~ = u chi with chi = 1 on the outer edges (u = 0 on the re-entrant
  // ones) and chi ~ r^2 at the corner: the data are u's boundary values,
  // but the r^(2/3) singularity is left to omega Phi to approximate.
  // (Transfinite interpolation of the six edge traces would add corner
  // singularities of its own: the traces' tangential derivatives disagree
  // at the convex corners.)
  const Expr chi = 1.0 - square(1.0 - square(x)) * square(1.0 - square(y));
  const PoissonProblem problem = dirichlet_problem(2, domain, exact, exact * chi, {-1, -1, 0}, {1, 1, 0});
  SolverOptions options;
  options.degree = 2;
  options.estimate_condition = false;
  const auto runs = refine<2>(problem, options, {0.25, 0.125, 0.0625});
  for (const RefinementRun& r : runs) std::printf("  h = %-8.4g L2 %.3e  H1 %.3e\n", r.h, l2(r.report), h1(r.report));
  const double l2_rate = last_rate(runs, l2), h1_rate = last_rate(runs, h1);
  std::printf("  L2 rate %.2f (4/3 expected), H1 rate %.2f (2/3 expected)\n", l2_rate, h1_rate);
  EXPECT_GE(l2_rate, 4.0 / 3.0 - 0.15);
  EXPECT_GE(h1_rate, 2.0 / 3.0 - 0.15);
}

// The square with a Robin hole (weak and structure routes side by side):
// robin_structure_test.cpp.

Expr ball_solution(const std::array<Expr, 3>& p) { return sin(kPi * p[0]) * sin(kPi * p[1]) * sin(kPi * p[2]) + p[0]; }

TEST(PoissonConvergence, UnitBallQuadratic) {
  const PoissonProblem problem = dirichlet_problem(3, ball({0, 0, 0}, 1.0, 3), ball_solution(coordinates()),
                                                   unit_sphere_extension(ball_solution, 3), {-1, -1, -1}, {1, 1, 1});
  SolverOptions options;
  options.degree = 2;
  options.estimate_condition = false;
  expect_rates(refine<3>(problem, options, {0.4, 0.2, 0.1}), 3 - 0.3, 2 - 0.3);
}

TEST(PoissonPatchTest, SplineSpaceSolutionIsReproduced) {
  // u = omega p + g with p in the spline space (degree <= n in each
  // variable) and g linear: both bases must hold it in the Dirichlet
  // structure, so the only error left is quadrature's.
  const Expr omega = ball({0.037, -0.021, 0}, 0.9, 2);
  const Expr x = Expr::x(), y = Expr::y();
  const Expr g = 0.5 + x + 2.0 * y;
  const Expr u = omega * (1.0 + x - 2.0 * y + x * y * y) + g;
  PoissonProblem problem = dirichlet_problem(2, omega, u, g, {-1, -1, 0}, {1, 1, 0});
  for (const BasisKind basis : {BasisKind::Web, BasisKind::Weighted}) {
    SolverOptions options;
    options.degree = 2;
    options.cell_width = 0.2;
    options.basis = basis;
    options.dirichlet = DirichletRoute::Structure;
    options.quadrature_points = 6;
    options.cg_tolerance = 1e-12;  // no discretization error: solve to round-off
    const auto report = solve_poisson<2>(problem, options).report;
    EXPECT_LT(*report.l2_error, 1e-9) << (basis == BasisKind::Web ? "web" : "weighted");
    EXPECT_LT(*report.h1_error, 1e-8) << (basis == BasisKind::Web ? "web" : "weighted");
  }
  // Degree 1 cannot hold x y^2: the same test must then fail to reproduce.
  SolverOptions options;
  options.degree = 1;
  options.dirichlet = DirichletRoute::Structure;
  options.cell_width = 0.2;
  EXPECT_GT(*solve_poisson<2>(problem, options).report.l2_error, 1e-6);
}

TEST(PoissonPatchTest, BallWithRobinReproducesAQuadratic) {
  // u = 2 - |x|^2 solves -laplace u = 6 with du/dn + 2u = 0 on the unit
  // sphere; with Robin only the weight is 1 and degree 2 holds u, so the
  // weak boundary terms and the 3D cut-cell rules are all that is left.
  PoissonProblem problem;
  problem.domain.dimension = 3;
  problem.domain.field = ball({0, 0, 0}, 1.0, 3);
  problem.domain.min = {-1, -1, -1};
  problem.domain.max = {1, 1, 1};
  problem.source = 6.0;
  problem.rest.kind = BoundaryKind::Robin;
  problem.rest.beta = 2.0;
  problem.exact = 2.0 - square(Expr::x()) - square(Expr::y()) - square(Expr::z());
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.25;
  options.estimate_condition = false;
  options.cg_tolerance = 1e-12;  // the space holds u: solve to round-off
  const SolveReport quadratic = solve_poisson<3>(problem, options).report;
  std::printf("  degree 2: L2 %.3e  H1 %.3e\n", *quadratic.l2_error, *quadratic.h1_error);
  // What is left is quadrature error of the cut cells (8e-7 here, 7e-8 at h = 1/6).
  EXPECT_LT(*quadratic.l2_error, 3e-6);
  EXPECT_LT(*quadratic.h1_error, 5e-5);
  options.degree = 1;
  EXPECT_GT(*solve_poisson<3>(problem, options).report.l2_error, 1e-4);
}

TEST(PoissonPatchTest, NeumannEdgeOnTheGridLattice) {
  // The square (-1,1)^2 with h = 0.1: its edges lie on cell faces, where
  // omega = 0 exactly at the ends of the quadrature lines. The Neumann edge
  // x = 1 must still get its surface points (it once got none, and the
  // condition silently became du/dn = 0: L2 error 0.12). The Dirichlet
  // extension is u itself, so what is left is the weak term's accuracy.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr exact = sin(x + 0.3) * cos(y);
  PoissonProblem problem =
      dirichlet_problem(2, box({-1, -1, 0}, {1, 1, 0}, 2, RSystem::r0()), exact, exact, {-1, -1, 0}, {1, 1, 0});
  problem.parts = {{"others", (1.0 + x) * (1.0 - square(y)), BoundaryKind::Dirichlet, exact},
                   {"right", 1.0 - x, BoundaryKind::Neumann, 0.0, 0.0, derivative(exact, 0)}};
  problem.rest = problem.parts[1];
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.1;
  options.estimate_condition = false;
  options.dirichlet = DirichletRoute::Structure;  // g~ = u: only the Neumann term's error is left
  const SolveReport report = solve_poisson<2>(problem, options).report;
  std::printf("  h = 0.1 on the lattice: %zu surface points, L2 %.3e\n", report.surface_points, *report.l2_error);
  EXPECT_GT(report.surface_points, 0u);
  EXPECT_LT(*report.l2_error, 1e-7);
}

/// The disk with k du/dn = h on the whole circle, and an exact solution of
/// zero mean: exp(x) cos(y) is harmonic (mean = its value 1 at the centre),
/// |x|^2 has mean 1/2, cos(pi x) sin(pi y) + x is odd. Neither f nor h
/// integrates to zero on its own, so the compatibility check has work to do.
PoissonProblem pure_neumann_disk() {
  PoissonProblem problem;
  problem.domain.dimension = 2;
  problem.domain.field = ball({0, 0, 0}, 1.0, 2);
  problem.domain.min = {-1, -1, 0};
  problem.domain.max = {1, 1, 0};
  const Expr x = Expr::x(), y = Expr::y();
  const Expr exact = exp(x) * cos(y) - 1.0 + square(x) + square(y) - 0.5 + disk_solution(coordinates());
  problem.exact = exact;
  problem.source = manufactured_source(exact, problem.conductivity, 2);
  problem.rest.kind = BoundaryKind::Neumann;
  problem.rest.flux = x * derivative(exact, 0) + y * derivative(exact, 1);  // n = (x, y) on the circle
  return problem;
}

TEST(PoissonConvergence, PureNeumannDiskWithZeroMean) {
  const PoissonProblem problem = pure_neumann_disk();
  for (int n : {2, 3}) {
    SolverOptions options;
    options.degree = n;
    options.estimate_condition = false;
    const auto runs = refine<2>(problem, options, {0.25, 0.125, 0.0625});
    for (const RefinementRun& r : runs)
      std::printf("  degree %d h = %-7.4g compatibility defect %.1e\n", n, r.h, *r.report.neumann_compatibility);
    expect_rates(runs, n + 1 - 0.3, n - 0.3);
  }
}

TEST(PoissonConvergence, PureNeumannDiskByTheStructure) {
  // The Robin structure with its second function on the whole circle: the
  // constant (P's vector of ones) is still the null space, and the
  // second function's rows take the same compatibility shift.
  const PoissonProblem problem = pure_neumann_disk();
  SolverOptions options;
  options.degree = 3;
  options.robin = RobinRoute::Structure;
  options.estimate_condition = false;
  const auto runs = refine<2>(problem, options, {0.125, 0.0625, 0.03125});
  for (const RefinementRun& r : runs)
    std::printf("  structure h = %-7.4g second-function unknowns %zu, L2 %.2e, H1 %.2e\n", r.h,
                r.report.second_unknowns, *r.report.l2_error, *r.report.h1_error);
  EXPECT_GT(runs.back().report.second_unknowns, 0u);
  expect_rates(runs, 4 - 0.3, 3 - 0.3);
}

TEST(PoissonProblemErrors, IncompatibleNeumannDataAreRefused) {
  // (f, 1) + <h, 1> = pi * 0.01 instead of 0 (relative 5e-4): far above
  // the quadrature's defect (about 1e-15, printed by the test above).
  PoissonProblem problem = pure_neumann_disk();
  problem.source = problem.source + 0.01;
  SolverOptions options;
  options.cell_width = 0.25;
  try {
    solve_poisson<2>(problem, options);
    ADD_FAILURE() << "incompatible data were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("incompatible Neumann data"), std::string::npos) << e.what();
  }
}

TEST(PoissonProblemErrors, TooCoarseAndEmptyDomains) {
  PoissonProblem problem = disk_problem();
  problem.domain.field = ball({0, 0, 0}, 0.05, 2);
  SolverOptions options;
  options.cell_width = 0.25;
  EXPECT_THROW(solve_poisson<2>(problem, options), std::runtime_error);
  problem.domain.field = ball({0, 0, 0}, 0.5, 2) - 10.0;  // negative everywhere
  EXPECT_THROW(solve_poisson<2>(problem, options), std::runtime_error);
}

TEST(PoissonProblemErrors, TooLargeForMemoryIsRefusedUpFront) {
  // The estimate comes from the classified grid, before any quadrature
  // point or matrix exists; the message gives the figures.
  SolverOptions options;
  options.cell_width = 0.02;
  options.estimate_condition = false;
  const SolveReport fits = solve_poisson<2>(disk_problem(), options).report;
  EXPECT_GT(fits.memory_estimate_mb, 1.0);
  EXPECT_LT(fits.memory_estimate_mb, 500.0);
  options.memory_limit_mb = 0.5 * fits.memory_estimate_mb;
  try {
    solve_poisson<2>(disk_problem(), options);
    ADD_FAILURE() << "not refused";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("too large for this machine"), std::string::npos) << message;
    EXPECT_NE(message.find("cells inside"), std::string::npos) << message;
    EXPECT_NE(message.find("B-splines"), std::string::npos) << message;
  }
  // A grid whose classification alone would not fit.
  options.memory_limit_mb = 1.0;
  options.cell_width = 0.0005;
  EXPECT_THROW(solve_poisson<2>(disk_problem(), options), std::runtime_error);
}

}  // namespace
}  // namespace sage::solver
