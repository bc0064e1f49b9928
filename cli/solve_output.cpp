#include "solve_output.hpp"

#include <sage/output/point_arrays.hpp>
#include <sage/sampling/pruned_grid.hpp>
#include <sage/solver/domain_probe.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sage::cli {

Grid output_grid(const SolveCommand& command, const solver::PoissonProblem& problem, double h) {
  Grid grid;
  grid.dimension = problem.dimension;
  grid.lo = problem.min;
  grid.hi = problem.max;
  if (!command.grid.empty()) {
    try {
      grid.points = Grid::parse_resolution(command.grid, problem.dimension);
    } catch (const std::invalid_argument& e) {
      throw UsageError{std::string("--grid: ") + e.what()};
    }
  } else {
    const int per_cell = problem.dimension == 2 ? 4 : 2, cap = problem.dimension == 2 ? 401 : 97;
    for (int a = 0; a < problem.dimension; ++a)
      grid.points[a] = std::clamp(static_cast<int>(std::ceil((grid.hi[a] - grid.lo[a]) / h)) * per_cell + 1, 2, cap);
  }
  if (problem.dimension == 2) grid.points[2] = 1;
  return grid;
}

bool sample_large_omega(const std::shared_ptr<const Tape>& domain, const Grid& grid, std::vector<double>& omega) {
  if (!domain || domain->code().size() <= kLargeField) return false;
  Approximation approximation;
  approximation.tolerance = kOutputOmegaTolerance * grid.diagonal();
  for_each_grid_point_pruned<double>(
      *domain, grid, [&](std::size_t i, const auto& results) { omega[i] = results.result(0); }, {}, &approximation);
  return true;
}

template <int D>
output::ClippedGrid clipped_output(const Grid& grid, const std::shared_ptr<const Tape>& domain,
                                   const std::shared_ptr<const solver::MeshDomain>& mesh, double cell_width) {
  std::vector<double> omega(grid.size());
  if (!sample_large_omega(domain, grid, omega)) {
#pragma omp parallel
    {
      solver::DomainProbe<D> probe(domain, mesh, cell_width);
#pragma omp for schedule(dynamic, 1024)
      for (std::size_t i = 0; i < grid.size(); ++i) omega[i] = probe.at(grid.point(i).data());
    }
  }
  return output::ClippedGrid(grid, omega);
}

template output::ClippedGrid clipped_output<2>(const Grid&, const std::shared_ptr<const Tape>&,
                                               const std::shared_ptr<const solver::MeshDomain>&, double);
template output::ClippedGrid clipped_output<3>(const Grid&, const std::shared_ptr<const Tape>&,
                                               const std::shared_ptr<const solver::MeshDomain>&, double);

void print_written(const std::string& path, const output::ClippedGrid& part, const Grid& grid) {
  std::printf("wrote %s: the domain's part of a grid of %zu points (%zu cells clipped at omega = 0, %zu points)\n",
              path.c_str(), grid.size(), part.cell_count(), part.point_count());
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
  if (domain && domain->code().size() > kLargeField)
    std::printf("  output omega: far-field patches within %g of the diagonal (%zu instructions)\n",
                kOutputOmegaTolerance, domain->code().size());
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
