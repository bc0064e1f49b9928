#pragma once
// The numeric policy for plain doubles, and the list of functions every
// scalar type of sage provides (double here; Tuple, Interval and Expr in
// their own headers). Generic code (R-functions, primitives, the tape
// evaluator) calls these unqualified, inside namespace sage, so one source
// serves all four types.
//
// Singular points, fixed once for all types:
//  - sqrt(0) = 0 and pow(0, r) = 0 (r > 0, not an integer) have all
//    derivatives 0 (a tuple there is the constant 0). This is the value an
//    R0 corner gets: R0 conjunction of x and y at (0, 0) has gradient (1, 1).
//  - abs(0) = 0 with all derivatives 0; step(0) = 1/2, so min/max where both
//    arguments tie return the average of the two.
//  - div_safe(x, 0) = 0: the quotient used by symbolic derivatives of sqrt
//    and real powers, so that they agree with the tuple convention above.
//  - Outside a function's domain (sqrt or log of a negative number, a real
//    power of a negative number) doubles and tuples give NaN, as IEEE does;
//    R-functions clamp their radicands, which are >= 0 up to round-off.
//  - Poles (x / 0, pow(0, -n)) give +-inf as IEEE does.

#include <algorithm>
#include <cmath>

namespace sage {

inline double square(double x) { return x * x; }
inline double step(double x) { return x > 0 ? 1.0 : (x < 0 ? 0.0 : 0.5); }
inline double clamp_nonneg(double x) { return x > 0 ? x : 0.0; }
inline double div_safe(double x, double y) { return y == 0 ? 0.0 : x / y; }
inline double pow_int(double x, int n) {
  double r = 1.0, b = n < 0 ? 1.0 / x : x;
  for (unsigned e = n < 0 ? -static_cast<unsigned>(n) : static_cast<unsigned>(n); e; e >>= 1) {
    if (e & 1u) r *= b;
    b *= b;
  }
  return r;
}
/// x^r; r = 1/2, 1/4, 1/8 (the roots of R0 and of Rp for p = 4, 8) by one,
/// two or three square roots, several times faster than std::pow and, like
/// it, within an ulp. Tuples and intervals take their roots from here.
inline double pow_real(double x, double r) {
  if (r == -1.0) return 1.0 / x;  // the reciprocal, correctly rounded (quotients of tuples start from it)
  const int roots = r == 0.5 ? 1 : r == 0.25 ? 2 : r == 0.125 ? 3 : 0;
  if (roots == 0 || !(x > 0)) return std::pow(x, r);  // pow's zeros, NaNs and infinities
  for (int i = 0; i < roots; ++i) x = std::sqrt(x);
  return x;
}
inline double min(double a, double b) { return a < b ? a : (b < a ? b : 0.5 * (a + b)); }
inline double max(double a, double b) { return a > b ? a : (b > a ? b : 0.5 * (a + b)); }
using std::abs;
using std::cos;
using std::exp;
using std::log;
using std::sin;
using std::sqrt;

/// Scalar traits: how to lift a constant into a scalar type.
template <class T>
struct ScalarTraits {
  static T constant(double c) { return T(c); }
};

}  // namespace sage
