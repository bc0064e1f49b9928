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

/// Values, first and (when `second_derivatives` is not null) second
/// derivatives (per unit t) of the degree + 1 splines nonzero on a cell, at
/// local coordinate t in [0, 1]. 0 <= degree <= kMaxDegree. Second
/// derivatives: B_d'' = B_{d-2}(x) - 2 B_{d-2}(x - 1) + B_{d-2}(x - 2).
inline void bspline_on_cell(int degree, double t, double* values, double* derivatives, double* second_derivatives) {
  // Levels d - 2, d - 1 and d of the recurrence; entry j is spline c + j,
  // and entries past d are 0 (never written).
  std::array<double, kMaxDegree + 2> before{}, previous{}, current{};
  current[0] = 1.0;
  for (int d = 1; d <= degree; ++d) {
    before = previous;
    previous = current;
    current[0] = (1.0 - t) * previous[0] / d;
    for (int j = 1; j <= d; ++j)  // previous[j - 1] starts one cell earlier than previous[j]
      current[j] = ((t + d - j) * previous[j - 1] + (1.0 - t + j) * previous[j]) / d;
  }
  values[0] = current[0];
  derivatives[0] = degree == 0 ? 0.0 : -previous[0];
  for (int j = 1; j <= degree; ++j) {
    values[j] = current[j];
    derivatives[j] = previous[j - 1] - previous[j];
  }
  if (!second_derivatives) return;
  for (int j = 0; j <= degree; ++j) {
    const double two_back = j >= 2 ? before[j - 2] : 0.0, one_back = j >= 1 ? before[j - 1] : 0.0;
    second_derivatives[j] = degree < 2 ? 0.0 : two_back - 2.0 * one_back + before[j];
  }
}

/// Values and first derivatives only.
inline void bspline_on_cell(int degree, double t, double* values, double* derivatives) {
  bspline_on_cell(degree, t, values, derivatives, nullptr);
}

}  // namespace sage::solver
