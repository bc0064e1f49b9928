#include <sage/solver/condition.hpp>

#include <Eigen/SparseCholesky>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sage::solver {

ConditionEstimate estimate_condition(const Eigen::SparseMatrix<double>& K, int iterations) {
  const Eigen::Index n = K.rows();
  Eigen::VectorXd scale = K.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::SparseMatrix<double> S = scale.asDiagonal() * K * scale.asDiagonal();
  ConditionEstimate estimate;
  // A fixed, non-special start vector (reproducible, not orthogonal to the
  // extreme eigenvectors in practice).
  Eigen::VectorXd start(n);
  for (Eigen::Index i = 0; i < n; ++i) start[i] = 1.0 + 0.5 * std::sin(1.7 * static_cast<double>(i) + 0.3);
  Eigen::VectorXd x = start.normalized();
  for (int k = 0; k < iterations; ++k) {
    Eigen::VectorXd y = S * x;
    estimate.lambda_max = x.dot(y);
    x = y.normalized();
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(S);
  if (factor.info() != Eigen::Success) throw std::runtime_error("condition estimate: the matrix is not positive definite");
  x = start.normalized();
  double rayleigh = std::numeric_limits<double>::infinity();
  for (int k = 0; k < iterations; ++k) {
    Eigen::VectorXd y = factor.solve(x);
    const Eigen::VectorXd Sy = S * y;
    rayleigh = y.dot(Sy) / y.dot(y);
    x = y.normalized();
  }
  estimate.lambda_min = rayleigh;
  if (!(estimate.lambda_min > 0)) throw std::runtime_error("condition estimate: the matrix is not positive definite");
  return estimate;
}

}  // namespace sage::solver
