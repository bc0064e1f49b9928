#include <sage/output/output_file.hpp>
#include <sage/output/point_layer.hpp>
#include <sage/output/vtk_writer.hpp>

#include "gdal_support.hpp"

#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>

namespace sage::output {

namespace {

struct Format {
  const char* extension;
  const char* driver;
};
constexpr Format kFormats[] = {{".csv", "CSV"},   {".geojson", "GeoJSON"},    {".json", "GeoJSON"},
                               {".gpkg", "GPKG"}, {".shp", "ESRI Shapefile"}, {".fgb", "FlatGeobuf"}};

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

bool is_csv(const std::string& path) { return lower(path).ends_with(".csv"); }

/// The dataset, CSV files with their coordinate columns found by name.
GDALDatasetUniquePtr open_points(const std::string& path) {
  register_gdal();
  const char* const csv_options[] = {"X_POSSIBLE_NAMES=x,lon,long,longitude,easting",
                                     "Y_POSSIBLE_NAMES=y,lat,latitude,northing",
                                     "Z_POSSIBLE_NAMES=z,elevation,height",
                                     "KEEP_GEOM_COLUMNS=YES",
                                     "AUTODETECT_TYPE=YES",
                                     nullptr};
  GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr,
                                                 is_csv(path) ? csv_options : nullptr, nullptr));
  if (!dataset) throw OutputError(path + ": GDAL cannot read it as vector data: " + gdal_message());
  return dataset;
}

OGRLayer& layer_of(GDALDataset& dataset, const std::string& path, const PointLayerOptions& options) {
  if (dataset.GetLayerCount() == 0) throw OutputError(path + ": no layers");
  OGRLayer* layer = options.layer ? dataset.GetLayerByName(options.layer->c_str()) : dataset.GetLayer(0);
  if (!layer) throw OutputError(path + ": no layer named \"" + *options.layer + "\"");
  return *layer;
}

/// --points-crs, or the layer's own, or none.
const OGRSpatialReference* points_crs(const std::string& path, OGRLayer& layer, const PointLayerOptions& options,
                                      OGRSpatialReference& given) {
  if (!options.crs) return layer.GetSpatialRef();
  if (given.SetFromUserInput(options.crs->c_str()) != OGRERR_NONE)
    throw OutputError(path + ": --points-crs " + *options.crs +
                      ": PROJ does not know this coordinate reference system (" + gdal_message() +
                      "); give it as EPSG:XXXX, a PROJ string or WKT");
  return &given;
}

std::string name_of(const OGRSpatialReference& srs) { return srs.GetName() ? srs.GetName() : "unnamed CRS"; }

const Format* format_of(const std::string& path) {
  for (const Format& f : kFormats)
    if (lower(path).ends_with(f.extension)) return &f;
  return nullptr;
}

}  // namespace

std::string point_layer_formats() {
  std::string list;
  for (const Format& f : kFormats) list += (list.empty() ? "" : ", ") + std::string(f.extension);
  return list;
}

PointLayer read_point_layer(const std::string& path, const std::string& plane_wkt, const PointLayerOptions& options) {
  const CPLErrorHandlerPusher quiet(CPLQuietErrorHandler);
  GDALDatasetUniquePtr dataset = open_points(path);
  OGRLayer& layer = layer_of(*dataset, path, options);
  PointLayer out;
  out.has_z = true;
  long long index = 0;
  layer.ResetReading();
  for (auto& feature : layer) {
    const std::string where = path + ": feature " + std::to_string(index++);
    const OGRGeometry* g = feature->GetGeometryRef();
    if (!g || g->IsEmpty())
      throw OutputError(where + " has no point" +
                        (is_csv(path) ? " (a CSV needs columns x and y, or lon and lat, and z for 3D)" : ""));
    if (wkbFlatten(g->getGeometryType()) != wkbPoint)
      throw OutputError(where + " is a " + OGRGeometryTypeToName(wkbFlatten(g->getGeometryType())) +
                        ": sage sample reads points");
    const OGRPoint* p = g->toPoint();
    out.has_z = out.has_z && p->Is3D();
    out.points.push_back({p->getX(), p->getY(), p->Is3D() ? p->getZ() : 0.0});
  }
  if (out.points.empty()) throw OutputError(path + ": no points");

  OGRSpatialReference given;
  const OGRSpatialReference* source = points_crs(path, layer, options, given);
  if (plane_wkt.empty()) {
    out.coordinates = "used as they are (the model has no coordinate reference system)";
    if (source && source->IsGeographic())
      out.warnings.push_back(path + ": the points are longitude/latitude (" + name_of(*source) +
                             "), but the model has no coordinate reference system to project them into");
    return out;
  }
  if (!source) {
    out.coordinates = "no coordinate reference system: used as coordinates of the model's plane";
    const bool degrees = std::all_of(out.points.begin(), out.points.end(), [](const std::array<double, 3>& p) {
      return std::abs(p[0]) <= 180.0 && std::abs(p[1]) <= 90.0;
    });
    if (degrees)
      out.warnings.push_back(path +
                             ": no coordinate reference system, and every coordinate lies within longitude/latitude "
                             "ranges: if they are degrees, give --points-crs EPSG:4326");
    return out;
  }
  std::unique_ptr<OGRSpatialReference> from(source->Clone());
  OGRSpatialReference plane;
  if (plane.importFromWkt(plane_wkt.c_str()) != OGRERR_NONE)
    throw OutputError(path + ": the model's coordinate reference system cannot be read: " + gdal_message());
  from->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  plane.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> transform(OGRCreateCoordinateTransformation(from.get(), &plane));
  if (!transform) throw OutputError(path + ": cannot transform the points: " + gdal_message());
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    double x = out.points[i][0], y = out.points[i][1];
    if (!transform->Transform(1, &x, &y))
      throw OutputError(path + ": feature " + std::to_string(i) + ": the transformation failed: " + gdal_message());
    out.points[i][0] = x;
    out.points[i][1] = y;
  }
  out.coordinates = name_of(*source) + " transformed into the model's plane (" + name_of(plane) + ")";
  return out;
}

void write_point_layer(const std::string& input, const PointLayerOptions& options, const std::string& output,
                       const std::vector<PointArray>& arrays) {
  const Format* format = format_of(output);
  if (!format) throw OutputError(output + ": sage writes points as " + point_layer_formats());
  std::error_code ignored;
  if (std::filesystem::equivalent(input, output, ignored))
    throw OutputError(output + ": is the points file itself; write the samples to another file");
  check_writable(output);
  const CPLErrorHandlerPusher quiet(CPLQuietErrorHandler);
  CPLErrorReset();
  GDALDatasetUniquePtr dataset = open_points(input);
  OGRLayer& in = layer_of(*dataset, input, options);
  OGRFeatureDefn* in_fields = in.GetLayerDefn();
  for (const PointArray& a : arrays)
    if (in_fields->GetFieldIndex(a.name.c_str()) >= 0)
      throw OutputError(input + ": the points already have an attribute named " + a.name);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(format->driver);
  if (!driver) throw OutputError(output + ": this GDAL has no " + format->driver + " driver");

  OGRSpatialReference given;
  const OGRSpatialReference* crs = points_crs(input, in, options, given);
  std::vector<const char*> layer_options;
  const bool three_d = wkbHasZ(in.GetGeomType()) != 0;
  if (std::string(format->driver) == "CSV" && !is_csv(input))
    layer_options.push_back(three_d ? "GEOMETRY=AS_XYZ" : "GEOMETRY=AS_XY");
  layer_options.push_back(nullptr);
  if (std::filesystem::exists(output)) driver->Delete(output.c_str());  // all of a Shapefile's files
  GDALDatasetUniquePtr file(driver->Create(output.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!file) throw OutputError(output + ": GDAL could not create it: " + gdal_message());
  // GDAL 3.6 takes the CRS as non-const; it clones it.
  OGRLayer* out = file->CreateLayer(in.GetName(), const_cast<OGRSpatialReference*>(crs), in.GetGeomType(),
                                    const_cast<char**>(layer_options.data()));
  if (!out) throw OutputError(output + ": GDAL could not create the layer: " + gdal_message());
  const int kept = in_fields->GetFieldCount();
  for (int f = 0; f < kept; ++f)
    if (out->CreateField(in_fields->GetFieldDefn(f)) != OGRERR_NONE)
      throw OutputError(output + ": cannot add the attribute " + in_fields->GetFieldDefn(f)->GetNameRef() + ": " +
                        gdal_message());
  for (const PointArray& a : arrays) {
    OGRFieldDefn field(a.name.c_str(), OFTReal);
    if (out->CreateField(&field) != OGRERR_NONE)
      throw OutputError(output + ": cannot add the attribute " + a.name + ": " + gdal_message());
  }
  std::vector<int> same(static_cast<std::size_t>(kept));
  for (int f = 0; f < kept; ++f) same[static_cast<std::size_t>(f)] = f;
  file->StartTransaction();
  std::size_t index = 0;
  in.ResetReading();
  for (auto& feature : in) {
    OGRFeature copy(out->GetLayerDefn());
    if (copy.SetFrom(feature.get(), same.data(), TRUE) != OGRERR_NONE)
      throw OutputError(output + ": feature " + std::to_string(index) + " cannot be copied: " + gdal_message());
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      if (index >= arrays[a].values.size())
        throw OutputError(input + ": more points than samples (was the file changed meanwhile?)");
      copy.SetField(kept + static_cast<int>(a), arrays[a].values[index]);
    }
    if (out->CreateFeature(&copy) != OGRERR_NONE)
      throw OutputError(output + ": feature " + std::to_string(index) + " cannot be written: " + gdal_message());
    ++index;
  }
  file->CommitTransaction();
  file.reset();  // closed and flushed
  if (CPLGetLastErrorType() >= CE_Failure) throw OutputError(output + ": GDAL could not write it: " + gdal_message());
}

}  // namespace sage::output
