// Claim (paper 004, sec. 5.3): automatic-differentiation tuples carry the
// value and every partial derivative through order K exactly (to round-off).
// Checked against closed forms (polynomials, exp/sin products via the
// Leibniz rule), against finite differences of the tuples' own lower-order
// partials at neighbouring points (every path, so mixed partials are
// symmetric), and against nested symbolic derivatives in every order.

#include "test_support.hpp"

#include <sage/expression/derivative.hpp>
#include <sage/scalars/interval.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/scalars/tuple.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace sage {
namespace {

using test::Point;

// ---- closed forms -------------------------------------------------------------

// d^a/dx^a d^b/dy^b of exp(2x) sin(3y).
double exp_sin(int a, int b, double x, double y) {
  return std::pow(2.0, a) * std::pow(3.0, b) * std::exp(2 * x) * std::sin(3 * y + b * M_PI / 2);
}
// d^a/dx^a d^b/dy^b of (x + 2y)^7.
double binom7(int a, int b, double x, double y) {
  const int k = a + b;
  if (k > 7) return 0.0;
  return test::falling_factorial(7, k) * std::pow(2.0, b) * std::pow(x + 2 * y, 7 - k);
}
// Leibniz rule for the product of the two above; `magnitude` collects the
// sum of |terms| to scale the tolerance.
double product_closed_form(int a, int b, double x, double y, double& magnitude) {
  double s = 0;
  magnitude = 0;
  for (int i = 0; i <= a; ++i)
    for (int j = 0; j <= b; ++j) {
      const double term =
          test::binomial_d(a, i) * test::binomial_d(b, j) * exp_sin(i, j, x, y) * binom7(a - i, b - j, x, y);
      s += term;
      magnitude += std::abs(term);
    }
  return s;
}

// 3D: u = exp(x - y) sin(2z), v = x^3 y^2 z.
double u3(const MultiIndex<3>& al, const Point& p) {
  return std::pow(-1.0, al[1]) * std::pow(2.0, al[2]) * std::exp(p[0] - p[1]) * std::sin(2 * p[2] + al[2] * M_PI / 2);
}
double v3(const MultiIndex<3>& al, const Point& p) {
  const int n[3] = {3, 2, 1};
  double r = 1;
  for (int i = 0; i < 3; ++i) {
    if (al[i] > n[i]) return 0.0;
    r *= test::falling_factorial(n[i], al[i]) * std::pow(p[i], n[i] - al[i]);
  }
  return r;
}
double uv3(const MultiIndex<3>& al, const Point& p, double& magnitude) {
  double s = 0;
  magnitude = 0;
  for (int i = 0; i <= al[0]; ++i)
    for (int j = 0; j <= al[1]; ++j)
      for (int k = 0; k <= al[2]; ++k) {
        const double term = test::binomial_d(al[0], i) * test::binomial_d(al[1], j) * test::binomial_d(al[2], k) *
                            u3({i, j, k}, p) * v3({al[0] - i, al[1] - j, al[2] - k}, p);
        s += term;
        magnitude += std::abs(term);
      }
  return s;
}

constexpr double kRoundOff = 1e-12;

TEST(Tuple, WorkedExampleFromHeader) {
  // x * y at (2, 3): 6 + 3 dx + 2 dy + dxdy (hand computed).
  using T = Tuple<2, 2>;
  const T t = T::variable(0, 2.0) * T::variable(1, 3.0);
  EXPECT_EQ(t.value(), 6.0);
  EXPECT_EQ(t.derivative({1, 0}), 3.0);
  EXPECT_EQ(t.derivative({0, 1}), 2.0);
  EXPECT_EQ(t.derivative({1, 1}), 1.0);
  EXPECT_EQ(t.derivative({2, 0}), 0.0);
  EXPECT_EQ(t.derivative({0, 2}), 0.0);
  EXPECT_EQ(t.derivative({3, 0}), 0.0);  // beyond the order: 0
}

TEST(Tuple, DirectArithmeticMatchesClosedFormThroughOrder6) {
  using T = Tuple<2, 6>;
  auto rng = test::make_rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    const double x = test::uniform(rng, -1, 1), y = test::uniform(rng, -1, 1);
    const T X = T::variable(0, x), Y = T::variable(1, y);
    const T f = exp(2.0 * X) * sin(3.0 * Y) * pow_int(X + 2.0 * Y, 7);
    for (int i = 0; i < T::size; ++i) {
      const auto al = T::indices.index[i];
      double mag = 0;
      const double expected = product_closed_form(al[0], al[1], x, y, mag);
      EXPECT_NEAR(f.derivative(al), expected, kRoundOff * (1 + mag)) << "alpha = (" << al[0] << "," << al[1] << ")";
    }
  }
}

TEST(Tuple, TapeEvaluationMatchesClosedFormThroughOrder6In2D) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr f = exp(2.0 * x) * sin(3.0 * y) * pow_int(x + 2.0 * y, 7);
  const Tape tape(f, 2);
  Evaluator<Tuple<2, 6>> ev(tape);
  auto rng = test::make_rng(2);
  for (int trial = 0; trial < 50; ++trial) {
    const Point p = test::random_point(rng, -1, 1, 2);
    const auto t = ev.at(p);
    for (int i = 0; i < t.size; ++i) {
      const auto al = t.indices.index[i];
      double mag = 0;
      const double expected = product_closed_form(al[0], al[1], p[0], p[1], mag);
      EXPECT_NEAR(t.derivative(al), expected, kRoundOff * (1 + mag));
    }
  }
}

TEST(Tuple, TapeEvaluationMatchesClosedFormThroughOrder6In3D) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr f = exp(x - y) * sin(2.0 * z) * (pow_int(x, 3) * square(y) * z);
  const Tape tape(f, 3);
  Evaluator<Tuple<3, 6>> ev(tape);
  auto rng = test::make_rng(3);
  for (int trial = 0; trial < 30; ++trial) {
    const Point p = test::random_point(rng, -1.5, 1.5);
    const auto t = ev.at(p);
    for (int i = 0; i < t.size; ++i) {
      const auto al = t.indices.index[i];
      double mag = 0;
      const double expected = uv3(al, p, mag);
      EXPECT_NEAR(t.derivative(al), expected, kRoundOff * (1 + mag));
    }
  }
}

TEST(Tuple, ElementaryFunctionsMatchUnivariateClosedForms) {
  // One variable through order 8: 1/(1+x), sqrt(1+x), log(1+x), cos(x)^... closed forms.
  using T = Tuple<1, 8>;
  for (double x : {-0.6, -0.1, 0.3, 1.7}) {
    const T X = T::variable(0, x);
    const T inv = T(1.0) / (T(1.0) + X), rt = sqrt(T(1.0) + X), lg = log(T(1.0) + X), cs = cos(X),
            sq = square(X - T(0.25));
    const T pw = pow_real(T(1.0) + X, -0.7);
    for (int k = 0; k <= 8; ++k) {
      const MultiIndex<1> al{k};
      const double fact = std::tgamma(k + 1.0);
      EXPECT_NEAR(inv.derivative(al), std::pow(-1.0, k) * fact / std::pow(1 + x, k + 1),
                  1e-12 * fact * std::pow(1 + x, -k - 1));
      EXPECT_NEAR(rt.derivative(al), test::falling_factorial(0.5, k) * std::pow(1 + x, 0.5 - k),
                  1e-12 * (1 + std::abs(test::falling_factorial(0.5, k) * std::pow(1 + x, 0.5 - k))));
      EXPECT_NEAR(pw.derivative(al), test::falling_factorial(-0.7, k) * std::pow(1 + x, -0.7 - k),
                  1e-12 * (1 + std::abs(test::falling_factorial(-0.7, k) * std::pow(1 + x, -0.7 - k))));
      const double log_k = k == 0 ? std::log(1 + x) : std::pow(-1.0, k - 1) * std::tgamma(k) / std::pow(1 + x, k);
      EXPECT_NEAR(lg.derivative(al), log_k, 1e-12 * (1 + std::abs(log_k)));
      EXPECT_NEAR(cs.derivative(al), std::cos(x + k * M_PI / 2), 1e-14);
      const double sq_k = k == 0 ? (x - 0.25) * (x - 0.25) : (k == 1 ? 2 * (x - 0.25) : (k == 2 ? 2.0 : 0.0));
      EXPECT_NEAR(sq.derivative(al), sq_k, 1e-15);
    }
  }
}

TEST(Tuple, IntegerPowersMatchBinomialClosedFormAndDoubleValues) {
  // (x - 0.3)^n through order 8: n! / (n - k)! (x - 0.3)^(n - k); the
  // value is the double evaluator's pow_int bit for bit.
  using T = Tuple<1, 8>;
  for (double x : {-2.5, -0.1, 0.31, 1.7, 40.0})
    for (int n : {1, 2, 3, 4, 7, 12}) {
      const T p = pow_int(T::variable(0, x) - T(0.3), n);
      EXPECT_EQ(p.value(), pow_int(x - 0.3, n)) << "n " << n << " x " << x;
      for (int k = 0; k <= 8; ++k) {
        const double expected = k > n ? 0.0 : test::falling_factorial(n, k) * std::pow(x - 0.3, n - k);
        EXPECT_NEAR(p.derivative(MultiIndex<1>{k}), expected, 1e-13 * (1 + std::abs(expected)))
            << "n " << n << " k " << k << " x " << x;
      }
    }
}

// Value and gradient tuples take shortcuts through sqrt and R0 (R0 trees
// spend most of their time there): the values are the double evaluator's
// bit for bit, and the gradients are the general path's (second-order
// tuples run it) and the closed form's.
TEST(Tuple, FirstOrderSqrtAndR0MatchTheGeneralPath) {
  using T1 = Tuple<2, 1>;
  using T2 = Tuple<2, 2>;
  auto rng = test::make_rng(21);
  for (int trial = 0; trial < 300; ++trial) {
    const double px = test::uniform(rng, -2, 2), py = test::uniform(rng, -2, 2);
    const double ax = test::uniform(rng, -1, 1), ay = test::uniform(rng, -1, 1);
    // x-like and y-like arguments with gradients (1, ax) and (ay, 1).
    auto args = [&](auto sx, auto sy) { return std::pair{sx + ax * sy, ay * sx + sy}; };
    const auto [u1, v1] = args(T1::variable(0, px), T1::variable(1, py));
    const auto [u2, v2] = args(T2::variable(0, px), T2::variable(1, py));
    const double u = u1.value(), v = v1.value();
    const T1 root1 = sqrt(square(u1) + 1.0);
    const T2 root2 = sqrt(square(u2) + 1.0);
    EXPECT_EQ(root1.value(), std::sqrt(u * u + 1.0));
    EXPECT_EQ(root1.value(), pow_real(square(u1) + 1.0, 0.5).value());
    EXPECT_NEAR(root1.c[1], root2.derivative({1, 0}), 1e-15);
    for (double sign : {-1.0, 1.0}) {
      const T1 r1 = r0_combine(u1, v1, sign);
      const T2 r2 = r0_combine(u2, v2, sign);
      EXPECT_EQ(r1.value(), r0_combine(u, v, sign));
      const double r = std::hypot(u, v);
      for (int axis = 0; axis < 2; ++axis) {
        const double du = axis == 0 ? 1.0 : ax, dv = axis == 0 ? ay : 1.0;
        const double closed = du + dv + sign * (u * du + v * dv) / r;
        const double general = r2.derivative(axis == 0 ? MultiIndex<2>{1, 0} : MultiIndex<2>{0, 1});
        EXPECT_NEAR(r1.c[1 + axis], closed, 1e-13 * (1 + std::abs(closed)));
        EXPECT_NEAR(r1.c[1 + axis], general, 1e-13 * (1 + std::abs(closed)));
      }
    }
  }
  // At the corner both arguments vanish: the general path's convention
  // (sqrt(0) has derivatives 0), so the gradient is that of x + y.
  const T1 corner = r0_combine(T1::variable(0, 0.0), T1::variable(1, 0.0), -1.0);
  EXPECT_EQ(corner.value(), 0.0);
  EXPECT_EQ(corner.c[1], 1.0);
  EXPECT_EQ(corner.c[2], 1.0);
}

TEST(Tuple, FirstOrderRpMatchesTheGeneralPath) {
  using T1 = Tuple<2, 1>;
  auto rng = test::make_rng(22);
  for (int p : {2, 4, 6, 8}) {
    for (int trial = 0; trial < 200; ++trial) {
      const double px = test::uniform(rng, -2, 2), py = test::uniform(rng, -2, 2);
      const double ax = test::uniform(rng, -1, 1), ay = test::uniform(rng, -1, 1);
      const T1 u1 = T1::variable(0, px) + ax * T1::variable(1, py), v1 = ay * T1::variable(0, px) + T1::variable(1, py);
      const double u = u1.value(), v = v1.value();
      for (double sign : {-1.0, 1.0}) {
        const T1 fast = rp_combine(u1, v1, p, sign);
        const T1 general = rp_combine<T1>(u1, v1, p, sign);  // the generic template: tuple pow_int, pow_real
        for (int k = 0; k < 3; ++k) EXPECT_EQ(fast.c[k], general.c[k]) << "p " << p << " coefficient " << k;
        const double s = std::pow(u, p) + std::pow(v, p);
        for (int axis = 0; axis < 2; ++axis) {
          const double du = axis == 0 ? 1.0 : ax, dv = axis == 0 ? ay : 1.0;
          const double closed =
              du + dv + sign * std::pow(s, 1.0 / p - 1) * (std::pow(u, p - 1) * du + std::pow(v, p - 1) * dv);
          EXPECT_NEAR(fast.c[1 + axis], closed, 1e-12 * (1 + std::abs(closed)));
        }
      }
    }
  }
  // A zero argument and the corner take the general path's conventions.
  const T1 zero = rp_combine(T1::variable(0, 0.0), T1::variable(1, 0.5), 4, -1.0);
  const T1 zero_general = rp_combine<T1>(T1::variable(0, 0.0), T1::variable(1, 0.5), 4, -1.0);
  const T1 corner = rp_combine(T1::variable(0, 0.0), T1::variable(1, 0.0), 4, -1.0);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(zero.c[k], zero_general.c[k]);
  EXPECT_EQ(corner.value(), 0.0);
  EXPECT_EQ(corner.c[1], 1.0);
  EXPECT_EQ(corner.c[2], 1.0);
}

// A composite with every kind of operation, smooth on [-1, 1]^2 (the R0
// arguments stay away from their corner).
Expr composite_2d() {
  const Expr x = Expr::x(), y = Expr::y();
  return log(1.0 + square(x) + square(y)) / (2.0 + sin(x * y)) + sqrt(2.0 + x * x * y) * cos(x - y) +
         r_and(x - 1.5, y + 2.0, RSystem::r0()) * exp(-0.5 * y) + pow_real(3.0 + x, 1.5) / (1.0 + square(y));
}

// Every partial of order k equals the central difference of the order
// k-1 partials (from tuples at neighbouring points) along each axis it
// contains: all differentiation paths agree, so mixed partials are symmetric.
template <int N>
void check_against_finite_differences(const Expr& f, double lo, double hi, int trials, std::uint64_t seed) {
  constexpr int K = 6;
  using T = Tuple<N, K>;
  const Tape tape(f, N);
  Evaluator<T> ev(tape);
  Evaluator<double> dv(tape);
  auto rng = test::make_rng(seed);
  for (int trial = 0; trial < trials; ++trial) {
    const Point p = test::random_point(rng, lo, hi, N);
    const T t = ev.at(p);
    EXPECT_NEAR(t.value(), dv.at(p), 1e-14 * (1 + std::abs(t.value())));
    for (int i = 1; i < T::size; ++i) {
      const auto al = T::indices.index[i];
      for (int axis = 0; axis < N; ++axis) {
        if (al[axis] == 0) continue;
        const auto lower = test::minus_unit<N>(al, axis);
        const double fd =
            test::central_difference([&](const Point& q) { return ev.at(q).derivative(lower); }, p, axis, 1e-3);
        EXPECT_NEAR(t.derivative(al), fd, 1e-6 * (1 + std::abs(fd)))
            << "order " << order_of<N>(al) << " axis " << axis << " at (" << p[0] << "," << p[1] << "," << p[2] << ")";
      }
    }
  }
}

TEST(Tuple, AllPartialsThroughOrder6AgreeWithFiniteDifferences2D) {
  check_against_finite_differences<2>(composite_2d(), -1, 1, 15, 4);
}

TEST(Tuple, AllPartialsThroughOrder6AgreeWithFiniteDifferences3D) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr f = sqrt(4.0 + x * y + z * z) * exp(0.3 * x * z) - cos(x + 2.0 * y - z) / (3.0 + x * y * z) +
                 r_or(x - 2.0, z + 2.5, RSystem::r_p(4)) * y;
  check_against_finite_differences<3>(f, -1, 1, 6, 5);
}

TEST(Tuple, MixedPartialsAreSymmetricOnDirectArithmetic) {
  // f(x, y) = exp(x y) sin(x + y^2): compute d/dx of the tuple of df/dy and
  // d/dy of the tuple of df/dx by finite differences of order-1 tuples.
  using T = Tuple<2, 1>;
  auto f = [](const Point& p) {
    const T X = T::variable(0, p[0]), Y = T::variable(1, p[1]);
    return exp(X * Y) * sin(X + Y * Y);
  };
  auto rng = test::make_rng(6);
  for (int trial = 0; trial < 30; ++trial) {
    const Point p = test::random_point(rng, -1, 1, 2);
    const double dxy = test::central_difference([&](const Point& q) { return f(q).derivative({0, 1}); }, p, 0);
    const double dyx = test::central_difference([&](const Point& q) { return f(q).derivative({1, 0}); }, p, 1);
    EXPECT_NEAR(dxy, dyx, 1e-8);
    using T2 = Tuple<2, 2>;
    const T2 X = T2::variable(0, p[0]), Y = T2::variable(1, p[1]);
    const T2 g = exp(X * Y) * sin(X + Y * Y);
    EXPECT_NEAR(g.derivative({1, 1}), dxy, 1e-8);
  }
}

TEST(Tuple, AgreesWithNestedSymbolicDerivativesInEveryOrder) {
  // For every multi-index of order <= 3 and every ordering of its
  // differentiations, the nested symbolic derivative evaluated in double
  // equals the tuple's partial: the mixed partials are symmetric.
  const Expr f = composite_2d();
  using T = Tuple<2, 3>;
  auto rng = test::make_rng(7);
  std::vector<Point> points;
  for (int i = 0; i < 8; ++i) points.push_back(test::random_point(rng, -1, 1, 2));
  for (int i = 1; i < T::size; ++i) {
    const auto al = T::indices.index[i];
    std::vector<int> vars;
    for (int v = 0; v < 2; ++v) vars.insert(vars.end(), static_cast<std::size_t>(al[v]), v);
    std::sort(vars.begin(), vars.end());
    do {
      Expr d = f;
      for (int v : vars) d = derivative(d, v);
      const Tape dt(d, 2);
      Evaluator<double> dv(dt);
      for (const Point& p : points) {
        const double sym = dv.at(p);
        const double tup = test::eval_tuple<2, 3>(f, p).derivative(al);
        EXPECT_NEAR(sym, tup, 1e-11 * (1 + std::abs(tup)));
      }
    } while (std::next_permutation(vars.begin(), vars.end()));
  }
}

// scalar.hpp takes the roots r = 1/2, 1/4, 1/8 (R0's and Rp's for p = 4,
// 8) by square roots instead of std::pow: as close to x^r as pow is, with
// pow's values at 0, inf, NaN and negative x; tuples and intervals take the
// same value.
TEST(Tuple, RootsBySquareRootsAreWithinAnUlpOfPow) {
  auto rng = test::make_rng(31);
  for (double r : {0.5, 0.25, 0.125}) {
    double worst = 0;
    for (int trial = 0; trial < 20000; ++trial) {
      const double x = std::ldexp(test::uniform(rng, 1, 2), static_cast<int>(test::uniform(rng, -1000, 1000)));
      const long double exact = std::pow(static_cast<long double>(x), static_cast<long double>(r));
      const double ulp = std::nextafter(static_cast<double>(exact), INFINITY) - static_cast<double>(exact);
      worst = std::max(worst, static_cast<double>(std::abs(pow_real(x, r) - exact) / ulp));
      ASSERT_EQ(pow_real(Tuple<2, 2>::variable(0, x), r).value(), pow_real(x, r));
      ASSERT_TRUE(pow_real(Interval(x), r).contains(pow_real(x, r)));
    }
    EXPECT_LT(worst, 1.0) << "r " << r;  // std::pow's own bound
    for (double x : {0.0, -0.0, 1.0 / 0.0, -1.0, -1.0 / 0.0, std::nan("")}) {
      const double expected = std::pow(x, r), root = pow_real(x, r);
      EXPECT_TRUE(root == expected || (std::isnan(root) && std::isnan(expected))) << x << " ^ " << r;
      EXPECT_EQ(std::signbit(root), std::signbit(expected)) << x << " ^ " << r;
    }
  }
}

TEST(Tuple, SingularPointConventions) {
  // scalar.hpp: sqrt at 0 is the constant 0 tuple; abs(0) likewise;
  // min/max at a tie average; x/0 is a pole.
  using T = Tuple<2, 3>;
  const T X = T::variable(0, 0.0), Y = T::variable(1, 0.0);
  const T s = sqrt(X * X + Y * Y);
  for (double c : s.c) EXPECT_EQ(c, 0.0);
  const T a = abs(X);
  for (double c : a.c) EXPECT_EQ(c, 0.0);
  const T m = min(X, Y);
  EXPECT_EQ(m.derivative({1, 0}), 0.5);
  EXPECT_EQ(m.derivative({0, 1}), 0.5);
  // R0 conjunction at the corner gets gradient (1, 1), as documented.
  const T r = r_and(X, Y, RSystem::r0());
  EXPECT_EQ(r.derivative({1, 0}), 1.0);
  EXPECT_EQ(r.derivative({0, 1}), 1.0);
  EXPECT_TRUE(std::isinf((T(1.0) / X).value()));
  EXPECT_TRUE(std::isnan(sqrt(T::variable(0, -1.0)).value()));
  // pow_int at 0 is exact: (x)^3 at 0 has d3/dx3 = 6.
  EXPECT_EQ(pow_int(X, 3).derivative({3, 0}), 6.0);
}

}  // namespace
}  // namespace sage
