#include "partial_bounds.hpp"

#include <sage/scalars/rfunction.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sage::detail {

namespace {

constexpr double kUnknown = std::numeric_limits<double>::infinity();

double mag(const Interval& x) { return std::max(std::abs(x.lo), std::abs(x.hi)); }
double mig(const Interval& x) { return x.contains_zero() ? 0.0 : std::min(std::abs(x.lo), std::abs(x.hi)); }

// |x| / (|x|^p + |y|^p)^(1/p) for x, y >= 0, without overflow.
double ratio(double x, double y, int p) {
  if (x == 0.0) return 0.0;
  if (p == 2) return x / std::hypot(x, y);
  if (x >= y) return 1.0 / std::pow(1.0 + std::pow(y / x, p), 1.0 / p);
  const double t = x / y;
  return t / std::pow(1.0 + std::pow(t, p), 1.0 / p);
}

// Rp (R0 for p = 2): d/dx (x + y + sign (x^p + y^p)^(1/p)) = 1 + sign
// (x / rho)^(p - 1). x / rho grows with x, and for x < 0 falls as |y| falls
// (its derivative in x is y^p / rho^(p + 1)), so its extremes over the box
// lie at x's ends with |y| smallest (towards -1, 1) or largest (towards 0).
double rp_partial(const Interval& x, const Interval& y, int p, double sign) {
  if (sign < 0) {
    const double least = x.lo < 0 ? -ratio(-x.lo, mig(y), p) : ratio(x.lo, mag(y), p);
    return 1.0 - (p == 2 ? least : std::pow(least, p - 1));
  }
  const double most = x.hi > 0 ? ratio(x.hi, mig(y), p) : -ratio(-x.hi, mag(y), p);
  return 1.0 + (p == 2 ? most : std::pow(most, p - 1));
}

double r_function_partial(const Instruction& ins, const Interval& x, const Interval& y) {
  const RSystem s{static_cast<RKind>(static_cast<int>(ins.p0)), ins.p1};
  const double sign = ins.op == Op::RAnd ? -1.0 : 1.0;
  switch (s.kind) {
    case RKind::MinMax: return 1.0;
    case RKind::R0: return rp_partial(x, y, 2, sign);
    case RKind::Rp: return rp_partial(x, y, static_cast<int>(s.parameter), sign);
    // d/dx = (1 -+ u / sqrt(u^2 + v^2)) / (1 + alpha) with u = x - alpha y,
    // v = sqrt(1 - alpha^2) y (the radicand is u^2 + v^2): R0's rule over
    // the enclosures of u and v.
    case RKind::RAlpha: {
      const double alpha = s.parameter, c = std::sqrt(1.0 - alpha * alpha);
      const Interval u(x.lo - alpha * (alpha > 0 ? y.hi : y.lo), x.hi - alpha * (alpha > 0 ? y.lo : y.hi));
      return rp_partial(u, Interval(c * y.lo, c * y.hi), 2, sign) / (1.0 + alpha);
    }
    // (x + y -+ r) r^m: (1 -+ x / r) r^m + (x + y -+ r) m r^(m - 2) x, and
    // |x|, |y|, r are at most R = the largest r over the box.
    case RKind::Rm: {
      const double r = std::hypot(mag(x), mag(y));
      return (2.0 + 3.0 * s.parameter) * std::pow(r, s.parameter);
    }
    // alpha = 1 / (1 + r^2), r^2 = x^2 + y^2, adds -(s x y / q + f) d alpha/dx
    // / (1 + alpha), d alpha/dx = -2 x alpha^2; with |x y| / q <= sqrt(1 +
    // r^2) (q^2 >= (1 - alpha^2) max(x, y)^2) and |f| <= 2 sqrt(2) r, those
    // terms stay below 2 r / (1 + r^2)^1.5 + 4 sqrt(2) r^2 / (1 + r^2)^2 <
    // 0.77 + 1.42: the partial is below 2 + 0.77 + 1.42 < 5 everywhere.
    case RKind::RAlphaVariable: return 5.0;
  }
  return kUnknown;
}

double bound_of(const Instruction& ins, const Interval& a, const Interval& b, int k) {
  const Interval& other = k == 0 ? b : a;
  switch (ins.op) {
    case Op::Neg:
    case Op::Offset:
    case Op::Add:
    case Op::Sub:
    case Op::Min:
    case Op::Max:
    case Op::Abs:
    case Op::Sin:
    case Op::Cos: return 1.0;
    case Op::Axpby: return std::abs(k == 0 ? ins.p0 : ins.p1);
    case Op::Scale: return std::abs(ins.p0);
    case Op::Mul: return mag(other);
    case Op::Square: return 2.0 * mag(a);
    case Op::Exp: return std::exp(a.hi);
    case Op::Log: return a.lo > 0 ? 1.0 / a.lo : kUnknown;
    case Op::Sqrt: return a.lo > 0 ? 0.5 / std::sqrt(a.lo) : kUnknown;
    case Op::Step: return a.contains_zero() ? kUnknown : 0.0;
    case Op::PowInt: {
      const int n = static_cast<int>(ins.p0);
      if (n == 0) return 0.0;
      if (n > 0) return n * std::pow(mag(a), n - 1);
      return mig(a) > 0 ? -n / std::pow(mig(a), 1 - n) : kUnknown;
    }
    case Op::PowReal: {
      const double r = ins.p0;  // base >= 0
      if (r == 0) return 0.0;
      if (r >= 1) return r * std::pow(mag(a), r - 1);
      return a.lo > 0 ? std::abs(r) * std::pow(a.lo, r - 1) : kUnknown;
    }
    case Op::Div:
    case Op::DivSafe: {
      const double least = mig(b);
      if (!(least > 0)) return kUnknown;
      return k == 0 ? 1.0 / least : mag(a) / (least * least);
    }
    case Op::RAnd:
    case Op::ROr: return k == 0 ? r_function_partial(ins, a, b) : r_function_partial(ins, b, a);
    case Op::Const:
    case Op::VarX:
    case Op::VarY:
    case Op::VarZ:
    case Op::Classify:
    case Op::Patch: return 0.0;
  }
  return kUnknown;
}

}  // namespace

double partial_bound(const Instruction& ins, const Interval& a, const Interval& b, int k) {
  if (a.is_nan() || b.is_nan()) return kUnknown;
  const double bound = bound_of(ins, a, b, k);
  return std::isnan(bound) ? kUnknown : bound;  // inf / inf, inf * 0 at unbounded enclosures
}

}  // namespace sage::detail
