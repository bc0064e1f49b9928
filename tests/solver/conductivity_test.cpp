// Variable conductivity, -div(k grad u) = f: every other rate test of the
// suite has k = 1, so these are what guards the per-point k of the
// assembly (the stiffness, the load's k grad g~ term and Nitsche's k dn u
// and sigma k u terms). Manufactured solutions (f from the exact u and k by
// symbolic differentiation) on domains that do not favour the grid: a disk
// off the grid's centre, and a square turned against the grid (edges at
// general angles, corners inside cells). The Dirichlet data g = u + omega b
// equal u on the boundary but not inside, so the structure route's g~ is
// not the solution either.
//
// With a smooth k bounded away from 0, Galerkin's error in the k-weighted
// energy norm is the best approximation's (Cea), whose constants depend on
// k's range but not on h: the rates are those of k = 1, n + 1 in L2
// (Aubin-Nitsche) and n in H1 for degree n. Asserted with the margin of
// the other rate tests (0.3). In 3D, a polynomial k and a solution in the
// spline space come back to round-off; a k that jumps across a line
// converges at the (lower) rates such a kink allows.
#include "manufactured.hpp"

#include <sage/scalars/rfunction.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace sage::solver {
namespace {

using namespace manufactured;

/// Dirichlet data u + omega b on the whole boundary, with conductivity k.
PoissonProblem variable_k_problem(const Expr& domain, const Expr& k, const Expr& exact, const Expr& bubble,
                                  std::array<double, 3> min, std::array<double, 3> max) {
  return conductivity_problem(domain, k, exact, exact + domain * bubble, min, max);
}

/// The square of half-side `half` about `centre`, turned by `angle`, as the
/// R0-conjunction of its four edges.
Expr turned_square(double angle, double half, std::array<double, 2> centre) {
  const double c = std::cos(angle), s = std::sin(angle);
  const std::array<std::array<double, 2>, 4> normals{{{c, s}, {-s, c}, {-c, -s}, {s, -c}}};
  Expr field;
  for (int e = 0; e < 4; ++e) {
    const auto& n = normals[e];
    const Expr edge = halfspace({centre[0] + half * n[0], centre[1] + half * n[1], 0}, {n[0], n[1], 0}, 2);
    field = e == 0 ? edge : r_and(field, edge, RSystem::r0());
  }
  return field;
}

std::vector<RefinementRun> study(const char* title, const PoissonProblem& problem, int degree, DirichletRoute route,
                                 const std::vector<double>& widths) {
  SolverOptions options;
  options.degree = degree;
  options.dirichlet = route;
  options.estimate_condition = false;
  const auto runs = refine<2>(problem, options, widths);
  std::printf("  %s, degree %d, %s\n", title, degree, route == DirichletRoute::Weak ? "Nitsche" : "structure");
  for (const RefinementRun& r : runs)
    std::printf("    h = %-7.4g unknowns %-6zu L2 %.3e  H1 %.3e\n", r.h, r.report.unknowns, l2(r.report), h1(r.report));
  std::printf("    last rates: L2 %.2f  H1 %.2f\n", last_rate(runs, l2), last_rate(runs, h1));
  return runs;
}

void expect_optimal(const std::vector<RefinementRun>& runs, int degree) {
  EXPECT_GE(last_rate(runs, l2), degree + 1 - 0.3);
  EXPECT_GE(last_rate(runs, h1), degree - 0.3);
}

TEST(VariableConductivity, SmoothKOnAnOffCentreDisk) {
  // k = 1 + x^2 / 2 + 0.3 x y + 0.2 sin(2 y), between 0.77 and 1.65 here.
  // Measured (h = 0.1 -> 0.05): Nitsche L2 3.34, H1 2.11 (degree 2) and
  // 4.93, 3.60 (degree 3); the structure 3.14, 2.05 and 4.02, 3.01. k read
  // at each cell's first point instead of its own gave L2 1.02, H1 1.02.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr disk = ball({0.07, -0.04, 0}, 0.93, 2);
  const Expr k = 1.0 + 0.5 * square(x) + 0.3 * x * y + 0.2 * sin(2.0 * y);
  const Expr u = exp(0.5 * x) * sin(1.3 * y + 0.4) + x * square(y);
  const PoissonProblem problem =
      variable_k_problem(disk, k, u, cos(1.7 * x - 0.4) * exp(0.6 * y), {-1, -1, 0}, {1, 1, 0});
  for (const int degree : {2, 3})
    for (const DirichletRoute route : {DirichletRoute::Weak, DirichletRoute::Structure})
      expect_optimal(study("disk, smooth k", problem, degree, route, {0.2, 0.1, 0.05}), degree);
}

TEST(VariableConductivity, KVaryingAHundredfoldOnATurnedSquare) {
  // k = exp(2.3 x): 0.107 at the square's left corner, 10.7 at its right
  // one. Nitsche's route (the structure loses orders at the corners:
  // solid_convergence_test.cpp). Measured (h = 0.1 -> 0.05): L2 3.75, H1
  // 2.29 (degree 2) and 5.06, 3.60 (degree 3).
  const Expr x = Expr::x(), y = Expr::y();
  const Expr square = turned_square(0.3, 0.8, {0.03, -0.02});
  const Expr k = exp(2.3 * x);
  const Expr u = sin(2.0 * x + 0.5) * cos(1.5 * y) + x * y;
  const PoissonProblem problem = variable_k_problem(square, k, u, 2.0 - x * y, {-1.2, -1.2, 0}, {1.2, 1.2, 0});
  for (const int degree : {2, 3})
    expect_optimal(study("turned square, k = exp(2.3 x)", problem, degree, DirichletRoute::Weak, {0.2, 0.1, 0.05}),
                   degree);
}

/// The cube of half-side 0.6 about (0.021, -0.013, 0.017), turned about z by
/// 0.3 and about x by 0.2, as the R0-conjunction of its faces.
Expr turned_cube() {
  const double c = std::cos(0.3), s = std::sin(0.3), ca = std::cos(0.2), sa = std::sin(0.2);
  // Columns of R_x(0.2) R_z(0.3): the cube's axes.
  const std::array<Vec3, 3> axes{Vec3{c, ca * s, sa * s}, Vec3{-s, ca * c, sa * c}, Vec3{0, -sa, ca}};
  const Vec3 centre{0.021, -0.013, 0.017};
  Expr field;
  bool first = true;
  for (const Vec3& axis : axes)
    for (const double side : {-1.0, 1.0}) {
      const Vec3 n{side * axis[0], side * axis[1], side * axis[2]};
      const Expr face = halfspace({centre[0] + 0.6 * n[0], centre[1] + 0.6 * n[1], centre[2] + 0.6 * n[2]}, n, 3);
      field = first ? face : r_and(field, face, RSystem::r0());
      first = false;
    }
  return field;
}

TEST(VariableConductivity, PolynomialKKeepsA3DSplineSpaceSolutionExact) {
  // In 3D the inside cells' stiffness comes by sum factorization from the
  // per-point k (tensor_cell_stiffness.hpp), and with k = 1 one cell's
  // matrix serves them all: both paths, and the cut cells' rank updates,
  // on a polynomial u of coordinate degree 2 (in the WEB space of degree 2)
  // with a polynomial k. Nitsche's form is consistent, and with Gauss rules
  // of 2n + 2 nodes on planar faces every integral is exact, so u comes
  // back to round-off; a k dropped, squared or read at another point would
  // leave an error of the size of k's variation.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr u = 1.0 + x - 2.0 * y + 0.5 * z + x * y * z + square(x) * z - 0.3 * square(y) * square(z);
  for (const Expr& k : {Expr(1.0), 1.0 + 0.5 * square(x) + 0.3 * y * z + 0.25 * square(z)}) {
    PoissonProblem problem;
    problem.domain.dimension = 3;
    problem.domain.field = turned_cube();
    problem.domain.min = {-1, -1, -1};
    problem.domain.max = {1, 1, 1};
    problem.conductivity = k;
    problem.source = manufactured_source(u, k, 3);
    problem.exact = u;
    problem.rest.value = u;
    SolverOptions options;
    options.degree = 2;
    options.cell_width = 0.25;
    options.quadrature_points = 6;
    options.linear_solver = LinearSolverKind::Direct;
    options.estimate_condition = false;
    const SolveReport report = solve_poisson<3>(problem, options).report;
    std::printf("  k %s: %zu inside cells, L2 %.2e  H1 %.2e\n", k.is_constant() ? "1" : "polynomial",
                report.cells_inside, *report.l2_error, *report.h1_error);
    EXPECT_GT(report.cells_inside, 20u);
    EXPECT_LT(*report.l2_error, 1e-12);
    EXPECT_LT(*report.h1_error, 1e-11);
  }
}

TEST(VariableConductivity, KJumpingAcrossALineOffTheGridLosesOrdersAsExpected) {
  // k = 1 on one side of a line at 0.4 rad through (0.1, -0.05), 10 on the
  // other, and u = s / k + cos(1.3 t) (1 + s^2) in the line's coordinates
  // (s across, t along): u and k du/ds are continuous, du/ds jumps tenfold.
  // The splines are smooth across the line, which no cell face follows, so
  // the best approximation of u's kink is O(h^(1/2)) in H1, and duality,
  // whose dual solution has the same kink, gives only h^(1/2) more in L2:
  // rates 1/2 and 1 whatever the degree (measured 0.49 and 0.98 at degree
  // 2, h = 0.05 -> 0.025; 0.49 and 1.00 at degree 3 down to h = 0.0125).
  // Not a failure of the solver: optimal rates need a fitted grid or an
  // enriched space. Asserted with a margin of 0.2 either way.
  const Expr x = Expr::x(), y = Expr::y();
  const double cosine = std::cos(0.4), sine = std::sin(0.4);
  const Expr s = (x - 0.1) * cosine + (y + 0.05) * sine, t = -(x - 0.1) * sine + (y + 0.05) * cosine;
  const Expr k = 1.0 + 9.0 * step(s);
  const Expr u = s / k + cos(1.3 * t) * (1.0 + square(s));
  const PoissonProblem problem =
      variable_k_problem(ball({0.07, -0.04, 0}, 0.93, 2), k, u, Expr(0.0), {-1, -1, 0}, {1, 1, 0});
  const auto runs = study("disk, k jumping 10-fold", problem, 2, DirichletRoute::Weak, {0.1, 0.05, 0.025});
  EXPECT_NEAR(last_rate(runs, l2), 1.0, 0.2);
  EXPECT_NEAR(last_rate(runs, h1), 0.5, 0.2);
}

}  // namespace
}  // namespace sage::solver
