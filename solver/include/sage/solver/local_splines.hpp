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
  static_assert(D == 2 || D == 3, "local splines are for 2 or 3 dimensions");
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
    // Tensor products, x offset fastest: entry k = j0 + m j1 (+ m^2 j2).
    const int m = n + 1;
    const auto count = static_cast<std::size_t>(D == 2 ? m * m : m * m * m);
    if (value.size() != count) {
      value.resize(count);
      for (auto& g : gradient) g.resize(count);
    }
    if (with_hessian)
      for (auto& e : hessian) e.resize(count);
    // factor[axis][order]: value, first or second derivative along that axis.
    const std::array<double, kMaxDegree + 1>* factor[D][3];
    for (int axis = 0; axis < D; ++axis) {
      factor[axis][0] = &v[axis];
      factor[axis][1] = &d[axis];
      factor[axis][2] = &dd[axis];
    }
    // One product per entry; `orders` gives the derivative order per axis.
    auto expand = [&](std::vector<double>& out, const std::array<int, D>& orders) {
      const auto& f0 = *factor[0][orders[0]];
      const auto& f1 = *factor[1][orders[1]];
      if constexpr (D == 2) {
        for (int j1 = 0; j1 < m; ++j1)
          for (int j0 = 0; j0 < m; ++j0) out[static_cast<std::size_t>(j0 + m * j1)] = f0[j0] * f1[j1];
      } else {
        const auto& f2 = *factor[2][orders[2]];
        for (int j2 = 0; j2 < m; ++j2)
          for (int j1 = 0; j1 < m; ++j1) {
            const double f12 = f1[j1] * f2[j2];
            double* row = out.data() + static_cast<std::size_t>(m * (j1 + m * j2));
            for (int j0 = 0; j0 < m; ++j0) row[j0] = f0[j0] * f12;
          }
      }
    };
    expand(value, {});
    for (int c = 0; c < D; ++c) {
      std::array<int, D> orders{};
      orders[c] = 1;
      expand(gradient[c], orders);
    }
    if (!with_hessian) return;
    for (int a = 0; a < D; ++a)
      for (int b = a; b < D; ++b) {
        std::array<int, D> orders{};
        ++orders[a];
        ++orders[b];
        expand(hessian[static_cast<std::size_t>(hessian_index(a, b))], orders);
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
