#pragma once
// Model: what every geometry source (JSON CSG model, GIS polygons, closed
// triangle meshes) becomes -- one expression of the field core plus what a
// user should know about how it was made.

#include <sage/expression/expression.hpp>
#include <sage/expression/triangle_surface.hpp>
#include <sage/scalars/rfunction.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage::geometry {

/// Bad input: the message names the file, the place in it (line:column,
/// JSON pointer, feature/ring/vertex, face) and what is wrong.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Bounds {
  std::array<double, 3> min{0, 0, 0};
  std::array<double, 3> max{0, 0, 0};
};

/// One named or unnamed leaf of the model, for summaries.
struct PrimitiveInfo {
  std::string name;     // empty when unnamed
  std::string type;     // "disk", "formula", "edge", "face", ...
  std::string pointer;  // where it came from (JSON pointer, ring/vertex, face)
};

/// A face of a CAD solid, as `sage info` lists it and boundary parts name
/// it. Lengths are in the model's unit; directions are unit vectors.
struct ModelFace {
  std::string surface;  // plane, cylinder, cone, sphere, torus, bspline, bezier, revolution, extrusion, offset, other
  std::string name;     // the file's name for the face, empty when none
  std::string colour;   // the file's colour for the face ("#rrggbb", STEP styles), empty when none
  double area = 0;
  std::array<double, 3> centroid{0, 0, 0};
  std::optional<std::array<double, 3>> normal;  // planes: the outward normal
  std::optional<std::array<double, 3>> axis;    // cylinders, cones, tori: the axis direction
  std::optional<std::array<double, 3>> center;  // a point of the axis; spheres and tori: the centre
  std::optional<double> radius;                 // cylinders, spheres, tori (major); cones: at `center`
  std::optional<double> minor_radius;           // tori
  std::optional<double> half_angle;             // cones, in degrees
  /// Exact models: the face's surface as a normalized field, zero on it.
  std::optional<Expr> exact_surface;
};

struct Model {
  std::string source;  // file name, for messages
  std::string name;
  int dimension = 2;
  RSystem rfunction = RSystem::r0();  // default for operators without their own
  std::optional<Bounds> bounds;
  /// GIS: the projected coordinate reference system the field is built in,
  /// as WKT2 (the local projection sage chose, or the data's own), for
  /// writers of georeferenced rasters. Empty when unknown: JSON models,
  /// meshes and GIS data without a coordinate system.
  std::string crs_wkt;
  Expr field;
  std::map<std::string, Expr> named;  // named nodes, by name
  std::vector<PrimitiveInfo> primitives;
  /// Meshes: the validated, outward-oriented triangles (the solver
  /// integrates cut cells from them instead of from the field, when
  /// `field_follows_surface`). CAD solids: their tessellation.
  std::shared_ptr<const TriangleSurface> surface;
  /// False when the field is exact and `surface` only approximates its
  /// zero set (CAD solids of analytic faces): cut cells then follow the
  /// field, and the triangles serve face selectors and pictures.
  bool field_follows_surface = true;
  /// CAD solids: faces 1..N (faces[i] is face i + 1, numbered as OCCT's
  /// TopExp::MapShapes and FreeCAD's FaceN), and the face each of the
  /// surface's triangles belongs to.
  std::vector<ModelFace> faces;
  std::vector<std::uint32_t> triangle_faces;
  /// CAD solids: the length unit of the coordinates ("millimetre", ...),
  /// and how far the tessellation may lie from the exact faces.
  std::string unit;
  double deflection = 0;
  /// Facts for `sage info` and the field summary: projection used,
  /// validation findings and repairs, well-formedness certificate, ...
  std::vector<std::string> notes;
  /// What the user should check before trusting the field (printed by the
  /// command line as warnings): coordinates that look like degrees but come
  /// without a coordinate reference system, say.
  std::vector<std::string> warnings;
};

/// Options shared by every geometry source; each reads what applies to it.
struct LoadOptions {
  /// Replaces the default R-function system.
  std::optional<RSystem> rfunction;
  /// Polygons and meshes: "csg" (well-formed CSG) or "brep" (trimmed
  /// edges/faces glued by R-conjunction, signed by point membership).
  std::string method = "csg";
  /// B-rep fields: orthogonalize the trimming at non-orthogonal meetings.
  bool orthogonalize = false;
  /// Fix what can be fixed safely (orientation is always fixed).
  bool repair = false;
  /// GIS: features to use, by index (empty: all), and an OGR attribute
  /// filter such as "NAME = 'Wisconsin'". Selected features are united.
  std::vector<long long> features;
  std::optional<std::string> where;
  std::optional<std::string> layer;
  /// GIS: the coordinate reference system of the data (EPSG:XXXX, a PROJ
  /// string or WKT), in place of the file's own or for files without one.
  std::optional<std::string> crs;
  /// Polygons (CSG): certify well-formedness by interval arithmetic
  /// (well_formedness.hpp) and add the result to the notes.
  bool certify = false;
  /// Meshes (CSG): deepest level of the convex deficiency decomposition
  /// before it is reported as not terminating.
  int csg_depth_limit = 64;
  /// CAD files: the solid to use (numbered from 1; default: all, united).
  std::optional<int> solid;
  /// CAD files: the tessellation's chordal deflection, in the model's unit
  /// (default: 1e-3 of the bounding box's diagonal).
  std::optional<double> deflection;
};

/// The path's extension in lower case (".step"), "" when it has none: what
/// the readers are picked by.
std::string lowercase_extension(const std::string& path);

/// Reads any geometry source sage knows, picked by extension (.json model
/// files; .geojson, .shp, .gpkg and other OGR formats; .off, .stl, .obj,
/// .ply meshes; .step, .stp, .iges, .igs, .brep CAD solids). A .json file
/// holding GeoJSON is read as GIS data.
/// Throws ModelError.
Model load_model(const std::string& path, const LoadOptions& options = {});

}  // namespace sage::geometry
