#pragma once
// The Galerkin assembly of linear elasticity (elasticity.hpp for the
// equations), by the shared cell loop (cell_loop.hpp): per cell the
// stiffness of D (n + 1)^D unknowns, component-major, with the tractions
// and pressures of loaded parts and Nitsche's terms of fixed components;
// one band per pair of components on or below the diagonal.

#include "discretization.hpp"

#include <sage/solver/elasticity.hpp>

#include <vector>

namespace sage::solver {

template <int D>
struct ElasticityAssemblyInput {
  const ElasticityProblem& problem;
  const SplineBasis<D>& basis;
  const std::vector<std::size_t>& candidates;  // ClassifiedGrid::candidates
  const std::vector<CellKind>& kinds;          // per grid cell
  const CellRules<D>& rules;
  const Tape* structure = nullptr;  // roots w_c, g~_c per component (the structure route), else none
  bool weak = false;                // Nitsche's terms on fixed components
  int inside_points = 0;            // Gauss points per direction of inside cells
  double nitsche_penalty = 0.0;     // gamma h / (2 mu + lambda)
};

struct ElasticityAssembly {
  std::vector<std::vector<double>> bands;  // per component pair (c, d), d <= c, at block_pair(c, d) (cell_loop.hpp)
  std::vector<std::vector<double>> loads;  // per component
};

template <int D>
ElasticityAssembly assemble_elasticity(const ElasticityAssemblyInput<D>& in);

}  // namespace sage::solver
