#pragma once
// Static linear elasticity on an implicit domain (or a mesh's solid), the
// vector counterpart of poisson.hpp, on the same grid, quadrature, WEB
// basis and linear solvers (discretization.hpp in solver/src):
//
//     -div sigma(u) = f                     in the domain {omega >= 0}
//     u_c = g_c  for the chosen components  on displacement parts
//     sigma n = t,  or  sigma n = -p n      on traction and pressure parts
//
// (elastic_material.hpp for sigma). Boundary not claimed by a named part
// belongs to the rest (traction-free unless the problem says otherwise); a
// displacement part leaves its other components traction-free (a roller).
//
// Method: u_c = w_c sum_j c_jc B_j^web + g~_c per component c, and
// Galerkin on the strain energy:
//
//     (sigma(u), eps(v)) = (f, v) + <t, v>_traction
//
// Displacement conditions, the same two routes as for Poisson:
//   weak (default): w_c = 1, g~_c = 0, and Nitsche's terms per fixed
//     component, with the traction t_c(u) = (sigma(u) n)_c:
//         - <t_c(u), v_c> - <u_c, t_c(v)> + <gamma u_c, v_c>
//         = - <g_c, t_c(v)> + <gamma g_c, v_c>,
//     gamma = penalty (2 mu + lambda) / h (2 mu + lambda bounds |sigma(v) n|^2
//     over the energy density, so the penalty of poisson.hpp is stable);
//   structure: w_c = omega_D of the parts that fix component c, g~_c the
//     transfinite extension of their data (boundary_structure.hpp).
//
// A body whose displacement conditions leave rigid motions free (no
// displacement part at all, or rollers along one direction) is solved up
// to those motions: the loads must do no work on them (net force and
// moment zero, to kLoadBalanceTolerance relative to the loads' size), the
// quadrature-level remainder is removed from the load, and the free
// motions are fixed by making the solution L2-orthogonal to them. Rigid
// motions are linear, so their coefficients in the basis are their values
// at the B-splines' Greville points.

#include <sage/solver/domain_probe.hpp>
#include <sage/solver/elastic_material.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/mesh_domain.hpp>
#include <sage/solver/problem_domain.hpp>
#include <sage/solver/solver_options.hpp>
#include <sage/tape/evaluator.hpp>

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sage::solver {

struct ElasticPart {
  std::string name;
  Expr selector;  // zero on this part (unused for the rest)
  /// The fixed components and their values (a roller fixes one).
  std::array<std::optional<Expr>, 3> displacement;
  std::array<Expr, 3> traction{Expr(0.0), Expr(0.0), Expr(0.0)};
  Expr pressure = 0.0;  // adds -pressure n to the traction
  bool loaded = false;  // a traction or pressure was given
  bool fixes(int component) const { return displacement[static_cast<std::size_t>(component)].has_value(); }
  bool fixed() const { return fixes(0) || fixes(1) || fixes(2); }
};

struct ElasticityProblem {
  ProblemDomain domain;
  ElasticMaterial material;
  std::array<Expr, 3> body_force{Expr(0.0), Expr(0.0), Expr(0.0)};
  std::vector<ElasticPart> parts;
  ElasticPart rest;                          // traction-free unless given
  std::optional<std::array<Expr, 3>> exact;  // exact displacement, for error norms
};

/// Largest relative net load on a free rigid motion that is accepted: the
/// surface rule on curved faces is not exact (the net force of a pressure
/// on a sphere came to 1.6e-6 of the loads at h = a / 2.5), while a load
/// that does not balance is off by order 1.
constexpr double kLoadBalanceTolerance = 1e-4;

template <int D>
class ElasticitySolution {
 public:
  SolveReport report;  // with its `elasticity` results
  ElasticMaterial material;
  SplineBasis<D> basis;
  Eigen::MatrixXd spline_coefficients;    // relevant B-splines x components (E c)
  std::shared_ptr<const Tape> structure;  // roots w_c, g~_c per component (structure route), else none
  std::shared_ptr<const Tape> domain;     // omega (not for mesh domains)
  std::shared_ptr<const MeshDomain> mesh;
  QuadratureDump quadrature;

  /// Evaluates u and its gradient at points; one per thread.
  class Probe {
   public:
    explicit Probe(const ElasticitySolution& solution);
    /// u at x into `displacement` (D values); the gradient g[a * D + b] =
    /// d u_a / d x_b into `gradient` when not null.
    void at(const double* x, double* displacement, double* gradient = nullptr);
    /// The stress at x in VTK's layout (elastic_material.hpp).
    std::array<double, 6> stress(const double* x);
    double omega(const double* x) { return domain_.at(x); }

   private:
    const ElasticitySolution* solution_;
    LocalSplines<D> local_;
    std::optional<Evaluator<Tuple<D, 1>>> structure_;
    DomainProbe<D> domain_;
  };
};

/// Solves the problem (SolverOptions' Robin fields do not apply). Throws
/// std::invalid_argument for a problem that cannot be posed (material out
/// of range, a part both fixed and loaded, loads that do not balance on a
/// free body) and std::runtime_error when the grid cannot carry it.
template <int D>
ElasticitySolution<D> solve_elasticity(const ElasticityProblem& problem, const SolverOptions& options);

}  // namespace sage::solver
