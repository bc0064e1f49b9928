#pragma once
// BackgroundGrid<D>: the uniform grid of square (cubic) cells that carries
// the B-spline basis, laid over the domain's bounding box but not fitted to
// the domain. Cell edges sit on the lattice h Z^D (the grid is anchored at
// the origin, not at the box), so moving a domain by a fraction of h moves
// its boundary across the cells, which is what the conditioning test needs.
//
// Cells and splines are numbered with x fastest. Along axis a there are
// cells[a] cells and cells[a] + degree splines (bspline.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace sage::solver {

template <int D>
struct BackgroundGrid {
  std::array<double, D> lo{};
  double h = 1.0;
  std::array<int, D> cells{};
  int degree = 3;

  /// The grid of cell width h covering [min, max].
  static BackgroundGrid covering(const std::array<double, D>& min, const std::array<double, D>& max, double h,
                                 int degree) {
    if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("cell width must be positive");
    BackgroundGrid g;
    g.h = h;
    g.degree = degree;
    for (int a = 0; a < D; ++a) {
      const double first = std::floor(min[a] / h), last = std::ceil(max[a] / h);
      g.lo[a] = first * h;
      g.cells[a] = std::max(1, static_cast<int>(last - first));
    }
    return g;
  }

  std::size_t cell_count() const {
    std::size_t n = 1;
    for (int a = 0; a < D; ++a) n *= static_cast<std::size_t>(cells[a]);
    return n;
  }
  std::array<int, D> cell_index(std::size_t linear) const {
    std::array<int, D> c{};
    for (int a = 0; a < D; ++a) {
      c[a] = static_cast<int>(linear % static_cast<std::size_t>(cells[a]));
      linear /= static_cast<std::size_t>(cells[a]);
    }
    return c;
  }
  std::array<double, D> cell_lo(const std::array<int, D>& c) const {
    std::array<double, D> p{};
    for (int a = 0; a < D; ++a) p[a] = lo[a] + c[a] * h;
    return p;
  }
  /// The cell holding x (clamped to the grid).
  std::array<int, D> cell_of(const double* x) const {
    std::array<int, D> c{};
    for (int a = 0; a < D; ++a) {
      const int i = static_cast<int>(std::floor((x[a] - lo[a]) / h));
      c[a] = std::min(std::max(i, 0), cells[a] - 1);
    }
    return c;
  }

  int splines_along(int axis) const { return cells[axis] + degree; }
  std::size_t spline_count() const {
    std::size_t n = 1;
    for (int a = 0; a < D; ++a) n *= static_cast<std::size_t>(splines_along(a));
    return n;
  }
  std::size_t spline_linear(const std::array<int, D>& i) const {
    std::size_t k = 0;
    for (int a = D - 1; a >= 0; --a)
      k = k * static_cast<std::size_t>(splines_along(a)) + static_cast<std::size_t>(i[a]);
    return k;
  }
  std::array<int, D> spline_index(std::size_t linear) const {
    std::array<int, D> i{};
    for (int a = 0; a < D; ++a) {
      i[a] = static_cast<int>(linear % static_cast<std::size_t>(splines_along(a)));
      linear /= static_cast<std::size_t>(splines_along(a));
    }
    return i;
  }
  /// The Greville point of spline i (the centre of its support, cells
  /// i - degree .. i): a linear function's B-spline coefficients are its
  /// values there.
  std::array<double, D> greville(const std::array<int, D>& i) const {
    std::array<double, D> x{};
    for (int a = 0; a < D; ++a) x[a] = lo[a] + h * (i[a] + 0.5 * (1 - degree));
    return x;
  }
  /// Splines nonzero on one cell: (degree + 1)^D.
  int local_count() const {
    int n = 1;
    for (int a = 0; a < D; ++a) n *= degree + 1;
    return n;
  }
};

}  // namespace sage::solver
