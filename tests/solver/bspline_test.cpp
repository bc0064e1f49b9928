// The B-spline basis: the worked example of bspline.hpp, partition of
// unity, derivatives against finite differences, and the WEB extension's
// promise to keep polynomials.
#include <sage/expression/primitives.hpp>
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

TEST(BSpline, SecondDerivativesAgainstDifferenceQuotients) {
  // Degree n >= 3 is C^2 across the knots, so central differences of the
  // first derivatives converge to the second everywhere, t = 0, 1 included.
  for (int n = 2; n <= kMaxDegree; ++n) {
    for (double t : {0.0, 0.21, 0.5, 0.77, 1.0}) {
      if (n == 2 && (t == 0.0 || t == 1.0)) continue;  // B_2'' jumps at the knots
      double v[kMaxDegree + 1], d[kMaxDegree + 1], dd[kMaxDegree + 1], dp[kMaxDegree + 1], dm[kMaxDegree + 1];
      bspline_on_cell(n, t, v, d, dd);
      const double e = 1e-5;
      bspline_on_cell(n, t + e, v, dp);
      bspline_on_cell(n, t - e, v, dm);
      double sum = 0.0;
      for (int j = 0; j <= n; ++j) {
        EXPECT_NEAR(dd[j], (dp[j] - dm[j]) / (2 * e), 1e-8) << "degree " << n << " t " << t;
        sum += dd[j];
      }
      EXPECT_NEAR(sum, 0.0, 1e-12);  // second derivative of the partition of unity
    }
  }
  double v[3], d[3], dd[3];
  bspline_on_cell(2, 0.3, v, d, dd);  // B_2 pieces: t^2/2, .., so B'' = 1, -2, 1
  EXPECT_NEAR(dd[0], 1.0, 1e-15);
  EXPECT_NEAR(dd[1], -2.0, 1e-15);
  EXPECT_NEAR(dd[2], 1.0, 1e-15);
}

TEST(BSpline, LocalSplineHessiansReproduceAQuadratic) {
  // Degree 3 holds x y and x^2: their spline coefficients come from the
  // Marsden identity; check the Hessians of the local sums.
  const auto grid = BackgroundGrid<3>::covering({-1, -1, -1}, {1, 1, 1}, 0.25, 3);
  LocalSplines<3> local;
  const double x[3] = {0.3, -0.55, 0.12};
  const auto cell = grid.cell_of(x);
  local.evaluate(grid, cell, x, true);
  // Coefficient of x_a x_b (a != b): product of Greville abscissae; of x_a^2:
  // the symmetric product of the knots' pairs, Greville^2 - (n + 1) h^2 / 12.
  double xy = 0.0, xx = 0.0, xy_mixed = 0.0, xx_pure = 0.0, zz_of_xy = 0.0;
  for (int k = 0; k < grid.local_count(); ++k) {
    const auto i = LocalSplines<3>::global_index(cell, 3, k);
    std::array<double, 3> greville{};
    for (int a = 0; a < 3; ++a) greville[a] = grid.lo[a] + grid.h * (i[a] - 3 + 0.5 * (3 + 1));
    const double c_xy = greville[0] * greville[1];
    const double c_xx = greville[0] * greville[0] - grid.h * grid.h * (3 + 1) / 12.0;
    xy += c_xy * local.value[k];
    xx += c_xx * local.value[k];
    xy_mixed += c_xy * local.hessian[LocalSplines<3>::hessian_index(0, 1)][k];
    zz_of_xy += c_xy * local.hessian[LocalSplines<3>::hessian_index(2, 2)][k];
    xx_pure += c_xx * local.hessian[LocalSplines<3>::hessian_index(0, 0)][k];
  }
  EXPECT_NEAR(xy, x[0] * x[1], 1e-13);
  EXPECT_NEAR(xx, x[0] * x[0], 1e-13);
  EXPECT_NEAR(xy_mixed, 1.0, 1e-11);
  EXPECT_NEAR(zz_of_xy, 0.0, 1e-11);
  EXPECT_NEAR(xx_pure, 2.0, 1e-11);
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
