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
};

/// `interior` is a point inside the domain, where the selectors' signs are
/// read. Throws std::invalid_argument for problems this solver does not
/// pose (a Dirichlet rest beside weak parts; a selector that
/// vanishes at the interior point).
BoundaryStructure boundary_structure(const PoissonProblem& problem, const std::array<double, 3>& interior);

}  // namespace sage::solver
