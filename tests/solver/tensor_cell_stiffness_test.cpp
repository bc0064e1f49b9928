// TensorCellStiffness: the sum-factorized stiffness of an inside cell must
// equal the direct sum over the tensor Gauss points of
// c0 B_j B_l + sum_a c1_a (B_j d_a B_l + d_a B_j B_l) + c2 grad B_j . grad B_l
// with the local splines of local_splines.hpp, for any coefficients.
#include <sage/solver/gauss.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include <gtest/gtest.h>

#include <random>

namespace sage::solver {
namespace {

void expect_direct_sum(int degree, int points) {
  BackgroundGrid<3> grid;
  grid.h = 0.3;
  grid.lo = {-0.6, 0.3, 0.9};  // the cell (0, 0, 0) is then [lo, lo + h]^3
  grid.cells = {4, 4, 4};
  grid.degree = degree;
  const GaussRule& rule = gauss_legendre(points);
  const int count = points * points * points, local = grid.local_count();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> c0(count), c2(count);
  std::array<std::vector<double>, 3> c1{c0, c0, c0};
  Eigen::MatrixXd direct = Eigen::MatrixXd::Zero(local, local);
  LocalSplines<3> splines;
  for (int p = 0; p < count; ++p) {
    c0[p] = uniform(random);
    c2[p] = uniform(random);
    for (auto& c : c1) c[p] = uniform(random);
    const std::array<double, 3> x{grid.lo[0] + grid.h * rule.nodes[p % points],
                                  grid.lo[1] + grid.h * rule.nodes[(p / points) % points],
                                  grid.lo[2] + grid.h * rule.nodes[p / (points * points)]};
    splines.evaluate(grid, {0, 0, 0}, x.data());
    for (int j = 0; j < local; ++j)
      for (int l = 0; l < local; ++l) {
        double s = c0[p] * splines.value[j] * splines.value[l];
        for (int a = 0; a < 3; ++a)
          s += c1[a][p] * (splines.value[j] * splines.gradient[a][l] + splines.gradient[a][j] * splines.value[l]) +
               c2[p] * splines.gradient[a][j] * splines.gradient[a][l];
        direct(j, l) += s;
      }
  }
  TensorCellStiffness tensor(degree, points, grid.h);
  ASSERT_EQ(tensor.point_count(), count);
  Eigen::MatrixXd factorized;
  tensor.compute(c0.data(), {c1[0].data(), c1[1].data(), c1[2].data()}, c2.data(), factorized);
  ASSERT_EQ(factorized.rows(), local);
  EXPECT_LT((factorized - direct).cwiseAbs().maxCoeff(), 1e-12 * direct.cwiseAbs().maxCoeff())
      << "degree " << degree << ", " << points << " points";
}

TEST(TensorCellStiffness, EqualsTheDirectSumOverThePoints) {
  expect_direct_sum(1, 2);
  expect_direct_sum(2, 3);
  expect_direct_sum(3, 4);
  expect_direct_sum(3, 5);
}

}  // namespace
}  // namespace sage::solver
