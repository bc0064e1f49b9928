#pragma once
// Sampling at scattered points with interval pruning, as pruned_grid.hpp
// samples grids: the points are split recursively at the middle of their
// bounding box on every axis, and each group runs the tape specialized to
// its box (exact: the same bits as the whole tape) or, with an
// Approximation, far-field patches over groups large enough to repay them.
// Groups are OpenMP tasks; the points are copied once and moved as they
// are split, so that every group is contiguous in memory. A tape with
// nothing to prune or patch runs slices of the list on all cores. Far mesh
// faces in single precision are left to grids (their check samples grid
// points): points run mesh faces exactly.

#include <sage/sampling/pruned_grid.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace sage {
namespace detail {

/// A point in the tree's order: where it is and its index in the caller's list.
struct LocatedPoint {
  std::array<double, 3> at;
  std::size_t index;
};

struct PointGroup {
  std::size_t first = 0, last = 0;  // positions in the tree's order
  std::size_t size() const { return last - first; }
};

/// The box spanned by a group's points.
inline std::array<Interval, 3> group_box(const std::vector<LocatedPoint>& points, PointGroup group, int dimension) {
  std::array<Interval, 3> box{Interval(0.0), Interval(0.0), Interval(0.0)};
  for (int a = 0; a < dimension; ++a) {
    double lo = points[group.first].at[a], hi = lo;
    for (std::size_t k = group.first; k < group.last; ++k) {
      lo = std::min(lo, points[k].at[a]);
      hi = std::max(hi, points[k].at[a]);
    }
    box[a] = Interval(lo, hi);
  }
  return box;
}

/// Splits the group at the middle of its box on every axis (2^D parts, as
/// grid blocks are halved) into `parts`, moving the points themselves so
/// that every group stays contiguous in memory (scattered input reads
/// memory in order from the first split on); returns how many are not
/// empty. Points all equal along the axes (nothing to halve) split by count.
inline std::size_t split_group(std::vector<LocatedPoint>& points, PointGroup group, const std::array<Interval, 3>& box,
                               int dimension, std::array<PointGroup, 8>& parts) {
  std::array<PointGroup, 8> pieces{};
  std::size_t count = 1;
  pieces[0] = group;
  for (int a = 0; a < dimension; ++a) {
    const double middle = 0.5 * (box[a].lo + box[a].hi);
    const std::size_t before = count;
    for (std::size_t k = 0; k < before; ++k) {
      const auto begin = points.begin() + static_cast<std::ptrdiff_t>(pieces[k].first);
      const auto end = points.begin() + static_cast<std::ptrdiff_t>(pieces[k].last);
      const auto cut = std::partition(begin, end, [&](const LocatedPoint& p) { return p.at[a] < middle; });
      const auto at = static_cast<std::size_t>(cut - points.begin());
      pieces[count++] = PointGroup{at, pieces[k].last};
      pieces[k].last = at;
    }
  }
  std::size_t kept = 0;
  for (std::size_t k = 0; k < count; ++k)
    if (pieces[k].size() > 0) parts[kept++] = pieces[k];
  if (kept > 1) return kept;
  parts[0] = PointGroup{group.first, group.first + group.size() / 2};
  parts[1] = PointGroup{group.first + group.size() / 2, group.last};
  return 2;
}

/// Whether a group is split, its tape specialized or patched.
inline bool splits(const Tape& tape, PointGroup group, const BlockPlan& plan) {
  const bool patch = plan.approximation && group.size() >= plan.patch_points;
  const bool prune =
      plan.prune && (group.size() > kLeafPoints || (group.size() >= 4 && tape.code().size() > kLongTape));
  return (patch || prune) && tape.code().size() > kSmallTape && group.size() > 1;
}

/// A leaf: the group's points in batches, by this thread's batch
/// evaluator (leaves spawn no tasks).
template <class T, class Visit>
void evaluate_group(const Tape& tape, const std::vector<LocatedPoint>& points, PointGroup group, Visit& visit) {
  BatchEvaluator<T>& batch = thread_batch<T>(tape, std::min(group.size(), kBatchPoints));
  batch.set_far_faces(false);
  std::array<std::array<double, 3>, kBatchPoints> at{};
  for (std::size_t first = group.first; first < group.last; first += kBatchPoints) {
    const std::size_t count = std::min(kBatchPoints, group.last - first);
    for (std::size_t l = 0; l < count; ++l) at[l] = points[first + l].at;
    batch.evaluate(at.data(), count);
    for (std::size_t l = 0; l < count; ++l) visit(points[first + l].index, batch.point(l));
  }
}

/// Visits a group whose box is `box`; `specialized`: `tape` is already
/// specialized to that box (by the parent, with its siblings).
template <class T, class Visit>
void visit_points(const Tape& tape, std::vector<LocatedPoint>& points, PointGroup group,
                  const std::array<Interval, 3>& box, Visit& visit, int depth, const BlockPlan& plan,
                  bool specialized = false) {
  const int dimension = tape.dimension();
  if (splits(tape, group, plan)) {
    std::optional<Tape> own;
    if (!specialized) {
      TapeSpecializer& specializer = thread_specializer(tape);
      own = plan.approximation && group.size() >= plan.patch_points
                ? specializer.approximate(box.data(), *plan.approximation)
                : specializer.specialize(box.data());
    }
    const Tape& next = own ? *own : tape;
    std::array<PointGroup, 8> parts;
    const std::size_t count = split_group(points, group, box, dimension, parts);
    std::array<std::array<Interval, 3>, 8> part_boxes;
    for (std::size_t c = 0; c < count; ++c) part_boxes[c] = group_box(points, parts[c], dimension);
    // Parts that specialize without patches do it together, in one pass over `next`.
    std::array<std::optional<Tape>, 8> part_tapes;
    std::array<bool, 8> together{};
    std::array<std::array<Interval, 3>, 8> batched_boxes;
    std::array<std::size_t, 8> which{};
    std::size_t batched = 0;
    for (std::size_t c = 0; c < count; ++c)
      if (splits(next, parts[c], plan) && !(plan.approximation && parts[c].size() >= plan.patch_points)) {
        together[c] = true;
        which[batched] = c;
        batched_boxes[batched++] = part_boxes[c];
      }
    if (batched > 0) {
      std::array<std::optional<Tape>, 8> made;
      thread_specializer(next).specialize_each(batched_boxes.data(), batched, made.data());
      for (std::size_t k = 0; k < batched; ++k) part_tapes[which[k]] = std::move(made[k]);
    }
    for (std::size_t c = 0; c < count; ++c) {
      const Tape* part_tape = part_tapes[c] ? &*part_tapes[c] : &next;
      const PointGroup part = parts[c];
      const std::array<Interval, 3>* part_box = &part_boxes[c];
      const bool part_specialized = together[c];
#pragma omp task default(shared) firstprivate(part, part_tape, part_box, part_specialized) if (depth < kTaskDepth)
      visit_points<T>(*part_tape, points, part, *part_box, visit, depth + 1, plan, part_specialized);
    }
#pragma omp taskwait
    return;
  }
  evaluate_group<T>(tape, points, group, visit);
}

}  // namespace detail

/// visit(index, results) once per point, concurrently for different
/// indices (results.result(root): the point's value of a root). Exact
/// without an approximation; with one of positive tolerance, groups of
/// points get far-field patches as grid blocks do.
template <class T, class Visit>
void for_each_point_pruned(const Tape& tape, const std::vector<std::array<double, 3>>& points, Visit visit,
                           const Approximation* approximation = nullptr) {
  if (points.empty()) return;
  detail::BlockPlan plan;
  plan.prune = TapeSpecializer::worthwhile(tape);
  if (approximation && approximation->tolerance > 0) {
    plan.approximation = approximation;
    std::size_t samples = 1;
    for (int a = 0; a < tape.dimension(); ++a) samples *= static_cast<std::size_t>(approximation->sampling_degree + 1);
    plan.patch_points = 3 * samples;
  }
  std::vector<detail::LocatedPoint> located(points.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < points.size(); ++i) located[i] = {points[i], i};
  const detail::PointGroup all{0, points.size()};
  if (!detail::splits(tape, all, plan)) {
    // Nothing to specialize or patch (a field without min/max nodes,
    // exactly): slices of the list on all cores, each a leaf.
    constexpr std::size_t kSlice = 4096;
    const std::size_t slices = (points.size() + kSlice - 1) / kSlice;
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t k = 0; k < slices; ++k)
      detail::evaluate_group<T>(tape, located, {k * kSlice, std::min(points.size(), (k + 1) * kSlice)}, visit);
    return;
  }
  const std::array<Interval, 3> box = detail::group_box(located, all, tape.dimension());
#pragma omp parallel
#pragma omp single
  detail::visit_points<T>(tape, located, all, box, visit, 0, plan);
}

}  // namespace sage
