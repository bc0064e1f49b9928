#include "solve_output.hpp"

#include <sage/output/clipped_grid.hpp>
#include <sage/output/point_arrays.hpp>
#include <sage/solver/solution_samples.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sage::cli {

Grid output_grid(const SolveCommand& command, const solver::ProblemDomain& domain, double h) {
  std::optional<std::array<int, 3>> points;
  if (!command.grid.empty()) {
    try {
      points = Grid::parse_resolution(command.grid, domain.dimension);
    } catch (const std::invalid_argument& e) {
      throw UsageError{std::string("--grid: ") + e.what()};
    }
  }
  return solver::solution_grid(domain.dimension, domain.min, domain.max, h, points);
}

namespace {

template <int D, class Solution, class Exact>
WrittenSolution write_points(const SolveCommand& command, const solver::ProblemDomain& domain, const Solution& solution,
                             const Exact& exact) {
  const Grid grid = output_grid(command, domain, command.options.cell_width);
  const output::ClippedGrid part(grid,
                                 solver::omega_on_grid<D>(solution.domain, solution.mesh, solution.basis.grid.h, grid));
  part.write(command.output_path, solver::sample_solution(solution, exact, part.points()));
  return {grid.size(), part.cell_count(), part.point_count()};
}

}  // namespace

template <int D>
WrittenSolution write_solution(const SolveCommand& command, const solver::ProblemDomain& domain,
                               const solver::PoissonSolution<D>& solution, const std::optional<Expr>& exact) {
  return write_points<D>(command, domain, solution, exact);
}

template <int D>
WrittenSolution write_solution(const SolveCommand& command, const solver::ProblemDomain& domain,
                               const solver::ElasticitySolution<D>& solution,
                               const std::optional<std::array<Expr, 3>>& exact) {
  return write_points<D>(command, domain, solution, exact);
}

template WrittenSolution write_solution<2>(const SolveCommand&, const solver::ProblemDomain&,
                                           const solver::PoissonSolution<2>&, const std::optional<Expr>&);
template WrittenSolution write_solution<3>(const SolveCommand&, const solver::ProblemDomain&,
                                           const solver::PoissonSolution<3>&, const std::optional<Expr>&);
template WrittenSolution write_solution<2>(const SolveCommand&, const solver::ProblemDomain&,
                                           const solver::ElasticitySolution<2>&,
                                           const std::optional<std::array<Expr, 3>>&);
template WrittenSolution write_solution<3>(const SolveCommand&, const solver::ProblemDomain&,
                                           const solver::ElasticitySolution<3>&,
                                           const std::optional<std::array<Expr, 3>>&);

void print_written(const std::string& path, const WrittenSolution& written) {
  std::printf("wrote %s: the domain's part of a grid of %zu points (%zu cells clipped at omega = 0, %zu points)\n",
              path.c_str(), written.grid_points, written.cells, written.points);
}

void write_quadrature(const SolveCommand& command, const solver::QuadratureDump& q) {
  if (command.quadrature_path.empty()) return;
  output::write_scattered_points(command.quadrature_path, q.coordinates,
                                 {{"weight", 1, q.weights}, {"on_surface", 1, q.on_surface}});
}

void print_solve_report(const solver::SolveReport& r, const std::shared_ptr<const Tape>& domain, bool mesh) {
  std::printf(
      "  cells: %zu in the grid, %zu inside, %zu cut; quadrature points: %zu volume, %zu surface; memory estimate %.0f "
      "MB\n",
      r.cells, r.cells_inside, r.cells_cut, r.volume_points, r.surface_points, r.memory_estimate_mb);
  if (solver::omega_from_patches(domain))
    std::printf("  output omega: far-field patches within %g of the diagonal (%zu instructions)\n",
                solver::kOutputOmegaTolerance, domain->code().size());
  else if (mesh)
    std::printf("  output omega: signed distance to the mesh, exact within %g cells\n", solver::kMeshDistanceBand);
  if (r.unbroken_boxes > 0)
    std::printf(
        "  mesh: %zu cut cells whose facets bend slightly (or meet many at a vertex) got lines over an unbroken base "
        "(exact along the lines, not across the bends)\n",
        r.unbroken_boxes);
  if (r.masked_boxes > 0 || r.unresolved_surface_boxes > 0)
    std::printf(
        "  warning: %zu sub-boxes of cut cells had no height direction and were filled with %zu sign-masked points "
        "(first-order accurate), and %zu sub-boxes' boundary got no surface points\n",
        r.masked_boxes, r.masked_points, r.unresolved_surface_boxes);
  std::printf("  unknowns: %zu (%zu inner B-splines, %zu outer), %zu nonzeros\n", r.unknowns, r.inner_splines,
              r.outer_splines, r.nonzeros);
  std::printf("  solver: %s, %d iteration%s", r.linear_solver.c_str(), r.iterations, r.iterations == 1 ? "" : "s");
  if (r.cg_tolerance > 0.0) std::printf(" (relative residual <= %.1e)", r.cg_tolerance);
  if (std::isfinite(r.condition))
    std::printf("; condition estimate %.3g (%.3g after diagonal scaling)", r.condition, r.scaled_condition);
  std::printf("\n");
}

}  // namespace sage::cli
