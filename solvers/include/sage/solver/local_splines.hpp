#pragma once
// The (n + 1)^D tensor-product B-splines nonzero on one grid cell, with
// their gradients, at a point of the cell. Local spline k has offsets
// m = (k mod (n+1), (k / (n+1)) mod (n+1), ...) from the cell: it is the
// global spline cell + m (bspline.hpp), x offset fastest.

#include <sage/solver/background_grid.hpp>
#include <sage/solver/bspline.hpp>

#include <array>
#include <vector>

namespace sage::solver {

template <int D>
struct LocalSplines {
  std::vector<double> value;
  std::vector<std::array<double, D>> gradient;

  void evaluate(const BackgroundGrid<D>& grid, const std::array<int, D>& cell, const double* x) {
    const int n = grid.degree, count = grid.local_count();
    value.resize(static_cast<std::size_t>(count));
    gradient.resize(static_cast<std::size_t>(count));
    std::array<std::array<double, kMaxDegree + 1>, D> v{}, d{};
    for (int a = 0; a < D; ++a) {
      const double t = (x[a] - grid.lo[a]) / grid.h - cell[a];
      bspline_on_cell(n, t, v[a].data(), d[a].data());
      for (int j = 0; j <= n; ++j) d[a][j] /= grid.h;
    }
    for (int k = 0; k < count; ++k) {
      std::array<int, D> m{};
      int rest = k;
      for (int a = 0; a < D; ++a) {
        m[a] = rest % (n + 1);
        rest /= n + 1;
      }
      double product = 1.0;
      for (int a = 0; a < D; ++a) product *= v[a][m[a]];
      value[k] = product;
      for (int a = 0; a < D; ++a) {
        double g = d[a][m[a]];
        for (int b = 0; b < D; ++b)
          if (b != a) g *= v[b][m[b]];
        gradient[k][a] = g;
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
