#pragma once
// Grid sampling with interval pruning: the grid's points are split into
// blocks recursively (halving every axis), and each block is evaluated
// with the tape specialized to the block's box (tape_specialization.hpp),
// so small blocks run the few instructions that matter there. The values
// and derivatives are the same, bit for bit, as point-by-point evaluation
// of the whole tape.
//
// Blocks are OpenMP tasks, so all cores share the work.
//
// With an Approximation (tape_specialization.hpp), blocks large enough to
// repay the samples get tapes with far-field Chebyshev patches instead:
// not bit-identical, within the stated tolerance, and fast for R-function
// trees that pruning cannot touch.

#include <sage/sampling/grid.hpp>
#include <sage/tape/batch_evaluator.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <memory>

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

// Evaluate without specializing below this: with the arithmetic in vector
// instructions, specializing blocks of 32 points cost more than it saved
// (1,000 balls' min/max union at 128^3, values, one thread: 0.28 s at 32,
// 0.19 s at 64; 128 slower with gradients).
constexpr std::size_t kLeafPoints = 64;
constexpr std::size_t kSmallTape = 16;  // too short to be worth specializing
// Over a block of m points a specialization costs about two passes of the
// tape and saves m passes of what it drops: with long tapes (large meshes,
// where shrinking is slow) it pays down to blocks of a few points.
constexpr std::size_t kLongTape = 4096;
constexpr int kTaskDepth = 8;              // deeper blocks run in their parent's task
constexpr std::size_t kBatchPoints = 128;  // points per BatchEvaluator run (64: fandisk 5-10% slower)

/// How blocks are specialized: exact pruning (where worthwhile) and, with
/// an approximation, patches over blocks of at least patch_points points.
struct BlockPlan {
  bool prune = true;
  const Approximation* approximation = nullptr;
  std::size_t patch_points = 0;
  bool far_faces = false;  // batches run far mesh faces in single precision
};

inline BlockPlan plan_for(const Tape& tape, const Grid& grid, const Approximation* approximation) {
  BlockPlan plan;
  plan.prune = TapeSpecializer::worthwhile(tape);
  plan.far_faces = approximation && approximation->far_faces && grid.dimension == 3;
  if (approximation && approximation->tolerance > 0) {
    plan.approximation = approximation;
    // A patch costs (n + 1)^dim samples of its subtree: fit it only over
    // blocks with several times as many points.
    std::size_t samples = 1;
    for (int a = 0; a < grid.dimension; ++a) samples *= static_cast<std::size_t>(approximation->sampling_degree + 1);
    plan.patch_points = 3 * samples;
  }
  return plan;
}

/// This thread's specializer, rebound to `tape`: its buffers are reused by
/// every block the thread specializes (and kept until the thread ends). A
/// block uses it only before it spawns its children's tasks, so tasks that
/// the thread interleaves never share it mid-use.
inline TapeSpecializer& thread_specializer(const Tape& tape) {
  thread_local std::unique_ptr<TapeSpecializer> specializer;
  if (specializer)
    specializer->rebind(tape);
  else
    specializer = std::make_unique<TapeSpecializer>(tape);
  return *specializer;
}

/// This thread's batch evaluator, rebound to `tape` and `width` lanes: a
/// leaf uses it for all its points (leaves spawn no tasks, so nothing else
/// on the thread uses it meanwhile).
template <class T>
BatchEvaluator<T>& thread_batch(const Tape& tape, std::size_t width) {
  thread_local std::unique_ptr<BatchEvaluator<T>> batch;
  if (batch)
    batch->rebind(tape, width);
  else
    batch = std::make_unique<BatchEvaluator<T>>(tape, width);
  return *batch;
}

/// Whether a block gets far-field patches (and so specializes alone).
inline bool patches(const GridBlock& block, const BlockPlan& plan) {
  return plan.approximation && block.size() >= plan.patch_points;
}

/// Whether a block is split, its tape specialized or patched, rather than
/// evaluated point by point.
inline bool splits(const Tape& tape, const GridBlock& block, const BlockPlan& plan) {
  const bool prune =
      plan.prune && (block.size() > kLeafPoints || (block.size() >= 4 && tape.code().size() > kLongTape));
  return (patches(block, plan) || prune) && tape.code().size() > kSmallTape;
}

/// The block's children: every axis with more than one point halved.
inline std::size_t children_of(const GridBlock& block, std::array<GridBlock, 8>& children) {
  std::array<int, 3> mid{};
  for (int a = 0; a < 3; ++a) mid[a] = (block.lo[a] + block.hi[a]) / 2;
  std::size_t count = 0;
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
    if (!skip) children[count++] = child;
  }
  return count;
}

/// Visits `block` with `tape`, already specialized to it when
/// `specialized` (its parent did that for all its children in one pass).
template <class T, class Visit>
void visit_block(const Tape& tape, const Grid& grid, const GridBlock& block, Visit& visit, int depth,
                 std::atomic<std::size_t>& done, const Progress& progress, const BlockPlan& plan,
                 bool specialized = false) {
  if (splits(tape, block, plan)) {
    std::optional<Tape> own;
    if (!specialized) {
      TapeSpecializer& specializer = thread_specializer(tape);
      const std::array<Interval, 3> box = block_box(grid, block);
      own = patches(block, plan) ? specializer.approximate(box.data(), *plan.approximation)
                                 : specializer.specialize(box.data());
    }
    const Tape& next = own ? *own : tape;
    std::array<GridBlock, 8> children;
    const std::size_t count = children_of(block, children);
    // Children that specialize without patches do it together, in one pass
    // over `next` (decoding it once instead of once per child).
    std::array<std::optional<Tape>, 8> child_tapes;
    std::array<bool, 8> together{};
    std::array<std::array<Interval, 3>, 8> boxes;
    std::array<std::size_t, 8> which{};
    std::size_t batched = 0;
    for (std::size_t c = 0; c < count; ++c)
      if (splits(next, children[c], plan) && !patches(children[c], plan)) {
        together[c] = true;
        which[batched] = c;
        boxes[batched++] = block_box(grid, children[c]);
      }
    if (batched > 0) {
      std::array<std::optional<Tape>, 8> made;
      thread_specializer(next).specialize_each(boxes.data(), batched, made.data());
      for (std::size_t k = 0; k < batched; ++k) child_tapes[which[k]] = std::move(made[k]);
    }
    for (std::size_t c = 0; c < count; ++c) {
      // Per task: the child, its tape (kept alive by this frame until the
      // taskwait) and whether it is specialized already.
      const Tape* child_tape = child_tapes[c] ? &*child_tapes[c] : &next;
      const GridBlock child = children[c];
      const bool child_specialized = together[c];
#pragma omp task default(shared) firstprivate(child, child_tape, child_specialized) if (depth < kTaskDepth)
      visit_block<T>(*child_tape, grid, child, visit, depth + 1, done, progress, plan, child_specialized);
    }
#pragma omp taskwait
    return;
  }
  // The block's points, a few grid rows per batch run by this thread's
  // BatchEvaluator (leaves spawn no tasks, so nothing else uses it
  // meanwhile): rows, so that patches sum their y and z factors once per row.
  BatchEvaluator<T>& batch = thread_batch<T>(tape, std::min(block.size(), kBatchPoints));
  batch.set_far_faces(plan.far_faces);
  const std::size_t nx_grid = static_cast<std::size_t>(grid.points[0]),
                    ny_grid = static_cast<std::size_t>(grid.points[1]);
  const std::size_t chunk = std::min(static_cast<std::size_t>(block.hi[0] - block.lo[0]), kBatchPoints);
  const std::size_t rows_per_batch = kBatchPoints / chunk;
  std::array<double, kBatchPoints> xs{};
  std::array<std::array<double, 2>, kBatchPoints> rows{};
  std::array<std::size_t, kBatchPoints> row_start{};  // grid index of each row's first point
  for (std::size_t first = static_cast<std::size_t>(block.lo[0]); first < static_cast<std::size_t>(block.hi[0]);
       first += chunk) {
    const std::size_t nx = std::min(chunk, static_cast<std::size_t>(block.hi[0]) - first);
    for (std::size_t i = 0; i < nx; ++i) xs[i] = grid.point(first + i)[0];
    std::size_t count = 0;
    auto flush = [&] {
      batch.evaluate_rows(xs.data(), nx, rows.data(), count);
      for (std::size_t r = 0; r < count; ++r)
        for (std::size_t i = 0; i < nx; ++i) visit(row_start[r] + i, batch.point(r * nx + i));
      count = 0;
    };
    for (int k = block.lo[2]; k < block.hi[2]; ++k)
      for (int j = block.lo[1]; j < block.hi[1]; ++j) {
        row_start[count] = first + nx_grid * (static_cast<std::size_t>(j) + ny_grid * static_cast<std::size_t>(k));
        const std::array<double, 3> p = grid.point(row_start[count]);
        rows[count] = {p[1], p[2]};
        if (++count == rows_per_batch) flush();
      }
    if (count > 0) flush();
  }
  const std::size_t total = done.fetch_add(block.size()) + block.size();
#ifdef _OPENMP
  if (omp_get_thread_num() != 0) return;  // Progress is called from one thread
#endif
  if (progress) progress(static_cast<double>(total) / static_cast<double>(grid.size()));
}

}  // namespace detail

/// Same contract as for_each_grid_point (grid.hpp): visit(index, results)
/// once per grid point, concurrently for different indices, where
/// results.result(root) is the point's value of a root (visit should take
/// `const auto&`: an Evaluator or a BatchEvaluator's Point). Here the
/// points run, in batches, a tape specialized to a block around them (and
/// with far-field patches when `approximation` has a positive tolerance).
template <class T, class Visit>
void for_each_grid_point_pruned(const Tape& tape, const Grid& grid, Visit visit, const Progress& progress = {},
                                const Approximation* approximation = nullptr) {
  detail::GridBlock all;
  for (int a = 0; a < 3; ++a) all.hi[a] = grid.points[a];
  std::atomic<std::size_t> done{0};
  const detail::BlockPlan plan = detail::plan_for(tape, grid, approximation);
  if (!detail::splits(tape, all, plan)) {
    // Nothing to specialize (no min/max node and no far field, or a tape
    // too short): blocks run in parallel, each in batches as a leaf block
    // is (the same bits as point by point). Slabs of whole grid rows, or,
    // for far faces, which need compact batches, bricks of 8 x 4 x 4
    // points (a batch each).
    const int rows_per_slab = std::max(1, static_cast<int>(4096 / std::max(1, grid.points[0])));
    const std::array<int, 3> shape =
        plan.far_faces ? std::array<int, 3>{8, 4, 4} : std::array<int, 3>{grid.points[0], rows_per_slab, 1};
    std::array<int, 3> blocks{};
    for (int a = 0; a < 3; ++a) blocks[a] = (grid.points[a] + shape[a] - 1) / shape[a];
    const int total = blocks[0] * blocks[1] * blocks[2];
#pragma omp parallel for schedule(dynamic, 1)
    for (int b = 0; b < total; ++b) {
      detail::GridBlock block;
      const std::array<int, 3> at{b % blocks[0], (b / blocks[0]) % blocks[1], b / (blocks[0] * blocks[1])};
      for (int a = 0; a < 3; ++a) {
        block.lo[a] = at[a] * shape[a];
        block.hi[a] = std::min(grid.points[a], block.lo[a] + shape[a]);
      }
      detail::visit_block<T>(tape, grid, block, visit, detail::kTaskDepth, done, progress, plan);
    }
    if (progress) progress(1.0);
    return;
  }
#pragma omp parallel
#pragma omp single
  detail::visit_block<T>(tape, grid, all, visit, 0, done, progress, plan);
  if (progress) progress(1.0);
}

}  // namespace sage
