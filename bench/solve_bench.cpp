// solve_bench: work-precision tables of the meshfree Poisson solver (issue 4).
//
// For the unit disk (u = cos(pi x) sin(pi y) + x) and the unit ball
// (u = sin(pi x) sin(pi y) sin(pi z) + x), Dirichlet data from the boundary
// values only (unit_sphere_extension), WEB basis, refines the background
// grid and prints per run: unknowns, CPU seconds per stage (field,
// classification, quadrature, assembly, solve; process CPU time, so a
// one-thread run on a busy machine still measures the work), their total,
// the wall-clock total, the peak resident memory of the solve, and the
// relative L2 and H1 errors reached, with the CG iterations and tolerance.
// The ball's cubic table is repeated at 18 and 19 cells with the former
// fixed tolerance 1e-12, to compare in the same run.
// Compare with the goals of the issue: disk to 1e-7 with <= 2e4 unknowns in
// < 0.65 s; ball to 1e-4 with <= 2e4 unknowns in < 3 s and < 500 MB.
//
// `solve_bench robin` (not part of `all`): the square (-1,1)^2 minus the
// disk r = 0.4 with a Robin hole (beta = 1), degrees 2 and 3, h = 0.2 down
// to 0.0125: errors and rates of the weak route and of the Robin structure
// with the global W (robin_band 0) and with the cut-off W (the default);
// then the unit ball of examples/problems/ball_robin.json with both weights
// (12, 16, 24 cells across). Degrees after `robin` replace 2 and 3.
//
// `solve_bench solids` (not part of `all`): issue 24's solids with edges
// and corners, Dirichlet data that differ from u inside (manufactured.hpp):
// the square and the cube, and the plate with a hole with mixed conditions
// on named faces; both Dirichlet routes (Nitsche's, the structure), degrees
// 2 and 3 (or those given), with the cut cells' points and the rates.
//
// `solve_bench elasticity` (not part of `all`): elasticity_tables.cpp.
//
//   solve_bench [disk|ball|robin [DEGREE...]|solids [DEGREE...]|elasticity|all]   (OMP_NUM_THREADS=1 for one-thread
//   figures)

#include <sage/expression/derivative.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>

#include "bench_support.hpp"

#include <solver_fixtures.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::bench {
void elasticity_tables();  // elasticity_tables.cpp
}

namespace {

using namespace sage;
using namespace sage::solver;
using sage::bench::peak_megabytes;
using sage::bench::reset_peak;

constexpr double kPi = 3.14159265358979323846;

/// cg_tolerance 0: the solver's automatic_cg_tolerance().
template <int D>
void table(const char* title, const PoissonProblem& problem, int degree, const std::vector<int>& cells_across,
           double cg_tolerance = 0.0) {
  char tolerance[32] = "automatic";
  if (cg_tolerance > 0) std::snprintf(tolerance, sizeof tolerance, "%.0e", cg_tolerance);
  std::printf("\n%s, degree %d, WEB basis, CG tolerance %s\n", title, degree, tolerance);
  std::printf("%6s %9s %8s %8s %8s %8s %8s %8s %8s %8s %6s %8s %10s %10s\n", "cells", "unknowns", "field", "classify",
              "quadr.", "assembly", "solve", "cpu s", "wall s", "peak MB", "iter.", "tol.", "L2 rel.", "H1 rel.");
  for (int n : cells_across) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = 2.0 / n;
    options.estimate_condition = false;
    options.cg_tolerance = cg_tolerance;
    reset_peak();
    const SolveReport r = solve_poisson<D>(problem, options).report;
    const StageSeconds& s = r.cpu_seconds;
    const double total = s.total() - s.errors;  // error norms are not part of the solve
    const double wall = r.seconds.total() - r.seconds.errors;
    std::printf("%6d %9zu %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.0f %6d %8.1e %10.3e %10.3e\n", n, r.unknowns,
                s.field, s.classification, s.quadrature, s.assembly, s.solve, total, wall, peak_megabytes(),
                r.iterations, r.cg_tolerance, *r.l2_error, *r.h1_error);
    std::fflush(stdout);
  }
}

PoissonProblem unit_problem(int dimension, const std::function<Expr(const std::array<Expr, 3>&)>& u) {
  PoissonProblem p;
  p.domain.dimension = dimension;
  p.domain.field = ball({0, 0, 0}, 1.0, dimension);
  p.domain.min = {-1, -1, dimension == 3 ? -1.0 : 0.0};
  p.domain.max = {1, 1, dimension == 3 ? 1.0 : 0.0};
  const Expr exact = u({Expr::x(), Expr::y(), Expr::z()});
  p.exact = exact;
  p.source = manufactured_source(exact, p.conductivity, dimension);
  p.dirichlet_extension = unit_sphere_extension(u, dimension);
  return p;
}

template <int D>
void robin_rates(const char* title, const PoissonProblem& problem, int degree, RobinRoute route, double band,
                 const std::vector<double>& widths) {
  std::printf("\n%s, degree %d\n%8s %9s %10s %10s %7s %7s %8s\n", title, degree, "h", "unknowns", "L2 rel.", "H1 rel.",
              "L2 rate", "H1 rate", "cpu s");
  double last_l2 = 0.0, last_h1 = 0.0, last_h = 0.0;
  for (double h : widths) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = h;
    options.robin = route;
    options.robin_band = band;
    options.estimate_condition = false;
    const SolveReport r = solve_poisson<D>(problem, options).report;
    const double l2 = *r.l2_error, h1 = *r.h1_error;
    if (last_l2 > 0.0)
      std::printf("%8.4g %9zu %10.3e %10.3e %7.2f %7.2f %8.2f\n", h, r.unknowns, l2, h1,
                  std::log(last_l2 / l2) / std::log(last_h / h), std::log(last_h1 / h1) / std::log(last_h / h),
                  r.cpu_seconds.total() - r.cpu_seconds.errors);
    else
      std::printf("%8.4g %9zu %10.3e %10.3e %7s %7s %8.2f\n", h, r.unknowns, l2, h1, "", "",
                  r.cpu_seconds.total() - r.cpu_seconds.errors);
    std::fflush(stdout);
    last_l2 = l2;
    last_h1 = h1;
    last_h = h;
  }
}

/// Work and precision under refinement, with the observed rates: the
/// solid problems of issue 24 (edges and corners), one Dirichlet route.
template <int D>
void solid_rates(const char* title, const PoissonProblem& problem, int degree, DirichletRoute route,
                 const std::vector<int>& cells_across) {
  std::printf("\n%s, degree %d, Dirichlet %s\n", title, degree,
              route == DirichletRoute::Weak ? "weak (Nitsche)" : "structure");
  std::printf("%6s %9s %8s %8s %8s %8s %8s %8s %8s %9s %10s %10s %7s %7s\n", "cells", "unknowns", "classify", "quadr.",
              "assembly", "solve", "cpu s", "peak MB", "cut", "pts/cut", "L2 rel.", "H1 rel.", "L2 rate", "H1 rate");
  double last_l2 = 0.0, last_h1 = 0.0, last_h = 0.0;
  const double longest = problem.domain.longest_side();
  for (int n : cells_across) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = longest / n;
    options.dirichlet = route;
    options.estimate_condition = false;
    reset_peak();
    const SolveReport r = solve_poisson<D>(problem, options).report;
    const StageSeconds& s = r.cpu_seconds;
    const double h = options.cell_width;
    // Cut cells: none when the faces lie on the grid's lattice (their cells are inside).
    const double cut_points =
        r.cells_cut > 0 ? static_cast<double>(r.cut_volume_points) / static_cast<double>(r.cells_cut) : 0.0;
    std::printf("%6d %9zu %8.3f %8.3f %8.3f %8.3f %8.3f %8.0f %8zu %9.1f %10.3e %10.3e", n, r.unknowns,
                s.classification, s.quadrature, s.assembly, s.solve, s.total() - s.errors, peak_megabytes(),
                r.cells_cut, cut_points, *r.l2_error, *r.h1_error);
    if (last_l2 > 0.0)
      std::printf(" %7.2f %7.2f", std::log(last_l2 / *r.l2_error) / std::log(last_h / h),
                  std::log(last_h1 / *r.h1_error) / std::log(last_h / h));
    if (r.masked_boxes > 0) std::printf("  (%zu masked sub-boxes)", r.masked_boxes);
    std::printf("\n");
    std::fflush(stdout);
    last_l2 = *r.l2_error;
    last_h1 = *r.h1_error;
    last_h = h;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "all";
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  std::printf("solve_bench: %d thread(s); stage columns in CPU seconds; errors are relative\n", threads);
  if (which == "disk" || which == "all") {
    const auto disk =
        unit_problem(2, [](const std::array<Expr, 3>& p) { return cos(kPi * p[0]) * sin(kPi * p[1]) + p[0]; });
    table<2>("Unit disk, u = cos(pi x) sin(pi y) + x", disk, 3, {16, 32, 64, 96, 128});
    table<2>("Unit disk, u = cos(pi x) sin(pi y) + x", disk, 4, {16, 32, 48, 56, 64});
  }
  if (which == "ball" || which == "all") {
    const auto ball3 = unit_problem(
        3, [](const std::array<Expr, 3>& p) { return sin(kPi * p[0]) * sin(kPi * p[1]) * sin(kPi * p[2]) + p[0]; });
    table<3>("Unit ball, u = sin(pi x) sin(pi y) sin(pi z) + x", ball3, 2, {8, 12, 16, 24});
    table<3>("Unit ball, u = sin(pi x) sin(pi y) sin(pi z) + x", ball3, 3, {8, 12, 16, 18, 19, 20});
    // The former fixed tolerance, in the same run: what the automatic one saves.
    table<3>("Unit ball, same", ball3, 3, {18, 19}, 1e-12);
  }
  if (which == "solids") {
    // Issue 24: solids with edges and corners, Dirichlet data that differ
    // from u inside; both Dirichlet routes side by side.
    std::vector<int> degrees;
    for (int i = 2; i < argc; ++i) degrees.push_back(std::atoi(argv[i]));
    if (degrees.empty()) degrees = {2, 3};
    for (int degree : degrees)
      for (const DirichletRoute route : {DirichletRoute::Weak, DirichletRoute::Structure})
        solid_rates<2>("Square (-1,1)^2, u = e^x sin(pi y/2) + x y, g = u + 2 (1-x^2)(1-y^2)", dirichlet_box(2), degree,
                       route, {16, 32, 64, 128});
    for (int degree : degrees)
      for (const DirichletRoute route : {DirichletRoute::Weak, DirichletRoute::Structure})
        solid_rates<3>("Cube (-1,1)^3, u = e^x sin(pi y/2) cos z + x y z, g = u + 2 prod (1-x_a^2)", dirichlet_box(3),
                       degree, route, {6, 12, 24});
    for (int degree : degrees)
      for (const DirichletRoute route : {DirichletRoute::Weak, DirichletRoute::Structure})
        solid_rates<3>("Plate (-1,1)^2 x (0,1) minus cylinder r = 0.4: Dirichlet sides, Neumann top/bottom, Robin hole",
                       plate_with_hole(), degree, route, {8, 16, 32});
  }
  if (which == "elasticity") sage::bench::elasticity_tables();
  if (which == "robin") {
    const PoissonProblem problem = square_with_robin_hole(1.0, 1.0);
    const double band = SolverOptions{}.robin_band;
    const std::vector<double> widths{0.2, 0.1, 0.05, 0.025, 0.0125};
    std::vector<int> degrees;
    for (int i = 2; i < argc; ++i) degrees.push_back(std::atoi(argv[i]));
    if (degrees.empty()) degrees = {2, 3};
    for (int degree : degrees) {
      robin_rates<2>("Square minus disk, Robin hole: weak route", problem, degree, RobinRoute::Weak, band, widths);
      robin_rates<2>("Same, Robin structure, global W (robin_band 0)", problem, degree, RobinRoute::Structure, 0.0,
                     widths);
      robin_rates<2>("Same, Robin structure, cut-off W (default robin_band)", problem, degree, RobinRoute::Structure,
                     band, widths);
    }
    // examples/problems/ball_robin.json: Robin on the whole sphere, u = 2 - r^2.
    const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
    PoissonProblem sphere;
    sphere.domain.dimension = 3;
    sphere.domain.field = ball({0, 0, 0}, 1.0, 3);
    sphere.domain.min = {-1, -1, -1};
    sphere.domain.max = {1, 1, 1};
    sphere.source = 6.0;
    sphere.exact = 2.0 - square(x) - square(y) - square(z);
    sphere.rest = BoundaryPart{"default", Expr(0.0), BoundaryKind::Robin, 0.0, 2.0, 0.0};
    const std::vector<double> ball_widths{2.0 / 12, 2.0 / 16, 2.0 / 24};
    for (int degree : degrees) {
      robin_rates<3>("Unit ball, Robin on the sphere: structure, global W", sphere, degree, RobinRoute::Structure, 0.0,
                     ball_widths);
      robin_rates<3>("Same, structure, cut-off W", sphere, degree, RobinRoute::Structure, band, ball_widths);
    }
  }
  return 0;
}
