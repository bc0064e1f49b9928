#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/pruned_grid.hpp>
#include <sage/sampling/pruned_points.hpp>
#include <sage/scalars/tuple.hpp>
#include <sage/tape/batch_evaluator.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace sage {

namespace {

/// The arrays for `n` points at order K, sized, with the names of the
/// higher partials; `positions[k]` gets order k's places in Tuple<N, K>.
template <int N, int K>
FieldSamples empty_samples(std::size_t n, std::vector<std::vector<int>>& positions) {
  FieldSamples s;
  s.order = K;
  s.omega.resize(n);
  if (K >= 1) {
    s.gradient.assign(3 * n, 0.0);
    s.gradient_norm.resize(n);
  }
  positions.assign(K + 1, {});
  using Layout = Tuple<N, K>;
  for (int i = 0; i < Layout::size; ++i) {
    const auto& alpha = Layout::indices.index[i];
    const int k = order_of<N>(alpha);
    if (k < 2) continue;
    positions[k].push_back(i);
  }
  for (int k = 2; k <= K; ++k) {
    DerivativeArray d;
    d.order = k;
    for (int i : positions[k]) {
      std::string name;
      for (int v = 0; v < N; ++v) name.append(static_cast<std::size_t>(Layout::indices.index[i][v]), "xyz"[v]);
      d.components.push_back(name);
    }
    d.values.resize(n * d.components.size());
    s.higher.push_back(std::move(d));
  }
  return s;
}

/// Stores point p's value (and derivatives) into the arrays.
template <int N, int K, class T>
void store(FieldSamples& s, std::size_t p, const T& t, const std::vector<std::vector<int>>& positions) {
  if constexpr (K == 0) {
    s.omega[p] = t;
  } else {
    s.omega[p] = t.value();
    double norm2 = 0;
    for (int v = 0; v < N; ++v) {
      s.gradient[3 * p + v] = t.c[1 + v];
      norm2 += t.c[1 + v] * t.c[1 + v];
    }
    s.gradient_norm[p] = std::sqrt(norm2);
    for (int k = 2; k <= K; ++k) {
      DerivativeArray& d = s.higher[k - 2];
      const std::size_t m = d.components.size();
      for (std::size_t c = 0; c < m; ++c) d.values[p * m + c] = t.derivative_at(positions[k][c]);
    }
  }
}

// Values only in doubles: the batch evaluator runs them in SIMD lanes.
template <int N, int K>
using SampleScalar = std::conditional_t<K == 0, double, Tuple<N, K>>;

template <int N, int K>
FieldSamples sample(const Tape& tape, const Grid& grid, const Progress& progress, const Approximation* approximation) {
  using T = SampleScalar<N, K>;
  std::vector<std::vector<int>> positions;
  FieldSamples s = empty_samples<N, K>(grid.size(), positions);
  s.grid = grid;
  s.far_field_tolerance = approximation ? approximation->tolerance : 0.0;
  s.far_faces = approximation && approximation->far_faces && grid.dimension == 3 && K <= 1;
  for_each_grid_point_pruned<T>(
      tape, grid, [&](std::size_t p, const auto& eval) { store<N, K>(s, p, eval.result(), positions); }, progress,
      approximation);
  return s;
}

/// At each of `points`, in groups pruned (and patched, with an
/// approximation) to their boxes, on all cores (pruned_points.hpp).
template <int N, int K>
FieldSamples sample_at(const Tape& tape, const std::vector<std::array<double, 3>>& points,
                       const Approximation* approximation) {
  using T = SampleScalar<N, K>;
  std::vector<std::vector<int>> positions;
  FieldSamples s = empty_samples<N, K>(points.size(), positions);
  s.far_field_tolerance = approximation ? approximation->tolerance : 0.0;
  for_each_point_pruned<T>(
      tape, points, [&](std::size_t p, const auto& eval) { store<N, K>(s, p, eval.result(), positions); },
      approximation);
  return s;
}

template <int N, int K = 0>
FieldSamples dispatch_points(const Tape& tape, const std::vector<std::array<double, 3>>& points, int order,
                             const Approximation* approximation) {
  if constexpr (K > kMaxSampleOrder) {
    throw std::invalid_argument("order " + std::to_string(order) + " is above the maximum " +
                                std::to_string(kMaxSampleOrder));
  } else {
    if (order == K) return sample_at<N, K>(tape, points, approximation);
    return dispatch_points<N, K + 1>(tape, points, order, approximation);
  }
}

template <int N, int K = 0>
FieldSamples dispatch(const Tape& tape, const Grid& grid, int order, const Progress& progress,
                      const Approximation* approximation) {
  if constexpr (K > kMaxSampleOrder) {
    throw std::invalid_argument("order " + std::to_string(order) + " is above the maximum " +
                                std::to_string(kMaxSampleOrder));
  } else {
    if (order == K) return sample<N, K>(tape, grid, progress, approximation);
    return dispatch<N, K + 1>(tape, grid, order, progress, approximation);
  }
}

// The largest |omega - exact omega| over `points` grid points (the same
// points every run), relative to the grid box's diagonal.
double far_faces_deviation(const Tape& tape, const Grid& grid, const std::vector<double>& omega, std::size_t points) {
  std::mt19937_64 random(20261206);
  std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
  constexpr std::size_t kBatch = 128;
  BatchEvaluator<double> exact(tape, kBatch);
  std::array<std::size_t, kBatch> index{};
  std::array<std::array<double, 3>, kBatch> at{};
  double deviation = 0;
  for (std::size_t done = 0; done < points; done += kBatch) {
    const std::size_t count = std::min(kBatch, points - done);
    for (std::size_t l = 0; l < count; ++l) {
      index[l] = pick(random);
      at[l] = grid.point(index[l]);
    }
    exact.evaluate(at.data(), count);
    for (std::size_t l = 0; l < count; ++l)
      deviation = std::max(deviation, std::fabs(omega[index[l]] - exact.result(l)));
  }
  return deviation / grid.diagonal();
}

FieldSamples dispatch_by_dimension(const Tape& tape, const Grid& grid, int order, const Progress& progress,
                                   const Approximation* approximation) {
  if (grid.dimension == 2) return dispatch<2>(tape, grid, order, progress, approximation);
  return dispatch<3>(tape, grid, order, progress, approximation);
}

}  // namespace

FieldSamples sample_field(const Tape& tape, const Grid& grid, int order, const Progress& progress,
                          const Approximation* approximation) {
  if (order < 0 || order > kMaxSampleOrder)
    throw std::invalid_argument("order must be from 0 to " + std::to_string(kMaxSampleOrder));
  if (grid.dimension != tape.dimension()) throw std::invalid_argument("grid and tape dimensions differ");
  FieldSamples s = dispatch_by_dimension(tape, grid, order, progress, approximation);
  if (!s.far_faces) return s;
  s.far_faces_deviation = far_faces_deviation(tape, grid, s.omega, approximation->far_faces_check_points);
  if (s.far_faces_deviation <= approximation->far_faces_limit) return s;
  // Beyond the limit (a field too large for single precision's roundings):
  // exactly, saying so.
  Approximation exact = *approximation;
  exact.far_faces = false;
  const double deviation = s.far_faces_deviation;
  s = dispatch_by_dimension(tape, grid, order, progress, &exact);
  s.far_faces_rejected = true;
  s.far_faces_deviation = deviation;
  return s;
}

FieldSamples sample_points(const Tape& tape, const std::vector<std::array<double, 3>>& points, int order,
                           const Approximation* approximation) {
  if (order < 0 || order > kMaxSampleOrder)
    throw std::invalid_argument("order must be from 0 to " + std::to_string(kMaxSampleOrder));
  if (tape.dimension() == 2) return dispatch_points<2>(tape, points, order, approximation);
  return dispatch_points<3>(tape, points, order, approximation);
}

}  // namespace sage
