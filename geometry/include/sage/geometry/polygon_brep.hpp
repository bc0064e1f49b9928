#pragma once
// Trimmed-edge B-rep fields of polygons (paper 004, sec. 4 and 5.1): each
// edge is a normalized trimmed segment (smooth normalized trimming; the
// trimming disk meets the edge's line orthogonally at both end points),
// the segments are glued by R-conjunction into a distance-like field w >= 0
// that vanishes exactly on the boundary, and w is signed by exact point
// membership: field = xi(p) w(p).

#include <sage/expression/classifier.hpp>
#include <sage/expression/expression.hpp>
#include <sage/geometry/polygon.hpp>
#include <sage/scalars/rfunction.hpp>

#include <memory>
#include <vector>

namespace sage::geometry {

/// Exact point membership in a polygon set: +1 inside, 0 on an edge, -1
/// outside (crossing count along +x with CGAL's exact predicates; the
/// edges are bucketed in horizontal slabs so a query reads few of them).
/// classify_box proves a box inside or outside when no edge meets it
/// (exact segment-rectangle test).
class PolygonClassifier : public PointClassifier {
 public:
  explicit PolygonClassifier(const PolygonSet& polygons);
  double classify(const double* p) const override;
  Interval classify_box(const Interval* box) const override;
  int dimension() const override { return 2; }
  /// Does any edge meet the closed box? Exact.
  bool edge_meets(const Interval* box) const;

 private:
  struct Segment {
    double ax, ay, bx, by;
  };
  std::size_t slab_of(double y) const;
  std::vector<Segment> segments_;
  std::vector<std::vector<std::uint32_t>> slabs_;
  double y0_ = 0, slab_height_ = 1;
};

/// The unsigned glued field w of all edges (>= 0, zero on the boundary).
Expr polygon_edge_distance(const PolygonSet& polygons, const RSystem& system);

/// The signed B-rep field xi * w.
Expr polygon_brep(const PolygonSet& polygons, const RSystem& system);

}  // namespace sage::geometry
