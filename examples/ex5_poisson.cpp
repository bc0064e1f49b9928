//                         sage example 5: a boundary value problem without a mesh
//
// Sample runs:  ex5_poisson
//
// Description:  Solves -laplace(u) = f on the unit disk with u given on the
//               circle, for u = cos(pi x) sin(pi y) + x, with cubic
//               WEB-splines on three background grids, and prints the
//               unknowns, the relative L2 and H1 errors and the observed
//               convergence rates (about 4 and 3). The domain is only a
//               field omega >= 0: no mesh is made. Then samples the finest
//               solution on the output grid `sage solve` uses, at the grid
//               points inside the disk, and checks it there. Adds to
//               example 4: the solver (what `sage solve` does, see
//               examples/problems/).

#include <sage/expression/primitives.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>
#include <sage/solver/solution_samples.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

int main() {
  using namespace sage;
  const double pi = 3.14159265358979323846;
  try {
    // 1. The exact solution, as a function of coordinate expressions, so it
    //    can be evaluated at x and at x / s below.
    auto u = [pi](const std::array<Expr, 3>& p) { return cos(pi * p[0]) * sin(pi * p[1]) + p[0]; };
    const Expr exact = u({Expr::x(), Expr::y(), Expr::z()});

    // 2. The problem: the domain field (disk, normalized: |grad| = 1 on the
    //    circle), its box, f = -laplace(u) by symbolic differentiation, and
    //    Dirichlet data g~ that equals u on the circle only.
    solver::PoissonProblem problem;
    problem.domain.dimension = 2;
    problem.domain.field = ball({0, 0, 0}, 1.0, 2);
    problem.domain.min = {-1, -1, 0};
    problem.domain.max = {1, 1, 0};
    problem.source = solver::manufactured_source(exact, 1.0, 2);
    problem.dirichlet_extension = solver::unit_sphere_extension(u, 2);
    problem.exact = exact;

    // 3. Solve on three grids: u = omega sum c_i B_i^web + g~.
    std::printf("%8s %9s %12s %12s %8s %8s\n", "h", "unknowns", "L2 error", "H1 error", "L2 rate", "H1 rate");
    double previous_l2 = 0, previous_h1 = 0;
    solver::PoissonSolution<2> solution;
    for (double h : {0.25, 0.125, 0.0625}) {
      solver::SolverOptions options;
      options.degree = 3;
      options.cell_width = h;
      solution = solver::solve_poisson<2>(problem, options);
      const solver::SolveReport& r = solution.report;
      std::printf("%8.4f %9zu %12.3e %12.3e", h, r.unknowns, *r.l2_error, *r.h1_error);
      if (previous_l2 > 0)
        std::printf(" %8.2f %8.2f", std::log2(previous_l2 / *r.l2_error), std::log2(previous_h1 / *r.h1_error));
      std::printf("\n");
      previous_l2 = *r.l2_error;
      previous_h1 = *r.h1_error;
    }
    // 4. Cubic splines: the L2 error falls like h^4 and the H1 error like h^3.
    if (!(previous_l2 < 1e-4)) return 1;

    // 5. The finest solution on the default output grid (4 points per cell)
    //    at the points where omega >= 0: u, grad_u, u_exact and error per
    //    point. (`sage solve` clips the grid's cells at omega = 0 with
    //    output::ClippedGrid and samples at the clipped cells' points.)
    const Grid grid = solver::solution_grid(2, problem.domain.min, problem.domain.max, solution.basis.grid.h);
    const std::vector<double> omega =
        solver::omega_on_grid<2>(solution.domain, solution.mesh, solution.basis.grid.h, grid);
    std::vector<std::array<double, 3>> inside;
    for (std::size_t i = 0; i < grid.size(); ++i)
      if (omega[i] >= 0.0) inside.push_back(grid.point(i));
    const std::vector<PointArray> arrays = solver::sample_solution(solution, problem.exact, inside);
    const auto error =
        std::find_if(arrays.begin(), arrays.end(), [](const PointArray& a) { return a.name == "error"; });
    if (error == arrays.end()) return 1;
    double largest_error = 0.0;  // of error = u - u_exact
    for (double e : error->values) largest_error = std::max(largest_error, std::abs(e));
    std::printf("%zu of the output grid's %zu points in the disk: largest |u - u_exact| %.2e\n", inside.size(),
                grid.size(), largest_error);
    return largest_error < 1e-4 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex5_poisson: %s\n", e.what());
    return 1;
  }
}
