#pragma once
// The solve of a symmetric positive definite system given by its lower
// triangle, shared by the solvers: a sparse LDLT, or conjugate gradients
// (the matrix product on all cores, symmetric_product.hpp) with multilevel
// Schwarz, incomplete Cholesky or Jacobi. Automatic means Jacobi while its
// rate promises to converge soon enough, then multilevel Schwarz when the
// unknowns' places are given (3D), else incomplete Cholesky.

#include "schwarz_preconditioner.hpp"

#include <sage/solver/solver_options.hpp>

#include <Eigen/SparseCore>

namespace sage::solver {

/// Solves system x = right (`system`: the lower triangle); records the
/// solver, its iterations and tolerance in `report`. Throws
/// std::runtime_error when the factorization fails, conjugate gradients do
/// not converge or the solution is not finite. `placement`: where the
/// unknowns sit on the grid, for the multilevel Schwarz preconditioner
/// (LinearSolverKind::Schwarz, and Automatic, which uses it when given).
Eigen::VectorXd solve_symmetric(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right,
                                LinearSolverKind kind, double tolerance, SolveReport& report,
                                const SplinePlacement* placement = nullptr);

}  // namespace sage::solver
