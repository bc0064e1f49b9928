#pragma once
// Condition estimates of a symmetric positive definite matrix K, as it is
// and after diagonal (Jacobi) scaling S = D^-1/2 K D^-1/2 (the matrix a
// diagonally preconditioned iteration sees): lambda_max by power
// iteration, lambda_min by inverse iteration with a sparse LDLT
// factorization, both through Rayleigh quotients. Estimates from below of
// cond_2, typically within a few per cent.

#include <Eigen/SparseCore>

namespace sage::solver {

struct ConditionEstimate {
  double condition = 0.0;         // of K
  double scaled_condition = 0.0;  // of D^-1/2 K D^-1/2
};

/// Throws std::runtime_error if K is not numerically positive definite.
ConditionEstimate estimate_condition(const Eigen::SparseMatrix<double>& K, int iterations = 60);

}  // namespace sage::solver
