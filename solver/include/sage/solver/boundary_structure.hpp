#pragma once
// The Dirichlet solution structure of a boundary split, shared by the
// physics: omega_D, which vanishes exactly on the parts whose value is
// prescribed, g~, which extends those values into the domain (poisson.hpp),
// and the oriented selectors of the parts. Poisson splits its boundary by
// the kind of each part (problem.hpp), elasticity once per displacement
// component by the parts that fix it (elasticity.hpp).

#include <sage/expression/expression.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace sage::solver {

/// The boundary as the structure sees it: parts told apart by selectors
/// (problem.hpp), each with a prescribed value or a weak condition.
struct BoundarySplit {
  struct Part {
    std::string name;
    Expr selector;              // zero on this part (unused for the rest)
    std::optional<Expr> value;  // prescribed (Dirichlet data, a fixed component); none: a weak condition
    bool robin = false;         // weak with a Robin coefficient not 0 (no pure Neumann problem then)
  };
  int dimension = 2;
  Expr field;  // the domain's omega (>= 0 inside): omega_D when the whole boundary is prescribed
  std::vector<Part> parts;
  Part rest;  // the boundary no part claims
  /// False when the problem gives no condition for the rest
  /// (PoissonProblem::rest_given).
  bool rest_given = true;
  /// Replaces the g~ built from the parts' values (PoissonProblem::dirichlet_extension).
  std::optional<Expr> extension;
};

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

/// Rvachev's transfinite interpolation of data g_k given on pieces where
/// the fields omega_k vanish:  sum_k g_k prod_{l != k} omega_l^2 / sum_m
/// prod_{l != m} omega_l^2. Equals g_k on piece k (away from the points
/// where two pieces meet), smooth elsewhere.
Expr transfinite_interpolation(const std::vector<Expr>& fields, const std::vector<Expr>& data);

/// `interior` is a point inside the domain, where the selectors' signs are
/// read. With `dirichlet_structure` false (Dirichlet conditions by
/// Nitsche's method) omega_D and g~ are left at 1 and 0. Throws
/// std::invalid_argument for splits this solver does not pose (for the
/// structure, a prescribed rest given beside weak parts: omega_D would need
/// the rest's own field; a selector that vanishes at the interior point).
BoundaryStructure boundary_structure(const BoundarySplit& split, const std::array<double, 3>& interior,
                                     bool dirichlet_structure = true);

}  // namespace sage::solver
