// SymmetricProduct (symmetric_product.hpp), the matrix product of
// conjugate gradients: A x from A's lower triangle on all cores, equal to
// Eigen's one-core product for any number of threads, also when called
// from inside another parallel region (a team of one).
#include <symmetric_product.hpp>

#include <gtest/gtest.h>

#include <random>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {
namespace {

/// A random symmetric matrix's lower triangle: a band of width 40 with
/// entries dropped at random, and some empty columns.
Eigen::SparseMatrix<double> random_lower(int n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0), chance(0.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int c = 0; c < n; ++c) {
    if (c % 17 == 5) continue;
    for (int r = c; r < std::min(n, c + 40); ++r)
      if (r == c || chance(random) < 0.3) entries.emplace_back(r, c, value(random));
  }
  Eigen::SparseMatrix<double> lower(n, n);
  lower.setFromTriplets(entries.begin(), entries.end());
  return lower;
}

TEST(SymmetricProduct, EqualsTheSelfAdjointProduct) {
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
#endif
  for (const int n : {1, 7, 1000}) {
    const Eigen::SparseMatrix<double> lower = random_lower(n, 11u + static_cast<unsigned>(n));
    const Eigen::VectorXd x = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd expected = lower.selfadjointView<Eigen::Lower>() * x;
    for (const int team : {1, 2, 3}) {
#ifdef _OPENMP
      omp_set_num_threads(team);
#endif
      const SymmetricProduct product(lower);
      Eigen::VectorXd y;
      product.apply(x, y);
      EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-13 * (1.0 + expected.cwiseAbs().maxCoeff()))
          << n << " unknowns, " << team << " threads";
      // Inside a parallel region the team is one thread: every slice still runs.
      Eigen::VectorXd nested;
#pragma omp parallel num_threads(2)
      {
#pragma omp single
        product.apply(x, nested);
      }
      EXPECT_LT((nested - expected).cwiseAbs().maxCoeff(), 1e-13 * (1.0 + expected.cwiseAbs().maxCoeff()))
          << n << " unknowns, " << team << " threads, nested";
    }
  }
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
}

}  // namespace
}  // namespace sage::solver
