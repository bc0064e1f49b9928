#include "linear_solve.hpp"

#include "freed_memory.hpp"
#include "message_text.hpp"
#include "symmetric_product.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage::solver {

namespace {

/// The system must be worth solving before any factorization touches it
/// (Eigen's incomplete Cholesky reads past its arrays when a column has no
/// diagonal entry): finite entries, a positive diagonal, a finite right
/// side. The problem's data are checked before assembly (data_check.hpp),
/// so these name what slipped through as an unknown's index.
void check_system(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right) {
  for (Eigen::Index c = 0; c < system.outerSize(); ++c) {
    Eigen::SparseMatrix<double>::InnerIterator entry(system, c);
    if (!entry || entry.row() != c || !(entry.value() > 0.0))
      throw std::runtime_error("the assembled system is not positive definite: unknown " + std::to_string(c) +
                               " has the diagonal entry " +
                               number_text(entry && entry.row() == c ? entry.value() : 0.0));
    for (; entry; ++entry)
      if (!std::isfinite(entry.value()))
        throw std::runtime_error("the assembled system holds " + number_text(entry.value()) + " in row " +
                                 std::to_string(entry.row()) + ", column " + std::to_string(c));
    if (!std::isfinite(right[c]))
      throw std::runtime_error("the assembled right side is " + number_text(right[c]) + " at unknown " +
                               std::to_string(c));
  }
}

/// What conjugate gradients reached.
struct CgResult {
  Eigen::VectorXd x;
  bool converged = false;
  double residual = 1.0;  // relative
};

/// Iterations without halving the best residual after which conjugate
/// gradients are said to stagnate: a singular, inconsistent system's
/// residual levels off, while the hardest systems of the test suite and the
/// benchmarks halve theirs within a few hundred iterations.
constexpr int kStagnationIterations = 2000;

/// When to give conjugate gradients up for a better preconditioner: every
/// `every` iterations from `first` on, the rate of the last half of the
/// iterations says how many more it needs (CG's residual falls about
/// geometrically once past its first fast phase, whose rate is
/// optimistic); past `budget` in all, it stops.
struct GiveUpRule {
  int first = 200;
  int every = 100;
  int budget = 4000;
};

/// Preconditioned conjugate gradients on the system's lower triangle from
/// `guess` (or 0), for at most `budget` iterations, or until `give_up`
/// says so; without either, throws when they do not converge. Throws at
/// once on a breakdown: a residual that is not finite, a direction of
/// non-positive curvature (the matrix is not positive definite), a
/// preconditioner that is not, or stagnation.
template <class Preconditioner>
CgResult conjugate_gradients(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right, double tolerance,
                             SolveReport& report, const Preconditioner& preconditioner, int budget = 0,
                             const Eigen::VectorXd* guess = nullptr, const GiveUpRule* give_up = nullptr) {
  report.cg_tolerance = tolerance;
  const SymmetricProduct a(system);
  const int limit = budget > 0 ? budget : 10 * static_cast<int>(system.rows()) + 100;
  CgResult result;
  result.x = guess ? *guess : Eigen::VectorXd::Zero(right.size());
  const double right_norm = right.norm();
  if (right_norm == 0.0) {
    result.x.setZero();
    result.converged = true;
    result.residual = 0.0;
    return result;
  }
  Eigen::VectorXd r(right.size());
  a.apply(result.x, r);
  r = right - r;
  Eigen::VectorXd z = preconditioner.solve(r);
  Eigen::VectorXd p = z, q(right.size());
  double rz = r.dot(z), best = r.norm();
  int iteration = 0, best_at = 0;
  auto breakdown = [&](const std::string& what) {
    report.iterations += iteration;
    return std::runtime_error("conjugate gradients broke down at iteration " + std::to_string(iteration) + ": " + what);
  };
  result.residual = best / right_norm;
  std::vector<double> history{result.residual};  // the relative residual per iteration
  auto hopeless = [&] {
    if (!give_up || iteration < give_up->first || (iteration - give_up->first) % give_up->every != 0) return false;
    const int half = iteration / 2;
    const double rate = std::log(result.residual / history[static_cast<std::size_t>(half)]) / (iteration - half);
    return !(rate < 0.0) || iteration + std::log(tolerance / result.residual) / rate > give_up->budget;
  };
  while (result.residual > tolerance && iteration < limit && !hopeless()) {
    ++iteration;
    a.apply(p, q);
    const double curvature = p.dot(q);
    if (!std::isfinite(curvature) || !std::isfinite(rz)) throw breakdown("a number that is not finite (NaN or inf)");
    if (!(curvature > 0.0))
      throw breakdown("the system is not positive definite (p.Ap = " + number_text(curvature) + ")");
    if (!(rz > 0.0)) throw breakdown("the preconditioner is not positive definite (r.Mr = " + number_text(rz) + ")");
    const double alpha = rz / curvature;
    result.x += alpha * p;
    r -= alpha * q;
    const double norm = r.norm();
    if (!std::isfinite(norm)) throw breakdown("the residual is not finite");
    result.residual = norm / right_norm;
    if (give_up) history.push_back(result.residual);
    if (norm < 0.5 * best) {
      best = norm;
      best_at = iteration;
    } else if (iteration - best_at >= kStagnationIterations) {
      throw breakdown("no progress in " + std::to_string(kStagnationIterations) + " iterations (relative residual " +
                      number_text(result.residual) +
                      "): the system is singular or too ill-conditioned for this solver (try --solver direct)");
    }
    z = preconditioner.solve(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  report.iterations += iteration;
  result.converged = result.residual <= tolerance;
  if (!result.converged && budget == 0 && !give_up)
    throw std::runtime_error("conjugate gradients did not converge in " + std::to_string(iteration) +
                             " iterations (relative residual " + number_text(result.residual) + ")");
  return result;
}

using Jacobi = Eigen::DiagonalPreconditioner<double>;
using IncompleteCholesky = Eigen::IncompleteCholesky<double>;

/// Conjugate gradients with incomplete Cholesky; with Jacobi when the
/// incomplete factorization finds no positive pivots even after its
/// shifts (it can, on a positive definite matrix far from diagonally
/// dominant). `before`: what ran first, for the report ("..., then ").
Eigen::VectorXd incomplete_cholesky_cg(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right,
                                       double tolerance, SolveReport& report, const std::string& before = "") {
  const std::string start = before.empty() ? "conjugate gradients, " : before;
  IncompleteCholesky factor(system);
  if (factor.info() == Eigen::Success) {
    report.linear_solver = start + "incomplete Cholesky";
    return conjugate_gradients(system, right, tolerance, report, factor).x;
  }
  report.linear_solver = start + "Jacobi (incomplete Cholesky failed: no positive pivots)";
  return conjugate_gradients(system, right, tolerance, report, Jacobi(system)).x;
}

/// Automatic: Jacobi's preconditioner is set up for free and enough for
/// easy systems (degree 2 on round domains: about 100 iterations), but its
/// iterations grow as 1/h, and domains with features a few cells wide (a
/// mesh's thin ears) make the WEB system's condition reach 1e8 after
/// scaling, where Jacobi needs thousands. So Jacobi while it promises to
/// converge within the budget; then the fallback, from where Jacobi left
/// off.
///
/// Without the unknowns' places: incomplete Cholesky after Jacobi's 4,000
/// iterations (its set-up costs several times a hundred Jacobi iterations).
constexpr GiveUpRule kBeforeIncompleteCholesky{};

/// With them: multilevel Schwarz after the Jacobi iterations its whole
/// solve costs, which fall with the size as its distinct blocks (near the
/// boundary) become fewer per unknown: measured 700 at 2e4 unknowns (the
/// ball, degree 2), 370 at 6e4 (the plate with a hole), 90 at 1e6. Looked
/// at every 25 iterations from 50 on.
GiveUpRule before_schwarz(Eigen::Index unknowns) {
  const double worth = 700.0 * std::sqrt(2e4 / std::max(1.0, static_cast<double>(unknowns)));
  GiveUpRule rule;
  rule.budget = static_cast<int>(std::clamp(worth, 60.0, 1000.0));
  rule.first = std::min(50, rule.budget / 2);
  rule.every = 25;
  return rule;
}

template <class Fallback>
Eigen::VectorXd jacobi_then(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right, double tolerance,
                            SolveReport& report, const GiveUpRule& rule, Fallback&& fallback) {
  report.linear_solver = "conjugate gradients, Jacobi";
  const CgResult jacobi =
      conjugate_gradients(system, right, tolerance, report, Jacobi(system), rule.budget, nullptr, &rule);
  if (jacobi.converged) return jacobi.x;
  return fallback("conjugate gradients, Jacobi (" + std::to_string(report.iterations) + " iterations, too slow), then ",
                  jacobi.x);
}

/// Conjugate gradients with multilevel Schwarz from `guess` (or 0); `before`: what ran first, for the report.
Eigen::VectorXd schwarz_cg(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right, double tolerance,
                           SolveReport& report, const SplinePlacement& placement, const std::string& before,
                           const Eigen::VectorXd* guess = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  const SchwarzPreconditioner schwarz(system, placement);
  report.preconditioner_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.preconditioner_mb = static_cast<double>(schwarz.bytes()) / (1024.0 * 1024.0);
  report.linear_solver = before + schwarz.description();
  return conjugate_gradients(system, right, tolerance, report, schwarz, 0, guess).x;
}

}  // namespace

Eigen::VectorXd solve_symmetric(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right,
                                LinearSolverKind kind, double tolerance, SolveReport& report,
                                const SplinePlacement* placement) {
  check_system(system, right);
  release_freed_memory();  // the assembly's temporaries
  if (kind == LinearSolverKind::Schwarz && !placement)
    throw std::invalid_argument("the Schwarz preconditioner needs the unknowns' places on the grid");
  Eigen::VectorXd x;
  switch (kind) {
    case LinearSolverKind::Schwarz:
      x = schwarz_cg(system, right, tolerance, report, *placement, "conjugate gradients, ");
      break;
    case LinearSolverKind::Direct: {
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(system);
      if (factor.info() != Eigen::Success)
        throw std::runtime_error(
            "the sparse factorization failed: the system is singular (is the basis stable? try --basis web)");
      Eigen::Index pivot = 0;
      const double least = factor.vectorD().minCoeff(&pivot);
      if (!(least > 0.0))
        throw std::runtime_error("the sparse factorization found the pivot " + number_text(least) +
                                 ": the system is not positive definite");
      x = factor.solve(right);
      report.linear_solver = "sparse LDLT (AMD ordering)";
      report.iterations = 1;
      break;
    }
    case LinearSolverKind::ConjugateGradient: x = incomplete_cholesky_cg(system, right, tolerance, report); break;
    case LinearSolverKind::JacobiConjugateGradient:
      x = conjugate_gradients(system, right, tolerance, report, Jacobi(system)).x;
      report.linear_solver = "conjugate gradients, Jacobi";
      break;
    case LinearSolverKind::Automatic:
      if (placement)
        x = jacobi_then(system, right, tolerance, report, before_schwarz(system.rows()),
                        [&](const std::string& before, const Eigen::VectorXd& guess) {
                          return schwarz_cg(system, right, tolerance, report, *placement, before, &guess);
                        });
      else
        x = jacobi_then(system, right, tolerance, report, kBeforeIncompleteCholesky,
                        [&](const std::string& before, const Eigen::VectorXd&) {
                          return incomplete_cholesky_cg(system, right, tolerance, report, before);
                        });
      break;
  }
  if (!x.allFinite()) throw std::runtime_error("the solve produced non-finite coefficients");
  return x;
}

}  // namespace sage::solver
