#pragma once
// The cell loop every physics shares. Over the candidate cells that carry
// quadrature points, on all cores, a physics' kernel fills each cell's
// matrix (the lower triangle of `blocks` x `blocks` blocks of the cell's
// local B-splines: a block per unknown of a B-spline, a displacement
// component, or the Robin structure's second function) and its right
// sides; the loop scatters them into the band layout of
// extended_system.hpp, one band per block pair on or below the diagonal.
// The cells go in (n + 1)^D colours, by their index modulo n + 1 on each
// axis: two cells of one colour share no B-spline, so the threads add
// into the one band with no race and no copy of their own (a copy per
// thread would double the largest array of the assembly), and every sum
// is taken in the colours' order: the same bits on any number of threads.
//
// A kernel (PoissonKernel, ElasticityKernel) is copied once per thread and
// provides:
//
//   int blocks() const;   int right_sides() const;
//   // Fills matrix (blocks * local square; the lower triangle is read) and
//   // right (blocks * local rows, right_sides columns); returns how many
//   // blocks, from the first, the cell touches.
//   int cell(const CellView<D>& cell, Eigen::MatrixXd& matrix, Eigen::MatrixXd& right);
//   // Adds another thread's kernel's own sums (in thread order).
//   void merge(const Kernel& other);

#include "discretization.hpp"

#include <sage/solver/local_splines.hpp>

#include <Eigen/Core>

#include <vector>

namespace sage::solver {

/// A cell as a kernel sees it.
template <int D>
struct CellView {
  std::array<int, D> index;                     // in the grid
  bool tabulated = false;                       // an inside cell with the common rule: `table` holds its splines
  const std::vector<VolumePoint<D>>& volume;    // its rule
  const std::vector<SurfacePoint<D>>& surface;  // (empty without surface rules)
  const InsideSplineTable& table;
};

/// The sums of the cell loop per relevant B-spline: the band of block pair
/// (b, c), c <= b, at bands[b (b + 1) / 2 + c]; right side s of block b at
/// right_sides[s * blocks + b].
struct CellSums {
  std::vector<std::vector<double>> bands;
  std::vector<std::vector<double>> right_sides;
};

inline std::size_t block_pair(int b, int c) { return static_cast<std::size_t>(b * (b + 1) / 2 + c); }

template <int D, class Kernel>
CellSums assemble_cells(const SplineBasis<D>& basis, const std::vector<std::size_t>& candidates,
                        const std::vector<CellKind>& kinds, const CellRules<D>& rules, int inside_points,
                        Kernel& kernel) {
  const BackgroundGrid<D>& grid = basis.grid;
  const int n = grid.degree, local = grid.local_count(), blocks = kernel.blocks(), sides = kernel.right_sides();
  const StencilLayout<D> layout(n);
  const std::size_t relevant = basis.relevant.size();
  const std::size_t band_size = relevant * static_cast<std::size_t>(layout.size);
  const InsideSplineTable table = inside_spline_table<D>(grid, inside_points);
  CellSums sums;
  sums.bands.assign(block_pair(blocks, 0), std::vector<double>(band_size, 0.0));
  sums.right_sides.assign(static_cast<std::size_t>(sides * blocks), std::vector<double>(relevant, 0.0));
  // The cells with points, by colour.
  int colours = 1;
  for (int a = 0; a < D; ++a) colours *= n + 1;
  std::vector<std::size_t> colour_start(static_cast<std::size_t>(colours) + 1, 0), order;
  auto colour_of = [&](std::size_t k) {
    const auto index = grid.cell_index(candidates[k]);
    int colour = 0;
    for (int a = D - 1; a >= 0; --a) colour = colour * (n + 1) + index[a] % (n + 1);
    return static_cast<std::size_t>(colour);
  };
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (!rules.volume[k].empty()) ++colour_start[colour_of(k) + 1];
  for (int c = 0; c < colours; ++c) colour_start[c + 1] += colour_start[c];
  order.resize(colour_start.back());
  {
    std::vector<std::size_t> fill(colour_start.begin(), colour_start.end() - 1);
    for (std::size_t k = 0; k < candidates.size(); ++k)
      if (!rules.volume[k].empty()) order[fill[colour_of(k)]++] = k;
  }
#pragma omp parallel
  {
    Kernel own_kernel(kernel);
    Eigen::MatrixXd matrix(blocks * local, blocks * local), right(blocks * local, sides);
    std::vector<long long> rows(static_cast<std::size_t>(local));
    for (int colour = 0; colour < colours; ++colour) {
#pragma omp for schedule(dynamic, 2)
      for (std::size_t o = colour_start[colour]; o < colour_start[colour + 1]; ++o) {
        const std::size_t k = order[o];
        const auto index = grid.cell_index(candidates[k]);
        const bool tabulated = kinds[candidates[k]] == CellKind::Inside &&
                               rules.volume[k].size() == static_cast<std::size_t>(table.points);
        const int touched =
            own_kernel.cell(CellView<D>{index, tabulated, rules.volume[k], rules.surface[k], table}, matrix, right);
        for (int j = 0; j < local; ++j)
          rows[j] = basis.relevant_of[grid.spline_linear(LocalSplines<D>::global_index(index, n, j))];
        // Fill the upper triangle: column j is then row j, read contiguously.
        matrix.template triangularView<Eigen::StrictlyUpper>() = matrix.transpose();
        for (int b = 0; b < touched; ++b)
          for (int j = 0; j < local; ++j) {
            const auto r = static_cast<std::size_t>(rows[j]);
            for (int s = 0; s < sides; ++s)
              sums.right_sides[static_cast<std::size_t>(s * blocks + b)][r] += right(b * local + j, s);
            const std::size_t slot = r * static_cast<std::size_t>(layout.size) + layout.centre - layout.position[j];
            for (int c = 0; c <= b; ++c) {
              double* row = sums.bands[block_pair(b, c)].data() + slot;
              const double* column = matrix.col(b * local + j).data() + c * local;
              for (int l = 0; l < local; ++l) row[layout.position[l]] += column[l];
            }
          }
      }
    }
    in_thread_order([&] { kernel.merge(own_kernel); });
  }
  return sums;
}

}  // namespace sage::solver
