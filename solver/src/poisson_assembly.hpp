#pragma once
// The Galerkin assembly of the Poisson solver (poisson.hpp for the
// equations): cell by cell on all cores, the matrix of the relevant
// B-splines in the band layout of extended_system.hpp and their loads,
// with the boundary integrals of Neumann and Robin parts and Nitsche's
// terms of weak Dirichlet parts; for the Robin structure's second function
// its own rows, and for pure Neumann problems the rows of (v_i, 1).

#include "discretization.hpp"

#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/problem.hpp>

#include <vector>

namespace sage::solver {

template <int D>
struct PoissonAssemblyInput {
  const PoissonProblem& problem;
  const BoundaryStructure& structure;
  const SplineBasis<D>& basis;
  const std::vector<std::size_t>& candidates;  // ClassifiedGrid::candidates
  const std::vector<CellKind>& kinds;          // per grid cell
  const CellRules<D>& rules;
  const Tape& trial;  // roots: scale, u0, transport per axis (structure route), second weight (trial_structure.hpp)
  bool structured = false;      // the Robin structure
  bool second = false;          // with its second function
  bool weak_dirichlet = false;  // Nitsche's terms on Dirichlet parts
  int inside_points = 0;        // Gauss points per direction of inside cells
  double nitsche_penalty = 0;   // sigma h
};

struct PoissonAssembly {
  std::vector<double> band, load;                   // P's matrix (band layout) and load, per relevant B-spline
  std::vector<double> second_band, coupling_band;   // Q's rows against Q and against P (second function)
  std::vector<double> second_load;                  // Q's load
  std::vector<double> mean_load, second_mean_load;  // pure Neumann: (v_i, 1)
  double data_size = 0.0;                           // pure Neumann: (|f|, 1) + <|h|, 1>
  double offset_mean = 0.0;                         // pure Neumann: (u0, 1)
};

/// Throws std::invalid_argument, naming a point, when the rest must be
/// empty and a surface point belongs to no named part.
template <int D>
PoissonAssembly assemble_poisson(const PoissonAssemblyInput<D>& in);

}  // namespace sage::solver
