// Polygon fields, CSG (decreasing convex hull) and trimmed-edge B-rep, on
// real GIS data and generated polygons: the sign agrees with CGAL's exact
// point-in-polygon classification at 10^5 random points per case; the
// gradient is unit on the edges; the B-rep field approaches the distance
// to second order; the CSG uses each edge's halfplane exactly once; and
// the well-formedness certificate accepts these fields and rejects a field
// with zeros off the boundary.

#include "polygon_test_support.hpp"

#include <sage/geometry/gis_reader.hpp>
#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/polygon_csg.hpp>
#include <sage/geometry/polygon_validation.hpp>
#include <sage/geometry/well_formedness.hpp>
#include <sage/tape/evaluator.hpp>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <atomic>
#include <functional>

namespace sage::geometry {
namespace {

struct Case {
  std::string name;
  PolygonSet polygons;
};

PolygonSet single(std::vector<Point2> outer, std::vector<std::vector<Point2>> holes = {}) {
  PolygonSet set;
  PolygonWithHoles p;
  p.outer = test::make_ring(std::move(outer));
  int k = 1;
  for (auto& h : holes) p.holes.push_back(test::make_ring(std::move(h), k++));
  set.polygons.push_back(std::move(p));
  validate_polygons(set, "generated");
  return set;
}

PolygonSet from_file(const std::string& name) {
  LoadOptions options;
  GisPolygons gis = read_gis_polygons(sage::test::test_data("gis/" + name), options);
  validate_polygons(gis.polygons, name);
  return gis.polygons;
}

std::vector<Case> cases() {
  std::mt19937_64 rng(11);
  std::vector<Case> c;
  c.push_back({"star with 3 holes",
               single(test::star(rng, {0, 0}, 60, 8, 10),
                      {test::star(rng, {4, 0}, 12, 0.8, 1.5, true), test::star(rng, {-2, 3.46}, 12, 0.8, 1.5, true),
                       test::star(rng, {-2, -3.46}, 12, 0.8, 1.5, true)})});
  c.push_back({"comb", single(test::comb(12))});
  c.push_back({"spiral", single(test::spiral(3, 40))});
  c.push_back({"nearly collinear", single(test::nearly_collinear(40, 1e-9))});
  {
    PolygonSet two = single(test::star(rng, {0, 0}, 30, 2, 3));
    PolygonWithHoles far;
    far.outer = test::make_ring(test::star(rng, {10, 1}, 25, 1, 2));
    two.polygons.push_back(far);
    validate_polygons(two, "generated");
    c.push_back({"two polygons", two});
  }
  c.push_back({"Washington Island", from_file("washington_island_wi_osm.geojson")});
  c.push_back({"Wisconsin", from_file("wisconsin_us-atlas_EPSG3070.geojson")});
  c.push_back({"Lake Vanern", from_file("lake_vanern_se_osm_EPSG32633.geojson")});
  return c;
}

struct Box {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  double diagonal() const { return std::hypot(x1 - x0, y1 - y0); }
};
Box box_of(const PolygonSet& set) {
  Box b;
  set.for_each_ring([&b](const Ring& r) {
    for (const auto& p : r.points) {
      b.x0 = std::min(b.x0, p[0]), b.x1 = std::max(b.x1, p[0]);
      b.y0 = std::min(b.y0, p[1]), b.y1 = std::max(b.y1, p[1]);
    }
  });
  return b;
}

// n random points in the box (10% margin) farther than `band` from every
// edge, with their exact classification (computed once per case).
struct Samples {
  std::vector<Point2> points;
  std::vector<int> side;
};
Samples random_samples(const PolygonSet& set, int n, double band) {
  const Box b = box_of(set);
  const double mx = 0.1 * (b.x1 - b.x0), my = 0.1 * (b.y1 - b.y0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(b.x0 - mx, b.x1 + mx), uy(b.y0 - my, b.y1 + my);
  std::vector<Point2> candidates(static_cast<std::size_t>(n));
  for (auto& q : candidates) q = {ux(rng), uy(rng)};
  std::vector<int> side(candidates.size(), 2);  // 2: too close to the boundary
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (test::boundary_distance(set, candidates[i]) > band) side[i] = test::reference_side(set, candidates[i]);
  Samples s;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (side[i] != 2) {
      s.points.push_back(candidates[i]);
      s.side.push_back(side[i]);
    }
  return s;
}

int sign_mismatches(const Samples& s, const Expr& field) {
  const Tape tape(field, 2);
  std::atomic<int> bad{0};
#pragma omp parallel
  {
    Evaluator<double> eval(tape);
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const double v = eval.at({s.points[i][0], s.points[i][1], 0});
      if ((s.side[i] > 0) != (v > 0) || (s.side[i] < 0) != (v < 0)) ++bad;
    }
  }
  return bad;
}

TEST(PolygonField, SignMatchesExactClassification) {
  for (const Case& c : cases()) {
    const int n = 100000;
    const Samples samples = random_samples(c.polygons, n, 1e-9 * box_of(c.polygons).diagonal());
    EXPECT_GT(samples.points.size(), static_cast<std::size_t>(n * 9 / 10)) << c.name;
    struct Variant {
      std::string name;
      Expr field;
    };
    std::vector<Variant> variants{{"csg r0", polygon_csg(c.polygons, RSystem::r0())},
                                  {"csg minmax", polygon_csg(c.polygons, RSystem::min_max())},
                                  {"csg rp:4", polygon_csg(c.polygons, RSystem::r_p(4))},
                                  {"brep r0", polygon_brep(c.polygons, RSystem::r0())}};
    for (const auto& v : variants) EXPECT_EQ(sign_mismatches(samples, v.field), 0) << c.name << ", " << v.name;
  }
}

// Calls f(edge start, edge end, unit inner normal, distance to the other
// edges from the edge's point at t) for sample points t of every edge.
void for_edge_points(const PolygonSet& set, const std::function<void(const Point2&, const Point2&, double)>& f) {
  set.for_each_ring([&](const Ring& r) {
    const std::size_t n = r.points.size();
    const std::size_t stride = std::max<std::size_t>(1, n / 150);
    for (std::size_t i = 0; i < n; i += stride) {
      const Point2& a = r.points[i];
      const Point2& b = r.points[(i + 1) % n];
      const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::hypot(dx, dy);
      const Point2 normal{-dy / len, dx / len};  // interior is on the left
      for (double t : {0.3, 0.5, 0.7}) f({a[0] + t * dx, a[1] + t * dy}, normal, len);
    }
  });
}

TEST(PolygonField, CsgGradientIsUnitOnEdges) {
  for (const Case& c : cases()) {
    const Tape tape(polygon_csg(c.polygons, RSystem::r0()), 2);
    Evaluator<Tuple<2, 1>> eval(tape);
    double worst = 0;
    for_edge_points(c.polygons, [&](const Point2& p, const Point2&, double) {
      const auto t = eval.at({p[0], p[1], 0});
      worst = std::max(worst, std::abs(std::hypot(t.c[1], t.c[2]) - 1.0));
    });
    EXPECT_LT(worst, 1e-6) << c.name;
  }
}

TEST(PolygonField, BrepGradientTendsToUnitAtEdges) {
  for (const Case& c : cases()) {
    const double diag = box_of(c.polygons).diagonal(), offset = 1e-10 * diag;
    const Tape tape(polygon_brep(c.polygons, RSystem::r0()), 2);
    Evaluator<Tuple<2, 1>> eval(tape);
    double worst = 0;
    int tested = 0;
    for_edge_points(c.polygons, [&](const Point2& p, const Point2& n, double) {
      // |grad| = 1 - O(offset / distance to the other edges): test where
      // the other edges are at least 1e-3 of the diagonal away.
      const Point2 q{p[0] + offset * n[0], p[1] + offset * n[1]};
      if (test::boundary_distance(c.polygons, {p[0] + 1e-3 * diag * n[0], p[1] + 1e-3 * diag * n[1]}) < 0.9e-3 * diag)
        return;
      ++tested;
      const auto t = eval.at({q[0], q[1], 0});
      worst = std::max(worst, std::abs(std::hypot(t.c[1], t.c[2]) - 1.0));
    });
    EXPECT_GT(tested, 10) << c.name;
    EXPECT_LT(worst, 1e-6) << c.name;
  }
}

TEST(PolygonField, BrepApproachesTheDistanceToSecondOrder) {
  for (const Case& c : cases()) {
    const double diag = box_of(c.polygons).diagonal();
    const Tape tape(polygon_brep(c.polygons, RSystem::r0()), 2);
    Evaluator<double> eval(tape);
    std::vector<double> error;
    const std::vector<double> distances{1e-4 * diag, 1e-5 * diag, 1e-6 * diag};
    for (double d : distances) {
      double worst = 0;
      for_edge_points(c.polygons, [&](const Point2& p, const Point2& n, double) {
        if (test::boundary_distance(c.polygons, {p[0] + 1e-2 * diag * n[0], p[1] + 1e-2 * diag * n[1]}) < 0.9e-2 * diag)
          return;  // keep away from the other edges
        const double v = eval.at({p[0] + d * n[0], p[1] + d * n[1], 0});
        worst = std::max(worst, std::abs(v - d));
      });
      error.push_back(worst);
    }
    for (std::size_t k = 0; k + 1 < error.size(); ++k) {
      const double order = std::log(error[k] / error[k + 1]) / std::log(distances[k] / distances[k + 1]);
      EXPECT_GT(order, 1.8) << c.name << ": errors " << error[k] << " -> " << error[k + 1];
    }
  }
}

// The leaves of an R-function tree: maximal subexpressions without
// R-function nodes (negations of R subtrees are walked through).
void collect_leaves(const Expr& e, std::vector<Expr>& leaves) {
  const bool r = e.op() == Op::RAnd || e.op() == Op::ROr;
  const bool negated_r = e.op() == Op::Neg && (e.arg(0).op() == Op::RAnd || e.arg(0).op() == Op::ROr);
  if (r) {
    collect_leaves(e.arg(0), leaves);
    collect_leaves(e.arg(1), leaves);
  } else if (negated_r) {
    collect_leaves(e.arg(0), leaves);
  } else {
    leaves.push_back(e);
  }
}

TEST(PolygonCsg, EachEdgeHalfplaneAppearsExactlyOnce) {
  for (const Case& c : cases()) {
    CsgStatistics stats;
    const Expr field = polygon_csg(c.polygons, RSystem::r0(), &stats);
    EXPECT_EQ(stats.halfplanes, c.polygons.edge_count()) << c.name;
    std::vector<Expr> leaves;
    collect_leaves(field, leaves);
    ASSERT_EQ(leaves.size(), c.polygons.edge_count() + stats.bridges) << c.name;
    // Every edge has a leaf vanishing at both its end points, with unit gradient.
    std::vector<Tape> tapes;
    for (const Expr& l : leaves) tapes.emplace_back(l, 2);
    const double tol = 1e-9 * box_of(c.polygons).diagonal();
    std::size_t matched = 0;
    c.polygons.for_each_ring([&](const Ring& r) {
      const std::size_t n = r.points.size();
      for (std::size_t i = 0; i < n; ++i) {
        const Point2& a = r.points[i];
        const Point2& b = r.points[(i + 1) % n];
        int found = 0;
        for (const Tape& t : tapes) {
          Evaluator<double> e(t);
          if (std::abs(e.at({a[0], a[1], 0})) < tol && std::abs(e.at({b[0], b[1], 0})) < tol) ++found;
        }
        matched += found >= 1;
      }
    });
    EXPECT_EQ(matched, c.polygons.edge_count()) << c.name;
  }
}

// Greenland's fjords are pockets whose edge lines fan out beyond their
// bridges over other parts of the coast: without the bridges' halfplanes
// the decreasing convex hull gave wrong signs at about 0.6% of the points.
TEST(PolygonCsg, GreenlandSignsAreExact) {
  LoadOptions options;
  options.repair = true;
  GisPolygons gis = read_gis_polygons(sage::test::test_data("gis/greenland_ne10m_EPSG3413.geojson"), options);
  validate_polygons(gis.polygons, "greenland");
  const Samples samples = random_samples(gis.polygons, 2000, 1e-9 * box_of(gis.polygons).diagonal());
  CsgStatistics stats;
  EXPECT_EQ(sign_mismatches(samples, polygon_csg(gis.polygons, RSystem::min_max(), &stats)), 0);
  EXPECT_GT(stats.bridges, 0u);
  EXPECT_EQ(sign_mismatches(samples, polygon_csg(gis.polygons, RSystem::r0())), 0);
}

TEST(WellFormedness, CertifiesPolygonFieldsAndRejectsSpuriousZeros) {
  for (const char* file : {"washington_island_wi_osm_EPSG3070.geojson", "wisconsin_us-atlas_EPSG3070.geojson"}) {
    const PolygonSet set = from_file(file);
    const Box b = box_of(set);
    const Bounds bounds{{b.x0 - 0.05 * b.diagonal(), b.y0 - 0.05 * b.diagonal(), 0},
                        {b.x1 + 0.05 * b.diagonal(), b.y1 + 0.05 * b.diagonal(), 0}};
    const Certificate ok = certify_no_spurious_zeros(polygon_csg(set, RSystem::r0()), set, bounds, 1e-3 * b.diagonal());
    EXPECT_TRUE(ok.certified) << file << ": " << ok.text;
    // A field vanishing on a whole line through the polygon is not well-formed.
    const double cx = 0.5 * (b.x0 + b.x1);
    const Expr bad = polygon_csg(set, RSystem::r0()) * (Expr::x() - cx);
    const Certificate no = certify_no_spurious_zeros(bad, set, bounds, 1e-3 * b.diagonal());
    EXPECT_FALSE(no.certified) << file;
    EXPECT_NE(no.text.find("NOT well-formed"), std::string::npos) << no.text;
  }
}

}  // namespace
}  // namespace sage::geometry
