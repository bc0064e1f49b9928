#include <sage/expression/trimming.hpp>
#include <sage/geometry/polygon_csg.hpp>

#include <CGAL/Convex_hull_traits_adapter_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sage::geometry {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using HullTraits = CGAL::Convex_hull_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::type>;

/// Builds the formula of one ring; positions are indices into the ring,
/// chains run forward (cyclically) from `first` to `last`.
class RingFormula {
 public:
  RingFormula(const Ring& ring, const RSystem& system) : ring_(ring), system_(system), n_(ring.points.size()) {
    for (const auto& p : ring.points) points_.emplace_back(p[0], p[1]);
  }

  Expr whole(CsgStatistics* stats) {
    // The closed ring: its hull vertices in ring order, hull on the left.
    std::vector<std::size_t> all(n_);
    for (std::size_t i = 0; i < n_; ++i) all[i] = i;
    std::vector<std::size_t> hull = hull_of(all);
    std::sort(hull.begin(), hull.end());
    std::vector<Expr> terms;
    for (std::size_t k = 0; k < hull.size(); ++k)
      add_step(hull[k], hull[(k + 1) % hull.size()], /*parent_hull_on_left=*/true, 1, terms);
    if (stats) {
      stats->halfplanes += halfplanes_;
      stats->bridges += bridges_;
      stats->depth = std::max(stats->depth, depth_);
    }
    return r_conjunction_n(terms, system_);
  }

 private:
  std::size_t next(std::size_t i) const { return (i + 1) % n_; }
  std::size_t previous(std::size_t i) const { return (i + n_ - 1) % n_; }
  std::size_t forward(std::size_t from, std::size_t to) const { return (to + n_ - from) % n_; }

  // The terms for the part of the ring from hull vertex `from` to `to`: an
  // edge, or the pocket chain between them (whose hull lies on the other
  // side of it than the parent's) and its bridge. The bridge's halfplane
  // (left of from -> to, on the parent's side) makes the pocket's term
  // exact beyond the bridge too (see polygon_csg.hpp).
  void add_step(std::size_t from, std::size_t to, bool parent_hull_on_left, int depth, std::vector<Expr>& terms) {
    if (next(from) == to) {
      ++halfplanes_;
      terms.push_back(edge_halfplane(ring_.points[from], ring_.points[to]));
      return;
    }
    terms.push_back(chain(from, to, !parent_hull_on_left, depth));
    // A bridge on the line of the pocket's first or last edge is left out:
    // that edge's halfplane is the same function, and two leaves vanishing
    // along one edge would spoil the normalization there (a comb's teeth).
    if (collinear(from, to, next(from)) || collinear(from, to, previous(to))) return;
    terms.push_back(edge_halfplane(ring_.points[from], ring_.points[to]));
    ++bridges_;
  }

  bool collinear(std::size_t a, std::size_t b, std::size_t c) const {
    return CGAL::collinear(points_[a], points_[b], points_[c]);
  }

  // The chain from `first` to `last` (its end points are extreme on its
  // hull): its hull vertices in chain order, steps combined by AND when the
  // hull lies left of the chain, by OR when it lies right.
  Expr chain(std::size_t first, std::size_t last, bool hull_on_left, int depth) {
    depth_ = std::max(depth_, depth);
    const std::size_t length = forward(first, last);
    std::vector<std::size_t> members(length + 1);
    for (std::size_t k = 0; k <= length; ++k) members[k] = (first + k) % n_;
    std::vector<std::size_t> hull = hull_of(members);
    // Order the hull vertices along the chain.
    std::sort(hull.begin(), hull.end(),
              [&](std::size_t a, std::size_t b) { return forward(first, a) < forward(first, b); });
    if (hull.size() < 3 || hull.front() != first || hull.back() != last)
      throw std::logic_error(ring_.where() + ": degenerate pocket between vertices " + std::to_string(first) + " and " +
                             std::to_string(last) + " (ring not validated?)");
    std::vector<Expr> terms;
    for (std::size_t k = 0; k + 1 < hull.size(); ++k) add_step(hull[k], hull[k + 1], hull_on_left, depth + 1, terms);
    return hull_on_left ? r_conjunction_n(terms, system_) : r_disjunction_n(terms, system_);
  }

  std::vector<std::size_t> hull_of(const std::vector<std::size_t>& members) const {
    std::vector<std::size_t> hull;
    CGAL::convex_hull_2(members.begin(), members.end(), std::back_inserter(hull),
                        HullTraits(CGAL::make_property_map(points_)));
    return hull;
  }

  const Ring& ring_;
  RSystem system_;
  std::size_t n_;
  mutable std::vector<K::Point_2> points_;  // mutable: the hull traits take a non-const map
  std::size_t halfplanes_ = 0;
  std::size_t bridges_ = 0;
  int depth_ = 0;
};

}  // namespace

Expr edge_halfplane(const Point2& a, const Point2& b) { return line_halfplane(a, b); }

Expr ring_csg(const Ring& ring, const RSystem& system, CsgStatistics* statistics) {
  return RingFormula(ring, system).whole(statistics);
}

Expr polygon_csg(const PolygonSet& polygons, const RSystem& system, CsgStatistics* statistics) {
  std::vector<Expr> parts;
  for (const auto& p : polygons.polygons) {
    Expr field = ring_csg(p.outer, system, statistics);
    if (!p.holes.empty()) {
      std::vector<Expr> holes;
      for (Ring h : p.holes) {
        // A clockwise hole reversed is the hole's own counter-clockwise ring.
        std::reverse(h.points.begin(), h.points.end());
        std::reverse(h.source_vertex.begin(), h.source_vertex.end());
        holes.push_back(ring_csg(h, system, statistics));
      }
      field = r_and(field, -r_disjunction_n(holes, system), system);
    }
    parts.push_back(field);
  }
  return r_disjunction_n(parts, system);
}

}  // namespace sage::geometry
