#pragma once
// Grid sampling with interval pruning: the grid's points are split into
// blocks recursively (halving every axis), and each block is evaluated
// with the tape specialized to the block's box (tape_specialization.hpp),
// so small blocks run the few instructions that matter there. The values
// and derivatives are the same, bit for bit, as point-by-point evaluation
// of the whole tape.
//
// Blocks are OpenMP tasks, so all cores share the work.

#include <sage/grid.hpp>
#include <sage/tape_specialization.hpp>

#include <array>
#include <atomic>
#include <cstddef>

namespace sage {

namespace detail {

/// Points with index i in [lo[a], hi[a]) along each axis a.
struct GridBlock {
  std::array<int, 3> lo{0, 0, 0};
  std::array<int, 3> hi{1, 1, 1};
  std::size_t size() const {
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) n *= static_cast<std::size_t>(hi[a] - lo[a]);
    return n;
  }
};

/// The box spanned by a block's points: the same arithmetic as
/// Grid::point, so every point of the block lies in it.
inline std::array<Interval, 3> block_box(const Grid& grid, const GridBlock& b) {
  std::array<Interval, 3> box{Interval(0.0), Interval(0.0), Interval(0.0)};
  for (int a = 0; a < grid.dimension; ++a)
    box[a] = Interval(grid.lo[a] + b.lo[a] * grid.spacing(a), grid.lo[a] + (b.hi[a] - 1) * grid.spacing(a));
  return box;
}

constexpr std::size_t kLeafPoints = 16;  // evaluate point by point below this
constexpr std::size_t kSmallTape = 16;   // too short to be worth specializing
constexpr int kTaskDepth = 8;            // deeper blocks run in their parent's task

template <class T, class Visit>
void visit_block(const Tape& tape, const Grid& grid, const GridBlock& block, Visit& visit, int depth,
                 std::atomic<std::size_t>& done, const Progress& progress) {
  if (block.size() > kLeafPoints && tape.code().size() > kSmallTape) {
    TapeSpecializer specializer(tape);
    const std::array<Interval, 3> box = block_box(grid, block);
    const std::optional<Tape> smaller = specializer.specialize(box.data());
    const Tape& next = smaller ? *smaller : tape;
    // Halve every axis that has more than one point.
    std::array<int, 3> mid{};
    for (int a = 0; a < 3; ++a) mid[a] = (block.lo[a] + block.hi[a]) / 2;
    for (int c = 0; c < 8; ++c) {
      GridBlock child = block;
      bool skip = false;
      for (int a = 0; a < 3; ++a) {
        const bool upper = (c >> a) & 1;
        if (block.hi[a] - block.lo[a] <= 1) {
          skip |= upper;
          continue;
        }
        (upper ? child.lo[a] : child.hi[a]) = mid[a];
      }
      if (skip) continue;
#pragma omp task default(shared) firstprivate(child) if (depth < kTaskDepth)
      visit_block<T>(next, grid, child, visit, depth + 1, done, progress);
    }
#pragma omp taskwait
    return;
  }
  Evaluator<T> eval(tape);
  const std::size_t nx = static_cast<std::size_t>(grid.points[0]), ny = static_cast<std::size_t>(grid.points[1]);
  for (int k = block.lo[2]; k < block.hi[2]; ++k)
    for (int j = block.lo[1]; j < block.hi[1]; ++j)
      for (int i = block.lo[0]; i < block.hi[0]; ++i) {
        const std::size_t index = static_cast<std::size_t>(i) + nx * (static_cast<std::size_t>(j) + ny * k);
        const auto p = grid.point(index);
        eval.evaluate(p.data());
        visit(index, eval);
      }
  const std::size_t total = done.fetch_add(block.size()) + block.size();
#ifdef _OPENMP
  if (omp_get_thread_num() != 0) return;  // Progress is called from one thread
#endif
  if (progress) progress(static_cast<double>(total) / static_cast<double>(grid.size()));
}

}  // namespace detail

/// Same contract as for_each_grid_point (grid.hpp): visit(index, evaluator)
/// once per grid point, concurrently for different indices; here the
/// evaluator runs a tape specialized to a block around the point.
template <class T, class Visit>
void for_each_grid_point_pruned(const Tape& tape, const Grid& grid, Visit visit, const Progress& progress = {}) {
  detail::GridBlock all;
  for (int a = 0; a < 3; ++a) all.hi[a] = grid.points[a];
  std::atomic<std::size_t> done{0};
  if (!TapeSpecializer::worthwhile(tape)) return for_each_grid_point<T>(tape, grid, visit, progress);
#pragma omp parallel
#pragma omp single
  detail::visit_block<T>(tape, grid, all, visit, 0, done, progress);
  if (progress) progress(1.0);
}

}  // namespace sage
