#pragma once
// One lane's arithmetic for the fused kernels (rfunction_lanes.cpp,
// smooth_trim.cpp, linear_form.cpp, trimmed_face.cpp), written once.
// A first-order tuple is an array of its N + 1 coefficients (value, then
// partials), a double is a double. Each step is the operators' arithmetic
// on their regular branch, operation for operation (tuple.hpp's for K = 1,
// scalar.hpp's for doubles), so a kernel built from steps gives the
// instructions' bits. Steps with another branch say whether the lane took
// the regular one; the others are the caller's to hand to the operators.
//
// Always inlined into loops over lanes, so the compiler keeps the arrays
// in vector registers: a kernel that chains steps never stores what it
// passes from one to the next.

#include <sage/scalars/tuple.hpp>
#include <sage/tape/linear_form.hpp>
#include <sage/tape/smooth_trim.hpp>

#include <cmath>

namespace sage::lane {

/// r0_combine(a, b, sign): value a0 + b0 + sign root, partials ak + bk +
/// slope (2 a0 ak + 2 b0 bk) with slope = sign root 0.5 / r2 (tuple.hpp's
/// detail::r0_from_root). Regular unless r2 = a0^2 + b0^2 is not > 0 (the
/// corner, or NaN).
template <int N>
[[gnu::always_inline]] inline bool r0(const double* a, const double* b, double sign, double* out) {
  const double r2 = a[0] * a[0] + b[0] * b[0];
  const bool regular = r2 > 0.0;
  const double safe = regular ? r2 : 1.0;  // a singular lane is redone by the operators
  const double root = std::sqrt(safe);
  const double slope = sign * root * 0.5 / safe;
  for (int k = 1; k <= N; ++k) out[k] = a[k] + b[k] + slope * (2.0 * a[0] * a[k] + 2.0 * b[0] * b[k]);
  out[0] = a[0] + b[0] + sign * root;
  return regular;
}

/// r0_combine<double>.
[[gnu::always_inline]] inline double r0(double a, double b, double sign) {
  const double r2 = a * a + b * b;
  return a + b + sign * std::sqrt(r2 > 0 ? r2 : 0.0);
}

/// square(a): value 0.0 + a0 a0, partials (0.0 + a0 ak) + ak a0 (the
/// product table accumulates into zeros).
template <int N>
[[gnu::always_inline]] inline void square(const double* a, double* out) {
  for (int k = 1; k <= N; ++k) out[k] = (0.0 + a[0] * a[k]) + a[k] * a[0];
  out[0] = 0.0 + a[0] * a[0];
}

/// The linear form's value, a p + b q + c k (+ d), from its arguments'
/// values: tuples through the product by a constant (0.0 + c0 k), doubles
/// as they are.
template <bool Tuples>
[[gnu::always_inline]] inline double linear_form_value(const LinearForm& f, double a0, double b0, double c0) {
  const double value = Tuples ? (a0 * f.p + b0 * f.q) + (0.0 + c0 * f.k) : (a0 * f.p + b0 * f.q) + c0 * f.k;
  return f.has_offset ? value + f.d : value;
}

/// A partial of the linear form: aj p + bj q + ((0.0 + c0 0.0) + cj k),
/// plus 0.0 for the Offset (T(d) has zero partials).
[[gnu::always_inline]] inline double linear_form_partial(const LinearForm& f, double c0, double aj, double bj,
                                                         double cj) {
  const double zero = 0.0 + c0 * 0.0;
  const double partial = (aj * f.p + bj * f.q) + (zero + cj * f.k);
  return f.has_offset ? partial + 0.0 : partial;
}

/// trim_smooth's run (smooth_trim.hpp) on tuples, each instruction as
/// tuple.hpp computes it:
///   Square      value 0.0 + a0 a0, partials (0.0 + a0 ak) + ak a0
///   h c (Scale) value 0.0 + h0 c, partials (0.0 + h0 0.0) + hk c
///   u^4         pow_int's powers by squaring: value (u0 u0)(u0 u0), slope
///               4.0 (u0 (u0 u0)), partials 0.0 + slope uk
///   sqrt        value sqrt(a0), slope sqrt(a0) 0.5 / a0, partials slope ak
///   Add, Axpby  by component, a p + b q
/// Regular unless u0 = 0 (pow_int's zero) or a root's argument is not > 0
/// (or NaN).
template <int N, bool Scale>
[[gnu::always_inline]] inline bool smooth_trim(const SmoothTrim& trim, const double* t, const double* h,
                                               const double* addend, double* w) {
  const double c = trim.scale, p = trim.root_weight, q = trim.t_weight;
  const double t0 = t[0], h0 = h[0];
  const double u0 = Scale ? 0.0 + h0 * c : h0;
  const double u2 = u0 * u0, slope_u = 4.0 * (u0 * u2);
  double a[N + 1];
  a[0] = (0.0 + t0 * t0) + u2 * u2;
  for (int k = 1; k <= N; ++k) {
    const double uk = Scale ? (0.0 + h0 * 0.0) + h[k] * c : h[k];
    a[k] = ((0.0 + t0 * t[k]) + t[k] * t0) + (0.0 + slope_u * uk);
  }
  const bool regular_a = a[0] > 0.0;
  const double a0 = regular_a ? a[0] : 1.0;
  const double r0 = std::sqrt(a0), slope_r = r0 * 0.5 / a0;
  double b[N + 1];
  const double m0 = r0 * p + t0 * q;
  b[0] = addend[0] + (0.0 + m0 * m0);
  for (int k = 1; k <= N; ++k) {
    const double mk = (slope_r * a[k]) * p + t[k] * q;
    b[k] = addend[k] + ((0.0 + m0 * mk) + mk * m0);
  }
  const bool regular_b = b[0] > 0.0;
  const double b0 = regular_b ? b[0] : 1.0;
  const double w0 = std::sqrt(b0), slope_w = w0 * 0.5 / b0;
  w[0] = w0;
  for (int k = 1; k <= N; ++k) w[k] = slope_w * b[k];
  return u0 != 0.0 && regular_a && regular_b;
}

/// trim_smooth's run through the operators, for the lanes where one of them
/// takes another branch.
template <int N>
Tuple<N, 1> smooth_trim_operators(const SmoothTrim& trim, const Tuple<N, 1>& t, const Tuple<N, 1>& h,
                                  const Tuple<N, 1>& addend) {
  const Tuple<N, 1> u = trim.has_scale ? h * Tuple<N, 1>(trim.scale) : h;
  const Tuple<N, 1> root = sqrt(square(t) + pow_int(u, 4));
  return sqrt(addend + square(root * trim.root_weight + t * trim.t_weight));
}

/// trim_smooth's run on doubles: t t, h c, (u u)(u u), sums, sqrt, R p + t q.
template <bool Scale>
[[gnu::always_inline]] inline double smooth_trim(const SmoothTrim& trim, double t, double h, double addend) {
  const double u = Scale ? h * trim.scale : h;
  const double u2 = u * u;
  const double m = std::sqrt(t * t + u2 * u2) * trim.root_weight + t * trim.t_weight;
  return std::sqrt(addend + m * m);
}

}  // namespace sage::lane
