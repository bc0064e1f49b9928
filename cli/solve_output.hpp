#pragma once
// What `sage solve` shares between its physics (command_solve.cpp for
// Poisson, solve_elasticity.cpp): the parsed command, the output grid, the
// domain field on it, and the grid cells that cover the domain.

#include "commands.hpp"

#include <sage/problems/problem_file.hpp>

#include <sage/output/clipped_grid.hpp>
#include <sage/solver/mesh_domain.hpp>

#include <sage/sampling/grid.hpp>
#include <sage/solver/solver_options.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sage::cli {

using problems::ProblemFile;

struct SolveCommand {
  std::string problem_path, output_path, quadrature_path, basis = "web", linear_solver = "auto", grid, robin,
                                                          dirichlet = "auto";
  solver::SolverOptions options;
  std::optional<int> cells;
  std::optional<double> h;
  bool quiet = false;
};

/// The output grid: --grid, else 4 points per background cell (at most 401
/// per axis in 2D, 2 and 97 in 3D), over the problem's box.
Grid output_grid(const SolveCommand& command, const solver::PoissonProblem& problem, double h);

/// Fields of more instructions than this get their output omega from grid
/// sampling with far-field patches (pruned_grid.hpp), within
/// kOutputOmegaTolerance of the diagonal: a polygon's R0 tree of 718 edges
/// takes 3 s at the 160,801 points of 128 cells, exactly.
constexpr std::size_t kLargeField = 2000;
constexpr double kOutputOmegaTolerance = 1e-10;

/// True when omega of `domain` is sampled (a large field); then fills `omega`.
bool sample_large_omega(const std::shared_ptr<const Tape>& domain, const Grid& grid, std::vector<double>& omega);

/// The part of the output grid in the domain: omega at the grid's points
/// (large fields by sample_large_omega, others by the domain's probe),
/// then the cells clipped at omega = 0 (output/clipped_grid.hpp), where
/// the solution is sampled.
template <int D>
output::ClippedGrid clipped_output(const Grid& grid, const std::shared_ptr<const Tape>& domain,
                                   const std::shared_ptr<const solver::MeshDomain>& mesh, double cell_width);

/// The summary's last line: what the solution file holds.
void print_written(const std::string& path, const output::ClippedGrid& part, const Grid& grid);

/// Writes the quadrature points when asked (--quadrature-points).
void write_quadrature(const SolveCommand& command, const solver::QuadratureDump& quadrature);

/// The lines of the summary that both physics print: cells, points,
/// memory, the output omega's source, unknowns, solver. (The first line
/// and the results are theirs.)
void print_solve_report(const solver::SolveReport& report, const std::shared_ptr<const Tape>& domain, bool mesh);

/// Solves the elasticity problem of `file` and writes it (solve_elasticity.cpp).
template <int D>
void solve_elasticity_and_write(const SolveCommand& command, const ProblemFile& file);

}  // namespace sage::cli
