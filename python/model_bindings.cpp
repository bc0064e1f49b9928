// sage.load() and sage.Model: a model's field at numpy points (exactly, the
// batch evaluator on all cores) and on grids (sage field's sampling plan:
// far-field patches where they pay, stated in "evaluation").

#include "bindings.hpp"

#include <sage/geometry/model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/tape.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <utility>

namespace sage::python {

namespace {

/// The samples as a dict of arrays: each point's numbers at `shape`.
py::dict dict_of(const FieldSamples& s, int dimension, const std::vector<py::ssize_t>& shape) {
  py::dict out;
  out["omega"] = array_of(shape, s.omega.data());
  if (s.gradient.empty()) return out;
  const std::size_t n = s.omega.size(), d = static_cast<std::size_t>(dimension);
  std::vector<double> gradient(n * d);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t a = 0; a < d; ++a) gradient[p * d + a] = s.gradient[3 * p + a];
  std::vector<py::ssize_t> vector_shape = shape;
  vector_shape.push_back(dimension);
  out["grad"] = array_of(vector_shape, gradient.data());
  out["grad_norm"] = array_of(shape, s.gradient_norm.data());
  std::vector<double> partial(n);
  for (const DerivativeArray& h : s.higher) {
    const std::size_t m = h.components.size();
    for (std::size_t c = 0; c < m; ++c) {
      for (std::size_t p = 0; p < n; ++p) partial[p] = h.values[p * m + c];
      out[py::str("d" + std::to_string(h.order) + "_" + h.components[c])] = array_of(shape, partial.data());
    }
  }
  return out;
}

PyModel wrap(geometry::Model model) {
  PyModel m;
  m.tape = std::make_shared<const Tape>(model.field, model.dimension);
  m.model = std::move(model);
  return m;
}

void check_order(int order) {
  if (order < 0 || order > kMaxSampleOrder)
    throw py::value_error("order must be from 0 to " + std::to_string(kMaxSampleOrder));
}

PyModel load(const std::string& path, const std::optional<std::string>& rfunction, const std::string& method,
             const std::optional<std::string>& crs, const std::optional<std::string>& layer,
             const std::optional<std::string>& where, const std::vector<long long>& features, bool repair,
             const std::optional<int>& solid, const std::optional<double>& deflection) {
  geometry::LoadOptions options;
  if (rfunction) options.rfunction = RSystem::parse(*rfunction);
  if (method != "csg" && method != "brep") throw py::value_error("method must be \"csg\" or \"brep\", not " + method);
  options.method = method;
  options.crs = crs;
  options.layer = layer;
  options.where = where;
  options.features = features;
  options.repair = repair;
  if (solid && *solid < 1) throw py::value_error("solid numbers solids from 1");
  if (deflection && !(*deflection > 0 && std::isfinite(*deflection)))
    throw py::value_error("deflection must be a positive length");
  options.solid = solid;
  options.deflection = deflection;
  py::gil_scoped_release unlocked;
  return wrap(geometry::load_model(path, options));
}

py::dict evaluate(const PyModel& self, const py::array_t<double, py::array::c_style | py::array::forcecast>& points,
                  int order, bool exact) {
  check_order(order);
  const std::vector<std::array<double, 3>> at = points_of(points, self.model.dimension, "points");
  const SamplingPlan plan =
      plan_points(*self.tape, at, order, exact ? std::optional<double>(0.0) : std::optional<double>());
  FieldSamples s;
  {
    py::gil_scoped_release unlocked;
    s = sample_points(*self.tape, at, order, &plan.approximation);
  }
  py::dict out = dict_of(s, self.model.dimension, {static_cast<py::ssize_t>(at.size())});
  out["evaluation"] = plan.description;
  return out;
}

/// The grid sample() samples: bounds given or the model's, a count per
/// axis (default 200 x 200 or 64^3) or a spacing.
Grid grid_of(const PyModel& self, const std::optional<std::vector<int>>& counts, std::optional<double> resolution,
             const std::optional<std::vector<double>>& bounds) {
  const int d = self.model.dimension;
  Grid grid;
  grid.dimension = d;
  if (bounds) {
    if (static_cast<int>(bounds->size()) != 2 * d)
      throw py::value_error("bounds: expected " + std::to_string(2 * d) + " numbers (xmin, xmax, ymin, ymax" +
                            (d == 3 ? ", zmin, zmax)" : ")"));
    for (int a = 0; a < d; ++a) {
      grid.lo[a] = (*bounds)[2 * a];
      grid.hi[a] = (*bounds)[2 * a + 1];
      if (!(grid.lo[a] < grid.hi[a])) throw py::value_error("bounds: each minimum must be below its maximum");
    }
  } else if (self.model.bounds) {
    grid.lo = self.model.bounds->min;
    grid.hi = self.model.bounds->max;
  } else {
    throw py::value_error(self.model.source + " has no bounds: give bounds=(xmin, xmax, ymin, ymax" +
                          (d == 3 ? ", zmin, zmax)" : ")"));
  }
  if (counts && resolution) throw py::value_error("give grid or resolution, not both");
  grid.points = counts ? Grid::checked_points({counts->begin(), counts->end()}, d, "grid") : Grid::default_points(d);
  if (resolution) grid.space_points(*resolution);  // std::invalid_argument: ValueError
  if (d == 2) grid.lo[2] = grid.hi[2] = 0.0;
  return grid;
}

py::dict sample(const PyModel& self, const std::optional<std::vector<int>>& counts, std::optional<double> resolution,
                const std::optional<std::vector<double>>& bounds, int order, bool exact) {
  check_order(order);
  const Grid grid = grid_of(self, counts, resolution, bounds);
  const int d = self.model.dimension;
  const SamplingPlan plan =
      plan_sampling(*self.tape, grid, order, exact ? std::optional<double>(0.0) : std::optional<double>());
  FieldSamples s;
  {
    py::gil_scoped_release unlocked;
    s = sample_field(*self.tape, grid, order, {}, &plan.approximation);
  }
  py::dict out = dict_of(s, d, grid_shape(grid));
  add_axes(out, grid);
  if (d == 2) {
    const double dx = grid.spacing(0), dy = grid.spacing(1);
    out["geotransform"] = py::make_tuple(grid.lo[0] - 0.5 * dx, dx, 0.0, grid.lo[1] - 0.5 * dy, 0.0, dy);
  }
  out["crs"] = self.model.crs_wkt;
  out["evaluation"] =
      s.far_faces_rejected ? std::string("exact (far faces in single precision deviated too much)") : plan.description;
  return out;
}

py::list faces_of(const PyModel& self) {
  py::list out;
  for (std::size_t i = 0; i < self.model.faces.size(); ++i) {
    const geometry::ModelFace& f = self.model.faces[i];
    py::dict d;
    d["number"] = i + 1;
    d["surface"] = f.surface;
    d["name"] = f.name;
    d["colour"] = f.colour;
    d["area"] = f.area;
    d["centroid"] = py::make_tuple(f.centroid[0], f.centroid[1], f.centroid[2]);
    for (const auto& [key, v] : {std::pair{"normal", &f.normal}, {"axis", &f.axis}, {"center", &f.center}})
      if (*v) d[key] = py::make_tuple((**v)[0], (**v)[1], (**v)[2]);
    for (const auto& [key, v] :
         {std::pair{"radius", &f.radius}, {"minor_radius", &f.minor_radius}, {"half_angle", &f.half_angle}})
      if (*v) d[key] = **v;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_models(py::module_& m) {
  py::class_<PyModel>(m, "Model",
                      "A model's normalized field omega: >= 0 inside, 0 on the boundary, < 0 outside, in the plane\n"
                      "(or space) of the model's coordinates; GIS data in longitude/latitude is projected to metres\n"
                      "(crs_wkt says how). Made by sage.load().")
      .def_property_readonly("dimension", [](const PyModel& p) { return p.model.dimension; })
      .def_property_readonly("name", [](const PyModel& p) { return p.model.name; })
      .def_property_readonly("source", [](const PyModel& p) { return p.model.source; })
      .def_property_readonly(
          "crs_wkt", [](const PyModel& p) { return p.model.crs_wkt; },
          "the coordinate reference system of the field's plane, as WKT ('' when none)")
      .def_property_readonly("notes", [](const PyModel& p) { return p.model.notes; })
      .def_property_readonly("warnings", [](const PyModel& p) { return p.model.warnings; })
      .def_property_readonly(
          "faces", &faces_of,
          "CAD solids: the faces, numbered from 1 (face 1 is faces[0]), as dicts with 'number',\n"
          "'surface' (plane, cylinder, ...), 'name' and 'colour' (the file's, or ''), 'area', 'centroid' and,\n"
          "where the surface has them, 'normal', 'axis', 'center', 'radius', 'minor_radius',\n"
          "'half_angle' (degrees); [] for other models")
      .def_property_readonly(
          "unit", [](const PyModel& p) { return p.model.unit; },
          "CAD solids: the length unit of the coordinates ('millimetre', ...); '' otherwise")
      .def_property_readonly(
          "bounds",
          [](const PyModel& p) -> py::object {
            if (!p.model.bounds) return py::none();
            const int d = p.model.dimension;
            py::list lo, hi;
            for (int a = 0; a < d; ++a) {
              lo.append(p.model.bounds->min[a]);
              hi.append(p.model.bounds->max[a]);
            }
            return py::make_tuple(py::tuple(lo), py::tuple(hi));
          },
          "((xmin, ymin[, zmin]), (xmax, ymax[, zmax])), or None")
      .def("evaluate", &evaluate, py::arg("points"), py::arg("order") = 1, py::kw_only(), py::arg("exact") = false,
           "evaluate(points, order=1, *, exact=False) -> dict\n\n"
           "omega and its derivatives at points, an (n, dimension) array in the model's coordinates, on\n"
           "all cores, as `sage sample` evaluates them (groups of nearby points run the field pruned to\n"
           "their box; far-field patches where they pay, within 1e-10 of the points' bounding box's\n"
           "diagonal, unless exact=True): 'omega' (n,), and for order >= 1 'grad' (n, dimension) and\n"
           "'grad_norm' (n,), for order k >= 2 each partial 'd<k>_<xy..>' (n,), e.g. 'd2_xy';\n"
           "'evaluation' says how.")
      .def("sample", &sample, py::kw_only(), py::arg("grid") = py::none(), py::arg("resolution") = py::none(),
           py::arg("bounds") = py::none(), py::arg("order") = 1, py::arg("exact") = false,
           "sample(*, grid=None, resolution=None, bounds=None, order=1, exact=False) -> dict\n\n"
           "omega and its derivatives on a regular grid, as `sage field` samples it: grid=(nx, ny[, nz])\n"
           "points per axis (default 200 x 200 or 64^3) or resolution=R (points R apart, the model's\n"
           "units), over bounds=(xmin, xmax, ymin, ymax[, zmin, zmax]) or the model's bounds. Arrays\n"
           "have shape (ny, nx) or (nz, ny, nx), row 0 at the smallest y; 'x', 'y' ('z') are the axes;\n"
           "2D: 'geotransform' (GDAL's, for these rows: np.flipud for north-up) and 'crs' (WKT).\n"
           "'evaluation' says how the field was evaluated (exact=True forbids approximation).")
      .def("__repr__", [](const PyModel& p) {
        return "<sage.Model " + std::to_string(p.model.dimension) + "D '" +
               (p.model.name.empty() ? p.model.source : p.model.name) + "'>";
      });
  m.def("load", &load, py::arg("path"), py::kw_only(), py::arg("rfunction") = py::none(), py::arg("method") = "csg",
        py::arg("crs") = py::none(), py::arg("layer") = py::none(), py::arg("where") = py::none(),
        py::arg("features") = std::vector<long long>{}, py::arg("repair") = false, py::arg("solid") = py::none(),
        py::arg("deflection") = py::none(),
        "load(path, *, rfunction=None, method='csg', crs=None, layer=None, where=None, features=[],\n"
        "     repair=False, solid=None, deflection=None) -> Model\n\n"
        "Reads a model as `sage field` does: a JSON model, GIS polygons (any vector format GDAL reads;\n"
        "layer, where='NAME = ...', features=[0, 2], crs='EPSG:4326' for data without one, repair), a\n"
        "closed triangle mesh (.off, .stl, .obj, .ply), or a CAD solid (.step, .stp, .iges, .igs, .brep;\n"
        "solid=N picks one, deflection sets the tessellation's; Model.faces lists the faces).\n"
        "rfunction: 'r0', 'rp:4', 'ralpha:0.5', 'minmax'... method: 'csg' (well-formed CSG) or 'brep'\n"
        "(trimmed edges/faces). Raises ModelError.");
  m.def(
      "from_geojson",
      [](const py::object& geojson, const std::optional<std::string>& crs, const std::string& method, bool repair) {
        return wrap(model_from_geojson(geojson, crs, method, repair));
      },
      py::arg("geojson"), py::kw_only(), py::arg("crs") = py::none(), py::arg("method") = "csg",
      py::arg("repair") = false,
      "from_geojson(geojson, *, crs=None, method='csg', repair=False) -> Model\n\n"
      "Polygons from GeoJSON: a dict (a FeatureCollection, Feature or geometry, as json.load gives\n"
      "it, or __geo_interface__) or its text. Longitude/latitude (RFC 7946) unless crs says otherwise.");
  m.def(
      "from_wkb",
      [](const py::bytes& wkb, const std::optional<std::string>& crs, const std::string& method, bool repair) {
        return wrap(model_from_wkb(wkb, crs, method, repair));
      },
      py::arg("wkb"), py::kw_only(), py::arg("crs") = py::none(), py::arg("method") = "csg", py::arg("repair") = false,
      "from_wkb(wkb, *, crs=None, method='csg', repair=False) -> Model\n\n"
      "A Polygon or MultiPolygon as WKB bytes (shapely's geometry.wkb; geopandas: gdf.union_all().wkb\n"
      "with crs=gdf.crs.to_wkt()). Planar coordinates unless crs is given.");
  m.def(
      "from_mesh",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
         const py::array_t<long long, py::array::c_style | py::array::forcecast>& triangles,
         const std::string& method) { return wrap(model_from_mesh(vertices, triangles, method)); },
      py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("method") = "csg",
      "from_mesh(vertices, triangles, *, method='csg') -> Model\n\n"
      "A closed triangle mesh from an (n, 3) float array of vertices and an (m, 3) integer array of\n"
      "triangles (0-based, outward or consistently oriented), validated as a mesh file would be.");
}

}  // namespace sage::python
