//                         sage example 5: a boundary value problem without a mesh
//
// Sample runs:  ex5_poisson
//
// Description:  Solves -laplace(u) = f on the unit disk with u given on the
//               circle, for u = cos(pi x) sin(pi y) + x, with cubic
//               WEB-splines on three background grids, and prints the
//               unknowns, the relative L2 and H1 errors and the observed
//               convergence rates (about 4 and 3). The domain is only a
//               field omega >= 0: no mesh is made. Adds to example 4: the
//               solver (what `sage solve` does, see examples/problems/).

#include <sage/expression/primitives.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>

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
    for (double h : {0.25, 0.125, 0.0625}) {
      solver::SolverOptions options;
      options.degree = 3;
      options.cell_width = h;
      const solver::SolveReport r = solver::solve_poisson<2>(problem, options).report;
      std::printf("%8.4f %9zu %12.3e %12.3e", h, r.unknowns, *r.l2_error, *r.h1_error);
      if (previous_l2 > 0)
        std::printf(" %8.2f %8.2f", std::log2(previous_l2 / *r.l2_error), std::log2(previous_h1 / *r.h1_error));
      std::printf("\n");
      previous_l2 = *r.l2_error;
      previous_h1 = *r.h1_error;
    }
    // 4. Cubic splines: the L2 error falls like h^4 and the H1 error like h^3.
    return previous_l2 < 1e-4 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex5_poisson: %s\n", e.what());
    return 1;
  }
}
