#pragma once
// Planar polygons with holes, as read from GIS data: the input of the
// polygon-to-field conversions.
//
// A ring is a closed sequence of distinct vertices (the closing vertex is
// not repeated). After validation, outer rings are counter-clockwise and
// holes clockwise, so the polygon's interior is on the left of every edge.
// Each ring remembers where it came from (feature, ring number in the
// feature's geometry, and the original vertex numbers), so that messages
// can name the place in the file.

#include <array>
#include <string>
#include <vector>

namespace sage::geometry {

using Point2 = std::array<double, 2>;

struct Ring {
  std::vector<Point2> points;
  std::vector<int> source_vertex;  // vertex number in the file, per point
  long long feature = 0;           // feature number in the layer (0-based)
  int polygon = 0;                 // polygon number within a multipolygon
  int ring = 0;                    // 0 = exterior, 1.. = interior rings

  /// "feature 3, polygon 0, ring 2" (with ", vertex 17" when given).
  std::string where(int vertex = -1) const;
};

struct PolygonWithHoles {
  Ring outer;
  std::vector<Ring> holes;
};

struct PolygonSet {
  std::vector<PolygonWithHoles> polygons;

  std::size_t edge_count() const;
  /// Calls f(ring) for every ring, outer rings and holes.
  template <class F>
  void for_each_ring(F f) const {
    for (const auto& p : polygons) {
      f(p.outer);
      for (const auto& h : p.holes) f(h);
    }
  }
};

}  // namespace sage::geometry
