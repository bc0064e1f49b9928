// load_mesh: read (mesh_reader.cpp), validate and orient
// (mesh_validation.cpp), then build the field: well-formed CSG for convex
// polyhedra (mesh_csg.cpp), else the trimmed-face field signed by point
// membership (mesh_field.cpp, mesh_classifier.cpp).
#include <sage/geometry/mesh_model.hpp>

#include "mesh_internal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace sage::geometry {

bool is_mesh_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
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

}  // namespace

Model load_mesh(const std::string& path, const LoadOptions& options) {
  if (options.method != "csg" && options.method != "brep")
    throw ModelError(path + ": unknown method '" + options.method + "' for a mesh (expected csg or brep)");
  mesh::Soup soup = mesh::read_mesh_soup(path, options.repair);
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
  if (valid.reversed_faces)
    model.notes.push_back("orientation fixed: " + std::to_string(valid.reversed_faces) + " of " +
                          std::to_string(soup.triangles.size()) +
                          " faces reversed to a consistent outward orientation");
  else
    model.notes.push_back("orientation: consistent and outward as read");

  if (options.method == "csg") {
    std::string reason;
    std::optional<mesh::ConvexCsg> csg;
    if (valid.components != 1)
      reason = std::to_string(valid.components) + " components";
    else if (valid.genus != 0)
      reason = "genus " + std::to_string(valid.genus);
    else
      csg = mesh::convex_csg(soup.points, soup.triangles, model.rfunction, reason);
    if (csg) {
      model.field = csg->field;
      model.notes.push_back("method: csg; the polyhedron is convex (checked exactly): R-conjunction (" +
                            model.rfunction.name() + ", balanced tree) of " + std::to_string(csg->planes.size()) +
                            " face halfspaces, each plane used once (coplanar adjacent faces merged)");
      for (std::size_t i = 0; i < csg->planes.size(); ++i) {
        if (i == kListedPrimitives) {
          model.primitives.push_back({"", "planes", "... " + std::to_string(csg->planes.size()) + " planes in all"});
          break;
        }
        model.primitives.push_back({"", "plane", face_list(soup, csg->planes[i])});
      }
      return model;
    }
    model.notes.push_back("method: csg is not available for this mesh (not convex: " + reason +
                          "); a well-formed CSG of a non-convex polyhedron (convex deficiency decomposition) is not "
                          "implemented; falling back to the trimmed-face (brep) field");
  }

  // Trimmed-face field signed by point membership.
  const RSystem trim_system = model.rfunction.kind == RKind::Rm ? RSystem::r0() : model.rfunction;
  const Expr w = mesh::brep_distance(soup.points, soup.triangles, model.rfunction, trim_system, options.orthogonalize);
  model.field = Expr::classify(mesh::make_mesh_classifier(soup.points, soup.triangles)) * w;
  model.notes.push_back("method: brep; field = xi * (R-conjunction (" + model.rfunction.name() +
                        ", balanced tree, triangles in file order) of the smooth normalized trimmings of the " +
                        std::to_string(soup.triangles.size()) + " triangle planes by their extruded regions" +
                        (options.orthogonalize ? ", orthogonalized" : "") + " (regions: R-conjunction " +
                        trim_system.name() + " of the edge planes)), xi exact point membership (CGAL)");
  model.primitives.push_back({"", "faces",
                              std::to_string(soup.triangles.size()) + " triangles from " +
                                  std::to_string(soup.file_faces) + " faces (0.." +
                                  std::to_string(soup.file_faces - 1) + ")"});
  return model;
}

}  // namespace sage::geometry
