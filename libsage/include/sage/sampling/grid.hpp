#pragma once
// Regular 2D/3D grids of sample points, and parallel evaluation of a tape
// over them.
//
// Points are numbered with x fastest, then y, then z (VTK's order):
// index = i + nx (j + ny k). A grid of n points along an axis spans
// [lo, hi] inclusive with spacing (hi - lo) / (n - 1).

#include <sage/scalars/interval.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage {

/// Most points a parsed grid may have: 2e8 points with value and gradient
/// already take about 8 GB as doubles.
constexpr long long kMaxGridPoints = 200'000'000;

struct Grid {
  int dimension = 2;
  std::array<double, 3> lo{0, 0, 0};
  std::array<double, 3> hi{1, 1, 1};
  std::array<int, 3> points{2, 2, 1};  // per axis; 1 along unused axes

  std::size_t size() const {
    return static_cast<std::size_t>(points[0]) * static_cast<std::size_t>(points[1]) *
           static_cast<std::size_t>(points[2]);
  }
  double spacing(int axis) const { return points[axis] > 1 ? (hi[axis] - lo[axis]) / (points[axis] - 1) : 0.0; }
  /// Length of the box's diagonal over the grid's axes (the unit of
  /// far-field tolerances).
  double diagonal() const {
    double sum = 0.0;
    for (int a = 0; a < dimension; ++a) sum += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    return std::sqrt(sum);
  }
  std::array<double, 3> point(std::size_t index) const {
    const std::size_t i = index % points[0], j = (index / points[0]) % points[1], k = index / points[0] / points[1];
    return {lo[0] + i * spacing(0), lo[1] + j * spacing(1), dimension == 3 ? lo[2] + k * spacing(2) : 0.0};
  }

  /// Number of cells (boxes between neighbouring points).
  std::size_t cell_count() const {
    std::size_t n = 1;
    for (int a = 0; a < dimension; ++a) n *= static_cast<std::size_t>(std::max(points[a] - 1, 0));
    return n;
  }
  /// The box of cell `index` (cells numbered like points, x fastest).
  std::array<Interval, 3> cell(std::size_t index) const {
    const std::size_t cx = static_cast<std::size_t>(points[0] - 1), cy = static_cast<std::size_t>(points[1] - 1);
    const std::size_t i = index % cx, j = (index / cx) % cy, k = index / cx / cy;
    // Both ends from point(), so neighbouring cells share their faces exactly.
    const std::size_t nx = static_cast<std::size_t>(points[0]), ny = static_cast<std::size_t>(points[1]);
    const std::array<double, 3> p = point(i + nx * (j + ny * k));
    const std::array<double, 3> q = point((i + 1) + nx * ((j + 1) + ny * (dimension == 3 ? k + 1 : k)));
    std::array<Interval, 3> box{Interval(p[0], q[0]), Interval(p[1], q[1]), Interval(0.0)};
    if (dimension == 3) box[2] = Interval(p[2], q[2]);
    return box;
  }

  /// The points per axis when none are given: 200 x 200 (2D), 64^3 (3D).
  static std::array<int, 3> default_points(int dimension);
  /// Point counts per axis as given (`dimension` of them), checked: whole
  /// numbers from 2 to 100000, at most kMaxGridPoints in all. Throws
  /// std::invalid_argument starting with `what` ("grid '64x64'", "grid").
  static std::array<int, 3> checked_points(const std::vector<double>& counts, int dimension, const std::string& what);
  /// Parses "200x200" (2D) or "64x64x64" (3D); throws std::invalid_argument.
  static std::array<int, 3> parse_resolution(const std::string& text, int dimension);
  /// Points `spacing` apart from lo on, up to the first at or past hi (hi
  /// moves there), at least two per axis; throws std::invalid_argument for
  /// a spacing that is not positive or gives too many points.
  void space_points(double spacing);
  /// Parses "xmin,xmax,ymin,ymax[,zmin,zmax]"; throws std::invalid_argument.
  static void parse_bounds(const std::string& text, int dimension, std::array<double, 3>& lo,
                           std::array<double, 3>& hi);
};

/// Progress callback: fraction done in [0, 1]. Called from one thread.
using Progress = std::function<void(double)>;

/// Evaluates `tape` with scalar type T at every grid point, in parallel on
/// all cores, and calls visit(index, evaluator) with the evaluator holding
/// that point's results. visit runs concurrently for different indices: it
/// must only write to slots owned by `index`.
template <class T, class Visit>
void for_each_grid_point(const Tape& tape, const Grid& grid, Visit visit, const Progress& progress = {}) {
  const std::size_t n = grid.size();
  const std::size_t chunk = 1024;
  std::atomic<std::size_t> done{0};
#pragma omp parallel
  {
    Evaluator<T> eval(tape);
    bool reporter = true;
#ifdef _OPENMP
    reporter = omp_get_thread_num() == 0;
#endif
#pragma omp for schedule(dynamic, 1)
    for (std::size_t start = 0; start < n; start += chunk) {
      const std::size_t end = std::min(n, start + chunk);
      for (std::size_t i = start; i < end; ++i) {
        const auto p = grid.point(i);
        eval.evaluate(p.data());
        visit(i, eval);
      }
      const std::size_t total = done.fetch_add(end - start) + (end - start);
      if (reporter && progress) progress(static_cast<double>(total) / static_cast<double>(n));
    }
  }
  if (progress) progress(1.0);
}

/// Encloses the tape's roots over every grid cell with interval
/// arithmetic, in parallel; visit(cell_index, evaluator) as above. A root
/// whose interval excludes 0 proves the cell holds none of its zero set.
template <class Visit>
void for_each_grid_cell(const Tape& tape, const Grid& grid, Visit visit) {
  const std::size_t n = grid.cell_count();
#pragma omp parallel
  {
    Evaluator<Interval> eval(tape);
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t c = 0; c < n; ++c) {
      const auto box = grid.cell(c);
      eval.evaluate_with(box.data());
      visit(c, eval);
    }
  }
}

}  // namespace sage
