#include <sage/geometry/polygon.hpp>

namespace sage::geometry {

std::string Ring::where(int vertex) const {
  std::string s = "feature " + std::to_string(feature) + ", polygon " + std::to_string(polygon) + ", ring " +
                  std::to_string(ring) + (ring == 0 ? " (exterior)" : " (hole)");
  if (vertex >= 0) s += ", vertex " + std::to_string(vertex);
  return s;
}

std::size_t PolygonSet::edge_count() const {
  std::size_t n = 0;
  for_each_ring([&n](const Ring& r) { n += r.points.size(); });
  return n;
}

}  // namespace sage::geometry
