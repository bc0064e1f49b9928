#pragma once
// Well-formed CSG of polygons by the decreasing convex hull (convex
// deficiency tree; paper 004, sec. 3.1 and 5.1).
//
// For a chain of a ring whose end points are consecutive vertices of its
// convex hull (the whole ring at the top), walk the hull vertices along the
// chain. Each step between consecutive hull vertices is either an edge of
// the ring -- its normalized halfplane, interior on the left -- or a
// sub-chain (a pocket), treated recursively, together with its bridge: the
// halfplane left of the hull edge that spans the pocket. The terms are
// combined by R-conjunction when the chain's hull lies on its inner side
// (the whole ring, and every second level of pockets) and by R-disjunction
// otherwise. The formula is monotone; each edge's halfplane appears exactly
// once, and each bridge once.
//
// Why the bridges: without them the decreasing convex hull is not always a
// formula. A pocket's term alone is right only inside the pocket's hull;
// beyond its bridge it can take either value wherever the pocket's edge
// lines fan out, and other parts of the ring may lie there (Greenland's
// fjords: 178 wrong signs in 20,000 points). With its bridge, the term of
// a chain is exactly the indicator of the polygon closed by that bridge,
// by induction over the pockets, so the whole formula is exact in the
// plane. Its zeros stay on the ring: off the ring, the points on both
// sides of a bridge's line have the same membership, so the result does
// not depend on that halfplane there, and an R-function vanishes only
// where its result depends on a vanishing argument. One exception: a
// bridge on the line of its pocket's first or last edge (a comb's teeth
// tops) is left out, since two leaves vanishing along one edge would spoil
// the normalization there; that case rests on the sign tests, not on the
// argument above.
// Holes enter as AND NOT, polygons are united.
//
// Rings must be validated (polygon_validation.hpp): simple, outer rings
// counter-clockwise, holes clockwise, no collinear consecutive vertices.

#include <sage/expression/expression.hpp>
#include <sage/geometry/polygon.hpp>
#include <sage/scalars/rfunction.hpp>

namespace sage::geometry {

struct CsgStatistics {
  std::size_t halfplanes = 0;  // edges used (each exactly once)
  std::size_t bridges = 0;     // pocket bridges (hull edges that are not ring edges)
  int depth = 0;               // deepest pocket nesting
};

/// The field of one ring's interior (counter-clockwise ring).
Expr ring_csg(const Ring& ring, const RSystem& system, CsgStatistics* statistics = nullptr);

/// The field of a polygon set: union of (outer AND NOT holes).
Expr polygon_csg(const PolygonSet& polygons, const RSystem& system, CsgStatistics* statistics = nullptr);

/// The normalized halfplane left of the directed edge a -> b.
Expr edge_halfplane(const Point2& a, const Point2& b);

}  // namespace sage::geometry
