// Claims of paper 004, sec. 4 (FORMULAS.md, Trimming), for the half-line
// y = 0, x >= 0 (h = y):
//  - normalized trimming with t = x is exactly the Euclidean distance to
//    the half-line, hence |grad| = 1 off it;
//  - smooth trimming agrees with it to first order near the half-line
//    (|w - d| / d -> 0), is |x| beyond the end on y = 0, differs far away;
//  - simple trimming is ~|y| near the half-line (relative error y^2/(4x)
//    for R0) and its derivative blows up at the end from outside;
//  - orthogonalization (fig. 13): with an inclined trimming line through
//    the end point, plain normalized trimming loses |grad w| = 1 near the
//    end point, orthogonalized trimming restores it;
//  - the segment field is zero exactly on the segment and distance-like,
//    and does not depend on the unit of length: h^4 is scaled by L^2.

#include "test_support.hpp"

#include <sage/expression/normalize.hpp>
#include <sage/expression/trimming.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

double distance_to_half_line(double x, double y) { return x >= 0 ? std::abs(y) : std::hypot(x, y); }

struct Field2 {
  explicit Field2(const Expr& e) : tape(e, 2), values(tape), tuples(tape) {}
  double value(double x, double y) { return values.at({x, y, 0}); }
  double grad_norm(double x, double y) { return test::gradient_norm(tuples.at({x, y, 0})); }
  Tape tape;
  Evaluator<double> values;
  Evaluator<Tuple<2, 1>> tuples;
};

TEST(Trimming, NormalizedIsTheEuclideanDistanceToTheHalfLine) {
  Field2 w(trim_normalized(Expr::y(), Expr::x()));
  auto rng = test::make_rng(20);
  for (int i = 0; i < 5000; ++i) {
    const double x = test::uniform(rng, -3, 3), y = test::uniform(rng, -3, 3);
    const double d = distance_to_half_line(x, y);
    EXPECT_NEAR(w.value(x, y), d, 1e-12 * (1 + d));
    EXPECT_NEAR(w.grad_norm(x, y), 1.0, 1e-12);
  }
  EXPECT_EQ(w.value(0, 0), 0.0);
  EXPECT_EQ(w.value(1.5, 0), 0.0);
}

// Points at distance d from the half-line, spread along it and around
// its end point (in the end point's normal cone, x < 0).
std::vector<std::array<double, 2>> points_near_half_line(double d, std::mt19937_64& rng, int n) {
  std::vector<std::array<double, 2>> pts;
  for (int i = 0; i < n; ++i) {
    if (i % 2 == 0) {
      const double x = test::uniform(rng, 0, 2), s = i % 4 == 0 ? 1.0 : -1.0;
      pts.push_back({x, s * d});
    } else {
      const double th = test::uniform(rng, M_PI / 2, 3 * M_PI / 2);
      pts.push_back({d * std::cos(th), d * std::sin(th)});
    }
  }
  return pts;
}

TEST(Trimming, SmoothAgreesWithTheDistanceToFirstOrderNearTheHalfLine) {
  Field2 w(trim_smooth(Expr::y(), Expr::x()));
  auto rng = test::make_rng(21);
  double previous = 1.0;
  for (double d : {1e-1, 1e-2, 1e-3, 1e-4}) {
    double worst_value = 0, worst_grad = 0;
    for (const auto& p : points_near_half_line(d, rng, 400)) {
      const double exact = distance_to_half_line(p[0], p[1]);
      worst_value = std::max(worst_value, std::abs(w.value(p[0], p[1]) - exact) / exact);
      worst_grad = std::max(worst_grad, std::abs(w.grad_norm(p[0], p[1]) - 1.0));
    }
    // |w - d| / d -> 0 (it shrinks with d), and |grad w| -> 1.
    EXPECT_LT(worst_value, 0.3 * d) << "d = " << d;
    EXPECT_LT(worst_grad, 2.0 * d) << "d = " << d;
    EXPECT_LT(worst_value, previous);
    previous = worst_value;
  }
  // Exactly |x| beyond the end on y = 0; zero on the half-line.
  for (double x : {-0.001, -0.5, -3.0}) EXPECT_NEAR(w.value(x, 0), std::abs(x), 1e-15);
  for (double x : {0.0, 0.5, 3.0}) EXPECT_EQ(w.value(x, 0), 0.0);
  // ... but it is not the distance far away.
  EXPECT_GT(std::abs(w.value(-1, 1) - std::sqrt(2.0)), 0.05);
  EXPECT_GT(std::abs(w.value(0.2, 2) - 2.0), 0.05);
}

TEST(Trimming, SimpleIsAbsYNearTheHalfLineAndBlowsUpAtTheEndFromOutside) {
  Field2 w(trim_simple(Expr::y(), Expr::x(), RSystem::r0()));
  // With R0: -((-y^2) AND x) = y^2 + y^4 / (2x) + O(y^8): w = |y| (1 + y^2/(4x) + ...).
  // (The next term is -y^4/(32 x^2); the round-off of x - sqrt(x^2 + y^4)
  // adds ~eps x / y^2 to the relative error, so y is not taken tiny.)
  for (double x : {0.1, 0.5, 2.0})
    for (double y : {5e-2, 1e-2, -1e-2, 3e-3, -1e-3}) {
      const double rel = (w.value(x, y) - std::abs(y)) / std::abs(y);
      EXPECT_NEAR(rel, y * y / (4 * x), 0.05 * y * y / (4 * x) + 1e-15 * x / (y * y)) << x << "," << y;
      EXPECT_NEAR(w.grad_norm(x, y), 1.0, 10 * y * y / x);  // normalized on both sides
    }
  // Zero on the half-line, positive elsewhere.
  EXPECT_EQ(w.value(0.7, 0), 0.0);
  EXPECT_GT(w.value(-0.1, 0), 0.0);
  // Beyond the end on y = 0: w = sqrt(-2x), so dw/dx = -1/sqrt(-2x) blows up.
  for (double x : {-1e-2, -1e-4, -1e-8}) {
    EXPECT_NEAR(w.value(x, 0), std::sqrt(-2 * x), 1e-12);
    EXPECT_NEAR(w.grad_norm(x, 0), 1 / std::sqrt(-2 * x), 1e-9 / std::sqrt(-2 * x));
  }
  EXPECT_GT(w.grad_norm(-1e-8, 0), 1000.0);
}

TEST(Trimming, OrthogonalizedTrimmingFunctionHasTheDerivedClosedForm) {
  // h = y, t = cos(b) x + sin(b) y (a trimming line through the origin,
  // at angle 90 - b to the half-line). t - h (grad h . grad t) = cos(b) x,
  // whose gradient has length sin(angle) = cos(b) and is orthogonal to
  // grad h; normalized: cos(b) x / sqrt(cos(b)^2 x^2 + cos(b)^2) = x / sqrt(1 + x^2).
  const Expr x = Expr::x(), y = Expr::y();
  auto rng = test::make_rng(22);
  for (double b_deg : {15.0, 30.0, 45.0, 60.0}) {
    const double b = b_deg * M_PI / 180;
    const Expr t = std::cos(b) * x + std::sin(b) * y;
    Field2 raw(t - y * (gradient(y, 2)[0] * gradient(t, 2)[0] + gradient(y, 2)[1] * gradient(t, 2)[1]));
    Field2 ortho(orthogonalize(y, t, 2));
    for (int i = 0; i < 200; ++i) {
      const double px = test::uniform(rng, -2, 2), py = test::uniform(rng, -2, 2);
      EXPECT_NEAR(raw.value(px, py), std::cos(b) * px, 1e-14);
      EXPECT_NEAR(ortho.value(px, py), px / std::sqrt(1 + px * px), 1e-14);
    }
    const auto g = raw.tuples.at({0.3, 0, 0}).gradient();
    EXPECT_NEAR(std::hypot(g[0], g[1]), std::cos(b), 1e-14);  // sin of the angle between the lines
    EXPECT_NEAR(g[1], 0.0, 1e-14);                            // orthogonal to grad h = (0, 1)
  }
}

TEST(Trimming, OrthogonalizationRestoresNormalizationNearTheEndPoint) {
  // Fig. 13 of paper 004: the half-line y = 0, x >= 0 trimmed by the line
  // x + y = 0 inclined at 45 degrees (t = (x + y)/sqrt(2)).
  const Expr x = Expr::x(), y = Expr::y();
  const Expr t = (x + y) * (1 / std::sqrt(2.0));
  Field2 plain(trim_normalized(y, t));
  Field2 ortho(trim_normalized(y, orthogonalize(y, t, 2)));
  Field2 ortho_smooth(trim_smooth(y, orthogonalize(y, t, 2)));

  const double eps = 1e-3;
  // (a) Next to the half-line just past its end point, on the side the
  // inclined line passes (y = -eps, 0 < x < eps): the normal direction is
  // -y. Plain: |grad|^2 = (y^2 + t^2 + sqrt(2) y t) / (y^2 + t^2) > 1.
  double plain_worst = 0, ortho_worst = 0, smooth_worst = 0;
  for (int i = 1; i < 20; ++i) {
    const double px = eps * i / 20.0, py = -eps;
    const double tt = (px + py) / std::sqrt(2.0);
    const double predicted = std::sqrt((py * py + tt * tt + std::sqrt(2.0) * py * tt) / (py * py + tt * tt));
    EXPECT_NEAR(plain.grad_norm(px, py), predicted, 1e-12);
    plain_worst = std::max(plain_worst, std::abs(plain.grad_norm(px, py) - 1));
    ortho_worst = std::max(ortho_worst, std::abs(ortho.grad_norm(px, py) - 1));
    smooth_worst = std::max(smooth_worst, std::abs(ortho_smooth.grad_norm(px, py) - 1));
    EXPECT_NEAR(ortho.value(px, py), eps, 1e-15);  // the distance |y|
  }
  EXPECT_GT(plain_worst, 0.25);  // measured 0.286 (sqrt(5/3) - 1 as x -> 0)
  EXPECT_LT(ortho_worst, 1e-12);
  EXPECT_LT(smooth_worst, 1e-6);

  // (b) In the normal cone of the end point (x < 0), along rays from it:
  // the gradient should be the unit ray direction and w the distance r.
  plain_worst = ortho_worst = smooth_worst = 0;
  double plain_value_worst = 0, ortho_value_worst = 0;
  for (int i = 1; i < 72; ++i) {
    const double th = M_PI / 2 + M_PI * i / 72.0;
    const double px = eps * std::cos(th), py = eps * std::sin(th);
    plain_worst = std::max(plain_worst, std::abs(plain.grad_norm(px, py) - 1));
    ortho_worst = std::max(ortho_worst, std::abs(ortho.grad_norm(px, py) - 1));
    smooth_worst = std::max(smooth_worst, std::abs(ortho_smooth.grad_norm(px, py) - 1));
    plain_value_worst = std::max(plain_value_worst, std::abs(plain.value(px, py) - eps) / eps);
    ortho_value_worst = std::max(ortho_value_worst, std::abs(ortho.value(px, py) - eps) / eps);
    // Directional derivative along the ray (the normal direction) is 1.
    const auto g = ortho.tuples.at({px, py, 0}).gradient();
    EXPECT_NEAR(g[0] * std::cos(th) + g[1] * std::sin(th), 1.0, 1e-5);
  }
  // Measured: plain |grad| = 0.54 at 157.5 degrees (|grad|^2 < 1 where
  // y > 0 > t) and 1.29 at 225 degrees, independent of eps; orthogonalized
  // 1 - |grad| = 1.5 eps^2 (1.5e-6 here), since t* = x / sqrt(1 + x^2).
  EXPECT_GT(plain_worst, 0.4);
  EXPECT_GT(plain_value_worst, 0.4);  // plain w is not the distance to the end point
  EXPECT_LT(ortho_worst, 2 * eps * eps);
  EXPECT_LT(ortho_value_worst, 2 * eps * eps);
  EXPECT_LT(smooth_worst, 2 * eps * eps);

  // (c) Where plain trimming was already fine: above the half-line
  // (y = +eps, x > 0) both have |grad| = 1.
  for (int i = 1; i < 20; ++i) {
    EXPECT_NEAR(plain.grad_norm(eps * i / 20.0, eps), 1.0, 1e-12);
    EXPECT_NEAR(ortho.grad_norm(eps * i / 20.0, eps), 1.0, 1e-12);
  }
}

TEST(Trimming, SegmentFieldIsZeroExactlyOnTheSegmentAndDistanceLikeNearIt) {
  const std::array<double, 2> a{0.5, -1.0}, b{2.0, 1.0};
  const double L = std::hypot(b[0] - a[0], b[1] - a[1]);
  const double ux = (b[0] - a[0]) / L, uy = (b[1] - a[1]) / L;
  auto dist = [&](double x, double y) {
    const double s = std::clamp((x - a[0]) * ux + (y - a[1]) * uy, 0.0, L);
    return std::hypot(x - a[0] - s * ux, y - a[1] - s * uy);
  };
  for (TrimMethod m : {TrimMethod::Normalized, TrimMethod::Smooth, TrimMethod::Simple}) {
    Field2 w(segment_field(a, b, m));
    // Zero on the segment, positive off it.
    for (double s : {0.0, 0.1, 0.5, 0.9, 1.0})
      EXPECT_NEAR(w.value(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])), 0.0, 1e-7);
    auto rng = test::make_rng(23);
    for (int i = 0; i < 500; ++i) {
      const double x = test::uniform(rng, -2, 4), y = test::uniform(rng, -3, 3);
      if (dist(x, y) > 1e-3) {
        EXPECT_GT(w.value(x, y), 0.0);
      }
    }
    if (m == TrimMethod::Simple) continue;
    // Distance to first order near the segment, including the end points.
    for (double d : {1e-3, 1e-4})
      for (int i = 0; i < 200; ++i) {
        const double s = test::uniform(rng, -0.3, 1.3), side = test::uniform(rng, -1, 1) < 0 ? -1.0 : 1.0;
        double x = a[0] + s * L * ux - side * d * uy, y = a[1] + s * L * uy + side * d * ux;
        if (s < 0 || s > 1) {  // around an end point, in its normal cone
          const auto& e = s < 0 ? a : b;
          const double th = test::uniform(rng, -M_PI / 2, M_PI / 2) + std::atan2(s < 0 ? -uy : uy, s < 0 ? -ux : ux);
          x = e[0] + d * std::cos(th);
          y = e[1] + d * std::sin(th);
        }
        const double exact = dist(x, y);
        EXPECT_NEAR(w.value(x, y), exact, 10 * exact * d) << "method " << static_cast<int>(m);
        EXPECT_NEAR(w.grad_norm(x, y), 1.0, 20 * d);
      }
  }
  EXPECT_THROW(segment_field(a, a, TrimMethod::Normalized), std::invalid_argument);
  EXPECT_THROW(trim_smooth(Expr::y(), Expr::x(), 0.0), std::invalid_argument);
  EXPECT_EQ(parse_trim_method("simple"), TrimMethod::Simple);
  EXPECT_EQ(parse_trim_method("normalized"), TrimMethod::Normalized);
  EXPECT_EQ(parse_trim_method("smooth"), TrimMethod::Smooth);
  EXPECT_THROW(parse_trim_method("bogus"), std::invalid_argument);
}

TEST(Trimming, TriangleFieldIsZeroExactlyOnTheTriangleAndDistanceLikeNearIt) {
  using V = std::array<double, 3>;
  const V a{0.25, -0.5, 1.0}, b{2.0, 0.5, 0.75}, c{0.5, 1.5, -0.25};
  auto mix = [](const V& p, double s, const V& q, double t) {
    return V{p[0] * s + q[0] * t, p[1] * s + q[1] * t, p[2] * s + q[2] * t};
  };
  auto add = [&](const V& p, const V& q) { return mix(p, 1.0, q, 1.0); };
  const V ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  V n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
  n = mix(n, 1.0 / std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), n, 0.0);
  const Tape tape(triangle_field(a, b, c), 3);
  const Tape reversed(triangle_field(a, c, b), 3);
  Evaluator<double> w(tape), w_reversed(reversed);
  Evaluator<Tuple<3, 1>> g(tape);
  auto rng = test::make_rng(31);
  for (int i = 0; i < 200; ++i) {
    // On the triangle (barycentric), zero; along its normal, |offset| to
    // first order with a gradient of unit length; the same field whichever
    // way the triangle turns.
    double s = test::uniform(rng, 0, 1), t = test::uniform(rng, 0, 1);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    const V on = add(a, add(mix(ab, s, ac, t), V{0, 0, 0}));
    EXPECT_NEAR(w.at(on), 0.0, 1e-7);
    for (double d : {1e-3, -1e-4}) {
      const V off = add(on, mix(n, d, n, 0.0));
      const double value = w.at(off);
      EXPECT_NEAR(value, std::abs(d), 10 * d * d + 1e-12);
      EXPECT_NEAR(w_reversed.at(off), value, 1e-12);
      EXPECT_NEAR(test::gradient_norm(g.at(off)), 1.0, 20 * std::abs(d));
    }
  }
  // Beside an edge, in the triangle's plane and outside it: the distance
  // to the edge.
  for (double d : {1e-3, 1e-4}) {
    const V middle = mix(add(a, b), 0.5, a, 0.0);
    V out{ab[1] * n[2] - ab[2] * n[1], ab[2] * n[0] - ab[0] * n[2], ab[0] * n[1] - ab[1] * n[0]};  // ab x n
    out = mix(out, d / std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]), out, 0.0);
    EXPECT_NEAR(w.at(add(middle, out)), d, 10 * d * d);
  }
  // Away from it, positive.
  for (int i = 0; i < 500; ++i) {
    const V p{test::uniform(rng, -1, 3), test::uniform(rng, -1.5, 2.5), test::uniform(rng, -1.5, 2)};
    const double plane = (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2];
    if (std::abs(plane) > 1e-3) {
      EXPECT_GT(w.at(p), 0.0);
    }
  }
}

// The same segment in metres and in kilometres (or any unit) gives the same
// field in that unit: w(k p; k a, k b) = k w(p; a, b), gradients equal.
// Unscaled, sqrt(t^2 + h^4) mixes lengths squared with lengths to the
// fourth: a coast in metres got another field than in kilometres, and
// complex branch points sqrt(|t|) from a far edge's carrier line, which
// spoil polynomial approximation of the far field.
TEST(Trimming, SmoothSegmentFieldDoesNotDependOnTheUnitOfLength) {
  const std::array<double, 2> a{0.3, -0.2}, b{1.1, 0.4};
  Field2 w(segment_field(a, b, TrimMethod::Smooth));
  auto rng = test::make_rng(24);
  for (double k : {1e-3, 7.0, 1e4}) {
    Field2 scaled(segment_field({k * a[0], k * a[1]}, {k * b[0], k * b[1]}, TrimMethod::Smooth));
    Evaluator<Tuple<2, 1>>& g = w.tuples;
    for (int i = 0; i < 300; ++i) {
      const double x = test::uniform(rng, -30, 30), y = test::uniform(rng, -30, 30);
      const double expected = k * w.value(x, y);
      EXPECT_NEAR(scaled.value(k * x, k * y), expected, 1e-12 * expected) << "k = " << k;
      const auto gw = g.at({x, y, 0}), gs = scaled.tuples.at({k * x, k * y, 0});
      EXPECT_NEAR(gs.c[1], gw.c[1], 1e-9);
      EXPECT_NEAR(gs.c[2], gw.c[2], 1e-9);
    }
  }
}

}  // namespace
}  // namespace sage
