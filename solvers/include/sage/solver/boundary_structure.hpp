#pragma once
// The Dirichlet solution structure of a problem: omega_D, which vanishes
// exactly on the Dirichlet parts, and g~, which extends the Dirichlet data
// into the domain (poisson.hpp), and the oriented selectors of the parts.

#include <sage/solver/problem.hpp>

#include <array>
#include <vector>

namespace sage::solver {

struct BoundaryStructure {
  Expr dirichlet_weight;        // omega_D (1 when there is no Dirichlet part)
  Expr dirichlet_extension;     // g~ (0 when there is no Dirichlet part)
  std::vector<Expr> selectors;  // per named part, >= 0 in the domain
  bool has_weak_parts = false;
  bool pure_neumann = false;  // no Dirichlet part, beta = 0 everywhere: u is fixed up to a constant
  // The rest was not given and the structure leaves it out of omega_D:
  // every boundary point must belong to a named part.
  bool rest_must_be_empty = false;
};

/// True when a and b are the same expression node or equal constants
/// (data given once for several parts).
bool same_expression(const Expr& a, const Expr& b);

/// `interior` is a point inside the domain, where the selectors' signs are
/// read. With `dirichlet_structure` false (Dirichlet conditions by
/// Nitsche's method) omega_D and g~ are left at 1 and 0. Throws
/// std::invalid_argument for problems this solver does not pose (for the
/// structure, a Dirichlet rest given beside weak parts: omega_D would need
/// the rest's own field; a selector that vanishes at the interior point).
BoundaryStructure boundary_structure(const PoissonProblem& problem, const std::array<double, 3>& interior,
                                     bool dirichlet_structure = true);

}  // namespace sage::solver
