#pragma once
// Condition estimate of a symmetric positive definite matrix after
// diagonal (Jacobi) scaling, S = D^-1/2 K D^-1/2, the matrix that a
// preconditioned iteration actually sees: lambda_max by power iteration,
// lambda_min by inverse iteration with a sparse Cholesky factorization
// (Rayleigh quotients, so both converge from above/below quickly). An
// estimate: a lower bound of the true cond_2(S) that is typically within a
// few per cent of it.

#include <Eigen/SparseCore>

namespace sage::solver {

struct ConditionEstimate {
  double lambda_min = 0.0;
  double lambda_max = 0.0;
  double condition() const { return lambda_max / lambda_min; }
};

/// Throws std::runtime_error if K is not numerically positive definite.
ConditionEstimate estimate_condition(const Eigen::SparseMatrix<double>& K, int iterations = 60);

}  // namespace sage::solver
