#pragma once
// A Poisson problem on an implicit domain (problem_domain.hpp), all data
// as expressions of x, y (, z):
//
//     -div(k grad u) = f              in the domain {omega >= 0}
//     u = g                           on Dirichlet parts
//     k du/dn = h                     on Neumann parts
//     k du/dn + beta u = h            on Robin parts   (n the outward normal)
//
// Boundary parts are told apart by selectors: a field that vanishes on its
// part (the field of the CSG primitive that contributes it, say). A
// boundary point belongs to the part whose selector is nearest zero there,
// or to `rest` when no selector vanishes. Selectors may have either sign
// inside the domain; the solver orients them.

#include <sage/expression/expression.hpp>
#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/problem_domain.hpp>

#include <optional>
#include <string>
#include <vector>

namespace sage::solver {

enum class BoundaryKind { Dirichlet, Neumann, Robin };

struct BoundaryPart {
  std::string name;
  Expr selector;  // zero on this part (unused for the rest of the boundary)
  BoundaryKind kind = BoundaryKind::Dirichlet;
  Expr value = 0.0;  // Dirichlet data g
  Expr beta = 0.0;   // Robin coefficient (0 for Neumann)
  Expr flux = 0.0;   // h
};

struct PoissonProblem {
  ProblemDomain domain;
  Expr conductivity = 1.0;  // k > 0
  Expr source = 0.0;        // f
  std::vector<BoundaryPart> parts;
  BoundaryPart rest;  // the boundary no part claims
  /// False when the problem gives no condition for the rest (a problem
  /// file without "default"): the rest is then Dirichlet u = 0, except
  /// with the Dirichlet structure beside Neumann or Robin parts, where the
  /// named parts must claim the whole boundary (the solver checks that at
  /// every surface point).
  bool rest_given = true;
  std::optional<Expr> exact;  // exact solution, for error norms
  /// Overrides the Dirichlet extension g~ built from the parts' data (for
  /// tests and callers that have a better extension of the boundary data).
  std::optional<Expr> dirichlet_extension;
};

/// The problem's boundary for the Dirichlet structure (boundary_structure.hpp):
/// Dirichlet parts prescribe their value, Neumann and Robin parts are weak.
BoundarySplit boundary_split(const PoissonProblem& problem);

}  // namespace sage::solver
