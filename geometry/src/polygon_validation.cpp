#include <sage/geometry/model.hpp>
#include <sage/geometry/polygon_validation.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace sage::geometry {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P2 = K::Point_2;

P2 cgal(const Point2& p) { return {p[0], p[1]}; }

/// `vertex` is the vertex number in the file (-1: the whole ring).
[[noreturn]] void fault(const std::string& source, const Ring& r, int vertex, const std::string& what) {
  throw ModelError(source + ": " + r.where(vertex) + ": " + what);
}

// One pass over the ring: drops duplicate consecutive vertices and
// collinear middle vertices (a stack: a removal can make the neighbours
// collinear). Returns the number of vertices removed.
std::size_t clean_pass(Ring& r, const std::string& source, ValidationReport& report) {
  std::vector<Point2> pts;
  std::vector<int> src;
  const std::size_t before = r.points.size();
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const Point2& p = r.points[i];
    if (!pts.empty() && pts.back() == p) {
      ++report.duplicate_vertices;
      continue;
    }
    while (pts.size() >= 2) {
      const P2 a = cgal(pts[pts.size() - 2]), b = cgal(pts.back()), c = cgal(p);
      if (CGAL::orientation(a, b, c) != CGAL::COLLINEAR) break;
      if (!CGAL::collinear_are_strictly_ordered_along_line(a, b, c))
        fault(source, r, src.back(), "the ring doubles back on itself here (a spike of zero width)");
      ++report.collinear_vertices;
      pts.pop_back();
      src.pop_back();
    }
    pts.push_back(p);
    src.push_back(r.source_vertex[i]);
  }
  while (pts.size() > 1 && pts.back() == pts.front()) {
    ++report.duplicate_vertices;
    pts.pop_back();
    src.pop_back();
  }
  r.points = std::move(pts);
  r.source_vertex = std::move(src);
  return before - r.points.size();
}

// Cleans the ring; passes repeat with the ring rotated by half, so that
// triples across the start are checked too, until nothing changes.
void clean_ring(Ring& r, const std::string& source, ValidationReport& report) {
  for (std::size_t i = 0; i < r.points.size(); ++i)
    if (!std::isfinite(r.points[i][0]) || !std::isfinite(r.points[i][1]))
      fault(source, r, r.source_vertex[i], "coordinate is not a finite number");
  bool changed = true;
  for (int pass = 0; (changed || pass < 2) && r.points.size() >= 3; ++pass) {
    changed = clean_pass(r, source, report) > 0;
    const auto half = static_cast<std::ptrdiff_t>(r.points.size() / 2);
    std::rotate(r.points.begin(), r.points.begin() + half, r.points.end());
    std::rotate(r.source_vertex.begin(), r.source_vertex.begin() + half, r.source_vertex.end());
  }
  if (r.points.size() < 3) fault(source, r, -1, "fewer than 3 distinct, non-collinear vertices");
}

bool counterclockwise(const Ring& r) {
  std::vector<P2> pts;
  for (const auto& p : r.points) pts.push_back(cgal(p));
  // The orientation at the lowest-leftmost vertex is exact and, for a
  // simple ring, the ring's orientation.
  return CGAL::orientation_2(pts.begin(), pts.end(), K()) == CGAL::COUNTERCLOCKWISE;
}

void orient(Ring& r, bool want_ccw, ValidationReport& report) {
  if (counterclockwise(r) == want_ccw) return;
  std::reverse(r.points.begin(), r.points.end());
  std::reverse(r.source_vertex.begin(), r.source_vertex.end());
  ++report.reoriented_rings;
}

// ---- edge intersections through a uniform grid ---------------------------------

struct Edge {
  const Ring* ring;
  int index;  // edge from vertex index to index + 1
  P2 a, b;
};

// Collinear segments that share more than a point.
bool overlap_along_line(const Edge& e, const Edge& f) {
  const auto common = CGAL::intersection(K::Segment_2(e.a, e.b), K::Segment_2(f.a, f.b));
  return common && boost::get<K::Segment_2>(&*common) != nullptr;
}

void check_intersections(const std::vector<Edge>& edges, const std::string& source, const std::string& remedy,
                         ValidationReport& report) {
  double x0 = edges[0].a.x(), x1 = x0, y0 = edges[0].a.y(), y1 = y0;
  for (const Edge& e : edges) {
    x0 = std::min(x0, e.a.x());
    x1 = std::max(x1, e.a.x());
    y0 = std::min(y0, e.a.y());
    y1 = std::max(y1, e.a.y());
  }
  const int cells = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(edges.size()))));
  const double cw = (x1 - x0) / cells * (1 + 1e-12) + 1e-300, ch = (y1 - y0) / cells * (1 + 1e-12) + 1e-300;
  auto cell_of = [&](double v, double lo, double size) {
    return std::clamp(static_cast<int>((v - lo) / size), 0, cells - 1);
  };
  std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(cells) * cells);
  for (std::uint32_t k = 0; k < edges.size(); ++k) {
    const Edge& e = edges[k];
    const int i0 = cell_of(std::min(e.a.x(), e.b.x()), x0, cw), i1 = cell_of(std::max(e.a.x(), e.b.x()), x0, cw);
    const int j0 = cell_of(std::min(e.a.y(), e.b.y()), y0, ch), j1 = cell_of(std::max(e.a.y(), e.b.y()), y0, ch);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) grid[static_cast<std::size_t>(j) * cells + i].push_back(k);
  }
  std::unordered_set<std::uint64_t> tested;
  for (const auto& bucket : grid)
    for (std::size_t u = 0; u < bucket.size(); ++u)
      for (std::size_t v = u + 1; v < bucket.size(); ++v) {
        const std::uint32_t p = std::min(bucket[u], bucket[v]), q = std::max(bucket[u], bucket[v]);
        if (!tested.insert((static_cast<std::uint64_t>(p) << 32) | q).second) continue;
        const Edge& e = edges[p];
        const Edge& f = edges[q];
        const int n = static_cast<int>(e.ring->points.size());
        const bool same_ring = e.ring == f.ring;
        const bool adjacent = same_ring && ((e.index + 1) % n == f.index || (f.index + 1) % n == e.index);
        if (adjacent) continue;  // they share a vertex; spikes were rejected already
        if (!CGAL::do_intersect(K::Segment_2(e.a, e.b), K::Segment_2(f.a, f.b))) continue;
        const auto o1 = CGAL::orientation(e.a, e.b, f.a), o2 = CGAL::orientation(e.a, e.b, f.b);
        const auto o3 = CGAL::orientation(f.a, f.b, e.a), o4 = CGAL::orientation(f.a, f.b, e.b);
        const std::string place =
            e.ring->where(e.ring->source_vertex[e.index]) + " and " + f.ring->where(f.ring->source_vertex[f.index]);
        if (o1 == CGAL::COLLINEAR && o2 == CGAL::COLLINEAR && overlap_along_line(e, f))
          throw ModelError(source + ": edges overlap along a line: the edge after " + place + " (" + remedy + ")");
        if (o1 != CGAL::COLLINEAR && o2 != CGAL::COLLINEAR && o3 != CGAL::COLLINEAR && o4 != CGAL::COLLINEAR)
          throw ModelError(source + ": edges cross: the edge after " + place +
                           " (a self-intersecting ring or crossing rings; " + remedy + ")");
        ++report.touchings;  // a vertex on another edge or vertex
      }
}

bool inside_ring(const Ring& ring, const P2& q, bool& on_boundary) {
  std::vector<P2> pts;
  for (const auto& p : ring.points) pts.push_back(cgal(p));
  const auto side = CGAL::bounded_side_2(pts.begin(), pts.end(), q, K());
  on_boundary = side == CGAL::ON_BOUNDARY;
  return side == CGAL::ON_BOUNDED_SIDE;
}

bool bbox_inside(const Ring& r, const Ring& other) {
  double ax0 = 1e300, ax1 = -1e300, ay0 = 1e300, ay1 = -1e300, bx0 = 1e300, bx1 = -1e300, by0 = 1e300, by1 = -1e300;
  for (const auto& p : r.points) {
    ax0 = std::min(ax0, p[0]), ax1 = std::max(ax1, p[0]), ay0 = std::min(ay0, p[1]), ay1 = std::max(ay1, p[1]);
  }
  for (const auto& p : other.points) {
    bx0 = std::min(bx0, p[0]), bx1 = std::max(bx1, p[0]), by0 = std::min(by0, p[1]), by1 = std::max(by1, p[1]);
  }
  return ax0 >= bx0 && ax1 <= bx1 && ay0 >= by0 && ay1 <= by1;
}

// A point of `r` not on `other`'s boundary (a vertex, else an edge midpoint).
bool inside_other(const Ring& r, const Ring& other) {
  if (!bbox_inside(r, other)) return false;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    bool on = false;
    const bool in = inside_ring(other, cgal(r.points[i]), on);
    if (!on) return in;
  }
  const auto& a = r.points[0];
  const auto& b = r.points[1];
  bool on = false;
  return inside_ring(other, P2(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])), on);
}

}  // namespace

std::vector<std::string> ValidationReport::notes() const {
  std::vector<std::string> n;
  if (duplicate_vertices)
    n.push_back(std::to_string(duplicate_vertices) + " duplicate vertices removed (zero-length edges)");
  if (collinear_vertices) n.push_back(std::to_string(collinear_vertices) + " collinear middle vertices removed");
  if (reoriented_rings)
    n.push_back(std::to_string(reoriented_rings) + " rings reoriented (outer counter-clockwise, holes clockwise)");
  if (touchings) n.push_back(std::to_string(touchings) + " places where rings touch at a point (tolerated)");
  return n;
}

ValidationReport validate_polygons(PolygonSet& set, const std::string& source, bool repaired) {
  // Never suggest the flag that was given.
  const std::string remedy = repaired ? "left after --repair, in the repaired geometry's numbering: leave the feature "
                                        "out (--feature, --where) or fix it in a GIS editor"
                                      : "use --repair to fix invalid geometry";
  ValidationReport report;
  if (set.polygons.empty()) throw ModelError(source + ": no polygons");
  for (auto& p : set.polygons) {
    clean_ring(p.outer, source, report);
    for (auto& h : p.holes) clean_ring(h, source, report);
  }
  // Crossings first: orientation and containment assume simple rings.
  std::vector<Edge> edges;
  set.for_each_ring([&edges](const Ring& r) {
    const int n = static_cast<int>(r.points.size());
    for (int i = 0; i < n; ++i) edges.push_back({&r, i, cgal(r.points[i]), cgal(r.points[(i + 1) % n])});
  });
  check_intersections(edges, source, remedy, report);

  for (auto& p : set.polygons) {
    orient(p.outer, true, report);
    for (auto& h : p.holes) {
      orient(h, false, report);
      if (!inside_other(h, p.outer))
        throw ModelError(source + ": " + h.where() + ": the hole lies outside its exterior ring");
    }
    for (std::size_t a = 0; a < p.holes.size(); ++a)
      for (std::size_t b = 0; b < p.holes.size(); ++b)
        if (a != b && inside_other(p.holes[a], p.holes[b]))
          throw ModelError(source + ": " + p.holes[a].where() + ": the hole lies inside another hole (" +
                           p.holes[b].where() + ")");
  }
  // Polygons of a set must not nest: one inside another (outside its holes)
  // would overlap it.
  for (std::size_t a = 0; a < set.polygons.size(); ++a)
    for (std::size_t b = 0; b < set.polygons.size(); ++b) {
      if (a == b || !inside_other(set.polygons[a].outer, set.polygons[b].outer)) continue;
      bool in_hole = false;
      for (const auto& h : set.polygons[b].holes) in_hole = in_hole || inside_other(set.polygons[a].outer, h);
      if (!in_hole)
        throw ModelError(source + ": " + set.polygons[a].outer.where() + ": the polygon lies inside another (" +
                         set.polygons[b].outer.where() + ")");
    }
  return report;
}

}  // namespace sage::geometry
