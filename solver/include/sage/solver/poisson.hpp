#pragma once
// The meshfree Poisson solver (problem.hpp for the equations):
//
//     u = omega_D sum_i c_i B_i^web + g~
//
// omega_D vanishes on the Dirichlet parts (the domain field itself when the
// whole boundary is Dirichlet, else the R0-conjunction of the oriented
// selectors of the Dirichlet parts), g~ extends the Dirichlet data
// (transfinite interpolation when it is given piece by piece), B^web is the
// spline space of web_basis.hpp. Neumann and Robin conditions enter weakly
// through the surface rule of domain_quadrature.hpp. Galerkin:
//
//     sum_j c_j [ (k grad v_j, grad v_i) + <beta v_j, v_i>_R ]
//         = (f, v_i) - (k grad u0, grad v_i) + <h - beta u0, v_i>_{N,R}
//
// with v_i = omega_D B_i^web and u0 = g~, assembled cell by cell on all
// cores and solved with conjugate gradients (LinearSolverKind) or a sparse
// LDLT. With RobinRoute::Structure the trial functions v_i and u0 are those
// of Rvachev's structure (trial_structure.hpp), which satisfy the Neumann
// and Robin conditions of the named parts identically; the equations are
// the same (the boundary integrals stay: they are the variational form).
//
// Pure Neumann problems (no Dirichlet part, beta = 0 on every part): u is
// then fixed only up to a constant. The data must be compatible,
// (f, 1) + <h, 1> = 0 to quadrature accuracy (else std::invalid_argument);
// the remaining quadrature-level discrepancy is removed from the load
// (as if f were shifted by a constant), one unknown's diagonal is doubled
// (which makes the matrix definite and, for compatible data, pins that
// unknown to 0 without changing the solution), and the constant is then
// fixed by zero mean, (u, 1) = 0. The constant function is the coefficient
// vector of ones in both bases (partition of unity; the WEB extension
// keeps constants).

#include <sage/solver/domain_probe.hpp>
#include <sage/solver/domain_quadrature.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/mesh_domain.hpp>
#include <sage/solver/problem.hpp>
#include <sage/solver/solver_options.hpp>
#include <sage/solver/trial_structure.hpp>
#include <sage/solver/web_basis.hpp>
#include <sage/tape/evaluator.hpp>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sage::solver {

template <int D>
class PoissonSolution {
 public:
  SolveReport report;
  SplineBasis<D> basis;
  Eigen::VectorXd spline_coefficients;  // of the relevant B-splines (E c)
  Eigen::VectorXd second_coefficients;  // the structure's second function Q (empty without one)
  /// Roots: scale, u0, then transport per axis for the structure route,
  /// then V W when it has a second function (trial_structure.hpp).
  std::shared_ptr<const Tape> structure;
  std::shared_ptr<const Tape> domain;  // omega (not for mesh domains)
  /// Mesh domains: the triangles against the grid; Probe::omega is then the
  /// signed distance to them, clamped at kMeshDistanceBand cell widths.
  std::shared_ptr<const MeshDomain> mesh;
  QuadratureDump quadrature;  // when SolverOptions::keep_quadrature

  /// Evaluates u (and grad u) at points; one per thread.
  class Probe {
   public:
    explicit Probe(const PoissonSolution& solution);
    /// u at x; writes grad u to `gradient` when not null.
    double at(const double* x, double* gradient = nullptr);
    double omega(const double* x) { return domain_.at(x); }

   private:
    const PoissonSolution* solution_;
    LocalSplines<D> local_;  // reused: no allocation per point
    Evaluator<Tuple<D, 1>> structure_;
    DomainProbe<D> domain_;
  };
};

/// Solves the problem. Throws std::invalid_argument for a problem that
/// cannot be posed (pure Neumann, Dirichlet default with weak parts; for
/// the structure route: degree 1, structured parts meeting Dirichlet parts,
/// a part's field vanishing inside the domain) and
/// std::runtime_error when the grid cannot carry it (empty domain, too
/// coarse) or the solve fails.
template <int D>
PoissonSolution<D> solve_poisson(const PoissonProblem& problem, const SolverOptions& options);

}  // namespace sage::solver
