// The B-spline basis: the worked example of bspline.hpp, partition of
// unity, derivatives against finite differences, and the WEB extension's
// promise to keep polynomials.
#include <sage/primitives.hpp>
#include <sage/solver/bspline.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/web_basis.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace sage::solver {
namespace {

TEST(BSpline, WorkedExampleDegreeOne) {
  double v[2], d[2];
  bspline_on_cell(1, 0.25, v, d);
  EXPECT_DOUBLE_EQ(v[0], 0.75);
  EXPECT_DOUBLE_EQ(v[1], 0.25);
  EXPECT_DOUBLE_EQ(d[0], -1.0);
  EXPECT_DOUBLE_EQ(d[1], 1.0);
}

TEST(BSpline, CubicPiecesAreTheCardinalSpline) {
  // B_3 at its knots: 1/6, 2/3, 1/6.
  double v[4], d[4];
  bspline_on_cell(3, 0.0, v, d);
  EXPECT_NEAR(v[0], 1.0 / 6, 1e-15);
  EXPECT_NEAR(v[1], 2.0 / 3, 1e-15);
  EXPECT_NEAR(v[2], 1.0 / 6, 1e-15);
  EXPECT_NEAR(v[3], 0.0, 1e-15);
}

TEST(BSpline, PartitionOfUnityAndDerivatives) {
  for (int n = 0; n <= kMaxDegree; ++n) {
    for (double t : {0.0, 0.1, 0.37, 0.5, 0.93, 1.0}) {
      double v[kMaxDegree + 1], d[kMaxDegree + 1], vp[kMaxDegree + 1], vm[kMaxDegree + 1], unused[kMaxDegree + 1];
      bspline_on_cell(n, t, v, d);
      double sum = 0.0, dsum = 0.0;
      for (int j = 0; j <= n; ++j) {
        sum += v[j];
        dsum += d[j];
      }
      EXPECT_NEAR(sum, 1.0, 1e-14) << "degree " << n;
      EXPECT_NEAR(dsum, 0.0, 1e-13) << "degree " << n;
      if (n < 2) continue;  // C^1 needs degree >= 2 for the difference quotient across t = 0, 1
      const double e = 1e-6;
      bspline_on_cell(n, t + e, vp, unused);
      bspline_on_cell(n, t - e, vm, unused);
      for (int j = 0; j <= n; ++j) EXPECT_NEAR(d[j], (vp[j] - vm[j]) / (2 * e), 1e-7) << "degree " << n;
    }
  }
}

TEST(BSpline, LocalSplinesReproduceLinearFunctions) {
  // Coefficients of x along a uniform grid are the Greville abscissae.
  const auto grid = BackgroundGrid<2>::covering({-1, -1}, {1, 1}, 0.25, 3);
  LocalSplines<2> local;
  const double x[2] = {0.3, -0.55};
  const auto cell = grid.cell_of(x);
  local.evaluate(grid, cell, x);
  double sum = 0.0, dx = 0.0;
  for (int k = 0; k < grid.local_count(); ++k) {
    const auto i = LocalSplines<2>::global_index(cell, 3, k);
    const double greville = grid.lo[0] + grid.h * (i[0] - 3 + 0.5 * (3 + 1));
    sum += greville * local.value[k];
    dx += greville * local.gradient[0][k];
  }
  EXPECT_NEAR(sum, x[0], 1e-14);
  EXPECT_NEAR(dx, 1.0, 1e-13);
}

TEST(WebBasis, ExtensionKeepsPolynomialCoefficients) {
  // Degree-2 coefficients of x^2 y (polynomial in the index) on the outer
  // splines are the Lagrange extrapolation of those on the inner ones.
  const auto grid = BackgroundGrid<2>::covering({-1, -1}, {1, 1}, 0.25, 2);
  std::vector<char> active(grid.cell_count(), 0), inside(grid.cell_count(), 0);
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    const auto i = grid.cell_index(c);
    const double cx = grid.lo[0] + (i[0] + 0.5) * grid.h, cy = grid.lo[1] + (i[1] + 0.5) * grid.h;
    const double r = std::hypot(cx, cy);
    active[c] = r < 0.95 ? 1 : 0;
    inside[c] = r < 0.7 ? 1 : 0;
  }
  const auto basis = build_basis(grid, active, inside, BasisKind::Web);
  ASSERT_GT(basis.outer_count, 0u);
  auto poly = [](const std::array<int, 2>& i) { return 0.5 * i[0] * i[0] * i[1] - 2.0 * i[1] + 3.0; };
  // Inner splines are the rows with a single entry (the identity part of E).
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = basis.extension;
  Eigen::VectorXd inner = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(basis.unknowns()));
  std::size_t inner_rows = 0;
  for (std::size_t r = 0; r < basis.relevant.size(); ++r) {
    const auto row = static_cast<Eigen::Index>(r);
    if (rows.innerVector(row).nonZeros() != 1) continue;
    ++inner_rows;
    Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, row);
    EXPECT_EQ(it.value(), 1.0);
    inner[it.col()] = poly(grid.spline_index(basis.relevant[r]));
  }
  EXPECT_EQ(inner_rows, basis.inner_count);
  const Eigen::VectorXd all = basis.extension * inner;
  for (std::size_t r = 0; r < basis.relevant.size(); ++r)
    EXPECT_NEAR(all[static_cast<Eigen::Index>(r)], poly(grid.spline_index(basis.relevant[r])), 1e-9);
}

}  // namespace
}  // namespace sage::solver
