#include <sage/solver/condition.hpp>

#include <Eigen/SparseCholesky>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sage::solver {

namespace {

/// lambda_max / lambda_min of a symmetric positive definite matrix.
double condition_of(const Eigen::SparseMatrix<double>& M, int iterations) {
  const Eigen::Index n = M.rows();
  // A fixed, non-special start vector: reproducible, and not orthogonal to
  // the extreme eigenvectors in practice.
  Eigen::VectorXd start(n);
  for (Eigen::Index i = 0; i < n; ++i) start[i] = 1.0 + 0.5 * std::sin(1.7 * static_cast<double>(i) + 0.3);
  Eigen::VectorXd x = start.normalized();
  double lambda_max = 0.0;
  for (int k = 0; k < iterations; ++k) {
    const Eigen::VectorXd y = M * x;
    lambda_max = x.dot(y);
    x = y.normalized();
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(M);
  if (factor.info() != Eigen::Success || (factor.vectorD().array() <= 0.0).any())
    throw std::runtime_error("condition estimate: the matrix is not numerically positive definite");
  x = start.normalized();
  double lambda_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k < iterations; ++k) {
    const Eigen::VectorXd y = factor.solve(x);
    lambda_min = y.dot(M * y) / y.dot(y);
    x = y.normalized();
  }
  if (!(lambda_min > 0))
    throw std::runtime_error("condition estimate: the matrix is not numerically positive definite");
  return lambda_max / lambda_min;
}

}  // namespace

ConditionEstimate estimate_condition(const Eigen::SparseMatrix<double>& K, int iterations) {
  const Eigen::VectorXd scale = K.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::SparseMatrix<double> S = scale.asDiagonal() * K * scale.asDiagonal();
  return {condition_of(K, iterations), condition_of(S, iterations)};
}

}  // namespace sage::solver
