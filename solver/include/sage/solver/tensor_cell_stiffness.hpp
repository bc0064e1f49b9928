#pragma once
// The stiffness matrix of one inside cell of a 3D grid by sum
// factorization. Inside cells carry the tensor Gauss rule, and their
// (n + 1)^3 local B-splines are tensor products (local_splines.hpp), so
//
//     S_jl = sum_q [ c0 B_j B_l + sum_a c1_a (B_j d_a B_l + d_a B_j B_l)
//                    + c2 grad B_j . grad B_l ](x_q)
//
// is contracted one axis at a time: (n + 1)^2 pairs of 1D B-splines per
// axis, Q points per axis. For v_j = w B_j and k grad v_j . grad v_l with
// quadrature weight W: c0 = k W |grad w|^2, c1_a = k W w d_a w,
// c2 = k W w^2. Degree 3 with 4^3 points: about 75 thousand multiply-adds
// instead of 400 thousand for the rank update of the 64 x 192 gradients.
//
// Points are numbered x fastest (the order of ImplicitCellQuadrature's tensor
// rule), local splines too (k = j0 + (n+1) j1 + (n+1)^2 j2).

#include <Eigen/Core>

#include <array>
#include <vector>

namespace sage::solver {

class TensorCellStiffness {
 public:
  /// B-splines of `degree` at the `points` Gauss nodes of a cell of width h.
  TensorCellStiffness(int degree, int points, double h);

  int point_count() const { return q_ * q_ * q_; }
  /// Writes S (all entries) into `stiffness` ((n+1)^3 square); the
  /// coefficients are given per point.
  void compute(const double* c0, const std::array<const double*, 3>& c1, const double* c2, Eigen::MatrixXd& stiffness);

 private:
  int m_, q_;  // splines and points per axis
  // 1D pair products per point, index [q][j * m + l]: values x values,
  // values x slopes + slopes x values, slopes x slopes.
  std::vector<double> value_value_, mixed_, slope_slope_;
  std::vector<double> y_mixed_, y_c1y_, y_c1z_, y_c2_;  // after axis 0: [q1 + Q q2][pair0]
  std::vector<double> z_value_, z_c1z_, z_c2_;          // after axis 1: [q2][pair1 * m^2 + pair0]
  std::vector<double> s_;                               // [pair2][pair1][pair0]
};

}  // namespace sage::solver
