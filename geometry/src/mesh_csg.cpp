// Well-formed CSG of a convex polyhedron (paper 004, sec. 3.1 and 5.1): the
// R-conjunction of its face halfspaces, each distinct plane used once.
//
// Convexity is decided with exact orientation predicates: every edge must
// be convex or flat (the far vertex of each neighbouring face not on the
// outer side of a face's plane), and every vertex must be on the inner side
// of (or on) every face plane. Faces joined by a flat edge are coplanar
// (exactly) and are merged into one plane.
#include "mesh_internal.hpp"

#include <sage/expression/primitives.hpp>

#include <cmath>
#include <map>

namespace sage::geometry::mesh {

FacePlane face_plane(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                     const std::vector<std::size_t>& group) {
  FacePlane out;
  std::array<double, 3>&n = out.normal, &c = out.anchor;
  double count = 0;
  for (std::size_t f : group) {
    const Point &a = points[triangles[f][0]], &b = points[triangles[f][1]], &d = points[triangles[f][2]];
    const auto cr = CGAL::cross_product(b - a, d - a);
    n[0] += cr.x(), n[1] += cr.y(), n[2] += cr.z();
    for (const Point* p : {&a, &b, &d}) {
      c[0] += p->x(), c[1] += p->y(), c[2] += p->z();
      count += 1;
    }
  }
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) n[i] /= len, c[i] /= count;
  return out;
}

std::optional<ConvexCsg> convex_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                    const RSystem& system, std::string& reason) {
  const std::size_t nf = triangles.size();
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> face_of_edge;  // directed edge -> face
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) face_of_edge[{triangles[f][k], triangles[f][(k + 1) % 3]}] = f;

  DisjointSets planes_of_faces(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Triangle& t = triangles[f];
    for (int k = 0; k < 3; ++k) {
      const std::size_t u = t[k], v = t[(k + 1) % 3];
      const auto it = face_of_edge.find({v, u});
      if (it == face_of_edge.end()) {
        reason = "the mesh is not closed";
        return std::nullopt;
      }
      const Triangle& g = triangles[it->second];
      const std::size_t far = g[0] != u && g[0] != v ? g[0] : g[1] != u && g[1] != v ? g[1] : g[2];
      switch (CGAL::orientation(points[t[0]], points[t[1]], points[t[2]], points[far])) {
        case CGAL::POSITIVE:
          reason = "edge (" + std::to_string(u) + ", " + std::to_string(v) + ") between triangles " +
                   std::to_string(f) + " and " + std::to_string(it->second) + " is concave";
          return std::nullopt;
        case CGAL::COPLANAR: planes_of_faces.unite(f, it->second); break;
        default: break;
      }
    }
  }

  // Planes in the order of their first triangle.
  ConvexCsg out;
  std::map<std::size_t, std::size_t> plane_of_root;
  for (std::size_t f = 0; f < nf; ++f) {
    const std::size_t r = planes_of_faces.find(f);
    const auto [it, fresh] = plane_of_root.emplace(r, out.planes.size());
    if (fresh) out.planes.emplace_back();
    out.planes[it->second].push_back(f);
  }

  std::vector<std::size_t> used;
  {
    std::vector<char> mark(points.size(), 0);
    for (const Triangle& t : triangles)
      for (std::size_t v : t) mark[v] = 1;
    for (std::size_t v = 0; v < points.size(); ++v)
      if (mark[v]) used.push_back(v);
  }
  // Global check (locally convex closed surfaces can still wind around);
  // cost planes x vertices.
  for (const auto& plane : out.planes) {
    const Triangle& t = triangles[plane.front()];
    for (std::size_t v : used)
      if (CGAL::orientation(points[t[0]], points[t[1]], points[t[2]], points[v]) == CGAL::POSITIVE) {
        reason = "vertex " + std::to_string(v) + " lies outside the plane of triangle " + std::to_string(plane.front());
        return std::nullopt;
      }
  }

  std::vector<Expr> halfspaces;
  for (const auto& plane : out.planes) {
    const FacePlane fp = face_plane(points, triangles, plane);
    const std::array<double, 3>&n = fp.normal, &c = fp.anchor;
    out.normals.push_back(n);
    out.anchors.push_back(c);
    halfspaces.push_back(halfspace(c, n, 3));
  }
  out.field = r_conjunction_n(std::move(halfspaces), system);
  return out;
}

}  // namespace sage::geometry::mesh
