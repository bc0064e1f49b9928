#pragma once
// R-functions (paper 004, sec. 2; FORMULAS.md): real functions whose sign
// behaves like a Boolean function of the signs of their arguments.
// Conjunction (intersection) takes the minus sign, disjunction (union) the
// plus sign, negation is -x. Sign convention: >= 0 means inside.
//
// | system            | x AND/OR y                                          |
// |-------------------|-----------------------------------------------------|
// | minmax            | min(x, y) / max(x, y)                               |
// | r0                | x + y -+ sqrt(x^2 + y^2)                            |
// | ralpha:A          | (x + y -+ sqrt(x^2 + y^2 - 2 A x y)) / (1 + A)      |
// | ralpha:var        | as ralpha with A = 1 / (1 + x^2 + y^2)              |
// | rp:P  (P even)    | x + y -+ (x^P + y^P)^(1/P)                          |
// | rm:M  (M even)    | (x + y -+ sqrt(x^2 + y^2)) (x^2 + y^2)^(M/2)        |
//
// Properties (tested in tests/libsage/rfunction_test.cpp): r0 is normalized
// to order 1 on the region's boundary away from the corner; rp to order
// P - 1; rm is M times differentiable at the corner with all partials 0
// there, not normalized; minmax is not differentiable on x = y.
//
// Every formula is generic over the scalar type (double, Tuple, Interval,
// Expr). Intervals get an exact rule for the monotone systems (minmax, r0,
// ralpha with constant A, rp): the result's ends are the function at the
// arguments' ends, each enclosed by interval arithmetic on point intervals.
//
// n-ary forms reduce as a balanced binary tree (see r_conjunction_n): the
// R-conjunction is associative in sign but not in value, so the shape is a
// choice. A balanced tree keeps the depth log2(n), so the field of n
// halfspaces is symmetric in them up to the pairing, values do not drift
// with the position in a long chain, and interval bounds stay tight.

#include <sage/scalars/interval.hpp>
#include <sage/scalars/scalar.hpp>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage {

/// Largest P of rp:P and M of rm:M. x^P under- and overflows doubles
/// beyond it: with P = 64, x^P + y^P is 0 for |x|, |y| < 1e-5 (giving the
/// wrong sign) and inf above 6e4 (GIS coordinates in metres).
constexpr int kMaxEvenParameter = 16;

enum class RKind : int { MinMax = 0, R0 = 1, RAlpha = 2, RAlphaVariable = 3, Rp = 4, Rm = 5 };

/// An R-function system and its parameter (alpha, p or m).
struct RSystem {
  RKind kind = RKind::R0;
  double parameter = 0.0;

  static RSystem min_max() { return {RKind::MinMax, 1.0}; }
  static RSystem r0() { return {RKind::R0, 0.0}; }
  static RSystem r_alpha(double alpha);
  static RSystem r_alpha_variable() { return {RKind::RAlphaVariable, 0.0}; }
  static RSystem r_p(int p);
  static RSystem r_m(int m);

  /// Parses "minmax", "r0", "ralpha:A", "ralpha:var", "rp:P", "rm:M".
  /// Throws std::invalid_argument with a message saying what is wrong.
  static RSystem parse(const std::string& text);
  std::string name() const;
  /// Monotone systems have the exact interval rule.
  bool is_monotone() const { return kind != RKind::Rm && kind != RKind::RAlphaVariable; }

  bool operator==(const RSystem&) const = default;
};

/// R0: x + y -+ sqrt(x^2 + y^2) (sign = -1 conjunction, +1 disjunction).
template <class T>
inline T r0_combine(const T& x, const T& y, double sign) {
  return x + y + sign * sqrt(clamp_nonneg(square(x) + square(y)));
}

/// Rp: x + y -+ (x^p + y^p)^(1/p), p even.
template <class T>
inline T rp_combine(const T& x, const T& y, int p, double sign) {
  return x + y + sign * pow_real(pow_int(x, p) + pow_int(y, p), 1.0 / p);
}

/// The R-function of the system: sign = -1 conjunction, +1 disjunction.
template <class T>
T r_combine(const T& x, const T& y, const RSystem& s, double sign) {
  switch (s.kind) {
    case RKind::MinMax: return sign < 0 ? min(x, y) : max(x, y);
    case RKind::R0: return r0_combine(x, y, sign);
    case RKind::RAlpha: {
      // x^2 + y^2 - 2 a x y, written so that at most half of it cancels:
      // as given it loses everything near x = y when a -> 1 (alpha = 1 was
      // min/max only to sqrt(machine epsilon), with partials of either sign).
      const double a = s.parameter;
      const T radicand =
          a >= 0 ? square(x - y) + (2.0 * (1.0 - a)) * (x * y) : square(x + y) - (2.0 * (1.0 + a)) * (x * y);
      return (x + y + sign * sqrt(clamp_nonneg(radicand))) * (1.0 / (1.0 + a));
    }
    case RKind::RAlphaVariable: {
      const T r2 = square(x) + square(y);
      const T a = T(1.0) / (T(1.0) + r2);
      return (x + y + sign * sqrt(clamp_nonneg(r2 - T(2.0) * a * (x * y)))) / (T(1.0) + a);
    }
    case RKind::Rp: return rp_combine(x, y, static_cast<int>(s.parameter), sign);
    case RKind::Rm: {
      const int m = static_cast<int>(s.parameter);
      const T r2 = square(x) + square(y);
      return (x + y + sign * sqrt(clamp_nonneg(r2))) * pow_int(r2, m / 2);
    }
  }
  return x;
}

/// Interval version: exact end-point rule for monotone systems.
inline Interval r_combine(const Interval& x, const Interval& y, const RSystem& s, double sign) {
  if (!s.is_monotone()) return r_combine<Interval>(x, y, s, sign);
  const Interval lo = r_combine<Interval>(Interval(x.lo), Interval(y.lo), s, sign);
  const Interval hi = r_combine<Interval>(Interval(x.hi), Interval(y.hi), s, sign);
  // Infinite ends (inf - inf) make NaN: fall back to the whole line there.
  return {std::isnan(lo.lo) ? -detail::kInf : lo.lo, std::isnan(hi.hi) ? detail::kInf : hi.hi};
}

template <class T>
T r_and(const T& x, const T& y, const RSystem& s) {
  return r_combine(x, y, s, -1.0);
}
template <class T>
T r_or(const T& x, const T& y, const RSystem& s) {
  return r_combine(x, y, s, +1.0);
}
template <class T>
T r_not(const T& x) {
  return -x;
}

/// n-ary R-conjunction / disjunction as a balanced binary tree:
/// ((a0 . a1) . (a2 . a3)) . ... Requires at least one argument.
template <class T, class Combine>
T reduce_balanced(std::vector<T> args, Combine combine) {
  if (args.empty()) throw std::invalid_argument("an n-ary R-function needs at least one argument");
  while (args.size() > 1) {
    std::vector<T> next;
    next.reserve((args.size() + 1) / 2);
    for (std::size_t i = 0; i + 1 < args.size(); i += 2) next.push_back(combine(args[i], args[i + 1]));
    if (args.size() % 2) next.push_back(args.back());
    args = std::move(next);
  }
  return args.front();
}

template <class T>
T r_conjunction_n(std::vector<T> args, const RSystem& s) {
  return reduce_balanced(std::move(args), [&](const T& a, const T& b) { return r_and(a, b, s); });
}
template <class T>
T r_disjunction_n(std::vector<T> args, const RSystem& s) {
  return reduce_balanced(std::move(args), [&](const T& a, const T& b) { return r_or(a, b, s); });
}

}  // namespace sage
