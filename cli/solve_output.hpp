#pragma once
// What `sage solve` shares between its physics (command_solve.cpp for
// Poisson, solve_elasticity.cpp): the parsed command, the output grid and
// the solution file, the summary's shared lines.

#include "commands.hpp"

#include <sage/problems/problem_file.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>
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
  std::string grid_note;      // why the default grid has more cells than 20, or empty
  std::string geometry_note;  // CAD domains: exact faces or their tessellation, or empty
};

/// The output grid: --grid, else solution_grid's default, over the problem's box.
Grid output_grid(const SolveCommand& command, const solver::ProblemDomain& domain, double h);

/// What write_solution wrote, for the summary's last line.
struct WrittenSolution {
  std::size_t grid_points = 0, cells = 0, points = 0;
};

/// Clips the output grid at omega = 0 (output/clipped_grid.hpp), samples
/// the solution at the clip's points (solver/solution_samples.hpp) and
/// writes them, with omega, to the command's output.
template <int D>
WrittenSolution write_solution(const SolveCommand& command, const solver::ProblemDomain& domain,
                               const solver::PoissonSolution<D>& solution, const std::optional<Expr>& exact);
template <int D>
WrittenSolution write_solution(const SolveCommand& command, const solver::ProblemDomain& domain,
                               const solver::ElasticitySolution<D>& solution,
                               const std::optional<std::array<Expr, 3>>& exact);

/// The summary's last line: what the solution file holds.
void print_written(const std::string& path, const WrittenSolution& written);

/// Writes the quadrature points when asked (--quadrature-points).
void write_quadrature(const SolveCommand& command, const solver::QuadratureDump& quadrature);

/// The lines of the summary that both physics print: cells, points,
/// memory, the output omega's source, unknowns, solver. (The first line
/// and the results are theirs.)
void print_solve_report(const solver::SolveReport& report, const std::shared_ptr<const Tape>& domain, bool mesh);

/// Solves the elasticity problem and writes it (solve_elasticity.cpp; the
/// Poisson overload is command_solve.cpp's).
template <int D>
void solve_and_write(const SolveCommand& command, const solver::ElasticityProblem& problem);

}  // namespace sage::cli
