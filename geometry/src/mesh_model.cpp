// load_mesh: read (mesh_reader.cpp), validate and orient
// (mesh_validation.cpp), then build the field: well-formed CSG for convex
// polyhedra (mesh_csg.cpp), the convex deficiency decomposition of the
// others (mesh_deficiency.cpp, its signs checked against point membership),
// else the trimmed-face field signed by point
// membership (mesh_field.cpp, mesh_classifier.cpp).
#include <sage/geometry/mesh_model.hpp>

#include "mesh_internal.hpp"

#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

namespace sage::geometry {

bool is_mesh_path(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  return ext == ".off" || ext == ".stl" || ext == ".obj" || ext == ".ply";
}

namespace {

constexpr std::size_t kListedPrimitives = 16;

std::string face_list(const mesh::Soup& soup, const std::vector<std::size_t>& triangles) {
  std::vector<std::size_t> faces;
  for (std::size_t t : triangles) faces.push_back(soup.origin[t]);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  std::string s = faces.size() == 1 ? "face " : "faces ";
  for (std::size_t i = 0; i < faces.size() && i < 8; ++i) s += (i ? ", " : "") + std::to_string(faces[i]);
  if (faces.size() > 8) s += ", ... (" + std::to_string(faces.size()) + ")";
  return s;
}

/// The face planes as primitives for `sage info`, the first
/// kListedPrimitives of them and a count.
void list_planes(Model& model, const mesh::Soup& soup, const std::vector<std::vector<std::size_t>>& planes) {
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (i == kListedPrimitives) {
      model.primitives.push_back({"", "planes", "... " + std::to_string(planes.size()) + " planes in all"});
      break;
    }
    model.primitives.push_back({"", "plane", face_list(soup, planes[i])});
  }
}

std::string plane_reuse(std::size_t reused) {
  return reused ? std::to_string(reused) + " used more than once" : std::string("each used once");
}

struct SignCheck {
  std::size_t points = 0, mismatches = 0;
  std::array<double, 3> first{0, 0, 0};  // the first mismatch
};

// The field's sign against exact point membership at uniform points of the
// bounds and at points just off both sides of the faces (the thin parts
// of pockets); points where |field| <= 1e-9 of the diagonal are skipped.
SignCheck check_signs(const Expr& field, const PointClassifier& xi, const mesh::Soup& soup, const Bounds& bounds,
                      double diagonal) {
  std::vector<std::array<double, 3>> samples;
  std::mt19937_64 rng(20261201);
  for (int k = 0; k < 4000; ++k) {
    std::array<double, 3> p;
    for (int i = 0; i < 3; ++i) p[i] = std::uniform_real_distribution<double>(bounds.min[i], bounds.max[i])(rng);
    samples.push_back(p);
  }
  const std::size_t stride = std::max<std::size_t>(1, soup.triangles.size() / 4000);
  for (std::size_t f = 0; f < soup.triangles.size(); f += stride) {
    const auto &a = soup.points[soup.triangles[f][0]], &b = soup.points[soup.triangles[f][1]],
               &c = soup.points[soup.triangles[f][2]];
    const auto n = CGAL::cross_product(b - a, c - a);
    const double scale = 1e-6 * diagonal / std::sqrt(n.squared_length());
    for (double side : {-1.0, 1.0})
      samples.push_back({(a.x() + b.x() + c.x()) / 3 + side * scale * n.x(),
                         (a.y() + b.y() + c.y()) / 3 + side * scale * n.y(),
                         (a.z() + b.z() + c.z()) / 3 + side * scale * n.z()});
  }
  const Tape tape(field, 3);
  Evaluator<double> eval(tape);
  SignCheck r;
  for (const auto& p : samples) {
    const double w = eval.at(p);
    if (!(std::abs(w) > 1e-9 * diagonal)) continue;
    const double truth = xi.classify(p.data());
    if (truth == 0) continue;
    ++r.points;
    if (w * truth < 0 && r.mismatches++ == 0) r.first = p;
  }
  return r;
}

}  // namespace

Model load_mesh(const std::string& path, const LoadOptions& options) {
  check_mesh_method(path, options);
  return mesh::model_from_soup(mesh::read_mesh_soup(path, options.repair), options);
}

void check_mesh_method(const std::string& path, const LoadOptions& options) {
  if (options.method != "csg" && options.method != "brep")
    throw ModelError(path + ": unknown method '" + options.method + "' for a mesh (expected csg or brep)");
}

namespace mesh {

TriangleSurface triangle_surface(const Soup& soup) {
  TriangleSurface out;
  for (const Point& p : soup.points) out.points.push_back({p.x(), p.y(), p.z()});
  for (const Triangle& t : soup.triangles)
    out.triangles.push_back(
        {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]), static_cast<std::uint32_t>(t[2])});
  return out;
}

Model model_from_soup(Soup soup, const LoadOptions& options) {
  const std::string& path = soup.path;
  mesh::Validated valid = mesh::validate_mesh(soup, options.repair);

  Model model;
  model.source = path;
  model.name = std::filesystem::path(path).stem().string();
  model.dimension = 3;
  model.rfunction = options.rfunction.value_or(RSystem::r0());
  model.notes = soup.notes;

  // Bounds: the bounding box enlarged by 10% of its diagonal on every side.
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const mesh::Triangle& t : soup.triangles)
    for (std::size_t v : t)
      for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], soup.points[v][i]);
        hi[i] = std::max(hi[i], soup.points[v][i]);
      }
  const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  Bounds bounds;
  for (int i = 0; i < 3; ++i) {
    bounds.min[i] = lo[i] - 0.1 * diagonal;
    bounds.max[i] = hi[i] + 0.1 * diagonal;
  }
  model.bounds = bounds;

  {
    std::ostringstream s;
    s << "mesh: " << valid.mesh.number_of_vertices() << " vertices, " << soup.triangles.size() << " triangles ("
      << soup.file_faces << " faces in the file), " << valid.components << " component(s), Euler characteristic "
      << valid.euler_characteristic << ", genus " << valid.genus;
    model.notes.push_back(s.str());
  }
  model.notes.push_back(
      "validation (exact predicates): closed, 2-manifold, orientable, no degenerate faces, no self-intersections");
  model.surface = std::make_shared<TriangleSurface>(triangle_surface(soup));
  if (valid.reversed_faces)
    model.notes.push_back("orientation fixed: " + std::to_string(valid.reversed_faces) + " of " +
                          std::to_string(soup.triangles.size()) +
                          " faces reversed to a consistent outward orientation");
  else
    model.notes.push_back("orientation: consistent and outward as read");

  std::shared_ptr<const PointClassifier> xi;
  if (options.method == "csg") {
    std::string reason;
    std::optional<mesh::ConvexCsg> csg;
    if (valid.components != 1)
      reason = std::to_string(valid.components) + " components";
    else
      csg = mesh::convex_csg(soup.points, soup.triangles, model.rfunction, reason);
    if (csg) {
      model.field = csg->field;
      model.notes.push_back("method: csg; the polyhedron is convex (checked exactly): R-conjunction (" +
                            model.rfunction.name() + ", balanced tree) of " + std::to_string(csg->planes.size()) +
                            " face halfspaces, each plane used once (coplanar adjacent faces merged)");
      list_planes(model, soup, csg->planes);
      return model;
    }
    if (valid.components > 1) {
      std::optional<mesh::ShellsCsg> shells =
          mesh::shells_csg(soup.points, soup.triangles, model.rfunction, options.csg_depth_limit, reason);
      if (shells) {
        xi = mesh::make_mesh_classifier(soup.points, soup.triangles);
        const SignCheck check = check_signs(shells->field, *xi, soup, bounds, diagonal);
        if (check.mismatches == 0) {
          model.field = shells->field;
          std::ostringstream note;
          note << "method: csg; " << valid.components << " shells (" << shells->solids << " solid, " << shells->cavities
               << " cavity boundaries), each its own CSG (convex, or the convex deficiency "
               << "decomposition), combined by nesting (solid AND NOT what lies directly inside it, "
               << model.rfunction.name() << "); " << shells->nodes << " convex components, depth " << shells->depth
               << "; " << shells->planes.size() << " face planes (" << plane_reuse(shells->reused) << ") and "
               << shells->bridges << " bridge planes (hull planes carrying no face)";
          model.notes.push_back(note.str());
          model.notes.push_back("csg sign check: agrees with exact point membership (CGAL) at " +
                                std::to_string(check.points) + " points");
          list_planes(model, soup, shells->planes);
          return model;
        }
        reason = "the nested shells' CSG disagrees with exact point membership at " + std::to_string(check.mismatches) +
                 " of " + std::to_string(check.points) + " points";
      }
    } else {
      const std::string not_convex = reason;
      std::optional<mesh::DeficiencyCsg> deficiency =
          mesh::deficiency_csg(soup.points, soup.triangles, model.rfunction, options.csg_depth_limit, reason);
      if (deficiency) {
        xi = mesh::make_mesh_classifier(soup.points, soup.triangles);
        const SignCheck check = check_signs(deficiency->field, *xi, soup, bounds, diagonal);
        if (check.mismatches == 0) {
          const std::size_t reused = static_cast<std::size_t>(std::count_if(
              deficiency->plane_uses.begin(), deficiency->plane_uses.end(), [](std::size_t uses) { return uses > 1; }));
          model.field = deficiency->field;
          std::ostringstream note;
          note << "method: csg; the polyhedron is not convex (" << not_convex
               << "): convex deficiency decomposition (alternating sum of volumes, CGAL convex_hull_3 with exact "
                  "predicates) into "
               << deficiency->nodes << " components, depth " << deficiency->depth
               << "; each component = R-conjunction (" << model.rfunction.name()
               << ") of its hull planes AND NOT its deficiencies; " << deficiency->planes.size() << " face planes ("
               << plane_reuse(reused) << ") and " << deficiency->bridges
               << " bridge planes (hull planes carrying no face)";
          model.notes.push_back(note.str());
          model.notes.push_back("csg sign check: agrees with exact point membership (CGAL) at " +
                                std::to_string(check.points) + " points");
          list_planes(model, soup, deficiency->planes);
          return model;
        }
        std::ostringstream why;
        why << "its convex deficiency decomposition disagrees with exact point membership at " << check.mismatches
            << " of " << check.points << " points (first at " << check.first[0] << ", " << check.first[1] << ", "
            << check.first[2] << ")";
        reason = why.str();
      } else {
        reason = "not convex (" + not_convex + ") and " + reason;
      }
    }
    model.notes.push_back("method: csg is not available for this mesh (" + reason +
                          "); falling back to the trimmed-face (brep) field");
  }

  // Trimmed-face field signed by point membership.
  const RSystem trim_system = model.rfunction.kind == RKind::Rm ? RSystem::r0() : model.rfunction;
  const Expr w = mesh::brep_distance(soup.points, soup.triangles, model.rfunction, trim_system, options.orthogonalize);
  if (!xi) xi = mesh::make_mesh_classifier(soup.points, soup.triangles);
  model.field = Expr::classify(xi) * w;
  model.notes.push_back(
      "method: brep; field = xi * (R-conjunction (" + model.rfunction.name() +
      ", balanced tree over median splits of the triangles' centroids) of the smooth normalized trimmings of the " +
      std::to_string(soup.triangles.size()) + " triangle planes by their extruded regions" +
      (options.orthogonalize ? ", orthogonalized" : "") + " (regions: R-conjunction " + trim_system.name() +
      " of the edge planes)), xi exact point membership (CGAL)");
  model.primitives.push_back({"", "faces",
                              std::to_string(soup.triangles.size()) + " triangles from " +
                                  std::to_string(soup.file_faces) + " faces (" + std::to_string(soup.first_face) +
                                  ".." + std::to_string(soup.first_face + soup.file_faces - 1) + ")"});
  return model;
}

}  // namespace mesh

}  // namespace sage::geometry
