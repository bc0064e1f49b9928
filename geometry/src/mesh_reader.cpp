// Reading meshes into a triangle soup: OFF and PLY with sage's readers
// (off_ply_reader.hpp: CGAL 5.5's trust the file), STL and OBJ with CGAL's
// polygon soup readers; planar polygons are triangulated.
#include "mesh_internal.hpp"
#include "off_ply_reader.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace sage::geometry::mesh {

namespace PMP = CGAL::Polygon_mesh_processing;

std::string Soup::face_name(std::size_t triangle) const {
  std::string name = "face " + std::to_string(origin.at(triangle));
  // Several triangles from one polygon: say which.
  std::size_t first = triangle;
  while (first > 0 && origin[first - 1] == origin[triangle]) --first;
  const bool split = (triangle + 1 < origin.size() && origin[triangle + 1] == origin[triangle]) || first != triangle;
  if (split) name += " (triangle " + std::to_string(triangle - first) + " of its triangulation)";
  return name;
}

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw ModelError(path + ": " + what); }

std::string vertex_list(const std::vector<std::size_t>& polygon) {
  std::string s;
  for (std::size_t i = 0; i < polygon.size(); ++i) s += (i ? ", " : "") + std::to_string(polygon[i]);
  return s;
}

// Triangulates a planar polygon (vertex indices into points): a fan when it
// is strictly convex, else CGAL's constrained Delaunay triangulation of the
// face (PMP::triangulate_faces on a one-face mesh).
std::vector<Triangle> triangulate_polygon(const Soup& soup, const std::vector<std::size_t>& polygon, std::size_t face) {
  const auto& P = soup.points;
  const std::size_t n = polygon.size();
  // A reference triple that is not collinear gives the plane.
  std::optional<std::array<std::size_t, 3>> ref;
  for (std::size_t i = 1; i + 1 < n && !ref; ++i)
    for (std::size_t j = i + 1; j < n && !ref; ++j)
      if (!CGAL::collinear(P[polygon[0]], P[polygon[i]], P[polygon[j]])) ref = {polygon[0], polygon[i], polygon[j]};
  if (!ref)
    fail(soup.path, "face " + std::to_string(face) + " (vertices " + vertex_list(polygon) +
                        ") is degenerate: all its vertices are collinear (zero area)");
  for (std::size_t k = 0; k < n; ++k)
    if (CGAL::orientation(P[(*ref)[0]], P[(*ref)[1]], P[(*ref)[2]], P[polygon[k]]) != CGAL::COPLANAR)
      fail(soup.path, "face " + std::to_string(face) + " is not planar: vertex " + std::to_string(polygon[k]) +
                          " lies off the plane of vertices " + std::to_string((*ref)[0]) + ", " +
                          std::to_string((*ref)[1]) + ", " + std::to_string((*ref)[2]) +
                          " (only triangles and planar polygons are supported)");
  // Strict convexity: every corner turns the same way, seen along the normal.
  const auto normal = CGAL::cross_product(P[(*ref)[1]] - P[(*ref)[0]], P[(*ref)[2]] - P[(*ref)[0]]);
  const Point& o = P[polygon[0]];
  const Point apex = o + normal;  // off the plane (inexact, only used for a side test)
  bool convex = true;
  CGAL::Orientation turn = CGAL::ZERO;
  for (std::size_t k = 0; k < n && convex; ++k) {
    const auto t = CGAL::orientation(P[polygon[k]], P[polygon[(k + 1) % n]], P[polygon[(k + 2) % n]], apex);
    if (t == CGAL::COPLANAR || (turn != CGAL::ZERO && t != turn)) convex = false;
    turn = t;
  }
  std::vector<Triangle> out;
  if (convex) {
    for (std::size_t k = 1; k + 1 < n; ++k) out.push_back({polygon[0], polygon[k], polygon[k + 1]});
    return out;
  }
  SurfaceMesh one;
  std::vector<SurfaceMesh::Vertex_index> vs;
  for (std::size_t v : polygon) vs.push_back(one.add_vertex(P[v]));
  if (one.add_face(vs) == SurfaceMesh::null_face() || !PMP::triangulate_faces(one))
    fail(soup.path, "face " + std::to_string(face) + " (vertices " + vertex_list(polygon) +
                        ") is a non-convex polygon that could not be triangulated");
  for (auto f : one.faces()) {
    // CGAL may report success on a self-intersecting polygon yet leave a
    // face that is no triangle (even a cycle that does not close): count
    // its corners up to four, no further.
    Triangle t{};
    std::size_t corners = 0;
    for (auto v : one.vertices_around_face(one.halfedge(f))) {
      if (corners == 3) {
        corners = 4;
        break;
      }
      t[corners++] = polygon[v.idx()];
    }
    if (corners != 3)
      fail(soup.path, "face " + std::to_string(face) + " (vertices " + vertex_list(polygon) +
                          ") is a non-convex polygon that could not be triangulated (it may cross itself)");
    out.push_back(t);
  }
  return out;
}

// The whole file, read to its size (a stream copy would hide a read error,
// and a folder named x.off would read as an empty file).
std::string read_file(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) fail(path, "not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) fail(path, "cannot read the file's size: " + error.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  std::string data(static_cast<std::size_t>(size), '\0');
  in.read(data.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) fail(path, "cannot read the file");
  return data;
}

// The file's points and polygons: OFF and PLY with sage's readers, STL and
// OBJ with CGAL's.
std::vector<std::vector<std::size_t>> read_polygons(const std::string& path, std::vector<Point>& points) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".off" || ext == ".ply") {
    const std::string data = read_file(path);
    PolygonSoup soup = ext == ".off" ? read_off(path, data) : read_ply(path, data);
    points = std::move(soup.points);
    return std::move(soup.polygons);
  }
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons);
  } catch (const std::exception& e) {
    fail(path, std::string("malformed mesh file: ") + e.what());
  }
  if (!ok) fail(path, "malformed or unreadable mesh file (CGAL's " + ext + " reader failed)");
  return polygons;
}

}  // namespace

Soup read_mesh_soup(const std::string& path, bool repair) {
  Soup soup;
  soup.path = path;
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) fail(path, "cannot open the file");
  }
  std::vector<std::vector<std::size_t>> polygons = read_polygons(path, soup.points);
  if (polygons.empty()) fail(path, "the mesh has no faces");

  for (std::size_t v = 0; v < soup.points.size(); ++v) {
    const Point& p = soup.points[v];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      fail(path, "vertex " + std::to_string(v) + " has a coordinate that is not a finite number");
  }
  for (std::size_t f = 0; f < polygons.size(); ++f)
    for (std::size_t v : polygons[f])
      if (v >= soup.points.size())
        fail(path, "face " + std::to_string(f) + " refers to vertex " + std::to_string(v) + ", but there are only " +
                       std::to_string(soup.points.size()) + " vertices");

  if (repair) {
    const std::size_t points_before = soup.points.size(), polygons_before = polygons.size();
    PMP::repair_polygon_soup(soup.points, polygons);
    if (polygons.empty()) fail(path, "no valid face is left after repair");
    std::ostringstream note;
    note << "repair: polygon soup cleaned (PMP::repair_polygon_soup): " << points_before - soup.points.size()
         << " duplicated or unused vertices merged or removed, " << polygons_before - polygons.size()
         << " duplicated or invalid faces removed";
    soup.notes.push_back(note.str());
  }

  soup.file_faces = polygons.size();
  std::size_t triangulated = 0;
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& polygon = polygons[f];
    if (polygon.size() < 3)
      fail(path, "face " + std::to_string(f) + " is degenerate: it has " + std::to_string(polygon.size()) +
                     " vertices (at least 3 are needed)");
    const std::set<std::size_t> distinct(polygon.begin(), polygon.end());
    if (distinct.size() != polygon.size())
      fail(path, "face " + std::to_string(f) + " (vertices " + vertex_list(polygon) +
                     ") is degenerate: it uses a vertex twice");
    if (polygon.size() == 3) {
      soup.triangles.push_back({polygon[0], polygon[1], polygon[2]});
      soup.origin.push_back(f);
      continue;
    }
    ++triangulated;
    for (const Triangle& t : triangulate_polygon(soup, polygon, f)) {
      soup.triangles.push_back(t);
      soup.origin.push_back(f);
    }
  }
  if (triangulated)
    soup.notes.push_back(std::to_string(triangulated) + " planar polygon faces triangulated into " +
                         std::to_string(soup.triangles.size() - (polygons.size() - triangulated)) + " triangles");
  return soup;
}

}  // namespace sage::geometry::mesh
