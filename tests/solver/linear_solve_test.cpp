// The linear solves notice breakdown instead of crashing or spinning
// (linear_solve.hpp): a system that is not positive definite, holds a
// number that is not finite, or has an unknown without a diagonal entry is
// refused before any factorization; conjugate gradients stop at a
// non-positive curvature, and when they make no progress; the direct
// factorization names a non-positive pivot.

#include "linear_solve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace sage::solver {
namespace {

/// The lower triangle of the path graph's Laplacian of n nodes plus shift * I
/// (shift 0: singular, the constants its null space).
Eigen::SparseMatrix<double> path_laplacian(int n, double shift) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    const double degree = (i > 0) + (i + 1 < n);
    entries.emplace_back(i, i, degree + shift);
    if (i > 0) entries.emplace_back(i, i - 1, -1.0);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

std::string failure(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& b, LinearSolverKind kind) {
  SolveReport report;
  try {
    solve_symmetric(a, b, kind, 1e-10, report);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

bool has(const std::string& text, const std::string& piece) { return text.find(piece) != std::string::npos; }

constexpr LinearSolverKind kAll[] = {LinearSolverKind::Direct, LinearSolverKind::ConjugateGradient,
                                     LinearSolverKind::JacobiConjugateGradient, LinearSolverKind::Automatic};

TEST(LinearSolve, PositiveDefiniteSystemsAreSolvedByEveryKind) {
  const Eigen::SparseMatrix<double> a = path_laplacian(200, 1e-2);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(200, -1.0, 2.0).array().sin();
  const Eigen::VectorXd b = a.selfadjointView<Eigen::Lower>() * expected;
  for (const LinearSolverKind kind : kAll) {
    SolveReport report;
    const Eigen::VectorXd x = solve_symmetric(a, b, kind, 1e-12, report);
    EXPECT_LT((x - expected).norm(), 1e-6 * expected.norm()) << report.linear_solver;
  }
}

TEST(LinearSolve, UnknownWithoutPositiveDiagonalIsRefusedBeforeAnyFactorization) {
  // An unknown with an empty column (what a conductivity of 0 assembled):
  // Eigen's incomplete Cholesky read past its arrays there.
  Eigen::SparseMatrix<double> a = path_laplacian(6, 1.0);
  a.coeffRef(3, 3) = 0.0;
  a.coeffRef(3, 2) = 0.0;
  a.coeffRef(4, 3) = 0.0;
  a.prune(0.0);
  for (const LinearSolverKind kind : kAll) {
    const std::string what = failure(a, Eigen::VectorXd::Ones(6), kind);
    EXPECT_TRUE(has(what, "not positive definite") && has(what, "unknown 3")) << what;
  }
  Eigen::SparseMatrix<double> negative = path_laplacian(6, 1.0);
  negative.coeffRef(2, 2) = -1.0;
  EXPECT_TRUE(has(failure(negative, Eigen::VectorXd::Ones(6), LinearSolverKind::ConjugateGradient), "unknown 2"));
}

TEST(LinearSolve, NumbersThatAreNotFiniteAreNamed) {
  Eigen::SparseMatrix<double> a = path_laplacian(6, 1.0);
  a.coeffRef(4, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(has(failure(a, Eigen::VectorXd::Ones(6), LinearSolverKind::Automatic), "row 4, column 3"));
  Eigen::VectorXd b = Eigen::VectorXd::Ones(6);
  b[5] = std::numeric_limits<double>::infinity();
  const std::string what = failure(path_laplacian(6, 1.0), b, LinearSolverKind::JacobiConjugateGradient);
  EXPECT_TRUE(has(what, "right side") && has(what, "unknown 5")) << what;
}

TEST(LinearSolve, IndefiniteSystemsStopConjugateGradientsAtOnce) {
  // Positive diagonal 1.2 with off-diagonals -1: eigenvalues 1.2 - 2 cos t
  // fill (-0.8, 3.2), so the matrix is indefinite, which no diagonal check sees.
  Eigen::SparseMatrix<double> indefinite = path_laplacian(400, 0.0);
  for (int i = 0; i < 400; ++i) indefinite.coeffRef(i, i) = 1.2;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(400, 0.0, 1.0);
  for (const LinearSolverKind kind : {LinearSolverKind::JacobiConjugateGradient, LinearSolverKind::Automatic}) {
    const std::string what = failure(indefinite, b, kind);
    EXPECT_TRUE(has(what, "not positive definite") && has(what, "broke down at iteration")) << what;
  }
  const std::string direct = failure(indefinite, b, LinearSolverKind::Direct);
  EXPECT_TRUE(has(direct, "pivot") && has(direct, "not positive definite")) << direct;
}

TEST(LinearSolve, InconsistentSingularSystemsEndWithAReason) {
  // The Neumann Laplacian with a load that does not sum to zero: no
  // solution, and the residual never halves again. CG must stop with the
  // reason instead of running to its limit of 10 n iterations.
  const int n = 3000;
  const Eigen::SparseMatrix<double> a = path_laplacian(n, 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  SolveReport report;
  try {
    solve_symmetric(a, b, LinearSolverKind::JacobiConjugateGradient, 1e-10, report);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_TRUE(has(what, "broke down at iteration") && has(what, "no progress")) << what;
    EXPECT_LT(report.iterations, 10 * n) << "stopped before the iteration limit";
  }
}

TEST(LinearSolve, AutomaticLeavesJacobiWhenItWouldTakeTooLong) {
  // A long path's Laplacian (condition about (2n / pi)^2 = 1.5e7, Jacobi
  // scaling gains nothing): Jacobi CG would need about n iterations, far
  // beyond its budget of 4,000, while incomplete Cholesky of a tridiagonal
  // matrix is exact. The automatic solver must leave Jacobi after its first
  // legs, say so, and still solve.
  const int n = 6000;
  const Eigen::SparseMatrix<double> a = path_laplacian(n, 1e-7);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(n, -3.0, 3.0).array().sin();
  const Eigen::VectorXd b = a.selfadjointView<Eigen::Lower>() * expected;
  SolveReport report;
  const Eigen::VectorXd x = solve_symmetric(a, b, LinearSolverKind::Automatic, 1e-12, report);
  EXPECT_TRUE(has(report.linear_solver, "Jacobi (") && has(report.linear_solver, "too slow), then incomplete Cholesky"))
      << report.linear_solver;
  EXPECT_LT(report.iterations, 4000) << report.linear_solver;
  EXPECT_LT((x - expected).norm(), 1e-6 * expected.norm());

  // A well-conditioned system stays on Jacobi.
  const Eigen::SparseMatrix<double> easy = path_laplacian(n, 1.0);
  SolveReport easy_report;
  solve_symmetric(easy, easy.selfadjointView<Eigen::Lower>() * expected, LinearSolverKind::Automatic, 1e-12,
                  easy_report);
  EXPECT_EQ(easy_report.linear_solver, "conjugate gradients, Jacobi");
}

}  // namespace
}  // namespace sage::solver
