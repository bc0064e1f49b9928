// Claims (papers 003 and 000): interval bisection along a ray finds the
// exact first hit of analytic surfaces (sphere, plane, torus) to 1e-9, and
// so does sphere tracing with Lipschitz bounds from interval gradients;
// interval bisection never misses a thin shell that point sampling along
// the ray misses, however thin.

#include <sage/expression/primitives.hpp>
#include <sage/render/ray_cast.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

namespace sage::render {
namespace {

const HitMethod kMethods[] = {HitMethod::IntervalBisection, HitMethod::SphereTracing};
const char* name(HitMethod m) { return m == HitMethod::IntervalBisection ? "interval" : "sphere"; }

struct Case {
  Ray ray;
  double expected;
};

/// Casts every case with both methods; returns the largest error.
double worst_error(const Expr& field, const std::vector<Case>& cases, HitMethod method) {
  const FieldTapes tapes(field);
  RayCaster caster(tapes, 1e-6);
  double worst = 0;
  for (const Case& c : cases) {
    const auto t = caster.first_hit(c.ray, 0, 20, method);
    if (!t) return INFINITY;
    worst = std::max(worst, std::abs(*t - c.expected));
  }
  return worst;
}

std::mt19937_64 rng(0x5A6E);
double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

TEST(RayCast, SphereHitDistanceIsExact) {
  const Vec3 c{0.2, -0.1, 0.3};
  const double r = 0.8;
  std::vector<Case> cases;
  for (int i = 0; i < 300; ++i) {
    // From a point outside towards a random point inside the sphere.
    const Vec3 o{uniform(-4, 4), uniform(-4, 4), 3.5};
    const Vec3 aim = c + Vec3{uniform(-0.5, 0.5), uniform(-0.5, 0.5), uniform(-0.5, 0.5)};
    const Vec3 d = normalized(aim - o), oc = o - c;
    const double b = dot(oc, d), disc = b * b - (dot(oc, oc) - r * r);
    cases.push_back({{o, d}, -b - std::sqrt(disc)});
  }
  for (HitMethod m : kMethods) {
    const double err = worst_error(ball({c[0], c[1], c[2]}, r, 3), cases, m);
    std::cout << "[ sphere, " << name(m) << " ] worst hit distance error " << err << "\n";
    EXPECT_LT(err, 1e-9) << name(m);
  }
}

TEST(RayCast, PlaneHitDistanceIsExact) {
  const Vec3 point{0.1, 0.2, -0.3}, normal = normalized({0.3, -0.2, 1});  // outward: solid below
  std::vector<Case> cases;
  for (int i = 0; i < 300; ++i) {
    // Start 0.5 to 5 above the plane: the sideways offset lies in the plane.
    const Vec3 sideways{uniform(-2, 2), uniform(-2, 2), 0};
    const Vec3 o = point + (sideways - dot(sideways, normal) * normal) + uniform(0.5, 5) * normal;
    const Vec3 d = normalized(Vec3{uniform(-0.5, 0.5), uniform(-0.5, 0.5), 0} - 1.0 * normal);
    cases.push_back({{o, d}, dot(point - o, normal) / dot(d, normal)});
  }
  for (HitMethod m : kMethods) {
    const double err =
        worst_error(halfspace({point[0], point[1], point[2]}, {normal[0], normal[1], normal[2]}, 3), cases, m);
    std::cout << "[ plane, " << name(m) << " ] worst hit distance error " << err << "\n";
    EXPECT_LT(err, 1e-9) << name(m);
  }
}

TEST(RayCast, TorusHitDistanceIsExact) {
  const double R = 1.0, r = 0.3;
  std::vector<Case> cases;
  // Straight down onto the tube: z = sqrt(r^2 - (rho - R)^2) at radius rho.
  for (int i = 0; i < 200; ++i) {
    const double rho = uniform(R - 0.95 * r, R + 0.95 * r), phi = uniform(0, 2 * M_PI), top = uniform(1, 4);
    cases.push_back({{{rho * std::cos(phi), rho * std::sin(phi), top}, {0, 0, -1}},
                     top - std::sqrt(r * r - (rho - R) * (rho - R))});
  }
  // Along a diameter in the plane of the ring: the outer equator first.
  for (int i = 0; i < 50; ++i) {
    const double phi = uniform(0, 2 * M_PI), start = uniform(2, 5);
    cases.push_back(
        {{{start * std::cos(phi), start * std::sin(phi), 0}, {-std::cos(phi), -std::sin(phi), 0}}, start - (R + r)});
  }
  for (HitMethod m : kMethods) {
    const double err = worst_error(torus({0, 0, 0}, {0, 0, 1}, R, r), cases, m);
    std::cout << "[ torus, " << name(m) << " ] worst hit distance error " << err << "\n";
    EXPECT_LT(err, 1e-9) << name(m);
  }
}

TEST(RayCast, MissesNothingAndFindsNothingWhereThereIsNothing) {
  const FieldTapes tapes(ball({0, 0, 0}, 1, 3));
  RayCaster caster(tapes, 1e-6);
  for (HitMethod m : kMethods) {
    EXPECT_FALSE(caster.first_hit({{-5, 1.001, 0}, {1, 0, 0}}, 0, 10, m)) << name(m);
    EXPECT_FALSE(caster.first_hit({{-5, 0, 0}, {1, 0, 0}}, 0, 3.9, m)) << name(m) << ": beyond t1";
    EXPECT_EQ(caster.first_hit({{0.5, 0, 0}, {1, 0, 0}}, 0, 10, m).value_or(-1), 0.0) << name(m) << ": inside";
  }
}

TEST(RayCast, ThinShellsMissedByPointSamplingAreFound) {
  // A spherical shell of half-thickness h: omega = h - | |p| - 1 |.
  const Expr radius = sqrt(square(Expr::x()) + square(Expr::y()) + square(Expr::z()));
  const Ray ray{{-3, 0.3, 0.2}, {1, 0, 0}};
  const double entry = 3 - std::sqrt(1 - 0.13);  // where the ray meets |p| = 1
  for (double h : {1e-3, 1e-6, 1e-9, 1e-12}) {
    const Expr shell = h - abs(radius - 1.0);
    const FieldTapes tapes(shell);
    RayCaster caster(tapes, 1e-6);
    int positive_samples = 0;
    for (double t = 0; t <= 6; t += 0.01) positive_samples += caster.value(ray.origin + t * ray.direction) >= 0;
    EXPECT_EQ(positive_samples, 0) << "test setup: point sampling should miss the shell, h = " << h;
    const auto hit = caster.first_hit(ray, 0, 6, HitMethod::IntervalBisection);
    ASSERT_TRUE(hit) << "h = " << h;
    // Within the shell's width along the ray, or within a leaf.
    EXPECT_NEAR(*hit, entry, std::max(1e-6, 4 * h)) << "h = " << h;
  }
}

TEST(RayCast, ClipsRaysToTheBox) {
  const auto span = clip_to_box({{-5, 0, 0}, {1, 0, 0}}, {-1, -1, -1}, {1, 1, 1});
  ASSERT_TRUE(span);
  EXPECT_DOUBLE_EQ(span->first, 4);
  EXPECT_DOUBLE_EQ(span->second, 6);
  EXPECT_FALSE(clip_to_box({{-5, 2, 0}, {1, 0, 0}}, {-1, -1, -1}, {1, 1, 1}));
}

}  // namespace
}  // namespace sage::render
