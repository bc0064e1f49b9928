#pragma once
// Poisson problems with exact solutions that the solver tests and
// bench/solve_bench share (not installed: they are studies, not API).

#include <sage/expression/primitives.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/problem.hpp>

namespace sage::solver {

/// The square (-1,1)^2 minus the disk r = 0.4: Dirichlet u = 0 on the
/// square (selected by the smooth product weight), Robin k du/dn + beta u = h
/// on the hole, with the data of the exact solution
/// cos(pi x / 2) cos(pi y / 2) (1 + x y + x / 2). The Robin routes' rate
/// study (robin_structure_test, solve_bench robin).
inline PoissonProblem square_with_robin_hole(const Expr& conductivity, const Expr& beta) {
  constexpr double kPi = 3.14159265358979323846;
  const RSystem r0 = RSystem::r0();
  const Expr x = Expr::x(), y = Expr::y();
  const Expr hole = ball({0, 0, 0}, 0.4, 2);
  PoissonProblem problem;
  problem.domain.dimension = 2;
  problem.domain.field = r_and(box({-1, -1, 0}, {1, 1, 0}, 2, r0), -hole, r0);
  problem.domain.min = {-1, -1, 0};
  problem.domain.max = {1, 1, 0};
  problem.conductivity = conductivity;
  const Expr exact = cos(0.5 * kPi * x) * cos(0.5 * kPi * y) * (1.0 + x * y + 0.5 * x);
  problem.exact = exact;
  problem.source = manufactured_source(exact, conductivity, 2);
  // n = -(x, y) / r on the hole (outward from the domain).
  const Expr outward_flux = -conductivity * (x * derivative(exact, 0) + y * derivative(exact, 1)) / 0.4;
  const BoundaryPart outer{"outer", (1.0 - square(x)) * (1.0 - square(y)) * 0.5, BoundaryKind::Dirichlet, 0.0};
  const BoundaryPart robin{"hole", hole, BoundaryKind::Robin, 0.0, beta, outward_flux + beta * exact};
  problem.parts = {outer, robin};
  problem.rest = robin;
  return problem;
}

/// The square (-1,1)^2 or the cube (-1,1)^3 as the R0-conjunction of its
/// faces, u = 0 nowhere: Dirichlet data g = u + 2 prod_a (1 - x_a^2), equal
/// to u on the boundary but not inside (so the structure's g~ is not the
/// solution), with u = e^x sin(pi y / 2) + x y in 2D and
/// e^x sin(pi y / 2) cos(z) + x y z in 3D. Edges and corners everywhere
/// the faces meet (issue 24's rate study).
inline PoissonProblem dirichlet_box(int dimension) {
  constexpr double kPi = 3.14159265358979323846;
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  PoissonProblem problem;
  problem.domain.dimension = dimension;
  problem.domain.field = box({-1, -1, -1}, {1, 1, 1}, dimension, RSystem::r0());
  problem.domain.min = {-1, -1, dimension == 3 ? -1.0 : 0.0};
  problem.domain.max = {1, 1, dimension == 3 ? 1.0 : 0.0};
  const Expr exact =
      dimension == 2 ? exp(x) * sin(0.5 * kPi * y) + x * y : exp(x) * sin(0.5 * kPi * y) * cos(z) + x * y * z;
  Expr bubble = 2.0;
  for (int a = 0; a < dimension; ++a) bubble = bubble * (1.0 - square(Expr::var(a)));
  problem.exact = exact;
  problem.source = manufactured_source(exact, problem.conductivity, dimension);
  problem.rest.value = exact + bubble;
  return problem;
}

/// The plate (-1,1)^2 x (0,1) minus the cylinder r = 0.4 about the z axis:
/// Dirichlet on the four side faces (named halfspaces, data g = u +
/// (1 - x^2)(1 - y^2), not u inside), Neumann on the top and bottom, Robin
/// k du/dn + beta u = h on the cylinder, with the data of the exact solution
/// u = e^(x/2) cos(y) (1 + z) + x y. Faces meet at right angles along
/// the plate's edges and the hole's rims.
inline PoissonProblem plate_with_hole(double beta = 1.0) {
  const RSystem r0 = RSystem::r0();
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  PoissonProblem problem;
  problem.domain.dimension = 3;
  const Expr hole = cylinder({0, 0, 0}, {0, 0, 1}, 0.4);
  problem.domain.field = r_and(box({-1, -1, 0}, {1, 1, 1}, 3, r0), -hole, r0);
  problem.domain.min = {-1, -1, 0};
  problem.domain.max = {1, 1, 1};
  const Expr exact = exp(0.5 * x) * cos(y) * (1.0 + z) + x * y;
  problem.exact = exact;
  problem.source = manufactured_source(exact, problem.conductivity, 3);
  const Expr g = exact + (1.0 - square(x)) * (1.0 - square(y));
  const Expr ux = derivative(exact, 0), uy = derivative(exact, 1), uz = derivative(exact, 2);
  problem.parts = {
      {"x-", 1.0 + x, BoundaryKind::Dirichlet, g},
      {"x+", 1.0 - x, BoundaryKind::Dirichlet, g},
      {"y-", 1.0 + y, BoundaryKind::Dirichlet, g},
      {"y+", 1.0 - y, BoundaryKind::Dirichlet, g},
      {"bottom", z, BoundaryKind::Neumann, 0.0, 0.0, -uz},
      {"top", 1.0 - z, BoundaryKind::Neumann, 0.0, 0.0, uz},
      // n = -(x, y, 0) / r on the hole (outward from the plate).
      {"hole", hole, BoundaryKind::Robin, 0.0, beta, -(x * ux + y * uy) / 0.4 + beta * exact},
  };
  problem.rest = problem.parts[4];
  return problem;
}

}  // namespace sage::solver
