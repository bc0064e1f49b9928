#pragma once
// A solution on an output grid, for the command line, the examples and
// library users alike: the grid a solve's output uses by default, the
// domain's field omega at its points (which output/clipped_grid.hpp clips
// at 0), and the solution's arrays at any points.

#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <sage/sampling/grid.hpp>
#include <sage/sampling/point_array.hpp>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace sage::solver {

/// The output grid over the box [min, max]: `points` per axis when given,
/// else 4 points per background cell of width `cell_width` in 2D (at most
/// 401 per axis), 2 in 3D (at most 97).
Grid solution_grid(int dimension, const std::array<double, 3>& min, const std::array<double, 3>& max, double cell_width,
                   const std::optional<std::array<int, 3>>& points = std::nullopt);

/// Domain fields of more instructions than this get omega on the output
/// grid from far-field patches (pruned_grid.hpp), within
/// kOutputOmegaTolerance of the grid's diagonal: a polygon's R0 tree of
/// 718 edges takes 3 s at the 160,801 points of 128 cells, exactly.
constexpr std::size_t kLargeField = 2000;
constexpr double kOutputOmegaTolerance = 1e-10;

/// True when omega_on_grid uses far-field patches for this domain field.
bool omega_from_patches(const std::shared_ptr<const Tape>& domain);

/// omega at the grid's points, in grid order: the domain's field (large
/// fields by far-field patches), or a mesh domain's signed distance (exact
/// within kMeshDistanceBand cell widths of `cell_width`), on all cores.
template <int D>
std::vector<double> omega_on_grid(const std::shared_ptr<const Tape>& domain,
                                  const std::shared_ptr<const MeshDomain>& mesh, double cell_width, const Grid& grid);

/// u, grad_u (3 components; z = 0 in 2D), and with the exact solution
/// u_exact and error = u - u_exact, at the points, on all cores.
template <int D>
std::vector<PointArray> sample_solution(const PoissonSolution<D>& solution, const std::optional<Expr>& exact,
                                        const std::vector<std::array<double, 3>>& points);

/// displacement (3 components), stress (6, VTK's symmetric-tensor order
/// xx, yy, zz, xy, yz, xz), von_mises, and with the exact displacement
/// displacement_exact and displacement_error, at the points, on all cores.
template <int D>
std::vector<PointArray> sample_solution(const ElasticitySolution<D>& solution,
                                        const std::optional<std::array<Expr, 3>>& exact,
                                        const std::vector<std::array<double, 3>>& points);

}  // namespace sage::solver
