#pragma once
// The checks of a problem's data before assembly (data_error.hpp): every
// formula the solver reads is evaluated at the quadrature points where it
// is read, and the first point (in the order of the cells) where one is not
// finite, or breaks its rule (k > 0, beta >= 0), throws DataError naming it.
//
//   volume points: the source, body force and exact solution; the
//     conductivity; the Dirichlet data where the structure route extends
//     them into the domain (g~ reads every part's value everywhere);
//   surface points: each part's data on the points it claims (nearest
//     selector, as the assembly decides), the selectors themselves, and the
//     conductivity (Nitsche's terms read it there).
//
// Constant data are checked once, not at every point.

#include "discretization.hpp"

#include <sage/solver/data_error.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/problem.hpp>

#include <string>
#include <vector>

namespace sage::solver {

/// What a datum must be, beyond finite and below kLargestDatum in magnitude
/// (data_error.hpp). A Robin coefficient must also stay below
/// kLargestBiotNumber k / h, k the conductivity at the point.
enum class DataNeed { Finite, Positive, RobinCoefficient };

/// One formula of a problem's data, its JSON pointer and what it must be.
struct DatumRule {
  std::string pointer;
  Expr formula;
  DataNeed need = DataNeed::Finite;
};

/// Where a problem's data are read.
struct DataRules {
  std::vector<DatumRule> volume;              // at the volume points
  std::vector<DatumRule> everywhere;          // at the volume and the surface points
  std::vector<DatumRule> selectors;           // of the named parts, in order; at the surface points
  std::vector<std::vector<DatumRule>> parts;  // per named part, then the rest: at the points the part claims
  Expr conductivity = 1.0;                    // k, for the Robin coefficients' limit
};

/// A Poisson problem's data. `dirichlet_inside`: the Dirichlet structure
/// route, whose extension reads the Dirichlet values throughout the domain.
DataRules poisson_data_rules(const PoissonProblem& problem, bool dirichlet_inside);

/// An elasticity problem's data. `fixed_inside`: the structure route (as above, for fixed components).
DataRules elasticity_data_rules(const ElasticityProblem& problem, bool fixed_inside);

/// Throws DataError at the first point where a datum breaks its rule.
template <int D>
void check_data(const DataRules& rules, const CellRules<D>& cells, double cell_width);

}  // namespace sage::solver
