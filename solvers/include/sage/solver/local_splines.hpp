#pragma once
// The (n + 1)^D tensor-product B-splines nonzero on one grid cell, with
// their gradients, at a point of the cell. Local spline k has offsets
// m = (k mod (n+1), (k / (n+1)) mod (n+1), ...) from the cell: it is the
// global spline cell + m (bspline.hpp), x offset fastest. Second
// derivatives on request (Rvachev's Robin structure needs them):
// hessian[hessian_index(a, b)][k] = d^2 B_k / dx_a dx_b.

#include <sage/solver/background_grid.hpp>
#include <sage/solver/bspline.hpp>

#include <array>
#include <vector>

namespace sage::solver {

template <int D>
struct LocalSplines {
  std::vector<double> value;
  std::array<std::vector<double>, D> gradient;  // gradient[a][k] = d B_k / d x_a
  static constexpr int kHessianEntries = D * (D + 1) / 2;
  std::array<std::vector<double>, kHessianEntries> hessian;  // filled by evaluate(..., true)

  /// Position of the pair (a, b) in `hessian`: (0,0), (1,1), .., then (0,1), (0,2), (1,2).
  static constexpr int hessian_index(int a, int b) {
    if (a == b) return a;
    const int lo = a < b ? a : b, hi = a < b ? b : a;
    return D + lo + hi - 1;
  }

  void evaluate(const BackgroundGrid<D>& grid, const std::array<int, D>& cell, const double* x,
                bool with_hessian = false) {
    const int n = grid.degree;
    std::array<std::array<double, kMaxDegree + 1>, D> v{}, d{}, dd{};
    for (int a = 0; a < D; ++a) {
      const double t = (x[a] - grid.lo[a]) / grid.h - cell[a];
      bspline_on_cell(n, t, v[a].data(), d[a].data(), with_hessian ? dd[a].data() : nullptr);
      for (int j = 0; j <= n; ++j) {
        d[a][j] /= grid.h;
        dd[a][j] /= grid.h * grid.h;
      }
    }
    // Tensor expansion axis by axis (x fastest): after axis a the arrays
    // hold the products over axes 0..a, for every offset combination.
    value.assign(1, 1.0);
    for (int c = 0; c < D; ++c) gradient[c].assign(1, 1.0);
    for (int a = 0; a < D; ++a) {
      const std::size_t length = value.size();
      value.resize(length * static_cast<std::size_t>(n + 1));
      for (int c = 0; c < D; ++c) gradient[c].resize(value.size());
      for (int m = n; m >= 0; --m) {  // backwards: entries [0, length) are read last
        const std::size_t base = length * static_cast<std::size_t>(m);
        for (std::size_t j = 0; j < length; ++j) value[base + j] = value[j] * v[a][m];
        for (int c = 0; c < D; ++c) {
          const double factor = c == a ? d[a][m] : v[a][m];
          for (std::size_t j = 0; j < length; ++j) gradient[c][base + j] = gradient[c][j] * factor;
        }
      }
    }
    if (!with_hessian) return;
    for (int a = 0; a < D; ++a)
      for (int b = a; b < D; ++b) {
        std::vector<double>& entry = hessian[static_cast<std::size_t>(hessian_index(a, b))];
        entry.assign(1, 1.0);
        for (int axis = 0; axis < D; ++axis) {
          const int order = (axis == a) + (axis == b);
          const auto& factor = order == 0 ? v[axis] : order == 1 ? d[axis] : dd[axis];
          const std::size_t length = entry.size();
          entry.resize(length * static_cast<std::size_t>(n + 1));
          for (int m = n; m >= 0; --m)
            for (std::size_t j = 0; j < length; ++j)
              entry[length * static_cast<std::size_t>(m) + j] = entry[j] * factor[m];
        }
      }
  }

  /// Global multi-index of local spline k on `cell`.
  static std::array<int, D> global_index(const std::array<int, D>& cell, int degree, int k) {
    std::array<int, D> i{};
    for (int a = 0; a < D; ++a) {
      i[a] = cell[a] + k % (degree + 1);
      k /= degree + 1;
    }
    return i;
  }
};

}  // namespace sage::solver
