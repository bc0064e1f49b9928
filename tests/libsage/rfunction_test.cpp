// Claims of paper 004, sec. 2 (FORMULAS.md, R-function table), checked with
// tuples on the R-functions of x and y:
//  - R0: |grad| = 1 on the boundary half-axes away from the corner, and
//    |grad|^2 = 3 -+ 2 (cos phi + sin phi) everywhere (bounded, direction
//    dependent), so |grad|^2 = 5 on x = 0, y < 0 for the conjunction;
//  - Rp: normalized to order p - 1 (first normal derivative 1, orders
//    2..p-1 zero) with the order-p normal derivative nonzero and equal to
//    its closed form -+(p-1)!/|y|^(p-1);
//  - R0^m: all partials through order m vanish at the corner, and are
//    continuous there (they shrink like r^(m+1-k) on the approach, by
//    homogeneity); not normalized;
//  - minmax: one-sided gradients differ on x = y;
//  - R_alpha (constant and alpha = 1/(1+x^2+y^2)): |grad| = 1 on the axes;
//  - monotonicity of the monotone systems; sign = Boolean function of signs;
//  - the Expr node evaluates the same as the generic formula.

#include "test_support.hpp"

#include <sage/scalars/rfunction.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

template <int K>
Tuple<2, K> rf(double x, double y, const RSystem& s, double sign) {
  return r_combine(Tuple<2, K>::variable(0, x), Tuple<2, K>::variable(1, y), s, sign);
}

// The boundary half-axes of x AND y (sign -1) or x OR y (sign +1), away
// from the corner, with the inner normal there.
struct AxisPoint {
  double x, y;
  int normal_axis;     // 0: normal along x, 1: along y
  double normal_sign;  // direction of the inner normal along that axis
};
std::vector<AxisPoint> boundary_axis_points(double sign) {
  std::vector<AxisPoint> pts;
  for (double s : {0.01, 0.3, 1.0, 2.5, 100.0}) {
    if (sign < 0) {  // AND: x = 0, y > 0 (normal +x) and y = 0, x > 0 (normal +y)
      pts.push_back({0.0, s, 0, 1.0});
      pts.push_back({s, 0.0, 1, 1.0});
    } else {  // OR: x = 0, y < 0 (normal +x) and y = 0, x < 0 (normal +y)
      pts.push_back({0.0, -s, 0, 1.0});
      pts.push_back({-s, 0.0, 1, 1.0});
    }
  }
  return pts;
}

TEST(RFunction, R0IsNormalizedOnTheBoundaryHalfAxes) {
  for (double sign : {-1.0, 1.0})
    for (const auto& a : boundary_axis_points(sign)) {
      const auto t = rf<1>(a.x, a.y, RSystem::r0(), sign);
      EXPECT_NEAR(t.value(), 0.0, 1e-15 * (1 + std::abs(a.x + a.y)));
      EXPECT_NEAR(test::gradient_norm(t), 1.0, 1e-14);
      // The gradient is the inner normal itself.
      EXPECT_NEAR(t.gradient()[a.normal_axis], a.normal_sign, 1e-14);
    }
}

TEST(RFunction, R0GradientSquaredIsThreeMinusTwoCosPlusSin) {
  // Paper 004 eq. (4)-(5): |grad|^2 = 3 -+ 2 (cos phi + sin phi), depends on
  // the direction only, bounded by 3 + 2 sqrt(2) near the corner.
  auto rng = test::make_rng(10);
  for (int i = 0; i < 200; ++i) {
    const double phi = test::uniform(rng, 0, 2 * M_PI), r = std::pow(10.0, test::uniform(rng, -6, 2));
    for (double sign : {-1.0, 1.0}) {
      const auto t = rf<1>(r * std::cos(phi), r * std::sin(phi), RSystem::r0(), sign);
      const double g2 = std::pow(test::gradient_norm(t), 2);
      EXPECT_NEAR(g2, 3 + sign * 2 * (std::cos(phi) + std::sin(phi)), 1e-12);
      EXPECT_LE(g2, 3 + 2 * std::sqrt(2.0) + 1e-12);
    }
  }
  // On x = 0, y < 0 the conjunction is not normalized: |grad|^2 = 5.
  for (double y : {-0.1, -1.0, -7.0})
    EXPECT_NEAR(std::pow(test::gradient_norm(rf<1>(0.0, y, RSystem::r0(), -1)), 2), 5.0, 1e-13);
  // Likewise the disjunction on x = 0, y > 0.
  for (double y : {0.1, 1.0, 7.0})
    EXPECT_NEAR(std::pow(test::gradient_norm(rf<1>(0.0, y, RSystem::r0(), 1)), 2), 5.0, 1e-13);
}

template <int P>
void check_rp_normalization() {
  const RSystem s = RSystem::r_p(P);
  for (double sign : {-1.0, 1.0})
    for (const auto& a : boundary_axis_points(sign)) {
      const auto t = rf<P>(a.x, a.y, s, sign);
      const double along = a.normal_axis == 0 ? a.y : a.x;  // the coordinate along the axis
      EXPECT_NEAR(t.value(), 0.0, 1e-14 * std::abs(along));
      MultiIndex<2> al{0, 0};
      for (int k = 1; k <= P; ++k) {
        al[a.normal_axis] = k;
        const double dk = t.derivative(al);
        if (k == 1) {
          EXPECT_NEAR(dk, 1.0, 1e-13) << "p=" << P;
        } else if (k < P) {
          EXPECT_NEAR(dk, 0.0, 1e-10 * std::tgamma(k + 1.0) / std::pow(std::abs(along), k - 1))
              << "p=" << P << " k=" << k;
        } else {
          // f = n -+ n^p / (p |s|^(p-1)) + O(n^2p): d^p f/dn^p = -+(p-1)!/|s|^(p-1).
          const double expected = sign * std::tgamma(P * 1.0) / std::pow(std::abs(along), P - 1);
          EXPECT_NE(dk, 0.0);
          EXPECT_NEAR(dk, expected, 1e-9 * std::abs(expected)) << "p=" << P << " at " << a.x << "," << a.y;
        }
      }
      // Tangential derivative is 0.
      EXPECT_NEAR(t.gradient()[1 - a.normal_axis], 0.0, 1e-13);
    }
}

TEST(RFunction, RpIsNormalizedToOrderPMinus1) {
  check_rp_normalization<2>();
  check_rp_normalization<4>();
  check_rp_normalization<6>();
  check_rp_normalization<8>();
}

template <int M>
void check_rm_corner() {
  const RSystem s = RSystem::r_m(M);
  for (double sign : {-1.0, 1.0}) {
    // At the corner every partial through order m is zero.
    const auto t0 = rf<M>(0.0, 0.0, s, sign);
    for (double c : t0.c) EXPECT_EQ(c, 0.0);
    // Approaching the corner along many directions: f is homogeneous of
    // degree m+1, so a partial of order k at r*u is r^(m+1-k) times its value
    // at u. It tends to 0 for every k <= m: the partials are continuous at
    // the corner, i.e. f is m times (continuously) differentiable there.
    for (int d = 0; d < 16; ++d) {
      const double phi = 2 * M_PI * (d + 0.37) / 16;
      const auto unit = rf<M>(std::cos(phi), std::sin(phi), s, sign);
      double unit_max = 0;
      for (int i = 0; i < unit.size; ++i) unit_max = std::max(unit_max, std::abs(unit.derivative_at(i)));
      double previous_max = std::numeric_limits<double>::infinity();
      for (double r : {1e-1, 1e-2, 1e-3, 1e-4}) {
        const auto t = rf<M>(r * std::cos(phi), r * std::sin(phi), s, sign);
        double max_abs = 0;
        for (int i = 0; i < t.size; ++i) {
          const int k = order_of<2>(t.indices.index[i]);
          const double expected = std::pow(r, M + 1 - k) * unit.derivative_at(i);
          EXPECT_NEAR(t.derivative_at(i), expected, 1e-9 * (std::abs(expected) + std::pow(r, M + 1 - k)));
          max_abs = std::max(max_abs, std::abs(t.derivative_at(i)));
        }
        EXPECT_LT(max_abs, previous_max);
        EXPECT_LE(max_abs, r * unit_max * (1 + 1e-9));  // every order <= m shrinks at least like r
        previous_max = max_abs;
      }
    }
  }
  // Not normalized: on x = 0, y > 0 the conjunction has gradient (y^m, 0).
  for (double y : {0.5, 2.0}) {
    const auto t = rf<1>(0.0, y, s, -1);
    EXPECT_NEAR(t.gradient()[0], std::pow(y, M), 1e-12 * std::pow(y, M));
    EXPECT_NEAR(t.gradient()[1], 0.0, 1e-12);
  }
}

TEST(RFunction, R0mHasAllPartialsThroughOrderMZeroAtTheCorner) {
  check_rm_corner<2>();
  check_rm_corner<4>();
}

TEST(RFunction, R0mOrderMPlus1IsNotContinuousAtTheCorner) {
  // The claim is sharp: the order m+1 partials are homogeneous of degree 0
  // (direction dependent, not shrinking), so f is not m+1 times differentiable.
  const RSystem s = RSystem::r_m(2);
  const auto a = rf<3>(1e-6, 0.0, s, -1), b = rf<3>(0.0, 1e-6, s, -1), c = rf<3>(-1e-6, -1e-6, s, -1);
  const double fa = a.derivative({3, 0}), fb = b.derivative({3, 0}), fc = c.derivative({3, 0});
  EXPECT_GT(std::max({std::abs(fa - fb), std::abs(fa - fc), std::abs(fb - fc)}), 0.1);
}

TEST(RFunction, MinMaxIsNotDifferentiableOnTheDiagonal) {
  for (double sign : {-1.0, 1.0})
    for (double a : {-2.0, -0.3, 0.7, 5.0}) {
      const double d = 1e-9;
      const auto above = rf<1>(a + d, a, RSystem::min_max(), sign);  // x > y
      const auto below = rf<1>(a - d, a, RSystem::min_max(), sign);  // x < y
      // min takes y above the diagonal and x below; max the other way round.
      const std::array<double, 2> ex = sign < 0 ? std::array<double, 2>{0, 1} : std::array<double, 2>{1, 0};
      const std::array<double, 2> ey = sign < 0 ? std::array<double, 2>{1, 0} : std::array<double, 2>{0, 1};
      EXPECT_EQ(above.gradient(), ex);
      EXPECT_EQ(below.gradient(), ey);
      // One-sided directional derivatives across the diagonal differ by 1 in x.
      EXPECT_NEAR(std::abs(above.gradient()[0] - below.gradient()[0]), 1.0, 0.0);
    }
  // ... yet it is normalized on the axes.
  for (double sign : {-1.0, 1.0})
    for (const auto& a : boundary_axis_points(sign))
      EXPECT_EQ(test::gradient_norm(rf<1>(a.x, a.y, RSystem::min_max(), sign)), 1.0);
}

TEST(RFunction, RAlphaIsNormalizedOnTheAxes) {
  std::vector<RSystem> systems = {RSystem::r_alpha_variable()};
  for (double alpha : {-0.9, -0.5, 0.0, 0.3, 0.9, 1.0}) systems.push_back(RSystem::r_alpha(alpha));
  for (const RSystem& s : systems)
    for (double sign : {-1.0, 1.0})
      for (const auto& a : boundary_axis_points(sign)) {
        const auto t = rf<1>(a.x, a.y, s, sign);
        EXPECT_NEAR(t.value(), 0.0, 1e-14 * (1 + std::abs(a.x + a.y))) << s.name();
        EXPECT_NEAR(test::gradient_norm(t), 1.0, 1e-12) << s.name() << " at " << a.x << "," << a.y;
      }
  // R_alpha with alpha = 0 is R0.
  auto rng = test::make_rng(11);
  for (int i = 0; i < 100; ++i) {
    const double x = test::uniform(rng, -3, 3), y = test::uniform(rng, -3, 3);
    EXPECT_NEAR(r_and(x, y, RSystem::r_alpha(0.0)), r_and(x, y, RSystem::r0()), 1e-14 * 6);
  }
}

TEST(RFunction, RAlphaWithAlphaOneIsMinMaxToRoundOff) {
  // FORMULAS.md: alpha = 1 gives min/max. Near x = y the radicand
  // x^2 + y^2 - 2xy cancels; the value must still be min/max to round-off
  // (not to sqrt(eps)), with partials in {0, 1/2, 1} (to round-off) and never negative.
  auto rng = test::make_rng(15);
  for (int i = 0; i < 20000; ++i) {
    const double x = test::uniform(rng, -5, 5), y = x * (1 + 1e-9 * test::uniform(rng, -1, 1));
    for (double sign : {-1.0, 1.0}) {
      const double expected = sign < 0 ? std::min(x, y) : std::max(x, y);
      EXPECT_NEAR(r_combine(x, y, RSystem::r_alpha(1.0), sign), expected, 4e-16 * std::abs(x));
      const auto t = rf<1>(x, y, RSystem::r_alpha(1.0), sign);
      for (double g : t.gradient()) {
        EXPECT_GE(g, 0.0);
        EXPECT_LT(std::min({std::abs(g), std::abs(g - 0.5), std::abs(g - 1)}), 1e-15) << g;
      }
    }
  }
}

TEST(RFunction, MonotoneSystemsAreNonDecreasingInEachArgument) {
  std::vector<RSystem> systems = {RSystem::min_max(), RSystem::r0(), RSystem::r_p(2), RSystem::r_p(4), RSystem::r_p(8)};
  for (double alpha : {-0.9, -0.5, 0.5, 1.0}) systems.push_back(RSystem::r_alpha(alpha));
  auto rng = test::make_rng(12);
  for (const RSystem& s : systems) {
    ASSERT_TRUE(s.is_monotone());
    for (int i = 0; i < 2000; ++i) {
      const double x1 = test::uniform(rng, -5, 5), x2 = test::uniform(rng, -5, 5);
      const double y1 = test::uniform(rng, -5, 5), y2 = test::uniform(rng, -5, 5);
      const double xl = std::min(x1, x2), xh = std::max(x1, x2), yl = std::min(y1, y2), yh = std::max(y1, y2);
      for (double sign : {-1.0, 1.0}) {
        const double lo = r_combine(xl, yl, s, sign), mid1 = r_combine(xh, yl, s, sign),
                     mid2 = r_combine(xl, yh, s, sign), hi = r_combine(xh, yh, s, sign);
        const double tol = 1e-13 * (1 + std::abs(lo) + std::abs(hi));
        EXPECT_LE(lo, mid1 + tol) << s.name();
        EXPECT_LE(lo, mid2 + tol) << s.name();
        EXPECT_LE(mid1, hi + tol) << s.name();
        EXPECT_LE(mid2, hi + tol) << s.name();
        // And the partials are non-negative.
        const auto t = rf<1>(x1, y1, s, sign);
        EXPECT_GE(t.gradient()[0], -1e-13) << s.name();
        EXPECT_GE(t.gradient()[1], -1e-13) << s.name();
      }
    }
  }
  EXPECT_FALSE(RSystem::r_m(2).is_monotone());
  EXPECT_FALSE(RSystem::r_alpha_variable().is_monotone());
}

TEST(RFunction, SignIsTheBooleanFunctionOfTheArgumentSigns) {
  auto rng = test::make_rng(13);
  for (const RSystem& s : test::all_rsystems())
    for (int i = 0; i < 2000; ++i) {
      const double x = test::uniform(rng, -4, 4), y = test::uniform(rng, -4, 4);
      const double a = r_and(x, y, s), o = r_or(x, y, s);
      EXPECT_EQ(a > 0, x > 0 && y > 0) << s.name() << " " << x << " " << y;
      EXPECT_EQ(o > 0, x > 0 || y > 0) << s.name() << " " << x << " " << y;
      EXPECT_EQ(r_not(x), -x);
    }
}

TEST(RFunction, MatchesTheFormulaTableAndTheExprNode) {
  auto rng = test::make_rng(14);
  const Expr x = Expr::x(), y = Expr::y();
  for (const RSystem& s : test::all_rsystems())
    for (double sign : {-1.0, 1.0}) {
      const Expr e = sign < 0 ? r_and(x, y, s) : r_or(x, y, s);
      ASSERT_EQ(e.op(), sign < 0 ? Op::RAnd : Op::ROr);
      const Tape tape(e, 2);
      Evaluator<double> ev(tape);
      for (int i = 0; i < 200; ++i) {
        const Point p = test::random_point(rng, -3, 3, 2);
        const double ref = test::reference_r(p[0], p[1], s, sign);
        EXPECT_NEAR(r_combine(p[0], p[1], s, sign), ref, 1e-12 * (1 + std::abs(ref))) << s.name();
        EXPECT_NEAR(ev.at(p), ref, 1e-12 * (1 + std::abs(ref))) << s.name();
      }
    }
}

TEST(RFunction, NaryFormsAreBalancedTrees) {
  // Documented shape: ((a0 . a1) . (a2 . a3)) . a4.
  const RSystem s = RSystem::r0();
  const std::vector<double> a = {0.3, 1.2, -0.4, 2.0, 0.9};
  const double expected = r_and(r_and(r_and(a[0], a[1], s), r_and(a[2], a[3], s), s), a[4], s);
  EXPECT_DOUBLE_EQ(r_conjunction_n(a, s), expected);
  const double expected_or = r_or(r_or(r_or(a[0], a[1], s), r_or(a[2], a[3], s), s), a[4], s);
  EXPECT_DOUBLE_EQ(r_disjunction_n(a, s), expected_or);
  EXPECT_THROW(r_conjunction_n(std::vector<double>{}, s), std::invalid_argument);
}

TEST(RFunction, ParseAndName) {
  for (const RSystem& s : test::all_rsystems()) EXPECT_EQ(RSystem::parse(s.name()), s) << s.name();
  for (const char* bad : {"", "r1", "rp", "rp:3", "rp:0", "rp:x", "rm:-2", "ralpha:1.5", "ralpha:-1", "minmax:2",
                          "r0:1", "ralpha:", "rp:4.5"})
    EXPECT_THROW(RSystem::parse(bad), std::invalid_argument) << bad;
  EXPECT_THROW(RSystem::r_p(3), std::invalid_argument);
  EXPECT_THROW(RSystem::r_alpha(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace sage

namespace sage {
namespace {

// P and M are capped where doubles still hold x^P: every allowed rp keeps
// the sign of min(x, y) from 1e-6 to 1e6.
TEST(RFunction, RpKeepsItsSignAcrossScalesUpToTheCap) {
  for (int p = 2; p <= kMaxEvenParameter; p += 2) {
    const RSystem s = RSystem::r_p(p);
    for (double scale : {1e-6, 1.0, 1e6}) {
      EXPECT_LT(r_and(-1.0 * scale, 2.0 * scale, s), 0.0) << p << " " << scale;
      EXPECT_GT(r_and(1.0 * scale, 2.0 * scale, s), 0.0) << p << " " << scale;
      EXPECT_GT(r_or(-1.0 * scale, 2.0 * scale, s), 0.0) << p << " " << scale;
    }
  }
  EXPECT_THROW(RSystem::parse("rp:18"), std::invalid_argument);
  EXPECT_THROW(RSystem::parse("rp:1e300"), std::invalid_argument);
  EXPECT_THROW(RSystem::r_p(64), std::invalid_argument);
}

}  // namespace
}  // namespace sage
