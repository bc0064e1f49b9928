#pragma once
// Internal to the mesh part of sage_geometry: the triangle soup shared by
// the reader, the validation, the field builders and the classifier.
//
// Pipeline (mesh_model.cpp):
//   read_mesh_soup       mesh_reader.cpp      file -> points + triangles
//     read_off, read_ply off_reader.cpp, ply_reader.cpp (else CGAL's readers)
//   validate_mesh        mesh_validation.cpp  exact checks, outward orientation
//   make_mesh_classifier mesh_classifier.cpp  xi(p) with Side_of_triangle_mesh
//   brep_distance / convex_csg     mesh_field.cpp, mesh_csg.cpp
//   deficiency_csg / shells_csg    mesh_deficiency.cpp, mesh_shells.cpp

#include <sage/expression/classifier.hpp>
#include <sage/expression/expression.hpp>
#include <sage/geometry/model.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sage::geometry::mesh {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Triangle = std::array<std::size_t, 3>;

// CGAL::orientation(p, q, r, s) for one plane (p, q, r) and many points s:
// the plane's cross product once, the sign of its product with s - p where
// that clearly exceeds its rounding error, and CGAL's exact predicate
// otherwise. The bound, 1e-13 max|dx| max|dy| max|dz| over the three
// differences, is 20 times CGAL's own filter's for its evaluation order
// (5.1e-15, Static_filters/Orientation_3.h), which covers this one's. The
// deficiency decomposition tests every hull plane against every vertex of
// a component: CGAL's predicate, called 7e7 times, took 0.75 s more of
// bunny00's load (mesh_deficiency.cpp).
class FilteredOrientation {
 public:
  FilteredOrientation(const Point& p, const Point& q, const Point& r) : p_(p), q_(q), r_(r) {
    const double pqx = q.x() - p.x(), pqy = q.y() - p.y(), pqz = q.z() - p.z();
    const double prx = r.x() - p.x(), pry = r.y() - p.y(), prz = r.z() - p.z();
    n_ = {pqy * prz - pqz * pry, pqz * prx - pqx * prz, pqx * pry - pqy * prx};
    max_ = {std::max(std::fabs(pqx), std::fabs(prx)), std::max(std::fabs(pqy), std::fabs(pry)),
            std::max(std::fabs(pqz), std::fabs(prz))};
  }

  CGAL::Orientation operator()(const Point& s) const {
    const std::optional<CGAL::Orientation> sign = filtered(s);
    return sign ? *sign : CGAL::orientation(p_, q_, r_, s);
  }

  /// The sign where the floating-point test decides it, else nothing.
  std::optional<CGAL::Orientation> filtered(const Point& s) const {
    const double psx = s.x() - p_.x(), psy = s.y() - p_.y(), psz = s.z() - p_.z();
    const double mx = std::max(max_[0], std::fabs(psx)), my = std::max(max_[1], std::fabs(psy)),
                 mz = std::max(max_[2], std::fabs(psz));
    const double smallest = std::min({mx, my, mz}), largest = std::max({mx, my, mz});
    if (!(smallest > 1e-90 && largest < 1e100)) return std::nullopt;  // the bound could underflow or overflow
    const double det = n_[0] * psx + n_[1] * psy + n_[2] * psz, bound = 1e-13 * mx * my * mz;
    if (det > bound) return CGAL::POSITIVE;
    if (det < -bound) return CGAL::NEGATIVE;
    return std::nullopt;
  }

 private:
  Point p_, q_, r_;
  std::array<double, 3> n_{}, max_{};
};

/// Union-find over 0..n-1 with path halving: faces merged across shared
/// edges or planes, corners of one vertex, pocket patches.
struct DisjointSets {
  std::vector<std::size_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) {
    for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  /// Puts a's set under b's root.
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

/// A triangle soup read from a file. Polygons with more than three vertices
/// are triangulated; origin[i] is the index, in the file, of the face that
/// triangle i comes from (for messages).
struct Soup {
  std::string path;
  std::vector<Point> points;
  std::vector<Triangle> triangles;
  std::vector<std::size_t> origin;
  std::size_t file_faces = 0;
  std::size_t first_face = 0;  // the number of the file's first face (CAD files count from 1)
  std::vector<std::string> notes;

  /// "face 12" or "face 12 (triangle 3 of its triangulation)".
  std::string face_name(std::size_t triangle) const;
};

/// Reads OFF and PLY with sage's readers (off_ply_reader.hpp), STL and OBJ
/// with CGAL's. With `repair`, merges
/// duplicated points and drops duplicated or invalid polygons first
/// (PMP::repair_polygon_soup), reporting counts. Throws ModelError naming
/// the file (unreadable, malformed, empty, a bad index or coordinate, a
/// polygon that is not planar or cannot be triangulated).
Soup read_mesh_soup(const std::string& path, bool repair);

/// The soup's points and triangles, as the field core and the solver keep them.
TriangleSurface triangle_surface(const Soup& soup);

/// The model of a soup: validation (validate_mesh), then the field by
/// options.method as load_mesh describes (mesh_model.cpp). CAD solids come
/// here as their tessellation (cad_model.cpp).
Model model_from_soup(Soup soup, const LoadOptions& options);

/// What validation found (beyond the faults, which throw).
struct Validated {
  SurfaceMesh mesh;                // face i = soup triangle i, outward
  std::size_t reversed_faces = 0;  // faces whose orientation was fixed
  std::size_t components = 0;      // connected components
  long long euler_characteristic = 0;
  long long genus = 0;  // total over the components
};

/// Exact checks in this order, each fault a ModelError naming the file and
/// the face (and vertices): degenerate faces (collinear vertices), border
/// edges (open mesh), non-manifold edges, non-manifold vertices,
/// non-orientable surfaces, self-intersections. Orientation is made
/// consistent and outward (PMP::orient_to_bound_a_volume); the soup's
/// triangles are rewritten accordingly. With `repair`, degenerate faces
/// are removed (PMP::remove_degenerate_faces) when that leaves a valid
/// closed mesh, and the soup is rebuilt from the repaired mesh.
Validated validate_mesh(Soup& soup, bool repair);

/// xi for a closed, outward oriented triangle mesh: exact point membership
/// (CGAL::Side_of_triangle_mesh over a prebuilt AABB tree, safe for
/// concurrent queries) and box classification (a box that meets no
/// triangle is wholly inside or outside, as its centre is).
std::shared_ptr<const PointClassifier> make_mesh_classifier(const std::vector<Point>& points,
                                                            const std::vector<Triangle>& triangles);

/// Trimmed-face field w >= 0 (zero exactly on the surface): per triangle the
/// smooth normalized trimming of its plane by its extruded region, glued
/// with r_conjunction_n (balanced tree, triangles in soup order).
/// `trim_system` builds the region t (must be normalized on its boundary).
Expr brep_distance(const std::vector<Point>& points, const std::vector<Triangle>& triangles, const RSystem& glue_system,
                   const RSystem& trim_system, bool orthogonalize);

/// The plane of a group of coplanar triangles: the area-weighted outward
/// unit normal and the centroid of their vertices (mesh_csg.cpp).
struct FacePlane {
  std::array<double, 3> normal{0, 0, 0};
  std::array<double, 3> anchor{0, 0, 0};
};
FacePlane face_plane(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                     const std::vector<std::size_t>& group);

/// The well-formed CSG of a convex polyhedron: one halfspace per distinct
/// face plane (coplanar adjacent faces merged), R-conjunction of them.
struct ConvexCsg {
  Expr field;
  std::vector<std::vector<std::size_t>> planes;  // triangles of each plane, by first triangle
  std::vector<std::array<double, 3>> normals;    // outward unit normal of each plane
  std::vector<std::array<double, 3>> anchors;    // a point of each plane
};

/// Exactly checks convexity of a closed, outward oriented, connected mesh;
/// returns nullopt (with the reason) when it is not convex.
std::optional<ConvexCsg> convex_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                    const RSystem& system, std::string& reason);

/// The well-formed CSG of a non-convex polyhedron by the convex deficiency
/// decomposition (mesh_deficiency.cpp): at each component, the
/// R-conjunction of its hull's planes (face planes, and bridges: hull planes
/// carrying no face) AND NOT the R-disjunction of its deficiency
/// components, recursively, with the faces reversed at odd depths.
struct DeficiencyCsg {
  Expr field;
  std::vector<std::vector<std::size_t>> planes;  // triangles of each face plane (exactly coplanar, same side)
  std::vector<std::size_t> plane_uses;           // leaves per face plane (1: used once)
  std::size_t bridges = 0;                       // hull planes carrying no face
  std::size_t nodes = 0;                         // components (the top one included)
  int depth = 0;                                 // deepest component
};

/// Builds the decomposition of a closed, outward oriented, connected mesh;
/// nullopt with the reason when it does not terminate (a component below
/// the top with no face on its own hull), exceeds max_depth levels, or meets
/// a degenerate component. Signs are exact by construction when every
/// deficiency component is bounded by one edge-connected patch of faces;
/// the caller checks them against point membership.
std::optional<DeficiencyCsg> deficiency_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                            const RSystem& system, int max_depth, std::string& reason);

/// Several shells (mesh_shells.cpp): separate solids, cavities (their
/// shells reversed bound solids), solids in cavities; each shell's own CSG
/// (convex, else the deficiency decomposition), combined by nesting:
/// solid AND NOT (union of what lies directly inside it), united at the top.
struct ShellsCsg {
  Expr field;
  std::size_t solids = 0, cavities = 0;
  std::vector<std::vector<std::size_t>> planes;  // face planes (soup triangles), shell by shell
  std::size_t reused = 0;                        // face planes used more than once
  std::size_t bridges = 0;
  std::size_t nodes = 0;  // convex components over all shells
  int depth = 0;
};

/// nullopt with the reason (naming the shell) when a shell's CSG fails.
std::optional<ShellsCsg> shells_csg(const std::vector<Point>& points, const std::vector<Triangle>& triangles,
                                    const RSystem& system, int max_depth, std::string& reason);

}  // namespace sage::geometry::mesh
