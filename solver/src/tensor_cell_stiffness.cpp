#include <sage/solver/bspline.hpp>
#include <sage/solver/gauss.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include <algorithm>
#include <stdexcept>

namespace sage::solver {

TensorCellStiffness::TensorCellStiffness(int degree, int points, double h) : m_(degree + 1), q_(points) {
  if (degree < 0 || degree > kMaxDegree || points < 1) throw std::invalid_argument("TensorCellStiffness: bad sizes");
  const GaussRule& rule = gauss_legendre(points);
  const int pairs = m_ * m_;
  value_value_.resize(static_cast<std::size_t>(q_ * pairs));
  mixed_.resize(value_value_.size());
  slope_slope_.resize(value_value_.size());
  for (int q = 0; q < q_; ++q) {
    std::array<double, kMaxDegree + 1> b{}, d{};
    bspline_on_cell(degree, rule.nodes[static_cast<std::size_t>(q)], b.data(), d.data());
    for (int j = 0; j < m_; ++j) d[static_cast<std::size_t>(j)] /= h;
    for (int j = 0; j < m_; ++j)
      for (int l = 0; l < m_; ++l) {
        const auto at = static_cast<std::size_t>(q * pairs + j * m_ + l);
        const auto uj = static_cast<std::size_t>(j), ul = static_cast<std::size_t>(l);
        value_value_[at] = b[uj] * b[ul];
        mixed_[at] = b[uj] * d[ul] + d[uj] * b[ul];
        slope_slope_[at] = d[uj] * d[ul];
      }
  }
  const auto pairs_u = static_cast<std::size_t>(pairs), q_u = static_cast<std::size_t>(q_);
  for (auto* y : {&y_mixed_, &y_c1y_, &y_c1z_, &y_c2_}) y->resize(q_u * q_u * pairs_u);
  for (auto* z : {&z_value_, &z_c1z_, &z_c2_}) z->resize(q_u * pairs_u * pairs_u);
  s_.resize(pairs_u * pairs_u * pairs_u);
}

void TensorCellStiffness::compute(const double* c0, const std::array<const double*, 3>& c1, const double* c2,
                                  Eigen::MatrixXd& stiffness) {
  const int P = m_ * m_, Q = q_;
  const double *vv = value_value_.data(), *mx = mixed_.data(), *ss = slope_slope_.data();
  // Axis 0: Y[q1 + Q q2][pair0]. y_mixed holds the terms that are plain
  // values along axes 1 and 2 (c0, c1_x, c2 along x); the others keep
  // their coefficient for a later axis.
  for (auto* y : {&y_mixed_, &y_c1y_, &y_c1z_, &y_c2_}) std::fill(y->begin(), y->end(), 0.0);
  for (int r = 0; r < Q * Q; ++r) {
    double *ym = y_mixed_.data() + r * P, *yy = y_c1y_.data() + r * P, *yz = y_c1z_.data() + r * P,
           *y2 = y_c2_.data() + r * P;
    for (int q0 = 0; q0 < Q; ++q0) {
      const int p = q0 + Q * r;
      const double a0 = c0[p], ax = c1[0][p], ay = c1[1][p], az = c1[2][p], a2 = c2[p];
      const double *v = vv + q0 * P, *x = mx + q0 * P, *s = ss + q0 * P;
      for (int k = 0; k < P; ++k) {
        ym[k] += v[k] * a0 + x[k] * ax + s[k] * a2;
        yy[k] += v[k] * ay;
        yz[k] += v[k] * az;
        y2[k] += v[k] * a2;
      }
    }
  }
  // Axis 1: Z[q2][pair1 * P + pair0].
  for (auto* z : {&z_value_, &z_c1z_, &z_c2_}) std::fill(z->begin(), z->end(), 0.0);
  for (int q2 = 0; q2 < Q; ++q2)
    for (int q1 = 0; q1 < Q; ++q1) {
      const int r = q1 + Q * q2;
      const double *ym = y_mixed_.data() + r * P, *yy = y_c1y_.data() + r * P, *yz = y_c1z_.data() + r * P,
                   *y2 = y_c2_.data() + r * P;
      for (int pair1 = 0; pair1 < P; ++pair1) {
        const double v = vv[q1 * P + pair1], x = mx[q1 * P + pair1], s = ss[q1 * P + pair1];
        double *zv = z_value_.data() + (q2 * P + pair1) * P, *zz = z_c1z_.data() + (q2 * P + pair1) * P,
               *z2 = z_c2_.data() + (q2 * P + pair1) * P;
        for (int k = 0; k < P; ++k) {
          zv[k] += v * ym[k] + x * yy[k] + s * y2[k];
          zz[k] += v * yz[k];
          z2[k] += v * y2[k];
        }
      }
    }
  // Axis 2: S[pair2][pair1 * P + pair0].
  std::fill(s_.begin(), s_.end(), 0.0);
  const int PP = P * P;
  for (int q2 = 0; q2 < Q; ++q2) {
    const double *zv = z_value_.data() + q2 * PP, *zz = z_c1z_.data() + q2 * PP, *z2 = z_c2_.data() + q2 * PP;
    for (int pair2 = 0; pair2 < P; ++pair2) {
      const double v = vv[q2 * P + pair2], x = mx[q2 * P + pair2], s = ss[q2 * P + pair2];
      double* out = s_.data() + pair2 * PP;
      for (int k = 0; k < PP; ++k) out[k] += v * zv[k] + x * zz[k] + s * z2[k];
    }
  }
  // S_jl with j = j0 + m j1 + m^2 j2, l likewise, pair_a = j_a m + l_a.
  const int m = m_, local = m * m * m;
  stiffness.resize(local, local);
  for (int l = 0; l < local; ++l) {
    const int l0 = l % m, l1 = (l / m) % m, l2 = l / (m * m);
    double* column = stiffness.col(l).data();
    for (int j = 0; j < local; ++j) {
      const int j0 = j % m, j1 = (j / m) % m, j2 = j / (m * m);
      column[j] = s_[static_cast<std::size_t>((j2 * m + l2) * PP + (j1 * m + l1) * P + j0 * m + l0)];
    }
  }
}

}  // namespace sage::solver
