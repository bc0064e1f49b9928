// A 1D study behind the Robin structure's second function (README,
// "Robin structure"): which trial space keeps the rates of degree n when
// the Robin condition is built into the trial functions.
//
// Problem: -u'' = f on (0, 1), u = cos 3x + x^2; Robin -u'(0) + beta u(0) =
// h at x = 0 (beta = 1; W = x is the normalized field of that end, D1 =
// d/dx) and u(1) = g at x = 1. B-splines of degree n on uniform cells;
// P = (1 - x) Phi + g carries the Dirichlet end; V = W (1 - W / delta)_+^8
// cuts the structure off at distance delta from the Robin end.
//   weak        u = P, the Robin condition in the weak form;
//   one field   u = P - V P' + V (beta P - h): `sage solve --robin
//               structure` before its second function, delta = h^(1/n);
//   two fields  the same + V W Q, Q a second spline on the B-splines that
//               meet the band: Rvachev's second component, which absorbs
//               V times the Robin defect so that P needs no layer.
// Every trial function meets the Robin condition exactly (V = 0, V' = 1
// and (V W Q)' = 0 at x = 0). Galerkin: int u' v' + beta u(0) v(0) = int f v
// + h v(0). Prints relative L2 and H1 errors, their rates, and the
// condition number of the Jacobi-scaled matrix (dense; 8 to 256 cells).
//
//   robin_structure_study [DEGREE]   (default 3; 2 to 5)

#include <sage/solver/bspline.hpp>
#include <sage/solver/gauss.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

namespace {

using sage::solver::bspline_on_cell;
using sage::solver::kMaxDegree;

constexpr double kBeta = 1.0;
double exact(double x) { return std::cos(3 * x) + x * x; }
double exact_slope(double x) { return -3 * std::sin(3 * x) + 2 * x; }
double source(double x) { return 9 * std::cos(3 * x) - 2; }
const double kRobinData = -exact_slope(0) + kBeta * exact(0);
const double kDirichletData = exact(1);

enum class Route { Weak, OneField, TwoFields };

// V = x (1 - x / delta)^8 below delta, and its first two derivatives.
std::array<double, 3> cut_off_weight(double x, double delta) {
  if (x >= delta) return {0, 0, 0};
  const double s = 1 - x / delta, p = 8;
  return {x * std::pow(s, p), std::pow(s, p) - x * p / delta * std::pow(s, p - 1),
          -2 * p / delta * std::pow(s, p - 1) + x * p * (p - 1) / (delta * delta) * std::pow(s, p - 2)};
}

struct Result {
  double l2, h1, condition;
};

Result solve(int n, int cells, Route route, double delta) {
  const double h = 1.0 / cells;
  const int splines = cells + n;  // spline i lives on cells i - n .. i
  // Q's splines: the first ones, whose support [(i - n) h, (i + 1) h] meets
  // (0, delta) by more than round-off (V W Q = 0 beyond delta).
  int band_splines = 0;
  while (route == Route::TwoFields && band_splines < splines && (band_splines - n) * h < delta - 1e-9 * h)
    ++band_splines;
  const int unknowns = splines + band_splines;

  // The trial functions' values and slopes at x, and the affine part's.
  Eigen::VectorXd value(unknowns), slope(unknowns);
  double offset = 0, offset_slope = 0;
  auto trial = [&](double x) {
    value.setZero();
    slope.setZero();
    const int cell = std::min(cells - 1, static_cast<int>(x / h));
    double b[kMaxDegree + 1], b1[kMaxDegree + 1], b2[kMaxDegree + 1];
    bspline_on_cell(n, x / h - cell, b, b1, b2);
    const auto v = route == Route::Weak ? std::array<double, 3>{0, 0, 0} : cut_off_weight(x, delta);
    const double omega = 1 - x;  // Dirichlet end
    for (int j = 0; j <= n; ++j) {
      const double s1 = b1[j] / h, s2 = b2[j] / (h * h);
      const double p = omega * b[j], p1 = omega * s1 - b[j], p2 = omega * s2 - 2 * s1;
      const int i = cell + j;
      value[i] = p - v[0] * p1 + v[0] * kBeta * p;
      slope[i] = p1 - v[1] * p1 - v[0] * p2 + kBeta * (v[1] * p + v[0] * p1);
      if (i < band_splines) {  // V W Q with W = x
        value[splines + i] = v[0] * x * b[j];
        slope[splines + i] = (v[1] * x + v[0]) * b[j] + v[0] * x * s1;
      }
    }
    // P's affine part is g; u's adds V (beta g - h).
    offset = kDirichletData + v[0] * (kBeta * kDirichletData - kRobinData);
    offset_slope = v[1] * (kBeta * kDirichletData - kRobinData);
  };

  // Gauss points on every cell, cells split at delta (V is C^7 there).
  std::vector<double> breaks;
  for (int c = 0; c <= cells; ++c) breaks.push_back(c * h);
  if (route != Route::Weak && delta < 1) breaks.push_back(delta);
  std::sort(breaks.begin(), breaks.end());
  const auto& rule = sage::solver::gauss_legendre(12);
  auto each_point = [&](const std::function<void(double, double)>& visit) {
    for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double a = breaks[k], width = breaks[k + 1] - a;
      if (width <= 0) continue;
      for (std::size_t q = 0; q < rule.nodes.size(); ++q) visit(a + width * rule.nodes[q], width * rule.weights[q]);
    }
  };

  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(unknowns, unknowns);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  each_point([&](double x, double w) {
    trial(x);
    matrix += w * slope * slope.transpose();
    rhs += w * (source(x) * value - offset_slope * slope);
  });
  trial(0.0);
  matrix += kBeta * value * value.transpose();
  rhs += (kRobinData - kBeta * offset) * value;
  const Eigen::VectorXd c = matrix.ldlt().solve(rhs);

  const Eigen::VectorXd scale = matrix.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(scale.asDiagonal() * matrix * scale.asDiagonal()).eigenvalues();
  double l2 = 0, h1 = 0, l2_norm = 0, h1_norm = 0;
  each_point([&](double x, double w) {
    trial(x);
    l2 += w * std::pow(value.dot(c) + offset - exact(x), 2);
    h1 += w * std::pow(slope.dot(c) + offset_slope - exact_slope(x), 2);
    l2_norm += w * exact(x) * exact(x);
    h1_norm += w * exact_slope(x) * exact_slope(x);
  });
  return {std::sqrt(l2 / l2_norm), std::sqrt(h1 / h1_norm), eigenvalues.maxCoeff() / eigenvalues.minCoeff()};
}

void table(const char* title, int n, Route route, const std::function<double(double)>& band) {
  std::printf("\n%s, degree %d\n%6s %8s %10s %10s %7s %7s %12s\n", title, n, "cells", "delta", "L2 rel.", "H1 rel.",
              "L2 rate", "H1 rate", "cond (Jacobi)");
  Result last{};
  for (int cells = 8; cells <= 256; cells *= 2) {
    const double delta = band(1.0 / cells);
    const Result r = solve(n, cells, route, delta);
    std::printf("%6d %8.4f %10.3e %10.3e", cells, route == Route::Weak ? 0.0 : delta, r.l2, r.h1);
    if (cells > 8)
      std::printf(" %7.2f %7.2f", std::log2(last.l2 / r.l2), std::log2(last.h1 / r.h1));
    else
      std::printf(" %7s %7s", "", "");
    std::printf(" %12.2e\n", r.condition);
    last = r;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 3;
  if (n < 2 || n > kMaxDegree) {
    std::fprintf(stderr, "robin_structure_study: degree must be 2 to %d\n", kMaxDegree);
    return 1;
  }
  std::printf("-u'' = f on (0, 1), u = cos 3x + x^2, Robin at 0 (beta = 1), Dirichlet at 1\n");
  table("weak", n, Route::Weak, [](double) { return 0.0; });
  table("one field, delta = h^(1/n)", n, Route::OneField, [n](double h) { return std::pow(h, 1.0 / n); });
  table("two fields, delta = 4 h", n, Route::TwoFields, [](double h) { return 4 * h; });
  table("two fields, delta = h^(2/3)", n, Route::TwoFields, [](double h) { return std::pow(h, 2.0 / 3); });
  table("two fields, delta = 0.3", n, Route::TwoFields, [](double) { return 0.3; });
  return 0;
}
