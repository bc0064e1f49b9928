#include <sage/output/geotiff_writer.hpp>
#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include "gdal_support.hpp"
#include "provenance.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <limits>
#include <memory>

namespace sage::output {

namespace {

/// One band: its values are values[i * stride] for grid point i.
struct Band {
  std::string name;
  const double* values;
  std::size_t stride;
};

std::vector<Band> bands_of(const FieldSamples& s) {
  std::vector<Band> bands{{"omega", s.omega.data(), 1}};
  if (s.gradient.empty()) return bands;  // order 0: values only
  bands.push_back({"grad_omega_x", s.gradient.data(), 3});
  bands.push_back({"grad_omega_y", s.gradient.data() + 1, 3});
  bands.push_back({"grad_norm", s.gradient_norm.data(), 1});
  for (const DerivativeArray& d : s.higher)
    for (std::size_t c = 0; c < d.components.size(); ++c)
      bands.push_back(
          {"d" + std::to_string(d.order) + "_omega_" + d.components[c], d.values.data() + c, d.components.size()});
  return bands;
}

GDALDriver* driver(const char* name, const std::string& path) {
  GDALDriver* d = GetGDALDriverManager()->GetDriverByName(name);
  if (!d) throw OutputError(path + ": this GDAL has no " + name + " driver");
  return d;
}

/// The samples in memory as GDAL's raster: pixels centred on the grid
/// points, north-up, non-finite values as NaN nodata.
GDALDatasetUniquePtr memory_raster(const std::string& path, const FieldSamples& s, const GeoTiffOptions& options) {
  const Grid& g = s.grid;
  const int nx = g.points[0], ny = g.points[1];
  const std::vector<Band> bands = bands_of(s);
  GDALDatasetUniquePtr raster(
      driver("MEM", path)
          ->Create("", nx, ny, static_cast<int>(bands.size()), options.float64 ? GDT_Float64 : GDT_Float32, nullptr));
  if (!raster) throw OutputError(path + ": GDAL cannot hold the raster: " + gdal_message());
  const double dx = g.spacing(0), dy = g.spacing(1);
  const double top = g.point(g.size() - 1)[1];  // the last row's y, as sampled
  double transform[6] = {g.lo[0] - 0.5 * dx, dx, 0.0, top + 0.5 * dy, 0.0, -dy};
  raster->SetGeoTransform(transform);
  if (!options.crs_wkt.empty()) {
    OGRSpatialReference srs;
    if (srs.importFromWkt(options.crs_wkt.c_str()) != OGRERR_NONE || raster->SetSpatialRef(&srs) != CE_None)
      throw OutputError(path + ": GDAL does not take the coordinate reference system: " + gdal_message());
  }
  raster->SetMetadataItem("evaluation", evaluation_text(s).c_str());
  raster->SetMetadataItem("far_field_tolerance", CPLSPrintf("%.17g", s.far_field_tolerance));

  const double nodata = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> row(static_cast<std::size_t>(nx));
  for (std::size_t b = 0; b < bands.size(); ++b) {
    GDALRasterBand* band = raster->GetRasterBand(static_cast<int>(b) + 1);
    band->SetDescription(bands[b].name.c_str());
    band->SetNoDataValue(nodata);
    for (int r = 0; r < ny; ++r) {
      const std::size_t first = static_cast<std::size_t>(ny - 1 - r) * static_cast<std::size_t>(nx);  // north-up
      for (std::size_t i = 0; i < row.size(); ++i) {
        const double v = bands[b].values[(first + i) * bands[b].stride];
        row[i] = std::isfinite(v) ? v : nodata;
      }
      if (band->RasterIO(GF_Write, 0, r, nx, 1, row.data(), nx, 1, GDT_Float64, 0, 0, nullptr) != CE_None)
        throw OutputError(path + ": GDAL cannot fill the raster: " + gdal_message());
    }
  }
  return raster;
}

/// `source` warped into the CRS `wkt` (bilinear; GDAL picks the pixel
/// size). GDALWarp carries a single source's band descriptions, nodata
/// and metadata over (the tests check it).
GDALDatasetUniquePtr warped(const std::string& path, GDALDataset& source, const std::string& wkt) {
  CPLStringList arguments;
  for (const char* argument : {"-t_srs", wkt.c_str(), "-r", "bilinear", "-of", "MEM"}) arguments.AddString(argument);
  std::unique_ptr<GDALWarpAppOptions, decltype(&GDALWarpAppOptionsFree)> warp(
      GDALWarpAppOptionsNew(arguments.List(), nullptr), GDALWarpAppOptionsFree);
  GDALDatasetH handle = GDALDataset::ToHandle(&source);
  GDALDatasetUniquePtr out(GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &handle, warp.get(), nullptr)));
  if (!warp || !out) throw OutputError(path + ": GDAL could not warp the raster: " + gdal_message());
  return out;
}

}  // namespace

bool is_geotiff_path(const std::string& path) { return path.ends_with(".tif") || path.ends_with(".tiff"); }

std::vector<std::string> geotiff_band_names(const FieldSamples& samples) {
  std::vector<std::string> names;
  for (const Band& b : bands_of(samples)) names.push_back(b.name);
  return names;
}

std::string crs_wkt_from(const std::string& text) {
  const CPLErrorHandlerPusher quiet(CPLQuietErrorHandler);
  OGRSpatialReference srs;
  char* wkt = nullptr;
  const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
  if (srs.SetFromUserInput(text.c_str()) != OGRERR_NONE || srs.exportToWkt(&wkt, options) != OGRERR_NONE) {
    CPLFree(wkt);
    throw OutputError(text + ": PROJ does not know this coordinate reference system (" + gdal_message() + ")");
  }
  std::string out = wkt;
  CPLFree(wkt);
  return out;
}

std::string crs_name(const std::string& wkt) {
  OGRSpatialReference srs;
  if (wkt.empty() || srs.importFromWkt(wkt.c_str()) != OGRERR_NONE || !srs.GetName()) return "";
  return srs.GetName();
}

void write_geotiff(const std::string& path, const FieldSamples& samples, const GeoTiffOptions& options) {
  if (samples.grid.dimension != 2) throw OutputError(path + ": a GeoTIFF holds 2D fields only (use .vti for 3D)");
  register_gdal();
  const CPLErrorHandlerPusher quiet(CPLQuietErrorHandler);
  CPLErrorReset();
  if (!options.warp_to_wkt.empty() && options.crs_wkt.empty())
    throw OutputError(path + ": the field has no coordinate reference system to warp from");
  GDALDatasetUniquePtr raster = memory_raster(path, samples, options);
  if (!options.warp_to_wkt.empty()) raster = warped(path, *raster, options.warp_to_wkt);
  // COG: tiles, DEFLATE with the floating-point predictor (smaller for
  // smooth fields) at level 1 (a 1000 x 1000 field of four bands in 0.21 s
  // against level 6's 0.29 s, 2% larger), overviews for QGIS's zoomed-out
  // views.
  const char* const cog_options[] = {"COMPRESS=DEFLATE", "LEVEL=1", "PREDICTOR=YES", "NUM_THREADS=ALL_CPUS", nullptr};
  write_atomically(path, [&](const std::string& temporary) {
    GDALDatasetUniquePtr file(
        driver("COG", path)
            ->CreateCopy(temporary.c_str(), raster.get(), FALSE, const_cast<char**>(cog_options), nullptr, nullptr));
    if (!file) throw OutputError(path + ": GDAL could not write the GeoTIFF: " + gdal_message());
    file.reset();  // closed (and flushed) before the rename
    if (CPLGetLastErrorType() >= CE_Failure)
      throw OutputError(path + ": GDAL could not write the GeoTIFF: " + gdal_message());
  });
}

}  // namespace sage::output
