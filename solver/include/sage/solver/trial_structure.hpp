#pragma once
// The trial functions of the solver: u = u0 + sum_j c_j v_j with
//
//     v_j = scale B_j - transport . grad B_j,
//
// B_j the WEB B-splines and scale, transport, u0 fields built once from the
// problem (expressions; their gradients come from tuples).
//
// Dirichlet structure (weak route for Neumann and Robin parts):
//     scale = omega_D, transport = 0, u0 = g~.
//
// Rvachev's structure for Robin and Neumann parts (structure route): with
// P = g~ + omega_D Phi, Phi = sum c_j B_j, and W a field vanishing on the
// Dirichlet parts and the structured parts, normalized there so that
// grad W = -n (n the outward normal; W >= 0 inside), D1 = grad W . grad,
// and V = localized_weight(W, omega_R, band) (V = W (1 - omega_R / band)_+^m,
// omega_R the structured parts' own field: V = 0 and grad V = grad W on the
// parts, V = 0 from omega_R = band on):
//
//     u = P - V D1(P) + V (beta P - h) / k.
//
// On a structured part V = 0, D1(V) = |grad W|^2 = 1, so u = P and
// D1(u) = D1(P) - D1(P) + (beta P - h) / k = (beta u - h) / k; since
// D1(u) = -du/dn there, this is k du/dn + beta u = h, for every Phi. On a
// Dirichlet part V = 0 and omega_D = 0, so u = g~. Written per spline:
//     scale = omega_D (1 + V beta / k) - V D1(omega_D),
//     transport = V omega_D grad W,
//     u0 = g~ (1 + V beta / k) - V D1(g~) - V h / k.
// Why the cut: grad u holds V times second derivatives of Phi, which
// degree-n splines approximate to O(h^(n-1)) only; with V = W = O(1) inside
// the route loses an order.
//
// With the cut, Rvachev's second function: u += M Q, Q = sum q_i B_i on
// the B-splines that meet the band, M = V omega_R. M vanishes to second
// order on the structured parts (and is 0 beyond the band), so the
// condition still holds for every coefficient vector, and M Q absorbs V
// times the Robin defect of the solution, which P alone could only follow
// with a layer of the band's width. With the band ~ h^(2/3) of the solver
// (poisson.hpp) the rates are those of degree n (README;
// bench/robin_structure_study in 1D).
//
// W: omega_R, the R0-conjunction of the named Neumann and Robin parts'
// oriented selectors, each normalized (FORMULAS.md); with Dirichlet parts
// W = omega_R omega_D^2 / (omega_D^2 + omega_R^2), which is still
// normalized on the structured parts but vanishes to second order on the
// Dirichlet parts: a first-order zero there (W = omega_D R0-and omega_R,
// say) would make the structure impose D1(u) = (beta g - h) / k on the
// Dirichlet parts as well, and the solution would not converge. W is
// singular where omega_D and omega_R vanish together: the parts must not
// meet. Without Dirichlet parts and without named weak parts, W is the
// normalized domain field. beta and h off the boundary: the part's
// data, or transfinite interpolation of the parts' data when they differ.
// Boundary left to the default part (no selector) keeps its condition
// weakly: the Galerkin equations keep the boundary integrals either way.

#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/problem.hpp>

#include <string>
#include <vector>

namespace sage::solver {

/// Weak: Neumann and Robin conditions by boundary integrals only.
/// Structure: Rvachev's structure as well (needs degree >= 2).
enum class RobinRoute { Weak, Structure };

/// Parses "weak" or "structure"; throws std::invalid_argument.
RobinRoute parse_robin_route(const std::string& text);

struct TrialStructure {
  Expr scale;                          // omega_D for the Dirichlet structure
  std::vector<Expr> transport;         // empty for the Dirichlet structure, else one per axis
  Expr offset;                         // u0
  Expr robin_weight;                   // V, the cut-off W (0 for the Dirichlet structure)
  Expr robin_field;                    // omega_R, for the checks of the solver (0 for the Dirichlet structure)
  Expr second_weight = 0.0;            // the second function's multiplier (0: no second function)
  bool joined_with_dirichlet = false;  // W built with omega_D (singular where omega_D and omega_R both vanish)
  bool structured() const { return !transport.empty(); }
  bool second_function() const { return !second_weight.is_constant(0.0); }
};

TrialStructure dirichlet_trial(const BoundaryStructure& structure);

/// W cut off at distance band from the structured parts, measured by
/// their normalized field `distance`: W (1 - distance / band)_+^power.
/// Where distance = W near the parts it is band psi(W / band) with psi(s) =
/// s (1 - s)^power: psi(0) = 0 and psi'(0) = 1 keep W normalized on them;
/// the cut-off is C^(power - 1). band <= 0 returns W.
Expr localized_weight(const Expr& w, const Expr& distance, double band, int power);

/// The structure route. Requires structure.has_weak_parts. band > 0 cuts W
/// off (localized_weight) with the given power (>= 2, so that the cut W is
/// C^1; 3 or more makes it C^2, as the solver's second derivatives of u
/// assume) and adds the second function; band <= 0 keeps the global W
/// and no second function.
TrialStructure robin_trial(const PoissonProblem& problem, const BoundaryStructure& structure, double band = 0.0,
                           int power = 3);

}  // namespace sage::solver
