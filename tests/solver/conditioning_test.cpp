// Conditioning under small shifts of the domain against the grid (Hollig,
// Reif, Wipper 2001). The square's edges lie on grid lines when unshifted;
// a shift by delta h leaves cells with slivers of width delta h inside. The
// plain weighted B-splines living on those slivers make the system matrix
// nearly singular as delta -> 0; the WEB basis ties them to inner
// B-splines, so its condition number does not depend on delta.
//
// The exactly unshifted square is a degenerate case (no outer B-splines at
// all, a smaller space), so the reference is the limit delta -> 0, i.e. the
// smallest shift: the WEB condition number must stay within a factor 10 of
// it over delta = 1e-1 .. 1e-6. The weighted basis' condition number grows
// like delta^-(4n + 2).
#include "manufactured.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace sage::solver {
namespace {

SolveReport shifted_square(BasisKind basis, double delta, int degree) {
  const double h = 0.125, s = delta * h;
  PoissonProblem problem;
  problem.domain.dimension = 2;
  problem.domain.field = box({-0.5 + s, -0.5 + s, 0}, {0.5 + s, 0.5 + s, 0}, 2, RSystem::r0());
  problem.domain.min = {-0.5 + s, -0.5 + s, 0};
  problem.domain.max = {0.5 + s, 0.5 + s, 0};
  problem.source = 1.0;
  SolverOptions options;
  options.degree = degree;
  options.cell_width = h;
  options.basis = basis;
  return solve_poisson<2>(problem, options).report;
}

TEST(PoissonConditioning, WebStaysBoundedWeightedDegrades) {
  const std::vector<double> deltas{1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
  for (int degree : {2, 3}) {
    std::printf("  degree %d  delta    WEB cond   (scaled)   weighted cond (scaled)\n", degree);
    std::vector<double> web, weighted;
    for (double delta : deltas) {
      // Both must solve and give an estimate: an exception fails the test
      // (it once stood for an infinite condition number, so a weighted
      // basis that always threw passed).
      const SolveReport a = shifted_square(BasisKind::Web, delta, degree);
      const SolveReport b = shifted_square(BasisKind::Weighted, delta, degree);
      std::printf("            %-8.0e %-10.3g %-10.3g %-13.3g %-10.3g\n", delta, a.condition, a.scaled_condition,
                  b.condition, b.scaled_condition);
      ASSERT_TRUE(std::isfinite(a.condition) && std::isfinite(b.condition)) << "delta " << delta;
      web.push_back(a.condition);
      weighted.push_back(b.condition);
    }
    const double web_reference = web.back();
    for (std::size_t k = 0; k < deltas.size(); ++k) {
      EXPECT_LT(web[k], 10 * web_reference) << "degree " << degree << ", delta " << deltas[k];
      EXPECT_GT(web[k], web_reference / 10) << "degree " << degree << ", delta " << deltas[k];
    }
    // The weighted basis: orders of magnitude worse at small shifts, and growing as delta falls.
    EXPECT_GT(weighted.back(), 1e4 * web_reference) << "degree " << degree;
    EXPECT_GT(weighted.back(), 100 * weighted[1]) << "degree " << degree;
    // How fast: the weighted B-spline at a corner, w B on a delta h x delta h
    // sliver, has w ~ delta h and B ~ delta^(2n) there, so its energy is
    // ~ delta^(4n + 2) against O(1) for the others: the condition number
    // grows by 4n + 2 decades per decade of delta (measured 10.0 and 14.0).
    const double decades = std::log10(weighted.back() / weighted[2]) / std::log10(deltas[2] / deltas.back());
    std::printf("  weighted: %.2f decades of condition per decade of delta\n", decades);
    EXPECT_NEAR(decades, 4 * degree + 2, 0.5) << "degree " << degree;
  }
}

}  // namespace
}  // namespace sage::solver
