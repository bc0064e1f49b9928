// Claim (paper 004, conclusions; FORMULAS.md): normalize(f) =
// f / sqrt(f^2 + |grad f|^2) has the sign and zero set of f, magnitude
// below 1, and |grad| = 1 on f = 0: it normalizes a non-normalized
// primitive to first order. Checked on an ellipse, a superquadric and a
// 3D ellipsoid at many analytically sampled boundary points.

#include "test_support.hpp"

#include <sage/expression/normalize.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

template <int N>
void check_normalized_on_boundary(const Expr& f, const std::vector<Point>& boundary, std::uint64_t seed) {
  const Expr g = normalize(f, N);
  const Tape raw_tape(f, N), tape(g, N);
  Evaluator<Tuple<N, 1>> raw(raw_tape), norm(tape);
  double raw_worst = 0;
  for (const Point& p : boundary) {
    const auto r = raw.at(p);
    const auto t = norm.at(p);
    ASSERT_NEAR(r.value(), 0.0, 1e-14) << "test setup: point not on the boundary";
    raw_worst = std::max(raw_worst, std::abs(test::gradient_norm(r) - 1));
    EXPECT_NEAR(t.value(), 0.0, 1e-14);
    EXPECT_NEAR(test::gradient_norm(t), 1.0, 1e-12);
    // The gradient keeps the direction of grad f (the inner normal).
    const auto gr = r.gradient(), gt = t.gradient();
    const double rn = test::gradient_norm(r);
    for (int i = 0; i < N; ++i) EXPECT_NEAR(gt[i], gr[i] / rn, 1e-12);
  }
  // The test means something only if f itself was not normalized there.
  EXPECT_GT(raw_worst, 0.2);

  // Same sign as f everywhere, and bounded by 1 in magnitude.
  Evaluator<double> fv(raw_tape), gv(tape);
  auto rng = test::make_rng(seed);
  for (int i = 0; i < 2000; ++i) {
    const Point p = test::random_point(rng, -3, 3, N);
    const double a = fv.at(p), b = gv.at(p);
    EXPECT_EQ(a > 0, b > 0);
    EXPECT_EQ(a < 0, b < 0);
    EXPECT_LT(std::abs(b), 1.0);
  }
}

TEST(Normalize, Ellipse) {
  const Expr x = Expr::x(), y = Expr::y();
  std::vector<Point> pts;
  for (int i = 0; i < 360; ++i) {
    const double th = 2 * M_PI * (i + 0.25) / 360;
    pts.push_back({2 * std::cos(th), std::sin(th), 0});
  }
  check_normalized_on_boundary<2>(1.0 - square(x) / 4.0 - square(y), pts, 30);
}

TEST(Normalize, Superquadric) {
  // 1 - x^4 - y^4: boundary points x = sgn(c) |c|^(1/2), y = sgn(s) |s|^(1/2)
  // (so x^4 + y^4 = c^2 + s^2 = 1).
  const Expr x = Expr::x(), y = Expr::y();
  std::vector<Point> pts;
  for (int i = 0; i < 360; ++i) {
    const double th = 2 * M_PI * (i + 0.25) / 360, c = std::cos(th), s = std::sin(th);
    pts.push_back({std::copysign(std::sqrt(std::abs(c)), c), std::copysign(std::sqrt(std::abs(s)), s), 0});
  }
  check_normalized_on_boundary<2>(1.0 - pow_int(x, 4) - pow_int(y, 4), pts, 31);
}

TEST(Normalize, Ellipsoid3D) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  std::vector<Point> pts;
  auto rng = test::make_rng(32);
  for (int i = 0; i < 500; ++i) {
    const double u = test::uniform(rng, -1, 1), ph = test::uniform(rng, 0, 2 * M_PI), s = std::sqrt(1 - u * u);
    pts.push_back({2 * s * std::cos(ph), 3 * s * std::sin(ph), 0.5 * u});
  }
  check_normalized_on_boundary<3>(1.0 - square(x) / 4.0 - square(y) / 9.0 - square(2.0 * z), pts, 33);
}

TEST(Normalize, GradientNormSquaredIsTheClosedForm) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr g2 = gradient_norm_squared(square(x) * y + sin(y), 2);
  auto rng = test::make_rng(34);
  for (int i = 0; i < 100; ++i) {
    const Point p = test::random_point(rng, -2, 2, 2);
    const double fx = 2 * p[0] * p[1], fy = p[0] * p[0] + std::cos(p[1]);
    EXPECT_NEAR(test::eval(g2, p, 2), fx * fx + fy * fy, 1e-12 * (1 + fx * fx + fy * fy));
  }
}

}  // namespace
}  // namespace sage
