#pragma once
// Generated polygons for the polygon tests: random star-shaped polygons
// with holes, combs, spirals and nearly collinear outlines, and an exact
// reference classification (CGAL's bounded_side_2) independent of sage's.

#include <sage/geometry/polygon.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace sage::geometry::test {

inline Ring make_ring(std::vector<Point2> points, int ring_index = 0) {
  Ring r;
  r.points = std::move(points);
  r.ring = ring_index;
  for (std::size_t i = 0; i < r.points.size(); ++i) r.source_vertex.push_back(static_cast<int>(i));
  return r;
}

/// A star-shaped polygon around c: n vertices at sorted random angles and
/// random radii in [r_min, r_max]; counter-clockwise unless clockwise.
inline std::vector<Point2> star(std::mt19937_64& rng, Point2 c, int n, double r_min, double r_max,
                                bool clockwise = false) {
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), radius(r_min, r_max);
  std::vector<double> a(static_cast<std::size_t>(n));
  for (double& v : a) v = angle(rng);
  std::sort(a.begin(), a.end());
  std::vector<Point2> p;
  for (double t : a) {
    const double r = radius(rng);
    p.push_back({c[0] + r * std::cos(t), c[1] + r * std::sin(t)});
  }
  if (clockwise) std::reverse(p.begin(), p.end());
  return p;
}

/// A comb: a bar [0, 2 teeth] x [0, 1] with `teeth` thin teeth up to y = 6
/// (counter-clockwise).
inline std::vector<Point2> comb(int teeth) {
  const double w = 2.0 * teeth;
  std::vector<Point2> p{{0, 0}, {w, 0}, {w, 1}};
  for (int k = teeth - 1; k >= 0; --k) {
    const double x = 2.0 * k;
    p.insert(p.end(), {{x + 1.6, 1}, {x + 1.6, 6}, {x + 0.4, 6}, {x + 0.4, 1}});
  }
  p.push_back({0, 1});
  return p;
}

/// A thick polygonal spiral of `turns` turns: out along the outer arm and
/// back along the inner one (counter-clockwise).
inline std::vector<Point2> spiral(double turns, int per_turn) {
  std::vector<Point2> outer, inner;
  const int n = static_cast<int>(turns * per_turn);
  for (int i = 0; i <= n; ++i) {
    const double t = 2 * M_PI * i / per_turn, r = 1 + 0.5 * t / (2 * M_PI);
    outer.push_back({(r + 0.15) * std::cos(t), (r + 0.15) * std::sin(t)});
    inner.push_back({(r - 0.15) * std::cos(t), (r - 0.15) * std::sin(t)});
  }
  std::vector<Point2> p = outer;
  p.insert(p.end(), inner.rbegin(), inner.rend());
  return p;
}

/// A rectangle whose long sides zig-zag by `wiggle` (nearly collinear edges).
inline std::vector<Point2> nearly_collinear(int n, double wiggle) {
  std::vector<Point2> p;
  for (int i = 0; i <= n; ++i) p.push_back({10.0 * i / n, (i % 2 ? wiggle : 0.0)});
  for (int i = n; i >= 0; --i) p.push_back({10.0 * i / n, 1.0 + (i % 2 ? -wiggle : 0.0)});
  return p;
}

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

/// Exact reference membership: +1 inside, 0 on, -1 outside.
inline int reference_side(const PolygonSet& set, const Point2& q) {
  const K::Point_2 p(q[0], q[1]);
  auto side = [&p](const Ring& r) {
    std::vector<K::Point_2> pts;
    for (const auto& v : r.points) pts.emplace_back(v[0], v[1]);
    return CGAL::bounded_side_2(pts.begin(), pts.end(), p, K());
  };
  for (const auto& poly : set.polygons) {
    const auto s = side(poly.outer);
    if (s == CGAL::ON_BOUNDARY) return 0;
    if (s == CGAL::ON_UNBOUNDED_SIDE) continue;
    bool in_hole = false;
    for (const auto& h : poly.holes) {
      const auto t = side(h);
      if (t == CGAL::ON_BOUNDARY) return 0;
      in_hole = in_hole || t == CGAL::ON_BOUNDED_SIDE;
    }
    return in_hole ? -1 : 1;
  }
  return -1;
}

/// Distance from q to the nearest edge of the set.
inline double boundary_distance(const PolygonSet& set, const Point2& q) {
  double best = 1e300;
  set.for_each_ring([&](const Ring& r) {
    const std::size_t n = r.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Point2& a = r.points[i];
      const Point2& b = r.points[(i + 1) % n];
      const double dx = b[0] - a[0], dy = b[1] - a[1];
      const double t = std::clamp(((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      best = std::min(best, std::hypot(a[0] + t * dx - q[0], a[1] + t * dy - q[1]));
    }
  });
  return best;
}

}  // namespace sage::geometry::test
