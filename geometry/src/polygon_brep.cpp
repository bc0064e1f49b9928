#include <sage/expression/trimming.hpp>
#include <sage/geometry/polygon_brep.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace sage::geometry {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
}

PolygonClassifier::PolygonClassifier(const PolygonSet& polygons) {
  double y1 = -1e300;
  y0_ = 1e300;
  polygons.for_each_ring([&](const Ring& r) {
    const std::size_t n = r.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Point2& a = r.points[i];
      const Point2& b = r.points[(i + 1) % n];
      segments_.push_back({a[0], a[1], b[0], b[1]});
      y0_ = std::min(y0_, a[1]);
      y1 = std::max(y1, a[1]);
    }
  });
  const std::size_t count = std::max<std::size_t>(1, segments_.size() / 4);
  slab_height_ = std::max((y1 - y0_) / static_cast<double>(count), 1e-300) * (1 + 1e-12);
  slabs_.resize(count);
  for (std::uint32_t k = 0; k < segments_.size(); ++k) {
    const Segment& s = segments_[k];
    const std::size_t lo = slab_of(std::min(s.ay, s.by)), hi = slab_of(std::max(s.ay, s.by));
    for (std::size_t j = lo; j <= hi; ++j) slabs_[j].push_back(k);
  }
}

std::size_t PolygonClassifier::slab_of(double y) const {
  const double t = std::floor((y - y0_) / slab_height_);
  if (!(t > 0)) return 0;
  return std::min(slabs_.size() - 1, static_cast<std::size_t>(t));
}

double PolygonClassifier::classify(const double* p) const {
  const K::Point_2 q(p[0], p[1]);
  if (!(p[1] >= y0_) || !(p[1] <= y0_ + slab_height_ * static_cast<double>(slabs_.size()))) return -1.0;
  bool inside = false;
  for (std::uint32_t k : slabs_[slab_of(p[1])]) {
    const Segment& s = segments_[k];
    const K::Point_2 a(s.ax, s.ay), b(s.bx, s.by);
    // On the edge?
    if (std::min(s.ay, s.by) <= p[1] && p[1] <= std::max(s.ay, s.by) && std::min(s.ax, s.bx) <= p[0] &&
        p[0] <= std::max(s.ax, s.bx) && CGAL::orientation(a, b, q) == CGAL::COLLINEAR)
      return 0.0;
    // Crossing rule with half-open y ranges: the edge crosses the ray from
    // q towards +x iff q is strictly on the edge's left (upward edge) or
    // right (downward edge).
    if (s.ay <= p[1] && p[1] < s.by) {
      if (CGAL::orientation(a, b, q) == CGAL::LEFT_TURN) inside = !inside;
    } else if (s.by <= p[1] && p[1] < s.ay) {
      if (CGAL::orientation(a, b, q) == CGAL::RIGHT_TURN) inside = !inside;
    }
  }
  return inside ? 1.0 : -1.0;
}

bool PolygonClassifier::edge_meets(const Interval* box) const {
  const K::Iso_rectangle_2 rectangle(box[0].lo, box[1].lo, box[0].hi, box[1].hi);
  const std::size_t lo = slab_of(box[1].lo), hi = slab_of(box[1].hi);
  for (std::size_t j = lo; j <= hi; ++j)
    for (std::uint32_t k : slabs_[j]) {
      const Segment& s = segments_[k];
      if (std::max(s.ax, s.bx) < box[0].lo || std::min(s.ax, s.bx) > box[0].hi || std::max(s.ay, s.by) < box[1].lo ||
          std::min(s.ay, s.by) > box[1].hi)
        continue;  // bounding boxes apart
      if (CGAL::do_intersect(K::Segment_2(K::Point_2(s.ax, s.ay), K::Point_2(s.bx, s.by)), rectangle)) return true;
    }
  return false;
}

Interval PolygonClassifier::classify_box(const Interval* box) const {
  if (edge_meets(box)) return {-1.0, 1.0};
  // No edge meets the box: it is wholly inside or wholly outside.
  const double centre[2] = {box[0].mid(), box[1].mid()};
  return Interval(classify(centre));
}

Expr polygon_edge_distance(const PolygonSet& polygons, const RSystem& system) {
  std::vector<Expr> edges;
  polygons.for_each_ring([&](const Ring& r) {
    const std::size_t n = r.points.size();
    for (std::size_t i = 0; i < n; ++i)
      edges.push_back(segment_field(r.points[i], r.points[(i + 1) % n], TrimMethod::Smooth));
  });
  return r_conjunction_n(edges, system);
}

Expr polygon_brep(const PolygonSet& polygons, const RSystem& system) {
  return Expr::classify(std::make_shared<const PolygonClassifier>(polygons)) * polygon_edge_distance(polygons, system);
}

}  // namespace sage::geometry
