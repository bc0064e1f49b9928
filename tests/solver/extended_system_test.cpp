// extended_system(): E^T A E from the band of A must be the lower triangle
// of the dense product, for both bases, in 2D and 3D; extended_product()
// the whole product of a band that is not symmetric.
#include <sage/solver/extended_system.hpp>
#include <sage/solver/local_splines.hpp>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <cmath>
#include <random>

namespace sage::solver {
namespace {

template <int D>
void expect_product_of_band(int degree, BasisKind kind, bool symmetric = true) {
  std::array<double, D> lo{}, hi{};
  lo.fill(-1.0);
  hi.fill(1.0);
  const auto grid = BackgroundGrid<D>::covering(lo, hi, D == 2 ? 0.2 : 0.25, degree);
  std::vector<char> active(grid.cell_count(), 0), inside(grid.cell_count(), 0);
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    const auto i = grid.cell_index(c);
    double r2 = 0.0;
    for (int a = 0; a < D; ++a) r2 += std::pow(grid.lo[a] + (i[a] + 0.5) * grid.h, 2);
    active[c] = r2 < 0.9 ? 1 : 0;
    inside[c] = r2 < 0.5 ? 1 : 0;
  }
  const SplineBasis<D> basis = build_basis(grid, active, inside, kind);
  const int width = 2 * degree + 1, local = grid.local_count();
  int stencil = 1;
  for (int a = 0; a < D; ++a) stencil *= width;
  const auto relevant = static_cast<Eigen::Index>(basis.relevant.size());
  // A random symmetric cell matrix per active cell, into the band and into A.
  std::vector<double> band(basis.relevant.size() * static_cast<std::size_t>(stencil), 0.0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(relevant, relevant);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    if (!active[c]) continue;
    const auto cell = grid.cell_index(c);
    Eigen::MatrixXd K(local, local);
    for (int j = 0; j < local; ++j)
      for (int l = 0; l <= j; ++l) {
        K(j, l) = K(l, j) = uniform(random);
        if (!symmetric) K(l, j) = uniform(random);
      }
    for (int j = 0; j < local; ++j)
      for (int l = 0; l < local; ++l) {
        const auto sj = LocalSplines<D>::global_index(cell, degree, j),
                   sl = LocalSplines<D>::global_index(cell, degree, l);
        const long long rj = basis.relevant_of[grid.spline_linear(sj)], rl = basis.relevant_of[grid.spline_linear(sl)];
        int slot = 0;
        for (int a = D - 1; a >= 0; --a) slot = slot * width + (sl[a] - sj[a] + degree);
        band[static_cast<std::size_t>(rj) * static_cast<std::size_t>(stencil) + static_cast<std::size_t>(slot)] +=
            K(j, l);
        A(rj, rl) += K(j, l);
      }
  }
  const Eigen::MatrixXd E = Eigen::MatrixXd(basis.extension);
  const Eigen::MatrixXd expected = E.transpose() * A * E;
  if (!symmetric) {
    const Eigen::SparseMatrix<double> product = extended_product(basis, band);
    EXPECT_LT((Eigen::MatrixXd(product) - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
    return;
  }
  const Eigen::SparseMatrix<double> system = extended_system(basis, band);
  ASSERT_EQ(system.rows(), expected.rows());
  ASSERT_EQ(system.cols(), expected.cols());
  const Eigen::MatrixXd lower = expected.triangularView<Eigen::Lower>();
  EXPECT_LT((Eigen::MatrixXd(system) - lower).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
  for (Eigen::Index p = 0; p < system.outerSize(); ++p) {  // the lower triangle, rows increasing in each column
    Eigen::Index previous = p - 1;
    for (Eigen::SparseMatrix<double>::InnerIterator it(system, p); it; ++it) {
      EXPECT_GT(it.row(), previous);
      previous = it.row();
    }
  }
}

TEST(ExtendedSystem, BandProductEqualsTheDenseProduct) {
  expect_product_of_band<2>(2, BasisKind::Web);
  expect_product_of_band<2>(3, BasisKind::Weighted);
  expect_product_of_band<3>(2, BasisKind::Web);
}

// extended_product(): the whole E^T A E of a band that is not symmetric
// (elasticity's couplings of two components).
TEST(ExtendedSystem, ProductOfAnUnsymmetricBand) {
  expect_product_of_band<2>(2, BasisKind::Web, false);
  expect_product_of_band<3>(3, BasisKind::Web, false);
}

}  // namespace
}  // namespace sage::solver
