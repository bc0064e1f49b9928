// load_cad: a CAD solid (cad_reader.cpp) tessellated by OpenCASCADE's
// BRepMesh within a stated chordal deflection, welded into one closed
// triangle soup whose triangles keep their face, and built into a field by
// the mesh path (mesh_model.cpp): the same validation, CSG or trimmed-face
// field and exact point membership as an STL of the same triangles.
#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/mesh_model.hpp>

// CGAL's headers (mesh_internal.hpp) before OCCT's: OCCT defines a macro
// Handle(), which CGAL uses as a name.
#include "mesh_internal.hpp"

#include "cad_internal.hpp"

#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Poly_Triangulation.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

namespace sage::geometry {

bool cad_available() { return true; }

std::string cad_library() { return std::string("OpenCASCADE ") + OCC_VERSION_COMPLETE; }

namespace cad {
namespace {

/// Tessellation nodes merged when closer than OCCT's own confusion
/// distance: faces meeting at an edge share its discretization, so their
/// nodes there coincide up to the rounding of each face's location.
class Welder {
 public:
  explicit Welder(double tolerance) : tolerance_(tolerance) {}

  std::size_t id(const gp_Pnt& p) {
    const std::array<long long, 3> cell = cell_of(p);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find(key({cell[0] + dx, cell[1] + dy, cell[2] + dz}));
          if (found == cells_.end()) continue;
          for (std::size_t k : found->second)
            if (points_[k].Distance(p) <= tolerance_) return k;
        }
    cells_[key(cell)].push_back(points_.size());
    points_.push_back(p);
    return points_.size() - 1;
  }

  const std::vector<gp_Pnt>& points() const { return points_; }

 private:
  std::array<long long, 3> cell_of(const gp_Pnt& p) const {
    return {static_cast<long long>(std::floor(p.X() / tolerance_)),
            static_cast<long long>(std::floor(p.Y() / tolerance_)),
            static_cast<long long>(std::floor(p.Z() / tolerance_))};
  }
  static std::uint64_t key(const std::array<long long, 3>& c) {
    return static_cast<std::uint64_t>(c[0]) * 73856093ULL ^ static_cast<std::uint64_t>(c[1]) * 19349663ULL ^
           static_cast<std::uint64_t>(c[2]) * 83492791ULL;
  }

  double tolerance_;
  std::vector<gp_Pnt> points_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

struct Tessellation {
  mesh::Soup soup;
  std::vector<ModelFace> faces;
  double deviation = 0;  // the largest of the faces' measured deflections, in mm
  std::size_t deviation_face = 0;
  std::size_t dropped = 0;  // triangles with two corners welded into one
};

/// What the file gives a face (its name, its colour), if anything: the
/// last entry for it.
std::string given_to(const TopoDS_Shape& face, const std::vector<std::pair<TopoDS_Shape, std::string>>& given) {
  for (auto it = given.rbegin(); it != given.rend(); ++it)
    if (it->first.IsSame(face)) return it->second;
  return {};
}

Tessellation tessellate(const std::string& path, const CadSolid& solid, double deflection_mm) {
  const TopoDS_Shape& shape = solid.shape;
  const double scale = solid.millimetres_per_unit;
  constexpr double kAngularDeflection = 20 * M_PI / 180;
  BRepMesh_IncrementalMesh mesher(shape, deflection_mm, false, kAngularDeflection, true);
  if (!mesher.IsDone()) throw ModelError(path + ": OpenCASCADE's mesher (BRepMesh) failed on the solid");
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  Tessellation out;
  out.soup.path = path;
  out.soup.file_faces = static_cast<std::size_t>(faces.Extent());
  out.soup.first_face = 1;
  Welder welder(Precision::Confusion());
  for (int f = 1; f <= faces.Extent(); ++f) {
    const TopoDS_Face& face = TopoDS::Face(faces(f));
    out.faces.push_back(describe_surface(face, scale));
    out.faces.back().name = given_to(face, solid.face_names);
    out.faces.back().colour = given_to(face, solid.face_colours);
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull() || triangulation->NbTriangles() == 0)
      throw ModelError(path + ": face " + std::to_string(f) + " (" + out.faces.back().surface +
                       ") could not be tessellated (BRepMesh made no triangle)");
    if (triangulation->Deflection() > out.deviation) {
      out.deviation = triangulation->Deflection();
      out.deviation_face = static_cast<std::size_t>(f);
    }
    std::vector<std::size_t> ids(static_cast<std::size_t>(triangulation->NbNodes()) + 1);
    for (int i = 1; i <= triangulation->NbNodes(); ++i)
      ids[static_cast<std::size_t>(i)] = welder.id(triangulation->Node(i).Transformed(location.Transformation()));
    const bool reversed = face.Orientation() == TopAbs_REVERSED;  // the triangles follow the surface's normal
    for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
      int a, b, c;
      triangulation->Triangle(t).Get(a, b, c);
      if (reversed) std::swap(b, c);
      const mesh::Triangle tri{ids[static_cast<std::size_t>(a)], ids[static_cast<std::size_t>(b)],
                               ids[static_cast<std::size_t>(c)]};
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
        ++out.dropped;  // collapsed at a degenerate edge (a sphere's pole, a cone's apex)
        continue;
      }
      out.soup.triangles.push_back(tri);
      out.soup.origin.push_back(static_cast<std::size_t>(f));
    }
  }
  for (const gp_Pnt& p : welder.points()) out.soup.points.emplace_back(p.X() / scale, p.Y() / scale, p.Z() / scale);
  return out;
}

std::string face_census(const std::vector<ModelFace>& faces) {
  std::map<std::string, std::size_t> by_type;
  for (const ModelFace& f : faces) ++by_type[f.surface];
  std::string s = std::to_string(faces.size()) + " faces (";
  bool first = true;
  for (const auto& [type, n] : by_type) {
    s += (first ? "" : ", ") + std::to_string(n) + " " + type;
    first = false;
  }
  return s + ")";
}

}  // namespace
}  // namespace cad

Model load_cad(const std::string& path, const LoadOptions& options) {
  check_mesh_method(path, options);
  if (options.deflection && !(*options.deflection > 0 && std::isfinite(*options.deflection)))
    throw ModelError(path + ": the deflection must be a positive length");
  cad::CadSolid solid = cad::read_cad_solid(path, options);
  cad::Tessellation tessellation;
  double deflection = 0;
  try {
    Bnd_Box box;
    BRepBndLib::Add(solid.shape, box);
    if (box.IsVoid()) throw ModelError(path + ": the solid has an empty bounding box");
    const double diagonal_mm = std::sqrt(box.SquareExtent()), scale = solid.millimetres_per_unit;
    deflection = options.deflection.value_or(1e-3 * diagonal_mm / scale);
    tessellation = cad::tessellate(path, solid, deflection * scale);
  } catch (const Standard_Failure& e) {
    throw ModelError(path + ": OpenCASCADE failed: " + (e.GetMessageString() ? e.GetMessageString() : "no message"));
  }
  // The exact field where every face is analytic (method csg, the default);
  // the tessellation's own field otherwise.
  std::string why_not_exact;
  std::optional<cad::ExactCsg> exact;
  if (options.method == "csg")
    exact = cad::exact_csg(solid, mesh::triangle_surface(tessellation.soup), tessellation.soup.origin,
                           std::max(deflection, tessellation.deviation / solid.millimetres_per_unit),
                           options.rfunction.value_or(RSystem::r0()), why_not_exact);
  LoadOptions mesh_options = options;
  mesh_options.repair = false;              // triangle i must stay triangle i: it carries its face
  if (exact) mesh_options.method = "brep";  // its field is replaced; brep is the cheaper to build
  std::vector<std::uint32_t> triangle_faces(tessellation.soup.origin.begin(), tessellation.soup.origin.end());
  Model model;
  try {
    model = mesh::model_from_soup(std::move(tessellation.soup), mesh_options);
  } catch (const ModelError& e) {
    throw ModelError(std::string(e.what()) + " (in the tessellation of the solid: a smaller --deflection may help)");
  }
  model.primitives.clear();  // the faces stand for them (`sage info` lists model.faces)
  model.faces = std::move(tessellation.faces);
  model.triangle_faces = std::move(triangle_faces);
  model.unit = solid.unit;
  model.deflection = std::max(deflection, tessellation.deviation / solid.millimetres_per_unit);

  std::vector<std::string> notes;
  notes.push_back(solid.format + " file read with OpenCASCADE; coordinates in its unit, " + solid.unit);
  for (const std::string& note : solid.notes) notes.push_back(note);
  notes.push_back(cad::face_census(model.faces) + ", numbered from 1 as in OCCT and FreeCAD (sage info lists them)");
  const std::size_t named = static_cast<std::size_t>(
      std::count_if(model.faces.begin(), model.faces.end(), [](const ModelFace& f) { return !f.name.empty(); }));
  if (!solid.face_names.empty())
    notes.push_back("face names: " + std::to_string(named) + " of " + std::to_string(model.faces.size()) +
                    " faces named in the file" +
                    (named < solid.face_names.size() ? " (faces rebuilt by repair or union lost theirs)" : ""));
  const std::size_t coloured = static_cast<std::size_t>(
      std::count_if(model.faces.begin(), model.faces.end(), [](const ModelFace& f) { return !f.colour.empty(); }));
  if (!solid.face_colours.empty())
    notes.push_back("face colours: " + std::to_string(coloured) + " of " + std::to_string(model.faces.size()) +
                    " faces coloured in the file (a query's \"colour #rrggbb\" picks them)");
  std::ostringstream t;
  t << "tessellation (BRepMesh): chordal deflection " << deflection << " " << solid.unit
    << (options.deflection ? " (--deflection)"
                           : " (default: 1e-3 of the bounding box's diagonal; --deflection sets it)")
    << ", angular 20 degrees; " << model.surface->triangles.size() << " triangles; measured deviation at most "
    << tessellation.deviation / solid.millimetres_per_unit << " " << solid.unit << " (face "
    << tessellation.deviation_face << ")";
  if (tessellation.dropped) t << "; " << tessellation.dropped << " triangles collapsed at degenerate edges dropped";
  notes.push_back(t.str());
  if (exact) {
    model.field = exact->field;
    model.field_follows_surface = false;
    for (std::size_t f = 0; f < model.faces.size(); ++f) model.faces[f].exact_surface = exact->face_surfaces[f];
    std::erase_if(model.notes,
                  [](const std::string& n) { return n.rfind("method: ", 0) == 0; });  // the replaced field's
    notes.insert(notes.end(), exact->notes.begin(), exact->notes.end());
    notes.push_back(
        "the field and the solver's cut cells follow the exact faces; the triangles only select faces and "
        "draw them");
  } else {
    if (options.method == "csg") notes.push_back("no exact field: " + why_not_exact);
    notes.push_back(
        "the field and the solver's cut cells follow the triangles: curved faces carry the deviation above");
  }
  model.notes.insert(model.notes.begin(), notes.begin(), notes.end());
  return model;
}

}  // namespace sage::geometry
