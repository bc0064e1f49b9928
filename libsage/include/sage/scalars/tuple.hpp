#pragma once
// Tuple<N, K>: a truncated multivariate Taylor series, the automatic
// differentiation type of sage (paper 004, sec. 5.3).
//
// A tuple holds the value and every partial derivative through total order
// K of a function of N variables at one point. It stores Taylor
// coefficients, not derivatives:
//
//     c[alpha] = (d^|alpha| f / dx^alpha) / alpha!,   alpha! = a1! a2! ...
//
// in the graded layout of multi_index.hpp; derivative(alpha) applies the
// alpha! back. Products are Cauchy products of the series, and an
// elementary function g is applied by composing its univariate Taylor
// series at the value with the non-constant part of the argument.
//
// Worked example (N = 2, K = 2): f = x * y at (2, 3).
//   x = 2 + 1 dx          -> c = {2, 1, 0, 0, 0, 0}
//   y = 3 + 1 dy          -> c = {3, 0, 1, 0, 0, 0}
//   x * y = 6 + 3 dx + 2 dy + 1 dx dy
//                         -> c = {6, 3, 2, 0, 1, 0}
//   derivative({1,1}) = 1! 1! * 1 = 1 = d2f/dxdy.
//
// Why N and K are compile-time: a tuple is a fixed array on the stack, the
// product table is a constant, loops unroll, and nothing allocates while a
// tape runs. Dimension is a template parameter across sage (2 and 3), and
// the command line dispatches a run-time --order once to an instantiation.
//
// Singular points follow scalar.hpp (sqrt at 0: constant 0 tuple, and so on).

#include <sage/scalars/multi_index.hpp>
#include <sage/scalars/scalar.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sage {

template <int N, int K>
class Tuple {
  static_assert(N >= 1 && N <= 3, "tuples are for 1, 2 or 3 variables");
  static_assert(K >= 0 && K <= 10, "order must be in 0..10");

 public:
  static constexpr int dimension = N;
  static constexpr int order = K;
  static constexpr int size = multi_index_count(N, K);
  static constexpr MultiIndexTable<N, K> indices{};
  static constexpr ProductTable<N, K> products{};
  static constexpr ProductTable<N, K, true> nilpotent_products{};

  /// Taylor coefficients in the graded layout.
  std::array<double, size> c{};

  Tuple() = default;
  Tuple(double constant) { c[0] = constant; }  // NOLINT: implicit like a double

  /// The independent variable `var` at `value`.
  static Tuple variable(int var, double value) {
    Tuple t(value);
    if (K >= 1) t.c[1 + var] = 1.0;
    return t;
  }

  double value() const { return c[0]; }

  /// The partial derivative d^alpha f (alpha! times the coefficient).
  double derivative(const MultiIndex<N>& alpha) const {
    const int i = indices.find(alpha);
    return i < 0 ? 0.0 : c[i] * factorial_product(alpha);
  }
  /// The partial derivative at layout position i.
  double derivative_at(int i) const { return c[i] * factorial_product(indices.index[i]); }

  /// Gradient (first partials).
  std::array<double, N> gradient() const {
    std::array<double, N> g{};
    if constexpr (K >= 1)
      for (int v = 0; v < N; ++v) g[v] = c[1 + v];
    return g;
  }

  Tuple& operator+=(const Tuple& o) {
    for (int i = 0; i < size; ++i) c[i] += o.c[i];
    return *this;
  }
  Tuple& operator-=(const Tuple& o) {
    for (int i = 0; i < size; ++i) c[i] -= o.c[i];
    return *this;
  }
  Tuple& operator*=(double s) {
    for (double& x : c) x *= s;
    return *this;
  }

  static double factorial_product(const MultiIndex<N>& alpha) {
    double f = 1.0;
    for (int e : alpha)
      for (int k = 2; k <= e; ++k) f *= k;
    return f;
  }
};

// ---- arithmetic -------------------------------------------------------------

template <int N, int K>
Tuple<N, K> operator+(Tuple<N, K> a, const Tuple<N, K>& b) {
  return a += b;
}
template <int N, int K>
Tuple<N, K> operator-(Tuple<N, K> a, const Tuple<N, K>& b) {
  return a -= b;
}
template <int N, int K>
Tuple<N, K> operator-(Tuple<N, K> a) {
  return a *= -1.0;
}
template <int N, int K>
Tuple<N, K> operator*(Tuple<N, K> a, double s) {
  return a *= s;
}
template <int N, int K>
Tuple<N, K> operator*(double s, Tuple<N, K> a) {
  return a *= s;
}

// Mixed with doubles, so generic code can write t + 1.0 or 2.0 / t.
template <int N, int K>
Tuple<N, K> operator+(Tuple<N, K> a, double s) {
  a.c[0] += s;
  return a;
}
template <int N, int K>
Tuple<N, K> operator+(double s, Tuple<N, K> a) {
  return a + s;
}
template <int N, int K>
Tuple<N, K> operator-(Tuple<N, K> a, double s) {
  return a + (-s);
}
template <int N, int K>
Tuple<N, K> operator-(double s, const Tuple<N, K>& a) {
  return -a + s;
}
template <int N, int K>
Tuple<N, K> operator/(Tuple<N, K> a, double s) {
  for (double& x : a.c) x /= s;
  return a;
}

template <int N, int K>
Tuple<N, K> operator*(const Tuple<N, K>& a, const Tuple<N, K>& b) {
  Tuple<N, K> r;
  for (const auto& t : Tuple<N, K>::products.terms) r.c[t.out] += a.c[t.lhs] * b.c[t.rhs];
  return r;
}

/// g(a) from g's univariate Taylor coefficients g_k = g^(k)(a0) / k! at the
/// value a0 of a: sum_k g_k (a - a0)^k, by Horner's rule,
///     r_K = g_K,   r_k = r_(k+1) d + g_k,   d = a - a0.
/// d has no constant term, so r_k is multiplied by d at least k more
/// times: only its orders <= K - k can reach the result. Each step thus
/// computes a prefix of the (order-sorted) product table, about a third of
/// the work of K full products for K = 6.
template <int N, int K>
Tuple<N, K> compose(const Tuple<N, K>& a, const std::array<double, K + 1>& g) {
  Tuple<N, K> r(g[K]);
  const auto& table = Tuple<N, K>::nilpotent_products;
  for (int k = K - 1; k >= 0; --k) {
    Tuple<N, K> next(g[k]);
    const int n = table.prefix[K - k];
    for (int t = 0; t < n; ++t) {
      const auto& term = table.terms[t];
      next.c[term.out] += r.c[term.lhs] * a.c[term.rhs];
    }
    r = next;
  }
  return r;
}

/// Taylor coefficients of t -> (a0 + t)^r at t = 0, a0 != 0, from its
/// value g0 = a0^r.
template <int K>
std::array<double, K + 1> power_series_from(double g0, double a0, double r) {
  std::array<double, K + 1> g{};
  g[0] = g0;
  for (int k = 1; k <= K; ++k) g[k] = g[k - 1] * (r - k + 1) / (k * a0);
  return g;
}

/// Taylor coefficients of t -> (a0 + t)^r at t = 0, a0 != 0; the value is
/// the double evaluator's, bit for bit.
template <int K>
std::array<double, K + 1> power_series(double a0, double r) {
  return power_series_from<K>(sage::pow_real(a0, r), a0, r);
}

template <int N, int K>
Tuple<N, K> pow_int(const Tuple<N, K>& a, int n);

template <int N, int K>
Tuple<N, K> pow_real(const Tuple<N, K>& a, double r) {
  if (r == std::floor(r) && std::abs(r) < 0x1p20) return pow_int(a, static_cast<int>(r));
  const double a0 = a.value();
  if (a0 == 0.0) return Tuple<N, K>(std::pow(0.0, r));  // singular: derivatives 0
  if (a0 < 0.0 && r != std::floor(r)) return Tuple<N, K>(std::numeric_limits<double>::quiet_NaN());
  return compose(a, power_series<K>(a0, r));
}

/// Taylor coefficients of t -> (a0 + t)^n at t = 0 for n >= 0:
/// C(n, k) a0^(n - k), powers by sage::pow_int (the value then equals the
/// double evaluator's bit for bit, and no std::pow runs).
template <int K>
std::array<double, K + 1> integer_power_series(double a0, int n) {
  std::array<double, K + 1> g{};
  double binomial = 1.0;
  for (int k = 0; k <= std::min(n, K); ++k) {
    g[k] = binomial * sage::pow_int(a0, n - k);
    binomial = binomial * (n - k) / (k + 1);
  }
  return g;
}

template <int N, int K>
Tuple<N, K> pow_int(const Tuple<N, K>& a, int n) {
  const double a0 = a.value();
  if (a0 != 0.0 && n >= 0) return compose(a, integer_power_series<K>(a0, n));
  if (a0 != 0.0) return compose(a, power_series<K>(a0, n));
  if (n < 0) return Tuple<N, K>(std::numeric_limits<double>::infinity());
  std::array<double, K + 1> g{};  // (0 + t)^n = t^n exactly
  if (n <= K) g[n] = 1.0;
  return compose(a, g);
}

template <int N, int K>
Tuple<N, K> sqrt(const Tuple<N, K>& a) {
  if constexpr (K == 1) {
    // pow_real's arithmetic for r = 1/2 without its series machinery (R0
    // trees take one sqrt per node): the same numbers, bit for bit.
    const double a0 = a.value();
    if (!(a0 > 0.0)) return pow_real(a, 0.5);  // 0, negative or NaN
    const double root = std::sqrt(a0), slope = root * 0.5 / a0;
    Tuple<N, K> r;
    r.c[0] = root;
    for (int k = 1; k <= N; ++k) r.c[k] = slope * a.c[k];
    return r;
  } else {
    return pow_real(a, 0.5);
  }
}

template <int N, int K>
Tuple<N, K> square(const Tuple<N, K>& a) {
  return a * a;
}

template <int N, int K>
Tuple<N, K> operator/(const Tuple<N, K>& a, const Tuple<N, K>& b) {
  if (b.value() == 0.0) return Tuple<N, K>(a.value() / 0.0);  // pole: +-inf (or NaN for 0/0)
  return a * compose(b, power_series<K>(b.value(), -1.0));
}

template <int N, int K>
Tuple<N, K> operator/(double s, const Tuple<N, K>& b) {
  return Tuple<N, K>(s) / b;
}

template <int N, int K>
Tuple<N, K> div_safe(const Tuple<N, K>& a, const Tuple<N, K>& b) {
  return b.value() == 0.0 ? Tuple<N, K>(0.0) : a / b;
}

template <int N, int K>
Tuple<N, K> exp(const Tuple<N, K>& a) {
  std::array<double, K + 1> g{};
  g[0] = std::exp(a.value());
  for (int k = 1; k <= K; ++k) g[k] = g[k - 1] / k;
  return compose(a, g);
}

template <int N, int K>
Tuple<N, K> log(const Tuple<N, K>& a) {
  const double a0 = a.value();
  if (!(a0 > 0.0)) return Tuple<N, K>(std::log(a0));  // -inf at 0, NaN below
  std::array<double, K + 1> g{};
  g[0] = std::log(a0);
  double p = 1.0;
  for (int k = 1; k <= K; ++k) {
    p /= a0;
    g[k] = (k % 2 ? 1.0 : -1.0) * p / k;
  }
  return compose(a, g);
}

namespace detail {
// Taylor coefficients of sin (phase 0) or cos (phase 1) at x0: the k-th
// derivative of sin is sin(x0 + k pi/2), a cycle of s, c, -s, -c.
template <int K>
std::array<double, K + 1> trig_series(double x0, int phase) {
  const double s = std::sin(x0), co = std::cos(x0);
  const double cycle[4] = {s, co, -s, -co};
  std::array<double, K + 1> g{};
  double fact = 1.0;
  for (int k = 0; k <= K; ++k) {
    if (k > 0) fact *= k;
    g[k] = cycle[(k + phase) % 4] / fact;
  }
  return g;
}
}  // namespace detail

template <int N, int K>
Tuple<N, K> sin(const Tuple<N, K>& a) {
  return compose(a, detail::trig_series<K>(a.value(), 0));
}
template <int N, int K>
Tuple<N, K> cos(const Tuple<N, K>& a) {
  return compose(a, detail::trig_series<K>(a.value(), 1));
}

template <int N, int K>
Tuple<N, K> abs(const Tuple<N, K>& a) {
  if (a.value() > 0) return a;
  if (a.value() < 0) return -a;
  return Tuple<N, K>(0.0);
}

template <int N, int K>
Tuple<N, K> step(const Tuple<N, K>& a) {
  return Tuple<N, K>(step(a.value()));
}

template <int N, int K>
Tuple<N, K> clamp_nonneg(const Tuple<N, K>& a) {
  return a.value() > 0 ? a : Tuple<N, K>(0.0);
}

/// The R0 function x + y -+ sqrt(x^2 + y^2) of first-order tuples (value
/// and gradient; rfunction.hpp's r0_combine for every other type): R0
/// trees spend most of their time here. The value is the double
/// evaluator's, bit for bit.
namespace detail {
/// R0 of first-order tuples off the corner, given root = sqrt(x0^2 + y0^2)
/// and slope = sign * root * 0.5 / (x0^2 + y0^2) (rfunction_lanes.cpp computes
/// these a vector at a time).
template <int N>
Tuple<N, 1> r0_from_root(const Tuple<N, 1>& x, const Tuple<N, 1>& y, double sign, double root, double slope) {
  const double x0 = x.c[0], y0 = y.c[0];
  Tuple<N, 1> r;
  r.c[0] = x0 + y0 + sign * root;
  for (int k = 1; k <= N; ++k) r.c[k] = x.c[k] + y.c[k] + slope * (2.0 * x0 * x.c[k] + 2.0 * y0 * y.c[k]);
  return r;
}
}  // namespace detail

template <int N>
Tuple<N, 1> r0_combine(const Tuple<N, 1>& x, const Tuple<N, 1>& y, double sign) {
  const double x0 = x.c[0], y0 = y.c[0], r2 = x0 * x0 + y0 * y0;
  if (!(r2 > 0.0)) return x + y + sign * sqrt(clamp_nonneg(x * x + y * y));  // the corner (or NaN)
  const double root = std::sqrt(r2);
  return detail::r0_from_root(x, y, sign, root, sign * root * 0.5 / r2);
}

namespace detail {
/// The first-order Rp of nonzero arguments from its scalar factors: root =
/// pow_real(s0, 1 / p) of s0 = x0^p + y0^p > 0, slope = d root / d s0 and
/// px, py = p x0^(p-1), p y0^(p-1) (rfunction_lanes.cpp computes these a
/// vector at a time).
template <int N>
Tuple<N, 1> rp_from_factors(const Tuple<N, 1>& x, const Tuple<N, 1>& y, double sign, double root, double slope,
                            double px, double py) {
  Tuple<N, 1> out;
  out.c[0] = x.c[0] + y.c[0] + sign * root;
  for (int k = 1; k <= N; ++k) out.c[k] = x.c[k] + y.c[k] + sign * (slope * (px * x.c[k] + py * y.c[k]));
  return out;
}
}  // namespace detail

/// The Rp function x + y -+ (x^p + y^p)^(1/p) of first-order tuples
/// (rfunction.hpp's rp_combine for every other type): the general path's
/// arithmetic (the same series coefficients, the same order of operations,
/// so the same numbers bit for bit) without its tuple temporaries.
template <int N>
Tuple<N, 1> rp_combine(const Tuple<N, 1>& x, const Tuple<N, 1>& y, int p, double sign) {
  const double x0 = x.c[0], y0 = y.c[0], r = 1.0 / p;
  const double s0 = sage::pow_int(x0, p) + sage::pow_int(y0, p);
  if (x0 == 0.0 || y0 == 0.0 || !(s0 > 0.0) || p < 2)  // zero arguments, the corner, NaN
    return x + y + sign * pow_real(pow_int(x, p) + pow_int(y, p), r);
  const auto gx = integer_power_series<1>(x0, p), gy = integer_power_series<1>(y0, p);
  const auto g = power_series<1>(s0, r);
  return detail::rp_from_factors(x, y, sign, g[0], g[1], gx[1], gy[1]);
}

template <int N, int K>
Tuple<N, K> min(const Tuple<N, K>& a, const Tuple<N, K>& b) {
  if (a.value() < b.value()) return a;
  if (b.value() < a.value()) return b;
  return 0.5 * (a + b);
}
template <int N, int K>
Tuple<N, K> max(const Tuple<N, K>& a, const Tuple<N, K>& b) {
  if (a.value() > b.value()) return a;
  if (b.value() > a.value()) return b;
  return 0.5 * (a + b);
}

}  // namespace sage
