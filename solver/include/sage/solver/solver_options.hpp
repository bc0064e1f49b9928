#pragma once
// What the solvers (poisson.hpp, elasticity.hpp) share: their options, the
// linear solvers and Dirichlet routes to choose from, and the report of a
// solve (sizes, stage times, errors, elasticity's results).

#include <sage/solver/trial_structure.hpp>
#include <sage/solver/web_basis.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace sage::solver {

/// Direct: sparse LDLT (AMD ordering). ConjugateGradient: preconditioned
/// with incomplete Cholesky; JacobiConjugateGradient: with the diagonal
/// (cheaper to set up, more iterations); Schwarz: with multilevel additive
/// Schwarz on cell blocks (schwarz_preconditioner.hpp: iterations nearly
/// independent of h and of the cuts). Automatic: conjugate gradients with
/// incomplete Cholesky in 2D; in 3D Jacobi, then Schwarz when Jacobi would
/// take longer than Schwarz's whole solve (linear_solve.cpp); Direct for
/// the Robin structure with its second function.
enum class LinearSolverKind { Automatic, Direct, ConjugateGradient, JacobiConjugateGradient, Schwarz };

/// How Dirichlet conditions are imposed. Weak: Nitsche's method, with the
/// WEB B-splines as trial functions and the symmetric terms
///
///     - <k dn u, v>_D - <u, k dn v>_D + <sigma k u, v>_D   (left)
///     - <g, k dn v>_D + <sigma k g, v>_D                    (right)
///
/// on the Dirichlet parts, sigma = penalty / h. The WEB extension keeps
/// every B-spline's share of the domain away from slivers, so a penalty of
/// the inverse-estimate size c (n + 1)^2 / h is stable for any cut.
/// Structure: u = omega_D Phi + g~ (this header's top). Automatic: weak,
/// except with the Robin structure, which is built on the Dirichlet
/// structure, and with plain weighted B-splines (BasisKind::Weighted), whose
/// slivers of support no penalty can bound.
enum class DirichletRoute { Automatic, Weak, Structure };

/// Parses "auto", "weak" or "structure"; throws std::invalid_argument.
DirichletRoute parse_dirichlet_route(const std::string& text);

/// Nitsche's penalty factor c of c (n + 1)^2 (the penalty is that over h).
constexpr double kNitschePenaltyFactor = 4.0;

/// The penalty used: `requested` when positive, else kNitschePenaltyFactor (degree + 1)^2.
double nitsche_penalty(double requested, int degree);

struct SolverOptions {
  int degree = 3;            // 1 .. kMaxDegree
  double cell_width = 0.05;  // h of the background grid
  BasisKind basis = BasisKind::Web;
  RobinRoute robin = RobinRoute::Weak;  // Structure needs degree >= 2
  DirichletRoute dirichlet = DirichletRoute::Automatic;
  double nitsche_penalty = 0.0;  // sigma h of the weak route; 0: nitsche_penalty(0, degree)
  // Structure route: the multiplier W is cut off at robin_band_width(), robin_band L (h / L)^(2/3) from
  // the structured parts (L the longest side of the box), and the structure gets its second function
  // there; 0 keeps the global W and no second function. robin_band_power: the cut-off's power (>= 2).
  double robin_band = 1.0;
  int robin_band_power = 8;
  LinearSolverKind linear_solver = LinearSolverKind::Automatic;
  bool estimate_condition = true;
  int quadrature_points = 0;     // per direction; 0: degree + 2
  int max_subdivision = 4;       // cut-cell subdivisions (domain_quadrature.hpp)
  double cg_tolerance = 0.0;     // relative residual; 0: automatic_cg_tolerance()
  bool keep_quadrature = false;  // fill PoissonSolution::quadrature (to show users the rule)
  double memory_limit_mb = 0.0;  // refuse solves estimated above it (memory_estimate.hpp); 0: what is available
};

/// The structure route's cut-off distance (SolverOptions::robin_band).
double robin_band_width(double fraction, double cell_width, double longest_side);

/// The quadrature points used, for display: 3 coordinates per point (z = 0
/// in 2D), the weight, and 1 for surface points, 0 for volume points.
struct QuadratureDump {
  std::vector<double> coordinates, weights, on_surface;
};

struct StageSeconds {
  double field = 0, classification = 0, quadrature = 0, assembly = 0, solve = 0, condition = 0, errors = 0;
  double total() const { return field + classification + quadrature + assembly + solve + condition + errors; }
};

/// What an elasticity solve finds beyond the shared report.
struct ElasticityResults {
  double strain_energy = 0.0;  // (sigma(u_h), eps(u_h)) / 2
  /// The largest von Mises stress at the volume quadrature points, and where.
  double max_von_mises = 0.0;
  std::array<double, 3> max_von_mises_at{};
  int free_rigid_motions = 0;          // rigid motions no displacement condition holds
  std::optional<double> load_balance;  // with free motions: their net load, relative
};

/// The report of a solve, of either physics.
struct SolveReport {
  std::size_t cells = 0, cells_inside = 0, cells_cut = 0;
  std::size_t relevant_splines = 0, inner_splines = 0, outer_splines = 0, unknowns = 0, nonzeros = 0;
  std::size_t second_unknowns = 0;  // of the structure's second function (included in unknowns)
  std::size_t volume_points = 0, surface_points = 0;
  // Fallbacks of the cut-cell rule (domain_quadrature.hpp): sub-boxes filled with sign-masked
  // Gauss points, the points they gave, and sub-boxes whose surface no rule resolved.
  std::size_t masked_boxes = 0, masked_points = 0, unresolved_surface_boxes = 0;
  std::size_t unbroken_boxes = 0;     // mesh cells whose base rule has no breaks (mesh_domain.hpp)
  std::size_t cut_volume_points = 0;  // volume points in cut cells (of volume_points)
  std::string linear_solver;
  std::string dirichlet_route;            // "weak (Nitsche)" or "structure"
  std::optional<double> nitsche_penalty;  // sigma h, when Dirichlet conditions were imposed weakly
  int iterations = 0;                     // 1 for a direct solve
  double cg_tolerance = 0.0;              // relative residual used (CG only)
  std::optional<double> robin_band;       // structure route: the multiplier's cut-off distance used (0: global W)
  double condition = std::numeric_limits<double>::quiet_NaN();         // of the system matrix
  double scaled_condition = std::numeric_limits<double>::quiet_NaN();  // after Jacobi scaling
  double memory_estimate_mb = 0.0;                                     // memory_estimate.hpp, from the classified grid
  double preconditioner_mb = 0.0;                                      // held by the multilevel Schwarz preconditioner
  double preconditioner_seconds = 0.0;                                 // its set-up, wall clock (of seconds.solve)
  StageSeconds seconds;                                                // wall clock
  StageSeconds cpu_seconds;                                            // process CPU time (all threads)
  /// Relative errors when the problem has an exact solution: L2 (|u - u_h| / |u|),
  /// and for Poisson the H1 seminorm (|u - u_h|_1 / |u|_1), for elasticity
  /// the energy norm of u - u_h over that of u.
  std::optional<double> l2_error, h1_error, energy_error;
  /// Pure Neumann Poisson problems: |(f, 1) + <h, 1>| / ((|f|, 1) + <|h|, 1>).
  std::optional<double> neumann_compatibility;
  std::optional<ElasticityResults> elasticity;  // elasticity solves
};

/// How far from a mesh domain's surface its `omega` output is the exact
/// signed distance, in cell widths (beyond: +-that).
constexpr double kMeshDistanceBand = 2.0;

/// Largest relative compatibility defect accepted for pure Neumann data.
constexpr double kNeumannCompatibilityTolerance = 1e-6;

/// The default relative residual of conjugate gradients: it follows the
/// discretization, not round-off. The L2 error of degree n is O(h^(n+1)),
/// and a relative residual r leaves an algebraic error of up to about
/// kappa r, kappa ~ (L / h)^2 after Jacobi scaling; so, with L the longest
/// side of the box,
///
///     tolerance = (h / L)^(n+3), clamped to [1e-12, 1e-6].
///
/// The errors of the convergence tests stay equal to 3 digits (the weak
/// Robin square, whose error constant is small, changed with (h/L)^(n+1));
/// the ball with 18 cells, degree 3, needs 86 Jacobi iterations instead
/// of 213 for 1e-12. A solution inside the spline space (patch tests) has
/// no discretization error to hide behind: solve it with 1e-12.
double automatic_cg_tolerance(double cell_width, double longest_side, int degree);

}  // namespace sage::solver
