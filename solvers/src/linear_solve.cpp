#include "linear_solve.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sage::solver {

namespace {

/// What conjugate gradients reached.
struct CgResult {
  Eigen::VectorXd x;
  bool converged = false;
  double residual = 1.0;  // relative
};

/// Conjugate gradients from `guess` (or 0), for at most `budget`
/// iterations; without a budget, throws when they do not converge.
template <class Preconditioner>
CgResult conjugate_gradients(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right, double tolerance,
                             SolveReport& report, int budget = 0, const Eigen::VectorXd* guess = nullptr) {
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower, Preconditioner> cg;
  cg.setTolerance(tolerance);
  report.cg_tolerance = tolerance;
  cg.setMaxIterations(budget > 0 ? budget : 10 * system.rows() + 100);
  cg.compute(system);
  if (cg.info() != Eigen::Success) throw std::runtime_error("the preconditioner could not be set up");
  CgResult result;
  if (guess) {
    result.x = cg.solveWithGuess(right, *guess);
  } else {
    result.x = cg.solve(right);
  }
  report.iterations += static_cast<int>(cg.iterations());
  result.converged = cg.info() == Eigen::Success;
  result.residual = cg.error();
  if (!result.converged && budget == 0)
    throw std::runtime_error("conjugate gradients did not converge in " + std::to_string(cg.iterations()) +
                             " iterations (relative residual " + std::to_string(cg.error()) + ")");
  return result;
}

/// 3D, automatic: Jacobi's preconditioner is set up for free and enough
/// for most domains (a few hundred to 1,400 iterations), but domains with
/// features a few cells wide (a mesh's thin ears) make the WEB system's
/// condition reach 1e8 after scaling, where Jacobi needs 8,000 iterations
/// and incomplete Cholesky 23 (its set-up costs several times a hundred
/// Jacobi iterations). So Jacobi in legs, while they promise convergence
/// within kJacobiBudget iterations.
constexpr int kJacobiProbe = 200;
constexpr int kJacobiBudget = 4000;

using Jacobi = Eigen::DiagonalPreconditioner<double>;
using IncompleteCholesky = Eigen::IncompleteCholesky<double>;

Eigen::VectorXd jacobi_then_incomplete_cholesky(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right,
                                                double tolerance, SolveReport& report) {
  report.linear_solver = "conjugate gradients, Jacobi";
  // Jacobi in legs: after each, the rate of the last leg says how many
  // more iterations it needs (CG's residual falls about geometrically
  // once past its first fast phase); beyond the budget, incomplete Cholesky.
  CgResult leg = conjugate_gradients<Jacobi>(system, right, tolerance, report, kJacobiProbe);
  int spent = kJacobiProbe, length = kJacobiProbe;
  double start = 1.0;
  while (!leg.converged) {
    const double per_iteration = std::log(leg.residual / start) / length;
    const double more = per_iteration < 0.0 ? std::log(tolerance / leg.residual) / per_iteration
                                            : std::numeric_limits<double>::infinity();
    if (spent + more > kJacobiBudget) break;
    start = leg.residual;
    length = std::max(kJacobiProbe, static_cast<int>(1.2 * more));
    leg = conjugate_gradients<Jacobi>(system, right, tolerance, report, length, &leg.x);
    spent += length;
  }
  if (leg.converged) return leg.x;
  report.linear_solver =
      "conjugate gradients, Jacobi (" + std::to_string(spent) + " iterations, too slow), then incomplete Cholesky";
  return conjugate_gradients<IncompleteCholesky>(system, right, tolerance, report).x;
}

}  // namespace

Eigen::VectorXd solve_symmetric(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right,
                                LinearSolverKind kind, double tolerance, SolveReport& report) {
  Eigen::VectorXd x;
  switch (kind) {
    case LinearSolverKind::Direct: {
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(system);
      if (factor.info() != Eigen::Success)
        throw std::runtime_error(
            "the sparse factorization failed: the system is singular (is the basis stable? try --basis web)");
      x = factor.solve(right);
      report.linear_solver = "sparse LDLT (AMD ordering)";
      report.iterations = 1;
      break;
    }
    case LinearSolverKind::ConjugateGradient:
      x = conjugate_gradients<IncompleteCholesky>(system, right, tolerance, report).x;
      report.linear_solver = "conjugate gradients, incomplete Cholesky";
      break;
    case LinearSolverKind::JacobiConjugateGradient:
      x = conjugate_gradients<Jacobi>(system, right, tolerance, report).x;
      report.linear_solver = "conjugate gradients, Jacobi";
      break;
    case LinearSolverKind::Automatic: x = jacobi_then_incomplete_cholesky(system, right, tolerance, report); break;
  }
  if (!x.allFinite()) throw std::runtime_error("the solve produced non-finite coefficients");
  return x;
}

}  // namespace sage::solver
