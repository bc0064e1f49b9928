#pragma once
// Uniform B-splines of degree n on a background grid of cells of width h.
//
// Along one axis, the spline with index i has its support on the cells
// i - n .. i (cell c covers [lo + c h, lo + (c + 1) h]), so a grid of
// `cells` cells carries cells + n splines, and on cell c the n + 1 splines
// c .. c + n are nonzero. With t in [0, 1] the local coordinate on cell c,
// entry j of the arrays below belongs to spline c + j.
//
// Values come from the recurrence of the cardinal B-spline
//     B_d(x) = (x B_{d-1}(x) + (d + 1 - x) B_{d-1}(x - 1)) / d,
// and derivatives from B_d'(x) = B_{d-1}(x) - B_{d-1}(x - 1); both per unit
// of t (divide derivatives by h for d/dx). Worked example, degree 1 at
// t = 0.25: values {0.75, 0.25}, derivatives {-1, 1}.

#include <array>

namespace sage::solver {

constexpr int kMaxDegree = 5;

/// Values and first derivatives (per unit t) of the degree + 1 splines
/// nonzero on a cell, at local coordinate t in [0, 1]. 0 <= degree <= kMaxDegree.
inline void bspline_on_cell(int degree, double t, double* values, double* derivatives) {
  std::array<double, kMaxDegree + 2> previous{};
  std::array<double, kMaxDegree + 2> current{};
  current[0] = 1.0;
  for (int d = 1; d <= degree; ++d) {
    previous = current;
    for (int j = 0; j <= d; ++j) {
      const double left = j > 0 ? previous[j - 1] : 0.0;  // B_{d-1}(x), starts one cell earlier
      const double right = j < d ? previous[j] : 0.0;     // B_{d-1}(x - 1)
      current[j] = ((t + d - j) * left + (1.0 - t + j) * right) / d;
    }
  }
  for (int j = 0; j <= degree; ++j) {
    values[j] = current[j];
    if (degree == 0) {
      derivatives[j] = 0.0;
    } else {
      const double left = j > 0 ? previous[j - 1] : 0.0;
      const double right = j < degree ? previous[j] : 0.0;
      derivatives[j] = left - right;
    }
  }
}

}  // namespace sage::solver
