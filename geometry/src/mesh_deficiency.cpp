// Well-formed CSG of a non-convex closed triangle mesh by the convex
// deficiency decomposition (alternating sum of volumes; paper 004, sec.
// 3.1 and 5.1), the 3D form of polygon_csg.cpp.
//
// A component X is given by its faces S (triangles of the mesh, oriented
// outward from X; the rest of its boundary are lids on the planes of its
// parent's hull). With H = convex_hull_3 of the vertices of S (every lid
// vertex is a vertex of S: lids are bounded by mesh edges), the faces of S
// lying on a plane of H (exact orientation tests) are hull faces; the
// others, split into edge-connected patches (not across edges lying on H,
// where two deficiencies only touch), bound the deficiency components of
// X, which are treated recursively with their faces reversed:
//
//   f(X) = AND(halfspaces of the planes of H) AND NOT OR(f(children)).
//
// Planes of H that are planes of the parent's hull (the lids) are left
// out: inside the parent's hull they hold anyway, so f(X) stays the exact
// indicator of X there, and leaving them out keeps the lids off the zero
// set. The planes of H that carry no face of S are bridges (as in 2D):
// with them, f(X) is exact everywhere inside the parent's hull, so by
// induction the whole formula has exact signs. Coplanar faces of the mesh
// share one halfspace node.
//
// The recursion stops at convex components (no pocket faces). It does not
// terminate when a component below the top has no face on its own hull
// (its only child would be itself, reversed); that, a depth limit, or a
// component that is not a proper solid is reported as the reason.
#include "mesh_internal.hpp"

#include <sage/expression/primitives.hpp>

#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace sage::geometry::mesh {

namespace {

std::uint64_t edge_key(std::size_t a, std::size_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
}

// Sorted small vectors: the hull planes a vertex lies on.
bool share(const std::vector<std::size_t>& a, const std::vector<std::size_t>& b, const std::vector<std::size_t>& c,
           std::size_t* common) {
  for (std::size_t g : a)
    if (std::binary_search(b.begin(), b.end(), g) && std::binary_search(c.begin(), c.end(), g)) {
      if (common) *common = g;
      return true;
    }
  return false;
}

class Decomposition {
 public:
  Decomposition(const std::vector<Point>& points, const std::vector<Triangle>& triangles, const RSystem& system,
                int max_depth)
      : points_(points), triangles_(triangles), system_(system), max_depth_(max_depth) {
    group_planes();
  }

  std::optional<DeficiencyCsg> run(std::string& reason) {
    std::vector<std::size_t> all(triangles_.size());
    std::iota(all.begin(), all.end(), 0);
    std::unordered_map<std::size_t, std::vector<std::size_t>> no_parent;
    auto field = component(all, /*reversed=*/false, no_parent, 0);
    if (!field) {
      reason = reason_;
      return std::nullopt;
    }
    out_.field = *field;
    for (std::size_t g = 0; g < plane_uses_.size(); ++g)
      if (plane_uses_[g] == 0) {
        reason = "internal: the plane of triangle " + std::to_string(out_.planes[g].front()) + " was never used";
        return std::nullopt;
      }
    out_.plane_uses = plane_uses_;
    return std::move(out_);
  }

 private:
  // Groups the mesh's triangles by plane (exactly coplanar, same outward
  // side): adjacent ones by the edge test, the others through a hash of
  // the rounded plane, confirmed exactly.
  void group_planes() {
    const std::size_t nf = triangles_.size();
    DisjointSets coplanar(nf);
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> faces_of_edge;
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) faces_of_edge[edge_key(triangles_[f][k], triangles_[f][(k + 1) % 3])].push_back(f);
    for (const auto& [key, fs] : faces_of_edge)
      for (std::size_t i = 1; i < fs.size(); ++i)
        if (same_plane(fs[0], fs[i])) coplanar.unite(fs[i], fs[0]);
    double scale = 0;
    for (const Point& p : points_) scale = std::max({scale, std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
    std::map<std::array<long long, 4>, std::vector<std::size_t>> roots_of_key;
    for (std::size_t f = 0; f < nf; ++f) {
      if (coplanar.find(f) != f) continue;
      const auto n = unit_normal(f);
      const Point& a = points_[triangles_[f][0]];
      const double d = (n[0] * a.x() + n[1] * a.y() + n[2] * a.z()) / (scale > 0 ? scale : 1);
      const std::array<long long, 4> key{std::llround(n[0] * 1e6), std::llround(n[1] * 1e6), std::llround(n[2] * 1e6),
                                         std::llround(d * 1e6)};
      auto& candidates = roots_of_key[key];
      bool merged = false;
      for (std::size_t r : candidates)
        if (same_plane(r, f)) {
          coplanar.unite(f, r);
          merged = true;
          break;
        }
      if (!merged) candidates.push_back(f);
    }
    plane_of_.assign(nf, 0);
    std::map<std::size_t, std::size_t> group_of_root;
    for (std::size_t f = 0; f < nf; ++f) {
      const auto [it, fresh] = group_of_root.emplace(coplanar.find(f), out_.planes.size());
      if (fresh) out_.planes.emplace_back();
      out_.planes[it->second].push_back(f);
      plane_of_[f] = it->second;
    }
    for (const auto& plane : out_.planes) {
      const FacePlane fp = face_plane(points_, triangles_, plane);
      leaves_.push_back(halfspace(fp.anchor, fp.normal, 3));
    }
    plane_uses_.assign(out_.planes.size(), 0);
  }

  std::array<double, 3> unit_normal(std::size_t f) const {
    const Point &a = points_[triangles_[f][0]], &b = points_[triangles_[f][1]], &c = points_[triangles_[f][2]];
    const auto cr = CGAL::cross_product(b - a, c - a);
    const double len = std::sqrt(cr.squared_length());
    return {cr.x() / len, cr.y() / len, cr.z() / len};
  }

  // Same plane and same outward side, exactly.
  bool same_plane(std::size_t f, std::size_t g) const {
    const Triangle &s = triangles_[f], &t = triangles_[g];
    const Point &a = points_[s[0]], &b = points_[s[1]], &c = points_[s[2]];
    for (std::size_t v : t)
      if (CGAL::orientation(a, b, c, points_[v]) != CGAL::COPLANAR) return false;
    // Same side: a point off the plane is on the same side of both.
    const Point &p = points_[t[0]], &q = points_[t[1]], &r = points_[t[2]];
    const Point off = a + CGAL::cross_product(b - a, c - a);
    return CGAL::orientation(a, b, c, off) == CGAL::orientation(p, q, r, off);
  }

  Triangle oriented(std::size_t f, bool reversed) const {
    const Triangle& t = triangles_[f];
    return reversed ? Triangle{t[0], t[2], t[1]} : t;
  }

  bool fail(std::string why) {
    reason_ = std::move(why);
    return false;
  }

  // The field of the component bounded by `faces` (mesh triangles,
  // reversed at odd depths) and lids on the planes of its parent's hull;
  // parent_planes maps each vertex to the parent's hull planes it lies on.
  std::optional<Expr> component(const std::vector<std::size_t>& faces, bool reversed,
                                const std::unordered_map<std::size_t, std::vector<std::size_t>>& parent_planes,
                                int depth) {
    ++out_.nodes;
    out_.depth = std::max(out_.depth, depth);
    if (depth > max_depth_) {
      fail("the decomposition is deeper than the limit of " + std::to_string(max_depth_) + " levels");
      return std::nullopt;
    }
    std::vector<std::size_t> vertices;
    for (std::size_t f : faces)
      for (std::size_t v : triangles_[f]) vertices.push_back(v);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    std::vector<Point> cloud;
    std::map<std::array<double, 3>, std::size_t> vertex_of_point;
    for (std::size_t v : vertices) {
      cloud.push_back(points_[v]);
      vertex_of_point.emplace(std::array<double, 3>{points_[v].x(), points_[v].y(), points_[v].z()}, v);
    }
    SurfaceMesh hull;
    CGAL::convex_hull_3(cloud.begin(), cloud.end(), hull);
    if (hull.number_of_faces() < 4 || !CGAL::is_triangle_mesh(hull)) {
      fail("a component at depth " + std::to_string(depth) + " (" + std::to_string(faces.size()) +
           " faces, from triangle " + std::to_string(faces.front()) + ") is flat");
      return std::nullopt;
    }

    // Hull facets grouped by plane; one representative triangle each.
    std::vector<SurfaceMesh::Face_index> hull_faces(hull.faces().begin(), hull.faces().end());
    DisjointSets hull_planes(hull_faces.size());
    auto facet_points = [&](SurfaceMesh::Face_index f) {
      std::array<Point, 3> p;
      int k = 0;
      for (auto v : hull.vertices_around_face(hull.halfedge(f))) p[k++] = hull.point(v);
      return p;
    };
    for (std::size_t i = 0; i < hull_faces.size(); ++i) {
      const auto p = facet_points(hull_faces[i]);
      for (auto h : hull.halfedges_around_face(hull.halfedge(hull_faces[i]))) {
        const auto g = hull.face(hull.opposite(h));
        const Point far = hull.point(hull.target(hull.next(hull.opposite(h))));
        if (CGAL::orientation(p[0], p[1], p[2], far) == CGAL::COPLANAR)
          hull_planes.unite(i, static_cast<std::size_t>(g.idx()));
      }
    }
    std::vector<std::array<Point, 3>> planes;
    {
      std::map<std::size_t, std::size_t> index_of_root;
      for (std::size_t i = 0; i < hull_faces.size(); ++i)
        if (index_of_root.emplace(hull_planes.find(i), planes.size()).second)
          planes.push_back(facet_points(hull_faces[i]));
    }

    // The hull planes through each vertex, and a vertex strictly inside each.
    std::unordered_map<std::size_t, std::vector<std::size_t>> on_plane;
    std::vector<std::size_t> inside(planes.size(), SIZE_MAX);
    for (std::size_t g = 0; g < planes.size(); ++g) {
      const auto& p = planes[g];
      const FilteredOrientation side(p[0], p[1], p[2]);
      for (std::size_t v : vertices) switch (side(points_[v])) {
          case CGAL::COPLANAR: on_plane[v].push_back(g); break;
          case CGAL::NEGATIVE: inside[g] = v; break;
          default:
            fail("internal: vertex " + std::to_string(v) + " outside its component's convex hull");
            return std::nullopt;
        }
    }

    if (std::find(inside.begin(), inside.end(), SIZE_MAX) != inside.end()) {
      fail("a component at depth " + std::to_string(depth) + " (" + std::to_string(faces.size()) +
           " faces, from triangle " + std::to_string(faces.front()) + ") is flat");
      return std::nullopt;
    }

    // Hull faces and the planes they give; the rest are pocket faces.
    std::vector<std::size_t> mesh_plane(planes.size(), SIZE_MAX);
    std::vector<std::size_t> pocket;
    std::size_t hull_face_count = 0;
    static const std::vector<std::size_t> none;
    auto planes_of = [&](std::size_t v) -> const std::vector<std::size_t>& {
      const auto it = on_plane.find(v);
      return it == on_plane.end() ? none : it->second;
    };
    for (std::size_t f : faces) {
      const Triangle t = oriented(f, reversed);
      std::size_t g = 0;
      if (!share(planes_of(t[0]), planes_of(t[1]), planes_of(t[2]), &g)) {
        pocket.push_back(f);
        continue;
      }
      if (CGAL::orientation(points_[t[0]], points_[t[1]], points_[t[2]], points_[inside[g]]) != CGAL::NEGATIVE) {
        fail("triangle " + std::to_string(f) + " lies on a plane of its component's convex hull (depth " +
             std::to_string(depth) + ") but faces inwards");
        return std::nullopt;
      }
      ++hull_face_count;
      if (mesh_plane[g] == SIZE_MAX) mesh_plane[g] = plane_of_[f];
    }
    if (depth > 0 && hull_face_count == 0) {
      fail("a component at depth " + std::to_string(depth) + " (" + std::to_string(faces.size()) +
           " triangles, from triangle " + std::to_string(faces.front()) +
           ") has no face on its own convex hull, so its deficiency is itself: the decomposition does not "
           "terminate");
      return std::nullopt;
    }

    std::vector<Expr> terms;
    for (std::size_t g = 0; g < planes.size(); ++g) {
      const auto& p = planes[g];
      if (mesh_plane[g] != SIZE_MAX) {
        ++plane_uses_[mesh_plane[g]];
        terms.push_back(reversed ? -leaves_[mesh_plane[g]] : leaves_[mesh_plane[g]]);
        continue;
      }
      // A lid plane (a plane of the parent's hull) is left out.
      auto parents_of = [&](const Point& q) -> const std::vector<std::size_t>& {
        const auto at = vertex_of_point.find({q.x(), q.y(), q.z()});
        if (at == vertex_of_point.end()) return none;
        const auto it = parent_planes.find(at->second);
        return it == parent_planes.end() ? none : it->second;
      };
      if (share(parents_of(p[0]), parents_of(p[1]), parents_of(p[2]), nullptr)) continue;
      const auto cr = CGAL::cross_product(p[1] - p[0], p[2] - p[0]);
      const double len = std::sqrt(cr.squared_length());
      terms.push_back(halfspace({p[0].x(), p[0].y(), p[0].z()}, {cr.x() / len, cr.y() / len, cr.z() / len}, 3));
      ++out_.bridges;
    }
    if (terms.empty()) {
      fail("a component at depth " + std::to_string(depth) + " lies wholly on its parent's hull planes");
      return std::nullopt;
    }
    Expr field = r_conjunction_n(std::move(terms), system_);
    if (pocket.empty()) return field;

    // Pockets: edge-connected patches of pocket faces, not joined across
    // edges that lie on the hull (two deficiencies meet there only).
    DisjointSets link(pocket.size());
    std::unordered_map<std::uint64_t, std::size_t> first_of_edge;
    for (std::size_t i = 0; i < pocket.size(); ++i) {
      const Triangle& t = triangles_[pocket[i]];
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = t[k], b = t[(k + 1) % 3];
        if (share(planes_of(a), planes_of(b), planes_of(b), nullptr)) continue;
        const auto [it, fresh] = first_of_edge.emplace(edge_key(a, b), i);
        if (!fresh) link.unite(i, it->second);
      }
    }
    std::map<std::size_t, std::vector<std::size_t>> patches;
    for (std::size_t i = 0; i < pocket.size(); ++i) patches[link.find(i)].push_back(pocket[i]);
    std::vector<Expr> children;
    for (const auto& [root, patch] : patches) {
      std::unordered_map<std::size_t, std::vector<std::size_t>> child_planes;
      for (std::size_t f : patch)
        for (std::size_t v : triangles_[f]) {
          const auto it = on_plane.find(v);
          if (it != on_plane.end()) child_planes.emplace(v, it->second);
        }
      auto child = component(patch, !reversed, child_planes, depth + 1);
      if (!child) return std::nullopt;
      children.push_back(*child);
    }
    return r_and(field, -r_disjunction_n(std::move(children), system_), system_);
  }

  const std::vector<Point>& points_;
  const std::vector<Triangle>& triangles_;
  RSystem system_;
  int max_depth_;
  std::vector<std::size_t> plane_of_;
  std::vector<Expr> leaves_;
  std::vector<std::size_t> plane_uses_;
  DeficiencyCsg out_;
  std::string reason_;
};

}  // namespace

std::optional<DeficiencyCsg> deficiency_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                            const RSystem& system, int max_depth, std::string& reason) {
  return Decomposition(points, triangles, system, max_depth).run(reason);
}

}  // namespace sage::geometry::mesh
