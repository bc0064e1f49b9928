// A solution on an output grid through the library (solution_samples.hpp):
// the default grid's size, omega at its points, and the solution's arrays
// at any points, against the exact solution.

#include "manufactured.hpp"

#include <sage/solver/solution_samples.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace sage::solver {
namespace {

TEST(SolutionSamples, DiskSolutionAtPointsAndOmegaOnTheDefaultGrid) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr exact = sin(x) * exp(y);
  PoissonProblem p = manufactured::dirichlet_problem(2, ball({0, 0, 0}, 1.0, 2), exact, exact + 0.3 * x * x,
                                                     {-1.1, -1.1, 0}, {1.1, 1.1, 0});
  p.dirichlet_extension.reset();  // Nitsche's route: the data are g's values on the circle
  p.rest.value = exact;
  SolverOptions options;
  options.degree = 3;
  options.cell_width = 2.2 / 16;
  const PoissonSolution<2> solution = solve_poisson<2>(p, options);

  const Grid grid = solution_grid(2, p.domain.min, p.domain.max, options.cell_width);
  EXPECT_EQ(grid.points[0], 16 * 4 + 1);  // 4 points per cell
  EXPECT_EQ(grid.points[2], 1);
  const std::vector<double> omega = omega_on_grid<2>(solution.domain, solution.mesh, solution.basis.grid.h, grid);
  ASSERT_EQ(omega.size(), grid.size());
  for (std::size_t i = 0; i < grid.size(); i += 97) {
    const auto q = grid.point(i);
    EXPECT_NEAR(omega[i], (1 - q[0] * q[0] - q[1] * q[1]) / 2, 1e-14);
  }

  const std::vector<std::array<double, 3>> points{{0, 0, 0}, {0.5, -0.3, 0}, {-0.7, 0.6, 0}, {0.99, 0, 0}};
  const std::vector<PointArray> arrays = sample_solution(solution, std::optional<Expr>(exact), points);
  ASSERT_EQ(arrays.size(), 4u);
  EXPECT_EQ(arrays[0].name, "u");
  EXPECT_EQ(arrays[1].name, "grad_u");
  EXPECT_EQ(arrays[1].components, 3);
  EXPECT_EQ(arrays[3].name, "error");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double px = points[i][0], py = points[i][1];
    EXPECT_NEAR(arrays[0].values[i], std::sin(px) * std::exp(py), 1e-5) << i;
    EXPECT_NEAR(arrays[1].values[3 * i], std::cos(px) * std::exp(py), 1e-3) << i;
    EXPECT_NEAR(arrays[1].values[3 * i + 1], std::sin(px) * std::exp(py), 1e-3) << i;
    EXPECT_EQ(arrays[1].values[3 * i + 2], 0.0);
    EXPECT_EQ(arrays[3].values[i], arrays[0].values[i] - arrays[2].values[i]);
  }
}

}  // namespace
}  // namespace sage::solver
