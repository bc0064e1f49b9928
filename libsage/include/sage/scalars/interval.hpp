#pragma once
// Interval: a closed interval [lo, hi] of doubles with an enclosure promise.
//
// Promise: for every operation F and every x in X (y in Y),
// f(x, y) lies in F(X, Y) -- for the real-number f, not just for its
// floating-point evaluation. Rounding is outward: every computed end point
// is moved at least one ulp outward after +, -, *, /, sqrt (correctly rounded in
// IEEE 754, so one ulp is enough) and two ulps after exp, log, sin, cos and
// pow (glibc documents errors of at most one ulp or so for them). The
// rounding mode of the FPU is never changed, so intervals are safe to use
// from any thread.
//
// Worked example: [1, 2] * [-3, 1] = [min(-3, 1, -6, 2), max(...)]
//                 = [-6, 2], then widened to [-6 - 1 ulp, 2 + 1 ulp].
//
// Domain: sqrt, log and real powers enclose the function over the part of
// the interval inside their domain (an R-function radicand [-1e-17, 4] is
// treated as [0, 4]); an interval wholly outside the domain gives NaN ends.
// Division by an interval containing 0 gives the whole line. Singular-point
// conventions (step(0) = 1/2, div_safe(x, 0) = 0) are enclosed too.

#include <sage/scalars/scalar.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sage {

struct Interval {
  double lo = 0.0;
  double hi = 0.0;

  Interval() = default;
  Interval(double v) : lo(v), hi(v) {}  // NOLINT: implicit like a double
  Interval(double l, double h) : lo(l), hi(h) {}

  double width() const { return hi - lo; }
  double mid() const { return 0.5 * (lo + hi); }
  bool contains(double x) const { return lo <= x && x <= hi; }
  bool contains_zero() const { return lo <= 0.0 && 0.0 <= hi; }
  bool is_nan() const { return std::isnan(lo) || std::isnan(hi); }
};

namespace detail {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Moves x down (up) by at least `ulps` units in the last place. For finite
// x, |x| * 2^-52 is between one and two ulps of x, so subtracting it lands
// at least one representable number lower whatever the rounding; the step
// is at least DBL_MIN (the smallest normal number), which covers x = 0
// and keeps subnormal operands, which are very slow on x86, out of the
// arithmetic. Several times faster than std::nextafter. Infinities and
// NaN pass through.
inline double outward_step(double x) {
  const double d = std::abs(x) * 0x1p-52;
  return d > std::numeric_limits<double>::min() ? d : std::numeric_limits<double>::min();
}
inline double down(double x, int ulps = 1) {
  if (!std::isfinite(x)) return x;
  for (int i = 0; i < ulps; ++i) x -= outward_step(x);
  return x;
}
inline double up(double x, int ulps = 1) {
  if (!std::isfinite(x)) return x;
  for (int i = 0; i < ulps; ++i) x += outward_step(x);
  return x;
}
inline Interval outward(double lo, double hi, int ulps = 1) { return {down(lo, ulps), up(hi, ulps)}; }
// For results that are exact (negation, min, max, constants) no widening.
}  // namespace detail

inline Interval operator+(const Interval& a, const Interval& b) { return detail::outward(a.lo + b.lo, a.hi + b.hi); }
inline Interval operator-(const Interval& a, const Interval& b) { return detail::outward(a.lo - b.hi, a.hi - b.lo); }
inline Interval operator-(const Interval& a) { return {-a.hi, -a.lo}; }

inline Interval operator*(const Interval& a, const Interval& b) {
  if (a.is_nan() || b.is_nan()) return {NAN, NAN};
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  // With NaN operands excluded, a NaN product is 0 * inf: 0 for the
  // enclosure of a product of sets.
  double lo = detail::kInf, hi = -detail::kInf;
  for (double v : p) {
    if (std::isnan(v)) v = 0.0;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return detail::outward(lo, hi);
}

inline Interval operator/(const Interval& a, const Interval& b) {
  if (b.contains_zero()) return {-detail::kInf, detail::kInf};
  const double p[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
  return detail::outward(*std::min_element(p, p + 4), *std::max_element(p, p + 4));
}

inline Interval square(const Interval& a) {
  const double l = a.lo * a.lo, h = a.hi * a.hi;
  if (a.contains_zero()) return {0.0, detail::up(std::max(l, h))};
  return detail::outward(std::min(l, h), std::max(l, h));
}

inline Interval pow_int(const Interval& a, int n) {
  if (n == 0) return Interval(1.0);
  if (n < 0) return Interval(1.0) / pow_int(a, -n);
  // pow_int on doubles squares and multiplies about 2 log2(n) times, each
  // rounding by half an ulp: widen by twice that.
  int ulps = 2;
  for (int m = n; m > 1; m >>= 1) ulps += 2;
  const double l = sage::pow_int(a.lo, n), h = sage::pow_int(a.hi, n);
  if (n % 2 == 1) return detail::outward(l, h, ulps);
  if (a.contains_zero()) return {0.0, detail::up(std::max(l, h), ulps)};
  return detail::outward(std::min(l, h), std::max(l, h), ulps);
}

inline Interval sqrt(const Interval& a) {
  if (a.hi < 0) return {NAN, NAN};
  return {a.lo <= 0 ? 0.0 : detail::down(std::sqrt(a.lo)), detail::up(std::sqrt(a.hi))};
}

inline Interval pow_real(const Interval& a, double r) {
  if (r == std::floor(r) && std::abs(r) < 0x1p20) return pow_int(a, static_cast<int>(r));
  if (a.hi < 0) return {NAN, NAN};
  const double l = sage::pow_real(std::max(a.lo, 0.0), r), h = sage::pow_real(a.hi, r);  // monotone
  return detail::outward(std::min(l, h), std::max(l, h), 2);
}

inline Interval exp(const Interval& a) {
  return {std::max(0.0, detail::down(std::exp(a.lo), 2)), detail::up(std::exp(a.hi), 2)};
}

inline Interval log(const Interval& a) {
  if (a.hi < 0) return {NAN, NAN};
  return {a.lo <= 0 ? -detail::kInf : detail::down(std::log(a.lo), 2), detail::up(std::log(a.hi), 2)};
}

namespace detail {
// Range of cos over a: cos peaks at 2 k pi and dips at (2k+1) pi. k pi is
// computed in floating point, so an extremum within a relative 1e-15 of the
// interval counts as inside: including one that is not there only loosens
// the enclosure, missing one would break it.
inline Interval cos_range(const Interval& a) {
  if (a.is_nan()) return a;
  // Past 2^52, k pi can no longer be stepped through in doubles.
  if (!(a.width() < 2 * M_PI) || std::abs(a.lo) > 0x1p52 || std::abs(a.hi) > 0x1p52) return {-1.0, 1.0};
  double lo = std::min(std::cos(a.lo), std::cos(a.hi));
  double hi = std::max(std::cos(a.lo), std::cos(a.hi));
  const double k_first = std::floor(a.lo / M_PI) - 1, k_last = std::ceil(a.hi / M_PI) + 1;
  for (double k = k_first; k <= k_last; k += 1.0) {
    const double t = k * M_PI, tol = 1e-15 * (1.0 + std::abs(t));
    if (t < a.lo - tol || t > a.hi + tol) continue;
    if (std::fmod(std::abs(k), 2.0) == 0.0)
      hi = 1.0;
    else
      lo = -1.0;
  }
  return {std::max(-1.0, down(lo, 2)), std::min(1.0, up(hi, 2))};
}
}  // namespace detail

inline Interval cos(const Interval& a) { return detail::cos_range(a); }
inline Interval sin(const Interval& a) {
  // sin(x) = cos(x - pi/2); the shift is rounded, so widen it by an ulp each way.
  const double h = M_PI / 2;
  return detail::cos_range({detail::down(a.lo - h), detail::up(a.hi - h)});
}

inline Interval abs(const Interval& a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return -a;
  return {0.0, std::max(-a.lo, a.hi)};
}

inline Interval min(const Interval& a, const Interval& b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
inline Interval max(const Interval& a, const Interval& b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }
inline Interval step(const Interval& a) { return {step(a.lo), step(a.hi)}; }
inline Interval clamp_nonneg(const Interval& a) { return {std::max(a.lo, 0.0), std::max(a.hi, 0.0)}; }

inline Interval div_safe(const Interval& a, const Interval& b) {
  if (b.lo == 0.0 && b.hi == 0.0) return Interval(0.0);
  if (!b.contains_zero()) return a / b;
  return {-detail::kInf, detail::kInf};
}

/// Hull of two intervals.
inline Interval hull(const Interval& a, const Interval& b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

}  // namespace sage
