// Exact validation of a triangle soup as the boundary of a solid: no
// degenerate faces, closed, 2-manifold, orientable, no self-intersections;
// then a consistent outward orientation.
#include "mesh_internal.hpp"

#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <numeric>
#include <queue>
#include <tuple>

namespace sage::geometry::mesh {

namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

[[noreturn]] void fail(const Soup& soup, const std::string& what) { throw ModelError(soup.path + ": " + what); }

std::string vertices_of(const Triangle& t) {
  return "vertices " + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]);
}

// One use of an undirected edge (lo, hi) by a face, from corner `local`
// to the next corner; forward when it runs lo -> hi.
struct EdgeUse {
  std::size_t lo, hi, face;
  int local;
  bool forward;
};

std::size_t local_index(const Triangle& t, std::size_t v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

SurfaceMesh build_mesh(const Soup& soup) {
  SurfaceMesh mesh;
  for (const Point& p : soup.points) mesh.add_vertex(p);
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const Triangle& t = soup.triangles[f];
    using V = SurfaceMesh::Vertex_index;
    if (mesh.add_face(V(static_cast<SurfaceMesh::size_type>(t[0])), V(static_cast<SurfaceMesh::size_type>(t[1])),
                      V(static_cast<SurfaceMesh::size_type>(t[2]))) == SurfaceMesh::null_face())
      fail(soup, soup.face_name(f) + " (" + vertices_of(t) + ") cannot be added to a 2-manifold mesh");
  }
  return mesh;
}

std::vector<Triangle> triangles_of(const SurfaceMesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    Triangle t{};
    int k = 0;
    for (auto v : mesh.vertices_around_face(mesh.halfedge(f))) t[k++] = v.idx();
    out.push_back(t);
  }
  return out;
}

// Same cyclic order?
bool same_orientation(const Triangle& a, const Triangle& b) {
  for (int s = 0; s < 3; ++s)
    if (a[0] == b[s] && a[1] == b[(s + 1) % 3] && a[2] == b[(s + 2) % 3]) return true;
  return false;
}

}  // namespace

Validated validate_mesh(Soup& soup, bool repair) {
  const auto& P = soup.points;
  auto& T = soup.triangles;
  const std::size_t nf = T.size();

  // 1. Degenerate faces (exact collinearity).
  std::size_t degenerate = 0, first_degenerate = nf;
  for (std::size_t f = 0; f < nf; ++f)
    if (CGAL::collinear(P[T[f][0]], P[T[f][1]], P[T[f][2]])) {
      if (!degenerate++) first_degenerate = f;
    }
  if (degenerate && !repair)
    fail(soup, soup.face_name(first_degenerate) + " (" + vertices_of(T[first_degenerate]) +
                   ") is degenerate: its vertices are collinear (zero area); " + std::to_string(degenerate) +
                   " degenerate face(s) in all (repair removes them)");

  // 2. Edges: each undirected edge must be used by exactly two faces.
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = T[f][k], b = T[f][(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), f, k, a < b});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.lo, x.hi, x.face) < std::tie(y.lo, y.hi, y.face);
  });
  std::vector<std::pair<std::size_t, std::size_t>> groups;  // [begin, end) in uses
  std::size_t border = 0, non_manifold = 0;
  std::optional<std::size_t> first_border, first_non_manifold;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    groups.emplace_back(i, j);
    if (j - i == 1) {
      if (!border++ || uses[i].face < uses[*first_border].face) first_border = i;
    } else if (j - i > 2) {
      if (!non_manifold++) first_non_manifold = i;
    }
    i = j;
  }
  if (border) {
    const EdgeUse& e = uses[*first_border];
    fail(soup, "the mesh is open: edge (" + std::to_string(e.lo) + ", " + std::to_string(e.hi) + ") of " +
                   soup.face_name(e.face) + " (" + vertices_of(T[e.face]) +
                   ") is a border edge, used by no other face; " + std::to_string(border) +
                   " border edge(s) in all (repair merges duplicated vertices, which stitches such borders)");
  }
  if (non_manifold) {
    const std::size_t g = *first_non_manifold;
    std::size_t end = g;
    while (end < uses.size() && uses[end].lo == uses[g].lo && uses[end].hi == uses[g].hi) ++end;
    std::string faces;
    for (std::size_t k = g; k < end; ++k) faces += (k > g ? ", " : "") + std::to_string(soup.origin[uses[k].face]);
    fail(soup, "non-manifold edge (" + std::to_string(uses[g].lo) + ", " + std::to_string(uses[g].hi) +
                   "): shared by " + std::to_string(end - g) + " faces (faces " + faces + "), first " +
                   soup.face_name(uses[g].face) + "; " + std::to_string(non_manifold) + " non-manifold edge(s) in all");
  }

  // 3. Non-manifold vertices: the corners at a vertex must form one fan.
  DisjointSets corners(3 * nf);
  for (const auto& [b, e] : groups) {
    const EdgeUse &u = uses[b], &w = uses[b + 1];
    for (std::size_t v : {u.lo, u.hi})
      corners.unite(3 * u.face + local_index(T[u.face], v), 3 * w.face + local_index(T[w.face], v));
  }
  {
    std::vector<std::size_t> root_of_vertex(P.size(), SIZE_MAX), face_of_vertex(P.size(), SIZE_MAX);
    std::size_t isolated = 0;
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t v = T[f][k], r = corners.find(3 * f + k);
        if (root_of_vertex[v] == SIZE_MAX) {
          root_of_vertex[v] = r;
          face_of_vertex[v] = f;
        } else if (root_of_vertex[v] != r) {
          fail(soup, "non-manifold vertex " + std::to_string(v) + ": " + soup.face_name(face_of_vertex[v]) + " and " +
                         soup.face_name(f) + " meet there but belong to separate fans of faces around it");
        }
      }
    for (std::size_t v = 0; v < P.size(); ++v) isolated += root_of_vertex[v] == SIZE_MAX;
    if (isolated) soup.notes.push_back(std::to_string(isolated) + " isolated vertices (used by no face) ignored");
  }

  // 4. Orientability, by breadth-first search over faces: `flip` makes the
  // two uses of every edge run in opposite directions.
  std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours(nf);  // (face, same direction)
  for (const auto& [b, e] : groups) {
    const EdgeUse &u = uses[b], &w = uses[b + 1];
    const bool same = u.forward == w.forward;
    neighbours[u.face].emplace_back(w.face, same);
    neighbours[w.face].emplace_back(u.face, same);
  }
  std::vector<int> flip(nf, -1);
  std::size_t components = 0;
  for (std::size_t start = 0; start < nf; ++start) {
    if (flip[start] >= 0) continue;
    ++components;
    flip[start] = 0;
    std::queue<std::size_t> queue;
    queue.push(start);
    while (!queue.empty()) {
      const std::size_t f = queue.front();
      queue.pop();
      for (const auto& [g, same] : neighbours[f]) {
        const int want = same ? 1 - flip[f] : flip[f];
        if (flip[g] < 0) {
          flip[g] = want;
          queue.push(g);
        } else if (flip[g] != want) {
          fail(soup, "the surface is not orientable: " + soup.face_name(f) + " and " + soup.face_name(g) +
                         " cannot be oriented consistently");
        }
      }
    }
  }
  const std::vector<Triangle> original = T;
  for (std::size_t f = 0; f < nf; ++f)
    if (flip[f]) std::swap(T[f][1], T[f][2]);

  Validated out;
  out.mesh = build_mesh(soup);

  if (degenerate) {  // repair: remove them with edge collapses and flips, then validate again
    PMP::remove_degenerate_faces(out.mesh);
    out.mesh.collect_garbage();
    Soup repaired;
    repaired.path = soup.path;
    repaired.points.assign(out.mesh.points().begin(), out.mesh.points().end());
    repaired.triangles = triangles_of(out.mesh);
    repaired.origin.resize(repaired.triangles.size());
    std::iota(repaired.origin.begin(), repaired.origin.end(), 0);
    repaired.file_faces = soup.file_faces;
    repaired.notes = soup.notes;
    repaired.notes.push_back("repair: " + std::to_string(degenerate) +
                             " degenerate face(s) removed (PMP::remove_degenerate_faces), " +
                             std::to_string(nf - repaired.triangles.size()) +
                             " triangles fewer; face numbers below refer to the repaired mesh");
    if (repaired.triangles.empty()) fail(soup, "no face is left after removing the degenerate faces");
    soup = std::move(repaired);
    return validate_mesh(soup, false);
  }

  // 5. Self-intersections (exact predicates; faces sharing an edge or a
  // vertex count only when they meet elsewhere too).
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections(out.mesh, std::back_inserter(pairs));
  if (!pairs.empty()) {
    auto [f, g] = pairs.front();
    for (const auto& pr : pairs)
      if (std::min(pr.first.idx(), pr.second.idx()) < std::min(f.idx(), g.idx())) std::tie(f, g) = pr;
    if (g.idx() < f.idx()) std::swap(f, g);
    fail(soup, "self-intersection: " + soup.face_name(f.idx()) + " (" + vertices_of(original[f.idx()]) + ") and " +
                   soup.face_name(g.idx()) + " (" + vertices_of(original[g.idx()]) + ") intersect; " +
                   std::to_string(pairs.size()) + " intersecting face pair(s) in all");
  }

  // 6. Outward orientation (nested components handled by CGAL).
  PMP::orient_to_bound_a_volume(out.mesh);
  T = triangles_of(out.mesh);
  for (std::size_t f = 0; f < nf; ++f) out.reversed_faces += !same_orientation(T[f], original[f]);

  out.components = components;
  std::size_t used_vertices = 0;
  {
    std::vector<char> used(P.size(), 0);
    for (const Triangle& t : T)
      for (std::size_t v : t) used[v] = 1;
    used_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  }
  out.euler_characteristic =
      static_cast<long long>(used_vertices) - static_cast<long long>(groups.size()) + static_cast<long long>(nf);
  out.genus = (2 * static_cast<long long>(components) - out.euler_characteristic) / 2;
  return out;
}

}  // namespace sage::geometry::mesh
