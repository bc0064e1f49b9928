// Convergence on solids with edges and corners (issue 24): the square and
// the cube as R0-conjunctions of their faces, and a plate with a
// cylindrical hole with Dirichlet, Neumann and Robin conditions on named
// faces (manufactured.hpp of the library). The Dirichlet data differ from
// the solution inside the domain. Nitsche's method (the default route)
// keeps the rates of degree n; the R-function structure, whose
// (u - g~) / omega_D is not smooth where faces meet, loses an order.
#include "manufactured.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace sage::solver {
namespace {

using namespace manufactured;

/// Solves on cells_across cells along the box's longest side and prints
/// the runs; returns them.
template <int D>
std::vector<RefinementRun> study(const char* title, const PoissonProblem& problem, int degree, DirichletRoute route,
                                 const std::vector<int>& cells_across) {
  SolverOptions options;
  options.degree = degree;
  options.dirichlet = route;
  options.estimate_condition = false;
  const double longest = problem.domain.longest_side();
  std::vector<double> widths;
  for (int n : cells_across) widths.push_back(longest / n);
  const std::vector<RefinementRun> runs = refine<D>(problem, options, widths);
  std::printf("  %s, degree %d, %s\n", title, degree, route == DirichletRoute::Weak ? "Nitsche" : "structure");
  for (const RefinementRun& r : runs)
    std::printf("    h = %-8.4g unknowns %-7zu L2 %.3e  H1 %.3e  cut cells %zu, %zu volume points in them\n", r.h,
                r.report.unknowns, l2(r.report), h1(r.report), r.report.cells_cut, r.report.cut_volume_points);
  std::printf("    last rates: L2 %.2f  H1 %.2f\n", last_rate(runs, l2), last_rate(runs, h1));
  return runs;
}

void expect_optimal(const std::vector<RefinementRun>& runs, int degree) {
  EXPECT_GE(last_rate(runs, l2), degree + 1 - 0.3);
  EXPECT_GE(last_rate(runs, h1), degree - 0.3);
  for (const RefinementRun& r : runs) EXPECT_EQ(r.report.masked_boxes, 0u);
}

TEST(SolidConvergence, SquareByNitscheAtOptimalRates) {
  // 16..64 cells put the edges on the grid's lattice, 17..68 not.
  for (const int degree : {2, 3}) {
    expect_optimal(study<2>("square", dirichlet_box(2), degree, DirichletRoute::Weak, {16, 32, 64}), degree);
    expect_optimal(study<2>("square, off the lattice", dirichlet_box(2), degree, DirichletRoute::Weak, {17, 34, 68}),
                   degree);
  }
}

TEST(SolidConvergence, SquareByTheStructureConvergesAtRatesTwoAndOne) {
  // What Nitsche's route is for: omega_D is an R-conjunction with corners,
  // where Phi = (u - g~) / omega_D behaves like r f(theta) about each
  // corner: D^2 Phi ~ 1 / r, so Phi is in H^(2 - eps) only, and the best
  // approximation converges at H1 rate 1 whatever the degree, L2 rate 2
  // (duality). Measured L2 2.00 and H1 1.00 at degrees 2 and 3, far below
  // degree 3's optimal 4 and 3, but converging: the lower bounds fail a
  // route that stalls.
  const auto runs = study<2>("square", dirichlet_box(2), 3, DirichletRoute::Structure, {16, 32, 64});
  EXPECT_LT(last_rate(runs, l2), 3.0);
  EXPECT_LT(last_rate(runs, h1), 2.0);
  EXPECT_GE(last_rate(runs, l2), 2.0 - 0.3);
  EXPECT_GE(last_rate(runs, h1), 1.0 - 0.3);
}

TEST(SolidConvergence, CubeByNitscheAtOptimalRates) {
  expect_optimal(study<3>("cube", dirichlet_box(3), 2, DirichletRoute::Weak, {5, 10, 20}), 2);
  expect_optimal(study<3>("cube", dirichlet_box(3), 3, DirichletRoute::Weak, {5, 11}), 3);
}

TEST(SolidConvergence, PlateWithHoleMixedConditionsAtOptimalRates) {
  // Dirichlet sides, Neumann top and bottom, Robin hole: each surface point
  // lies on one face, with that face's normal and that part's data. (Odd
  // cell counts: the faces off the lattice at both levels. The error's
  // constant depends on how the faces cut the cells, by up to 3 between
  // 14 and 15 cells, which would blur rates on grids this coarse.)
  for (const int degree : {2, 3})
    expect_optimal(study<3>("plate with hole", plate_with_hole(), degree, DirichletRoute::Weak, {9, 19}), degree);
}

}  // namespace
}  // namespace sage::solver
