// Conditioning under small shifts of the domain against the grid: the WEB
// basis keeps the (Jacobi-scaled) condition number within a factor 10 of
// the unshifted one; plain weighted B-splines degrade as slivers of cells
// appear (Hollig, Reif, Wipper 2001).
#include "manufactured.hpp"

#include <gtest/gtest.h>

namespace sage::solver {
namespace {
using namespace manufactured;

double condition_with_shift(BasisKind basis, double delta, int degree) {
  const double h = 0.125;
  // The square's edges lie on grid lines for delta = 0.
  const double s = delta * h;
  PoissonProblem problem;
  problem.dimension = 2;
  problem.domain = box({-0.5 + s, -0.5 + s, 0}, {0.5 + s, 0.5 + s, 0}, 2, RSystem::r0());
  problem.min = {-0.5 + s, -0.5 + s, 0};
  problem.max = {0.5 + s, 0.5 + s, 0};
  problem.source = 1.0;
  SolverOptions options;
  options.degree = degree;
  options.cell_width = h;
  options.basis = basis;
  return solve_poisson<2>(problem, options).report.condition;
}

TEST(PoissonConditioning, WebStaysBoundedWeightedDegrades) {
  for (int degree : {2, 3}) {
    const double web0 = condition_with_shift(BasisKind::Web, 0.0, degree);
    const double weighted0 = condition_with_shift(BasisKind::Weighted, 0.0, degree);
    double worst_web = 0.0, worst_weighted = 0.0;
    std::printf("  degree %d   delta       web cond    weighted cond\n", degree);
    std::printf("              0           %-11.3g %-11.3g\n", web0, weighted0);
    for (double delta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      const double web = condition_with_shift(BasisKind::Web, delta, degree);
      double weighted = std::numeric_limits<double>::infinity();
      try {
        weighted = condition_with_shift(BasisKind::Weighted, delta, degree);
      } catch (const std::runtime_error&) {
        // numerically singular: the degradation the WEB basis avoids
      }
      std::printf("              %-11.0e %-11.3g %-11.3g\n", delta, web, weighted);
      worst_web = std::max(worst_web, web);
      worst_weighted = std::max(worst_weighted, weighted);
      EXPECT_LT(web, 10 * web0) << "delta " << delta;
    }
    EXPECT_GT(worst_weighted, 100 * worst_web) << "degree " << degree;
  }
}

}  // namespace
}  // namespace sage::solver
