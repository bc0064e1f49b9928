// Claims: bounded-operator fields (paper 001) ray cast as fast as other
// fields, because their interval extension is tight (bounded.hpp: linear
// bounds from tangents and chords of the level curve). Outside both
// supports the enclosure is 0 instead of the whole line, so rays skip
// empty space. Rays hit the right surface: beyond one support, the other
// ball's sphere (to 1e-9); in the transition zone, the first root of the
// field found by fine point sampling along the ray (to 1e-9). A small
// picture takes a bounded number of interval evaluations per ray (a count,
// not a time; the loose intervals took 98,000 per ray on an 8x6 picture).
// The same holds for the sharp transition (issue 5).

#include <sage/expression/bounded.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/render/ray_cast.hpp>
#include <sage/render/solid.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

namespace sage::render {
namespace {

/// Two bounded balls, centres (-0.5, 0, 0) and (0.5, 0, 0), radii 0.8 and
/// 0.7, support half-width 0.5, united with theta 15 and 70 degrees.
Expr bounded_union_of_balls(const BoundedTransition& t) {
  const Expr a = bounded_potential(ball({-0.5, 0, 0}, 0.8, 3), 0.5);
  const Expr b = bounded_potential(ball({0.5, 0, 0}, 0.7, 3), 0.5);
  return iso_field(bounded_compose(BoundedOp::Union, a, b, t, 3), t.iso);
}

BoundedTransition transition() {
  BoundedTransition t;
  t.theta1 = 15 * M_PI / 180;
  t.theta2 = 70 * M_PI / 180;
  return t;
}

/// First root of the field along the ray in [0, t1] by point sampling
/// every `step` and bisection in doubles; NaN if none.
double sampled_first_root(RayCaster& c, const Ray& ray, double t1, double step) {
  auto f = [&](double t) { return c.value(ray.origin + t * ray.direction); };
  for (double a = 0; a < t1; a += step) {
    double lo = a, hi = a + step;
    if (f(hi) < 0) continue;
    for (int i = 0; i < 80; ++i) {
      const double m = 0.5 * (lo + hi);
      (f(m) >= 0 ? hi : lo) = m;
    }
    return hi;
  }
  return NAN;
}

TEST(BoundedRender, EnclosureOutsideTheSupportsIsZero) {
  const FieldTapes tapes(bounded_union_of_balls(transition()));
  Evaluator<Interval> box(tapes.field);
  // A box far from both balls: the potentials are 0 (up to outward
  // rounding), so omega = G - 1/2 is enclosed near -1/2.
  const Interval b[3] = {{2.0, 2.5}, {1.0, 1.5}, {-0.2, 0.2}};
  box.evaluate_with(b);
  std::cout << "[ bounded union ] enclosure far outside: [" << box.result().lo << ", " << box.result().hi << "]\n";
  EXPECT_LT(box.result().hi, -0.49);
  EXPECT_GT(box.result().lo, -0.51);
}

TEST(BoundedRender, RaysHitTheRightSurface) {
  for (const std::string variant : {"", " with profile", " sharp"}) {
    BoundedTransition t = transition();
    if (variant == " with profile") t.profile_points = {{0.05, 0.72, 0}};
    t.sharp = variant == " sharp";
    const FieldTapes tapes(bounded_union_of_balls(t));
    RayCaster caster(tapes, 1e-7);
    // Along -x from (3, 0, 0): the left ball's field (0.64 - (x + 0.5)^2) /
    // 1.6 is below -0.5 (outside its support) for x > 0.7, so G is the
    // right ball's potential there and the first hit its sphere, x = 1.2.
    const Ray axis{{3, 0, 0}, {-1, 0, 0}};
    const auto hit = caster.first_hit(axis, 0, 6, HitMethod::IntervalBisection);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(*hit, 1.8, 1e-9);
    // Rays down through the transition zone between the balls.
    double worst = 0;
    for (int i = 0; i <= 20; ++i) {
      const double x = -0.4 + 0.04 * i;
      const Ray down{{x, 0.3, 3}, normalized({0.05, -0.1, -1})};
      const double expected = sampled_first_root(caster, down, 6, 1e-3);
      ASSERT_TRUE(std::isfinite(expected));
      for (HitMethod m : {HitMethod::IntervalBisection, HitMethod::SphereTracing}) {
        const auto h = caster.first_hit(down, 0, 6, m);
        ASSERT_TRUE(h) << "x = " << x;
        worst = std::max(worst, std::abs(*h - expected));
      }
    }
    std::cout << "[ bounded union" << variant << " ] worst hit error against sampled roots: " << worst << "\n";
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(BoundedRender, SmallPictureNeedsFewIntervalEvaluationsPerRay) {
  SolidOptions o;
  o.width = 64, o.height = 48;
  const Vec3 lo{-1.5, -1.0, -1.0}, hi{1.4, 1.0, 1.0};
  o.camera = camera_for_box(lo, hi);
  for (bool sharp : {false, true}) {
    BoundedTransition t = transition();
    t.sharp = sharp;
    const SolidPicture pic = render_solid(bounded_union_of_balls(t), lo, hi, o);
    const double per_ray = static_cast<double>(pic.stats.interval_evaluations) / pic.stats.rays;
    std::cout << "[ bounded union picture" << (sharp ? ", sharp" : "") << " ] " << pic.stats.hits << " hits of "
              << pic.stats.rays << " rays, " << per_ray << " interval evaluations per ray\n";
    EXPECT_GT(pic.stats.hits, 300);
    EXPECT_LT(per_ray, 1000);
  }
}

}  // namespace
}  // namespace sage::render
