#pragma once
// Small helpers shared by the libsage test suites: seeded random numbers,
// one-shot evaluation of an expression, finite differences, and the table
// of one-operation test cases (a reference implementation of every op in
// kAllOps, written independently of libsage, with the domain where it is
// smooth) used by the tape and interval sweeps.

#include <sage/expression/classifier.hpp>
#include <sage/expression/derivative.hpp>
#include <sage/expression/expression.hpp>
#include <sage/expression/opcode.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/scalars/tuple.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace sage::test {

using Point = std::array<double, 3>;

/// Every suite uses a fixed seed: failures are reproducible.
inline std::mt19937_64 make_rng(std::uint64_t salt = 0) { return std::mt19937_64(0x5A6E'2024ULL + salt); }

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Point random_point(std::mt19937_64& rng, double lo, double hi, int dimension = 3) {
  Point p{0, 0, 0};
  for (int i = 0; i < dimension; ++i) p[i] = uniform(rng, lo, hi);
  return p;
}

/// Value of `e` at p (dimension 3 tape, so z is allowed).
inline double eval(const Expr& e, const Point& p, int dimension = 3) {
  const Tape tape(e, dimension);
  Evaluator<double> ev(tape);
  return ev.at(p);
}

/// Tuple of `e` at p.
template <int N, int K>
Tuple<N, K> eval_tuple(const Expr& e, const Point& p) {
  const Tape tape(e, N);
  Evaluator<Tuple<N, K>> ev(tape);
  return ev.at(p);
}

template <int N, int K>
double gradient_norm(const Tuple<N, K>& t) {
  double s = 0;
  for (double g : t.gradient()) s += g * g;
  return std::sqrt(s);
}

/// Central difference of f along `axis` at p, Richardson-extrapolated
/// (error O(h^4)).
template <class F>
double central_difference(const F& f, Point p, int axis, double h = 1e-4) {
  auto cd = [&](double step) {
    Point a = p, b = p;
    a[axis] += step;
    b[axis] -= step;
    return (f(a) - f(b)) / (2 * step);
  };
  return (4 * cd(h / 2) - cd(h)) / 3;
}

/// Multi-index helpers.
template <int N>
MultiIndex<N> minus_unit(MultiIndex<N> a, int i) {
  --a[i];
  return a;
}

inline double falling_factorial(double n, int k) {
  double r = 1;
  for (int i = 0; i < k; ++i) r *= n - i;
  return r;
}

inline double binomial_d(int n, int k) { return static_cast<double>(binomial(n, k)); }

// ---- one-operation cases ------------------------------------------------------

/// One node of kind `op` at the root, over inner linear arguments u and v of
/// the point (or directly x and y when `chain` is false).
struct OpCase {
  std::string name;
  Op op;
  std::function<Expr(const Expr& x, const Expr& y, const Expr& z)> build;
  std::function<double(const Point&)> reference;  // independent of libsage
  std::function<bool(const Point&)> smooth;       // where the op is smooth (derivative test)
};

inline std::vector<RSystem> all_rsystems() {
  return {RSystem::min_max(),     RSystem::r0(),         RSystem::r_alpha(0.5),
          RSystem::r_alpha(-0.5), RSystem::r_alpha(1.0), RSystem::r_alpha_variable(),
          RSystem::r_p(2),        RSystem::r_p(4),       RSystem::r_p(6),
          RSystem::r_p(8),        RSystem::r_m(2),       RSystem::r_m(4)};
}

/// Reference R-function, written from the table in FORMULAS.md and
/// evaluated in long double (so that it is not subject to the same
/// double round-off as the library).
inline double reference_r(double xd, double yd, const RSystem& s, double sign) {
  using L = long double;
  const L x = xd, y = yd, sg = sign;
  switch (s.kind) {
    case RKind::MinMax: return sign < 0 ? std::min(xd, yd) : std::max(xd, yd);
    case RKind::R0: return static_cast<double>(x + y + sg * std::sqrt(x * x + y * y));
    case RKind::RAlpha: {
      const L a = s.parameter;
      return static_cast<double>((x + y + sg * std::sqrt(std::max(L(0), x * x + y * y - 2 * a * x * y))) / (1 + a));
    }
    case RKind::RAlphaVariable: {
      const L a = 1 / (1 + x * x + y * y);
      return static_cast<double>((x + y + sg * std::sqrt(std::max(L(0), x * x + y * y - 2 * a * x * y))) / (1 + a));
    }
    case RKind::Rp: {
      const L p = s.parameter;
      return static_cast<double>(x + y + sg * std::pow(std::pow(x, p) + std::pow(y, p), 1 / p));
    }
    case RKind::Rm: {
      const L m = s.parameter;
      return static_cast<double>((x + y + sg * std::sqrt(x * x + y * y)) * std::pow(x * x + y * y, m / 2));
    }
  }
  return NAN;
}

/// Membership in the ball |p| < 1.2 (3D), with an exact box rule: the
/// squared distance range over the box decides inside / outside.
class BallClassifier : public PointClassifier {
 public:
  static constexpr double kRadius2 = 1.44;
  static double reference(const Point& p) {
    const double r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    return r2 < kRadius2 ? 1.0 : (r2 > kRadius2 ? -1.0 : 0.0);
  }
  double classify(const double* p) const override { return reference({p[0], p[1], p[2]}); }
  Interval classify_box(const Interval* box) const override {
    Interval r2(0.0);
    for (int i = 0; i < 3; ++i) r2 = r2 + square(box[i]);
    if (r2.hi < kRadius2) return Interval(1.0);
    if (r2.lo > kRadius2) return Interval(-1.0);
    return {-1.0, 1.0};
  }
  int dimension() const override { return 3; }
};

/// Every op of kAllOps with a reference and a smooth domain. R-function ops
/// appear once per system of all_rsystems(). With chain = true the op is
/// applied to u = x + y/2 and v = y - x/4 + z/2 (so the chain rule is
/// exercised); with chain = false to u = x, v = y.
inline std::vector<OpCase> op_cases(bool chain) {
  auto U = [chain](const Expr& x, const Expr& y) { return chain ? x + 0.5 * y : x; };
  auto V = [chain](const Expr& x, const Expr& y, const Expr& z) { return chain ? y - 0.25 * x + 0.5 * z : y; };
  auto u = [chain](const Point& p) { return chain ? p[0] + 0.5 * p[1] : p[0]; };
  auto v = [chain](const Point& p) { return chain ? p[1] - 0.25 * p[0] + 0.5 * p[2] : p[1]; };
  auto always = [](const Point&) { return true; };
  std::vector<OpCase> cases;
  auto unary = [&](const std::string& name, Op op, double p0, std::function<double(double)> ref,
                   std::function<bool(double)> dom) {
    cases.push_back({name, op, [=](const Expr& x, const Expr& y, const Expr&) { return Expr::make(op, U(x, y), p0); },
                     [=](const Point& p) { return ref(u(p)); }, [=](const Point& p) { return dom(u(p)); }});
  };
  auto binary = [&](const std::string& name, Op op, double p0, double p1, std::function<double(double, double)> ref,
                    std::function<bool(double, double)> dom) {
    cases.push_back(
        {name, op,
         [=](const Expr& x, const Expr& y, const Expr& z) { return Expr::make(op, U(x, y), V(x, y, z), p0, p1); },
         [=](const Point& p) { return ref(u(p), v(p)); }, [=](const Point& p) { return dom(u(p), v(p)); }});
  };
  auto away = [](double a, double m) { return std::abs(a) > m; };
  for (Op op : kAllOps) {
    switch (op) {
      case Op::Const:
        cases.push_back({"const", op, [](const Expr&, const Expr&, const Expr&) { return Expr(2.75); },
                         [](const Point&) { return 2.75; }, always});
        break;
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const int i = static_cast<int>(op) - static_cast<int>(Op::VarX);
        cases.push_back({std::string(op_name(op)), op,
                         [i](const Expr& x, const Expr& y, const Expr& z) { return i == 0 ? x : (i == 1 ? y : z); },
                         [i](const Point& p) { return p[i]; }, always});
        break;
      }
      case Op::Neg:
        unary(
            "neg", op, 0, [](double a) { return -a; }, [](double) { return true; });
        break;
      case Op::Square:
        unary(
            "square", op, 0, [](double a) { return a * a; }, [](double) { return true; });
        break;
      case Op::Sqrt:
        unary(
            "sqrt", op, 0, [](double a) { return std::sqrt(a); }, [](double a) { return a > 0.1; });
        break;
      case Op::Exp:
        unary(
            "exp", op, 0, [](double a) { return std::exp(a); }, [](double) { return true; });
        break;
      case Op::Log:
        unary(
            "log", op, 0, [](double a) { return std::log(a); }, [](double a) { return a > 0.1; });
        break;
      case Op::Sin:
        unary(
            "sin", op, 0, [](double a) { return std::sin(a); }, [](double) { return true; });
        break;
      case Op::Cos:
        unary(
            "cos", op, 0, [](double a) { return std::cos(a); }, [](double) { return true; });
        break;
      case Op::Abs:
        unary(
            "abs", op, 0, [](double a) { return std::abs(a); }, [=](double a) { return away(a, 1e-2); });
        break;
      case Op::Step:
        unary(
            "step", op, 0, [](double a) { return a > 0 ? 1.0 : (a < 0 ? 0.0 : 0.5); },
            [=](double a) { return away(a, 1e-2); });
        break;
      case Op::PowInt:
        for (int n : {3, 5, -1, -2})
          unary(
              "pow_int:" + std::to_string(n), op, n, [n](double a) { return std::pow(a, n); },
              [=](double a) { return n > 0 || away(a, 0.2); });
        break;
      case Op::PowReal:
        for (double r : {1.5, 0.3, -0.7})
          unary(
              "pow_real:" + std::to_string(r), op, r, [r](double a) { return std::pow(a, r); },
              [](double a) { return a > 0.1; });
        break;
      case Op::Add:
        binary(
            "add", op, 0, 0, [](double a, double b) { return a + b; }, [](double, double) { return true; });
        break;
      case Op::Axpby:
        binary(
            "axpby", op, 1.5, -0.75, [](double a, double b) { return 1.5 * a - 0.75 * b; },
            [](double, double) { return true; });
        break;
      case Op::Sub:
        binary(
            "sub", op, 0, 0, [](double a, double b) { return a - b; }, [](double, double) { return true; });
        break;
      case Op::Mul:
        binary(
            "mul", op, 0, 0, [](double a, double b) { return a * b; }, [](double, double) { return true; });
        break;
      case Op::Div:
        binary(
            "div", op, 0, 0, [](double a, double b) { return a / b; }, [=](double, double b) { return away(b, 0.2); });
        break;
      case Op::DivSafe:
        binary(
            "div_safe", op, 0, 0, [](double a, double b) { return b == 0 ? 0.0 : a / b; },
            [=](double, double b) { return away(b, 0.2); });
        break;
      case Op::Min:
        binary(
            "min", op, 0, 0, [](double a, double b) { return std::min(a, b); },
            [=](double a, double b) { return away(a - b, 1e-2); });
        break;
      case Op::Max:
        binary(
            "max", op, 0, 0, [](double a, double b) { return std::max(a, b); },
            [=](double a, double b) { return away(a - b, 1e-2); });
        break;
      case Op::Classify: {
        auto ball = std::make_shared<const BallClassifier>();
        cases.push_back({"classify", op, [ball](const Expr&, const Expr&, const Expr&) { return Expr::classify(ball); },
                         [](const Point& p) { return BallClassifier::reference(p); },
                         [](const Point& p) {  // piecewise constant: smooth off the sphere
                           return std::abs(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1.2) > 1e-2;
                         }});
        break;
      }
      case Op::RAnd:
      case Op::ROr: {
        const double sign = op == Op::RAnd ? -1.0 : 1.0;
        for (const RSystem& s : all_rsystems()) {
          // Smooth away from the corner, and (minmax, alpha = 1) off x = y.
          const bool kink_on_diagonal = s.kind == RKind::MinMax || (s.kind == RKind::RAlpha && s.parameter == 1.0);
          binary(
              std::string(op_name(op)) + "[" + s.name() + "]", op, static_cast<int>(s.kind), s.parameter,
              [s, sign](double a, double b) { return reference_r(a, b, s, sign); },
              [=](double a, double b) { return std::hypot(a, b) > 0.1 && (!kink_on_diagonal || away(a - b, 1e-2)); });
        }
        break;
      }
      case Op::Patch: break;  // tapes only: chebyshev_patch_test.cpp
      case Op::Offset:
      case Op::Scale: break;  // tapes only: tape_test.cpp
    }
  }
  return cases;
}

}  // namespace sage::test
