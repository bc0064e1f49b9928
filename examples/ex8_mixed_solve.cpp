//                         sage example 8: mixed boundary conditions on a CSG part
//
// Sample runs:  ex8_mixed_solve
//
// Description:  A 3D part, the plate (-1,1)^2 x (0,1) minus a through hole
//               of radius 0.4, with a different condition on each named
//               part of its boundary: Dirichlet on the four sides, Neumann
//               (insulated up to a given flux) on the top and bottom, Robin
//               (convection) in the hole. The data come from a known
//               solution, so the errors can be measured; the Dirichlet data
//               differ from the solution inside, so nothing is given away.
//               Solves with quadratic WEB-splines on two grids, prints the
//               errors and the rates, and checks them (L2 about h^3, H1
//               about h^2: the edges and corners where faces meet cost
//               nothing). This is what `sage solve` does with
//               examples/problems/block_with_hole.json. Adds to example 5:
//               solids, named parts, Neumann and Robin conditions.

#include <sage/expression/derivative.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>

#include <cmath>
#include <cstdio>
#include <exception>

int main() {
  using namespace sage;
  using solver::BoundaryKind;
  try {
    const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
    const RSystem r0 = RSystem::r0();

    // 1. The part: a box AND NOT a cylinder, as one R0 field (>= 0 inside).
    const Expr hole = cylinder({0, 0, 0}, {0, 0, 1}, 0.4);  // >= 0 inside the cylinder
    solver::PoissonProblem problem;
    problem.domain.dimension = 3;
    problem.domain.field = r_and(box({-1, -1, 0}, {1, 1, 1}, 3, r0), -hole, r0);
    problem.domain.min = {-1, -1, 0};
    problem.domain.max = {1, 1, 1};

    // 2. The solution we pretend not to know, and f = -laplace(u).
    const Expr u = exp(0.5 * x) * cos(y) * (1.0 + z) + x * y;
    problem.exact = u;
    problem.source = solver::manufactured_source(u, 1.0, 3);

    // 3. The boundary parts. Each is named by a field that vanishes on it
    //    (its selector); a boundary point belongs to the part whose
    //    selector is nearest zero. Fluxes are k du/dn with n outward.
    const Expr ux = derivative(u, 0), uy = derivative(u, 1), uz = derivative(u, 2);
    const Expr g = u + (1.0 - square(x)) * (1.0 - square(y));  // = u on the sides only
    problem.parts = {
        {"left", 1.0 + x, BoundaryKind::Dirichlet, g},
        {"right", 1.0 - x, BoundaryKind::Dirichlet, g},
        {"front", 1.0 + y, BoundaryKind::Dirichlet, g},
        {"back", 1.0 - y, BoundaryKind::Dirichlet, g},
        {"bottom", z, BoundaryKind::Neumann, 0.0, 0.0, -uz},
        {"top", 1.0 - z, BoundaryKind::Neumann, 0.0, 0.0, uz},
        // In the hole n = -(x, y, 0) / 0.4; Robin: du/dn + beta u = h.
        {"hole", hole, BoundaryKind::Robin, 0.0, 2.0, -(x * ux + y * uy) / 0.4 + 2.0 * u},
    };
    problem.rest = problem.parts[4];  // nothing is left over; any part would do

    // 4. Solve on two grids (the defaults: Nitsche's method for the
    //    Dirichlet sides, boundary integrals for the rest).
    std::printf("%8s %9s %12s %12s %8s %8s\n", "h", "unknowns", "L2 error", "H1 error", "L2 rate", "H1 rate");
    double previous_l2 = 0, previous_h1 = 0, l2_rate = 0, h1_rate = 0;
    for (double h : {0.125, 0.0625}) {
      solver::SolverOptions options;
      options.degree = 2;
      options.cell_width = h;
      options.estimate_condition = false;
      const solver::SolveReport r = solver::solve_poisson<3>(problem, options).report;
      std::printf("%8.4f %9zu %12.3e %12.3e", h, r.unknowns, *r.l2_error, *r.h1_error);
      if (previous_l2 > 0) {
        l2_rate = std::log2(previous_l2 / *r.l2_error);
        h1_rate = std::log2(previous_h1 / *r.h1_error);
        std::printf(" %8.2f %8.2f", l2_rate, h1_rate);
      }
      std::printf("\n");
      previous_l2 = *r.l2_error;
      previous_h1 = *r.h1_error;
    }
    // 5. Quadratic splines: optimal rates are 3 (L2) and 2 (H1).
    return l2_rate > 2.7 && h1_rate > 1.7 && previous_l2 < 2e-6 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex8_mixed_solve: %s\n", e.what());
    return 1;
  }
}
