// Claim (paper 004, sec. 3.3; primitives.hpp): every primitive is >= 0
// inside, 0 on its boundary, < 0 outside and normalized to first order
// (|grad| = 1, pointing inward) on its boundary. Boundary points and
// membership are computed analytically in the test, independently of the
// library; composite primitives (capped cylinder, box) are checked on
// faces away from their edges, where the R-function keeps normalization.

#include "test_support.hpp"

#include <sage/expression/primitives.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

struct Sample {
  Point p;
  Point inner_normal;  // unit
};

Point add(const Point& a, const Point& b, double s = 1.0) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Point unit(const Point& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}
// Two unit vectors orthogonal to u (unit).
std::pair<Point, Point> frame(const Point& u) {
  const Point t = std::abs(u[0]) < 0.9 ? Point{1, 0, 0} : Point{0, 1, 0};
  const Point e1 = unit(cross(u, t));
  return {e1, cross(u, e1)};
}

template <int N>
void check_primitive(const std::string& name, const Expr& f, const std::vector<Sample>& boundary,
                     const std::function<int(const Point&)>& membership, double lo, double hi, std::uint64_t seed) {
  SCOPED_TRACE(name);
  const Tape tape(f, N);
  Evaluator<Tuple<N, 1>> tv(tape);
  Evaluator<double> dv(tape);
  ASSERT_FALSE(boundary.empty());
  for (const Sample& s : boundary) {
    const auto t = tv.at(s.p);
    EXPECT_NEAR(t.value(), 0.0, 1e-13);
    EXPECT_NEAR(test::gradient_norm(t), 1.0, 1e-12);
    const auto g = t.gradient();
    for (int i = 0; i < N; ++i) EXPECT_NEAR(g[i], s.inner_normal[i], 1e-12);
    // Just inside is positive, just outside negative, by the distance.
    EXPECT_NEAR(dv.at(add(s.p, s.inner_normal, 1e-6)), 1e-6, 1e-10);
    EXPECT_NEAR(dv.at(add(s.p, s.inner_normal, -1e-6)), -1e-6, 1e-10);
  }
  auto rng = test::make_rng(seed);
  int inside = 0, outside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Point p = test::random_point(rng, lo, hi, N);
    const int m = membership(p);
    const double v = dv.at(p);
    if (m > 0) {
      EXPECT_GT(v, 0.0) << p[0] << "," << p[1] << "," << p[2];
      ++inside;
    }
    if (m < 0) {
      EXPECT_LT(v, 0.0) << p[0] << "," << p[1] << "," << p[2];
      ++outside;
    }
  }
  EXPECT_GT(inside, 100);  // the sample really tests both sides
  EXPECT_GT(outside, 100);
}

TEST(Primitives, Halfspace) {
  for (int dim : {2, 3}) {
    const Point p0{0.3, -0.2, dim == 3 ? 0.5 : 0.0};
    const Point n = dim == 3 ? Point{1, 2, -2} : Point{3, -4, 0};  // outward, not unit
    const Point un = unit(n), inner{-un[0], -un[1], -un[2]};
    const auto [e1, e2] = frame(un);
    std::vector<Sample> pts;
    auto rng = test::make_rng(40);
    for (int i = 0; i < 100; ++i) {
      Point q = add(add(p0, e1, test::uniform(rng, -3, 3)), e2, dim == 3 ? test::uniform(rng, -3, 3) : 0.0);
      if (dim == 2) q = add(p0, Point{-un[1], un[0], 0}, test::uniform(rng, -3, 3));
      pts.push_back({q, inner});
    }
    auto member = [&](const Point& q) { return dot(add(q, p0, -1), un) < 0 ? 1 : -1; };
    const Expr f = halfspace(p0, n, dim);
    if (dim == 2)
      check_primitive<2>("halfspace 2D", f, pts, member, -3, 3, 41);
    else
      check_primitive<3>("halfspace 3D", f, pts, member, -3, 3, 41);
  }
}

TEST(Primitives, BallAndDisk) {
  const Point c{0.5, -0.25, 0.75};
  const double r = 1.3;
  auto rng = test::make_rng(42);
  std::vector<Sample> disk, ball_pts;
  for (int i = 0; i < 200; ++i) {
    const double th = test::uniform(rng, 0, 2 * M_PI);
    disk.push_back({{c[0] + r * std::cos(th), c[1] + r * std::sin(th), 0}, {-std::cos(th), -std::sin(th), 0}});
    const double u = test::uniform(rng, -1, 1), s = std::sqrt(1 - u * u);
    const Point d{s * std::cos(th), s * std::sin(th), u};
    ball_pts.push_back({add(c, d, r), {-d[0], -d[1], -d[2]}});
  }
  check_primitive<2>(
      "disk", ball(c, r, 2), disk, [&](const Point& p) { return std::hypot(p[0] - c[0], p[1] - c[1]) < r ? 1 : -1; },
      -2, 2, 43);
  check_primitive<3>(
      "ball", ball(c, r, 3), ball_pts,
      [&](const Point& p) { return std::sqrt(dot(add(p, c, -1), add(p, c, -1))) < r ? 1 : -1; }, -2, 2, 44);
  EXPECT_THROW(ball(c, 0.0, 3), std::invalid_argument);
  EXPECT_THROW(ball(c, -1.0, 2), std::invalid_argument);
  EXPECT_THROW(ball(c, 1.0, 4), std::invalid_argument);
}

// Axial frame of an axis through `o` with direction u: point at axial
// coordinate h, radius rho, angle th.
Point axial_point(const Point& o, const Point& u, double h, double rho, double th, Point* radial = nullptr) {
  const auto [e1, e2] = frame(u);
  const Point rad = add(Point{0, 0, 0},
                        add(Point{std::cos(th) * e1[0], std::cos(th) * e1[1], std::cos(th) * e1[2]}, e2, std::sin(th)));
  if (radial) *radial = rad;
  return add(add(o, u, h), rad, rho);
}
// Axial coordinate and distance to the axis.
std::pair<double, double> axial_coordinates(const Point& o, const Point& u, const Point& p) {
  const Point q = add(p, o, -1);
  const double h = dot(q, u);
  return {h, std::sqrt(std::max(0.0, dot(q, q) - h * h))};
}

TEST(Primitives, Cylinder) {
  const Point o{0.2, -0.1, 0.3}, dir{1, 1, 2};
  const Point u = unit(dir);
  const double r = 0.8;
  auto rng = test::make_rng(45);
  std::vector<Sample> pts;
  for (int i = 0; i < 200; ++i) {
    Point rad;
    const Point p = axial_point(o, u, test::uniform(rng, -3, 3), r, test::uniform(rng, 0, 2 * M_PI), &rad);
    pts.push_back({p, {-rad[0], -rad[1], -rad[2]}});
  }
  check_primitive<3>(
      "cylinder", cylinder(o, dir, r), pts,
      [&](const Point& p) { return axial_coordinates(o, u, p).second < r ? 1 : -1; }, -2, 2, 46);
  EXPECT_THROW(cylinder(o, {0, 0, 0}, r), std::invalid_argument);
}

TEST(Primitives, CappedCylinder) {
  const Point base{0.1, 0.2, -0.5}, dir{0, 1, 1};
  const Point u = unit(dir);
  const double r = 0.7, height = 1.5;
  for (const RSystem& s : {RSystem::r0(), RSystem::min_max(), RSystem::r_p(4)}) {
    auto rng = test::make_rng(47);
    std::vector<Sample> pts;
    for (int i = 0; i < 100; ++i) {
      // Side, away from the rims.
      Point rad;
      const Point p =
          axial_point(base, u, test::uniform(rng, 0.2, height - 0.2), r, test::uniform(rng, 0, 2 * M_PI), &rad);
      pts.push_back({p, {-rad[0], -rad[1], -rad[2]}});
      // Caps, away from the rims.
      const double rho = test::uniform(rng, 0, r - 0.2), th = test::uniform(rng, 0, 2 * M_PI);
      pts.push_back({axial_point(base, u, 0, rho, th), u});
      pts.push_back({axial_point(base, u, height, rho, th), {-u[0], -u[1], -u[2]}});
    }
    check_primitive<3>(
        "capped cylinder " + s.name(), capped_cylinder(base, dir, r, height, s), pts,
        [&](const Point& p) {
          const auto [h, rho] = axial_coordinates(base, u, p);
          return h > 0 && h < height && rho < r ? 1 : -1;
        },
        -1.5, 1.5, 48);
  }
  EXPECT_THROW(capped_cylinder(base, dir, r, 0.0, RSystem::r0()), std::invalid_argument);
}

TEST(Primitives, Cone) {
  const Point apex{0.1, -0.3, -1.0}, dir{0.2, 0.1, 1};
  const Point u = unit(dir);
  const double a = 0.5;  // half-angle, radians
  auto rng = test::make_rng(49);
  std::vector<Sample> pts;
  for (int i = 0; i < 200; ++i) {
    const double s = test::uniform(rng, 0.05, 3), th = test::uniform(rng, 0, 2 * M_PI);
    Point rad;
    const Point p = axial_point(apex, u, s * std::cos(a), s * std::sin(a), th, &rad);
    // Inner normal: sin(a) u - cos(a) radial.
    pts.push_back({p, add(Point{std::sin(a) * u[0], std::sin(a) * u[1], std::sin(a) * u[2]}, rad, -std::cos(a))});
  }
  check_primitive<3>(
      "cone", cone(apex, dir, a), pts,
      [&](const Point& p) {
        const auto [h, rho] = axial_coordinates(apex, u, p);
        return h > 0 && rho < h * std::tan(a) ? 1 : -1;
      },
      -2, 2, 50);
  EXPECT_THROW(cone(apex, dir, 0.0), std::invalid_argument);
  EXPECT_THROW(cone(apex, dir, M_PI / 2), std::invalid_argument);
}

TEST(Primitives, Torus) {
  const Point c{0.1, 0.2, 0.3}, dir{1, 0, 1};
  const Point u = unit(dir);
  const double R = 1.2, r = 0.4;
  auto rng = test::make_rng(51);
  std::vector<Sample> pts;
  for (int i = 0; i < 200; ++i) {
    const double th = test::uniform(rng, 0, 2 * M_PI), ph = test::uniform(rng, 0, 2 * M_PI);
    Point rad;
    axial_point(c, u, 0, 1, th, &rad);
    // Tube centre circle point + r (cos ph radial + sin ph u); inner normal points back to the tube centre.
    const Point tube = add(c, rad, R);
    const Point d = add(Point{std::cos(ph) * rad[0], std::cos(ph) * rad[1], std::cos(ph) * rad[2]}, u, std::sin(ph));
    pts.push_back({add(tube, d, r), {-d[0], -d[1], -d[2]}});
  }
  check_primitive<3>(
      "torus", torus(c, dir, R, r), pts,
      [&](const Point& p) {
        const auto [h, rho] = axial_coordinates(c, u, p);
        return std::hypot(rho - R, h) < r ? 1 : -1;
      },
      -1.8, 1.8, 52);
  EXPECT_THROW(torus(c, dir, 0.0, r), std::invalid_argument);
}

TEST(Primitives, Ellipsoid) {
  const Point c{0.2, -0.1, 0.3}, ax{1.5, 0.7, 1.1};
  auto rng = test::make_rng(53);
  std::vector<Sample> e2, e3;
  for (int i = 0; i < 200; ++i) {
    const double th = test::uniform(rng, 0, 2 * M_PI);
    // Boundary (c + a cos, c + b sin); inner normal -(x/a^2, y/b^2) normalized.
    const Point p2{c[0] + ax[0] * std::cos(th), c[1] + ax[1] * std::sin(th), 0};
    e2.push_back({p2, unit({-std::cos(th) / ax[0], -std::sin(th) / ax[1], 0})});
    const double w = test::uniform(rng, -1, 1), s = std::sqrt(1 - w * w);
    const Point d{s * std::cos(th), s * std::sin(th), w};
    e3.push_back({{c[0] + ax[0] * d[0], c[1] + ax[1] * d[1], c[2] + ax[2] * d[2]},
                  unit({-d[0] / ax[0], -d[1] / ax[1], -d[2] / ax[2]})});
  }
  auto inside = [&](const Point& p, int dim) {
    double s = 0;
    for (int i = 0; i < dim; ++i) s += std::pow((p[i] - c[i]) / ax[i], 2);
    return s < 1 ? 1 : -1;
  };
  // Normalized to first order only: off the boundary the value is the
  // distance up to O(d^2), well inside the +-1e-6 probe tolerance.
  check_primitive<2>(
      "ellipse", ellipsoid(c, ax, 2), e2, [&](const Point& p) { return inside(p, 2); }, -2, 2, 54);
  check_primitive<3>(
      "ellipsoid", ellipsoid(c, ax, 3), e3, [&](const Point& p) { return inside(p, 3); }, -2, 2, 55);
  EXPECT_THROW(ellipsoid(c, {1, 0, 1}, 3), std::invalid_argument);
}

TEST(Primitives, Box) {
  const Point lo{-0.5, -1.0, 0.0}, hi{1.0, 0.5, 2.0};
  for (int dim : {2, 3})
    for (const RSystem& s : {RSystem::r0(), RSystem::min_max(), RSystem::r_p(2)}) {
      auto rng = test::make_rng(56);
      std::vector<Sample> pts;
      for (int face = 0; face < 2 * dim; ++face)
        for (int i = 0; i < 30; ++i) {
          const int axis = face / 2;
          Point p{0, 0, 0}, n{0, 0, 0};
          for (int k = 0; k < dim; ++k) p[k] = test::uniform(rng, lo[k] + 0.2, hi[k] - 0.2);
          p[axis] = face % 2 ? hi[axis] : lo[axis];
          n[axis] = face % 2 ? -1 : 1;
          pts.push_back({p, n});
        }
      auto member = [&](const Point& p) {
        for (int k = 0; k < dim; ++k)
          if (!(p[k] > lo[k] && p[k] < hi[k])) return -1;
        return 1;
      };
      const Expr f = box(lo, hi, dim, s);
      if (dim == 2)
        check_primitive<2>("box 2D " + s.name(), f, pts, member, -1.5, 2.5, 57);
      else
        check_primitive<3>("box 3D " + s.name(), f, pts, member, -1.5, 2.5, 57);
    }
  EXPECT_THROW(box(hi, lo, 3, RSystem::r0()), std::invalid_argument);
}

}  // namespace
}  // namespace sage
