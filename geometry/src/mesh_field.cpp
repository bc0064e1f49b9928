// The trimmed-face field of a closed triangle mesh (paper 004, sec. 5.1;
// FORMULAS.md "From boundary representation to a solid function").
//
// Triangle i with vertices a, b, c (outward orientation), outward unit
// normal n:
//   h_i = n . (a - p)                 signed distance to its plane, > 0 inside
//   s_j = m_j . (p - v_j)             one per edge v_j -> v_k, m_j = n x (v_k - v_j)
//                                     normalized: the plane through the edge
//                                     perpendicular to the face, > 0 on the
//                                     triangle's side
//   t_i = s_0 AND s_1 AND s_2         the triangle extruded along n; R0 (or any
//                                     normalized system) keeps |grad t| = 1 on
//                                     its sides away from their meeting lines
//   w_i = trim_smooth(h_i, t_i)       >= 0, zero exactly on the triangle
//                                     (trimming.hpp's triangle_field)
//   w   = w_0 AND ... AND w_{n-1}     a balanced tree over a bounding volume
//                                     hierarchy of the triangles (below)
// The edge planes are perpendicular to the face, so h_i and t_i already
// meet orthogonally; orthogonalize (optional) then only renormalizes t_i.
//
// The conjunction's tree follows the triangles' space: each node splits
// its triangles at the median centroid along the longest side of their
// centroids' box, so every subtree is a compact cluster. Interval pruning
// then drops whole clusters, and over a grid block the far-field
// approximation (tape_specialization.hpp) replaces a far cluster by one
// patch; in file order a subtree mixes near and far triangles and neither
// works. The zero set is the same for every tree; values off the surface
// depend on the tree's shape (R-functions are not associative).
#include "mesh_internal.hpp"

#include <sage/expression/trimming.hpp>

#include <algorithm>
#include <array>
#include <stdexcept>

namespace sage::geometry::mesh {

namespace {

using V3 = std::array<double, 3>;

/// The conjunction of faces[order[lo..hi)] as a tree of median splits of
/// their centroids along the longest axis.
Expr spatial_conjunction(const std::vector<Expr>& faces, const std::vector<V3>& centroids, std::vector<int>& order,
                         std::size_t lo, std::size_t hi, const RSystem& system) {
  if (hi - lo == 1) return faces[static_cast<std::size_t>(order[lo])];
  V3 low = centroids[static_cast<std::size_t>(order[lo])], high = low;
  for (std::size_t k = lo; k < hi; ++k)
    for (int a = 0; a < 3; ++a) {
      low[a] = std::min(low[a], centroids[static_cast<std::size_t>(order[k])][a]);
      high[a] = std::max(high[a], centroids[static_cast<std::size_t>(order[k])][a]);
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (high[a] - low[a] > high[axis] - low[axis]) axis = a;
  const std::size_t middle = lo + (hi - lo) / 2;
  std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(lo), order.begin() + static_cast<std::ptrdiff_t>(middle),
                   order.begin() + static_cast<std::ptrdiff_t>(hi), [&](int i, int j) {
                     const double ci = centroids[static_cast<std::size_t>(i)][axis];
                     const double cj = centroids[static_cast<std::size_t>(j)][axis];
                     return ci < cj || (ci == cj && i < j);  // ties by index: the same tree on every platform
                   });
  return r_and(spatial_conjunction(faces, centroids, order, lo, middle, system),
               spatial_conjunction(faces, centroids, order, middle, hi, system), system);
}

}  // namespace

Expr brep_distance(const std::vector<Point>& points, const std::vector<Triangle>& triangles, const RSystem& glue_system,
                   const RSystem& trim_system, bool orthogonalize) {
  auto coordinates = [](const Point& p) { return std::array<double, 3>{p.x(), p.y(), p.z()}; };
  std::vector<Expr> faces;
  std::vector<V3> centroids;
  faces.reserve(triangles.size());
  centroids.reserve(triangles.size());
  for (const Triangle& tri : triangles) {
    const Point &a = points[tri[0]], &b = points[tri[1]], &c = points[tri[2]];
    centroids.push_back({(a.x() + b.x() + c.x()) / 3, (a.y() + b.y() + c.y()) / 3, (a.z() + b.z() + c.z()) / 3});
    faces.push_back(triangle_field(coordinates(a), coordinates(b), coordinates(c), trim_system, orthogonalize));
  }
  if (faces.empty()) throw std::invalid_argument("a mesh field needs at least one triangle");
  std::vector<int> order(faces.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  return spatial_conjunction(faces, centroids, order, 0, faces.size(), glue_system);
}

}  // namespace sage::geometry::mesh
