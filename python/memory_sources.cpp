// Models from memory rather than files: GeoJSON (a dict or its text),
// shapely-style WKB geometries, and numpy vertex/triangle arrays. Each
// goes through the same reader as a file: GeoJSON and WKB through GDAL's
// in-memory files (/vsimem/), meshes through a temporary OFF file, so the
// validation, projection and messages are the ones of `sage field`.

#include "bindings.hpp"

#include <sage/geometry/model.hpp>

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <pybind11/stl.h>

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>

namespace sage::python {

namespace {

std::string unique_name(const std::string& stem, const std::string& extension) {
  static std::atomic<int> counter{0};
  return stem + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + extension;
}

void register_gdal() {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
}

/// An in-memory file that GDAL reads, removed when it goes.
class MemoryFile {
 public:
  explicit MemoryFile(const std::string& extension) : path_(unique_name("/vsimem/sage_python", extension)) {}
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  ~MemoryFile() { VSIUnlink(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

geometry::LoadOptions options_of(const std::optional<std::string>& crs, const std::string& method, bool repair) {
  if (method != "csg" && method != "brep") throw py::value_error("method must be \"csg\" or \"brep\", not " + method);
  geometry::LoadOptions options;
  options.crs = crs;
  options.method = method;
  options.repair = repair;
  return options;
}

/// load_model, its messages naming `name` in place of the temporary path.
geometry::Model load_named(const std::string& path, const geometry::LoadOptions& options, const std::string& name) {
  try {
    geometry::Model model = geometry::load_model(path, options);
    model.source = name;
    return model;
  } catch (const geometry::ModelError& e) {
    std::string message = e.what();
    for (auto at = message.find(path); at != std::string::npos; at = message.find(path))
      message.replace(at, path.size(), name);
    throw geometry::ModelError(message);
  }
}

}  // namespace

geometry::Model model_from_geojson(const py::object& geojson, const std::optional<std::string>& crs,
                                   const std::string& method, bool repair) {
  const std::string text = py::isinstance<py::str>(geojson)
                               ? geojson.cast<std::string>()
                               : py::module_::import("json").attr("dumps")(geojson).cast<std::string>();
  register_gdal();
  MemoryFile file(".geojson");
  VSILFILE* out = VSIFOpenL(file.path().c_str(), "wb");
  if (!out) throw std::runtime_error("GDAL could not make an in-memory file");
  VSIFWriteL(text.data(), 1, text.size(), out);
  VSIFCloseL(out);
  py::gil_scoped_release unlocked;
  return load_named(file.path(), options_of(crs, method, repair), "GeoJSON from Python");
}

geometry::Model model_from_wkb(const py::bytes& wkb, const std::optional<std::string>& crs, const std::string& method,
                               bool repair) {
  register_gdal();
  const std::string data = wkb;
  OGRGeometry* parsed = nullptr;
  if (OGRGeometryFactory::createFromWkb(data.data(), nullptr, &parsed, data.size()) != OGRERR_NONE || !parsed)
    throw py::value_error("the bytes are not a WKB geometry");
  const std::unique_ptr<OGRGeometry> geometry(parsed);
  // A FlatGeobuf file keeps "no CRS" (GeoJSON would mean WGS84): planar
  // coordinates stay planar unless `crs` says otherwise.
  MemoryFile file(".fgb");
  {
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("FlatGeobuf");
    if (!driver) throw std::runtime_error("this GDAL has no FlatGeobuf driver");
    GDALDatasetUniquePtr dataset(driver->Create(file.path().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference srs;
    if (crs && srs.SetFromUserInput(crs->c_str()) != OGRERR_NONE)
      throw py::value_error("crs " + *crs + ": PROJ does not know this coordinate reference system");
    OGRLayer* layer = dataset
                          ? dataset->CreateLayer("geometry", crs ? &srs : nullptr, geometry->getGeometryType(), nullptr)
                          : nullptr;
    if (!layer) throw std::runtime_error("GDAL could not make an in-memory layer");
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetGeometry(geometry.get());
    if (layer->CreateFeature(&feature) != OGRERR_NONE) throw py::value_error("the geometry cannot be written");
  }
  py::gil_scoped_release unlocked;
  return load_named(file.path(), options_of(std::nullopt, method, repair), "WKB geometry from Python");
}

geometry::Model model_from_mesh(const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                                const py::array_t<long long, py::array::c_style | py::array::forcecast>& triangles,
                                const std::string& method) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3) throw py::value_error("vertices: expected shape (n, 3)");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3) throw py::value_error("triangles: expected shape (m, 3)");
  const std::filesystem::path path = std::filesystem::temp_directory_path() / unique_name("sage_python_mesh", ".off");
  {
    std::ofstream off(path);
    off.precision(17);
    off << "OFF\n" << vertices.shape(0) << " " << triangles.shape(0) << " 0\n";
    const auto v = vertices.unchecked<2>();
    for (py::ssize_t i = 0; i < vertices.shape(0); ++i) off << v(i, 0) << " " << v(i, 1) << " " << v(i, 2) << "\n";
    const auto t = triangles.unchecked<2>();
    for (py::ssize_t i = 0; i < triangles.shape(0); ++i)
      off << "3 " << t(i, 0) << " " << t(i, 1) << " " << t(i, 2) << "\n";
  }
  geometry::Model model;
  try {
    py::gil_scoped_release unlocked;
    model = load_named(path.string(), options_of(std::nullopt, method, false), "mesh from Python");
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
  std::filesystem::remove(path);
  return model;
}

}  // namespace sage::python
