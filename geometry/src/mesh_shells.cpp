// Well-formed CSG of a mesh with several shells (separate solids, cavities,
// solids inside cavities): each shell bounds a solid (a cavity's shell
// reversed), given by its own CSG (convex_csg, else deficiency_csg); by
// nesting, each solid's term is its field AND NOT the union of the terms of
// the shells directly inside it, and the top-level terms are united. The
// shells are disjoint, so on each shell only its own term vanishes.
#include "mesh_internal.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <unordered_map>

namespace sage::geometry::mesh {

namespace {

struct Shell {
  std::vector<std::size_t> triangles;  // in the soup
  std::vector<Triangle> solid;         // outward from the solid it bounds
  double volume = 0;                   // signed, as oriented in the soup
  Expr field;
  std::vector<std::size_t> children;
};

}  // namespace

std::optional<ShellsCsg> shells_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                    const RSystem& system, int max_depth, std::string& reason) {
  const std::size_t nf = triangles.size();
  DisjointSets connected(nf);
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> first_of_edge;
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto a = std::min(triangles[f][k], triangles[f][(k + 1) % 3]);
      const auto b = std::max(triangles[f][k], triangles[f][(k + 1) % 3]);
      const auto [it, fresh] = first_of_edge.emplace(std::make_pair(a, b), f);
      if (!fresh) connected.unite(f, it->second);
    }
  std::vector<Shell> shells;
  {
    std::map<std::size_t, std::size_t> index_of_root;
    for (std::size_t f = 0; f < nf; ++f) {
      const auto [it, fresh] = index_of_root.emplace(connected.find(f), shells.size());
      if (fresh) shells.emplace_back();
      shells[it->second].triangles.push_back(f);
    }
  }

  ShellsCsg out;
  for (std::size_t s = 0; s < shells.size(); ++s) {
    Shell& shell = shells[s];
    for (std::size_t f : shell.triangles) {
      const Point &a = points[triangles[f][0]], &b = points[triangles[f][1]], &c = points[triangles[f][2]];
      shell.volume += CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN) / 6;
    }
    const bool cavity = shell.volume < 0;
    (cavity ? out.cavities : out.solids) += 1;
    for (std::size_t f : shell.triangles) {
      const Triangle& t = triangles[f];
      shell.solid.push_back(cavity ? Triangle{t[0], t[2], t[1]} : t);
    }
    const std::string name = std::string(cavity ? "cavity" : "shell") + " from triangle " +
                             std::to_string(shell.triangles.front()) + " (" + std::to_string(shell.triangles.size()) +
                             " triangles)";
    std::string why;
    auto global = [&](const std::vector<std::vector<std::size_t>>& planes) {
      for (const auto& plane : planes) {
        out.planes.emplace_back();
        for (std::size_t f : plane) out.planes.back().push_back(shell.triangles[f]);
      }
    };
    if (auto convex = convex_csg(points, shell.solid, system, why)) {
      shell.field = convex->field;
      global(convex->planes);
      out.nodes += 1;
      continue;
    }
    std::string deficiency_why;
    auto deficiency = deficiency_csg(points, shell.solid, system, max_depth, deficiency_why);
    if (!deficiency) {
      reason = name + ": not convex (" + why + ") and " + deficiency_why + " (triangle numbers within the shell)";
      return std::nullopt;
    }
    shell.field = deficiency->field;
    global(deficiency->planes);
    out.bridges += deficiency->bridges;
    out.nodes += deficiency->nodes;
    out.depth = std::max(out.depth, deficiency->depth);
    out.reused += static_cast<std::size_t>(std::count_if(deficiency->plane_uses.begin(), deficiency->plane_uses.end(),
                                                         [](std::size_t uses) { return uses > 1; }));
  }

  // Nesting: the parent of a shell is the smallest solid containing one of
  // its vertices (shells are disjoint: one vertex decides).
  std::vector<std::shared_ptr<const PointClassifier>> inside;
  for (const Shell& shell : shells) inside.push_back(make_mesh_classifier(points, shell.solid));
  std::vector<std::size_t> roots;
  for (std::size_t s = 0; s < shells.size(); ++s) {
    const Point& p = points[triangles[shells[s].triangles.front()][0]];
    const double q[3] = {p.x(), p.y(), p.z()};
    std::size_t best = SIZE_MAX;
    for (std::size_t o = 0; o < shells.size(); ++o)
      if (o != s && inside[o]->classify(q) > 0 &&
          (best == SIZE_MAX || std::abs(shells[o].volume) < std::abs(shells[best].volume)))
        best = o;
    if (best == SIZE_MAX)
      roots.push_back(s);
    else
      shells[best].children.push_back(s);
  }
  // Solids and cavities alternate down the nesting (outward orientation).
  std::function<std::optional<Expr>(std::size_t, bool)> term = [&](std::size_t s, bool solid) -> std::optional<Expr> {
    if ((shells[s].volume > 0) != solid) {
      reason = "shell from triangle " + std::to_string(shells[s].triangles.front()) +
               (solid ? " is a cavity outside every solid" : " is a solid directly inside a solid");
      return std::nullopt;
    }
    if (shells[s].children.empty()) return shells[s].field;
    std::vector<Expr> inner;
    for (std::size_t c : shells[s].children) {
      auto t = term(c, !solid);
      if (!t) return std::nullopt;
      inner.push_back(*t);
    }
    return r_and(shells[s].field, -r_disjunction_n(std::move(inner), system), system);
  };
  std::vector<Expr> top;
  for (std::size_t r : roots) {
    auto t = term(r, true);
    if (!t) return std::nullopt;
    top.push_back(*t);
  }
  out.field = r_disjunction_n(std::move(top), system);
  return out;
}

}  // namespace sage::geometry::mesh
