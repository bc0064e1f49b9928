#pragma once
// Validation of polygons with CGAL's exact predicates, before any field is
// built. Harmless defects are fixed and counted; real faults throw
// ModelError naming the file, feature, polygon, ring and vertex.
//
// Fixed and reported:   duplicate consecutive vertices (zero-length
//                       edges), collinear middle vertices, orientation
//                       (outer rings become counter-clockwise, holes
//                       clockwise).
// Tolerated, counted:   rings touching at a point (a vertex on another
//                       ring's vertex or edge), as real GIS data has.
// Faults:               non-finite coordinates, rings with fewer than 3
//                       distinct vertices, spikes (a ring doubling back
//                       on itself), edges that cross or overlap, holes
//                       outside their shell, a polygon inside another.

#include <sage/geometry/polygon.hpp>

#include <string>
#include <vector>

namespace sage::geometry {

struct ValidationReport {
  std::size_t duplicate_vertices = 0;
  std::size_t collinear_vertices = 0;
  std::size_t reoriented_rings = 0;
  std::size_t touchings = 0;

  /// One line per nonzero count, for `sage info`.
  std::vector<std::string> notes() const;
};

/// Cleans `polygons` in place and checks them; `source` names the file.
/// `repaired`: the polygons were already repaired (--repair), so faults
/// suggest leaving features out rather than --repair.
ValidationReport validate_polygons(PolygonSet& polygons, const std::string& source, bool repaired = false);

}  // namespace sage::geometry
