#include <sage/output/geotiff_writer.hpp>
#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include "gdal_support.hpp"
#include "provenance.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
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
    for (std::size_t c = 0; c < d.components.size(); ++c) {
      std::string name = "d";  // appended piece by piece: GCC 12 warns falsely on "d" + std::string
      name += std::to_string(d.order);
      name += "_omega_";
      name += d.components[c];
      bands.push_back({name, d.values.data() + c, d.components.size()});
    }
  return bands;
}

GDALDriver* driver(const char* name, const std::string& path) {
  GDALDriver* d = GetGDALDriverManager()->GetDriverByName(name);
  if (!d) throw OutputError(path + ": this GDAL has no " + name + " driver");
  return d;
}

/// A raster in memory: GDAL's MEM dataset over pixels that sage owns.
struct MemoryRaster {
  std::vector<std::byte> pixels;  // band after band, row after row from the top
  GDALDatasetUniquePtr dataset;
};

/// Band `b`'s pixels, north-up, non-finite values as NaN, converted to
/// `Pixel` row by row on all cores.
template <typename Pixel>
void fill_band(Pixel* out, const Band& band, int nx, int ny) {
#pragma omp parallel for schedule(static)
  for (int r = 0; r < ny; ++r) {
    const std::size_t first = static_cast<std::size_t>(ny - 1 - r) * static_cast<std::size_t>(nx);  // north-up
    Pixel* row = out + static_cast<std::size_t>(r) * static_cast<std::size_t>(nx);
    for (int i = 0; i < nx; ++i) {
      const double v = band.values[(first + static_cast<std::size_t>(i)) * band.stride];
      row[i] = std::isfinite(v) ? static_cast<Pixel>(v) : std::numeric_limits<Pixel>::quiet_NaN();
    }
  }
}

/// The samples in memory as GDAL's raster: pixels centred on the grid
/// points, north-up, non-finite values as NaN nodata. The pixels are
/// converted on all cores straight into the buffer the MEM bands wrap
/// (DATAPOINTER), with no copy through RasterIO.
MemoryRaster memory_raster(const std::string& path, const FieldSamples& s, const GeoTiffOptions& options) {
  const Grid& g = s.grid;
  const int nx = g.points[0], ny = g.points[1];
  const std::vector<Band> bands = bands_of(s);
  const GDALDataType type = options.float64 ? GDT_Float64 : GDT_Float32;
  const std::size_t pixel_bytes = options.float64 ? sizeof(double) : sizeof(float);
  const std::size_t band_bytes = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * pixel_bytes;
  MemoryRaster raster;
  raster.pixels.resize(band_bytes * bands.size());
  raster.dataset.reset(driver("MEM", path)->Create("", nx, ny, 0, type, nullptr));
  if (!raster.dataset) throw OutputError(path + ": GDAL cannot hold the raster: " + gdal_message());
  GDALDataset& data = *raster.dataset;
  const double dx = g.spacing(0), dy = g.spacing(1);
  const double top = g.point(g.size() - 1)[1];  // the last row's y, as sampled
  double transform[6] = {g.lo[0] - 0.5 * dx, dx, 0.0, top + 0.5 * dy, 0.0, -dy};
  data.SetGeoTransform(transform);
  if (!options.crs_wkt.empty()) {
    OGRSpatialReference srs;
    if (srs.importFromWkt(options.crs_wkt.c_str()) != OGRERR_NONE || data.SetSpatialRef(&srs) != CE_None)
      throw OutputError(path + ": GDAL does not take the coordinate reference system: " + gdal_message());
  }
  data.SetMetadataItem("evaluation", evaluation_text(s).c_str());
  data.SetMetadataItem("far_field_tolerance", CPLSPrintf("%.17g", s.far_field_tolerance));

  for (std::size_t b = 0; b < bands.size(); ++b) {
    std::byte* first = raster.pixels.data() + b * band_bytes;
    if (options.float64)
      fill_band(reinterpret_cast<double*>(first), bands[b], nx, ny);
    else
      fill_band(reinterpret_cast<float*>(first), bands[b], nx, ny);
    char pointer[64] = {};
    CPLPrintPointer(pointer, first, sizeof(pointer));
    std::string data_pointer = "DATAPOINTER=";
    data_pointer += pointer;
    const char* const band_options[] = {data_pointer.c_str(), nullptr};
    if (data.AddBand(type, const_cast<char**>(band_options)) != CE_None)
      throw OutputError(path + ": GDAL cannot hold the raster: " + gdal_message());
    GDALRasterBand* band = data.GetRasterBand(static_cast<int>(b) + 1);
    band->SetDescription(bands[b].name.c_str());
    band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
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

const char* compression_name(GeoTiffCompression compression) {
  switch (compression) {
    case GeoTiffCompression::zstd: return "ZSTD";
    case GeoTiffCompression::deflate: return "DEFLATE";
    case GeoTiffCompression::none: return "NONE";
  }
  return "NONE";
}

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

GeoTiffLayout write_geotiff(const std::string& path, const FieldSamples& samples, const GeoTiffOptions& options) {
  if (samples.grid.dimension != 2) throw OutputError(path + ": a GeoTIFF holds 2D fields only (use .vti for 3D)");
  register_gdal();
  const CPLErrorHandlerPusher quiet(CPLQuietErrorHandler);
  CPLErrorReset();
  if (!options.warp_to_wkt.empty() && options.crs_wkt.empty())
    throw OutputError(path + ": the field has no coordinate reference system to warp from");
  MemoryRaster memory = memory_raster(path, samples, options);
  GDALDatasetUniquePtr warp;
  if (!options.warp_to_wkt.empty()) warp = warped(path, *memory.dataset, options.warp_to_wkt);
  GDALDataset* raster = warp ? warp.get() : memory.dataset.get();
  // COG: 512-pixel tiles compressed on all cores, at level 1 with the
  // floating-point predictor (a 1000 x 1000 field of four bands: ZSTD
  // 0.03 s, DEFLATE 0.06 s, 10.1 MB either way, 16.8 MB uncompressed).
  // Overviews only past geotiff_overview_side pixels: GDAL's COG driver
  // builds them in a temporary file and copies the whole raster again
  // (DEFLATE: 0.14 s with them), and QGIS draws rasters that small fast
  // without.
  const bool overviews = std::max(raster->GetRasterXSize(), raster->GetRasterYSize()) > geotiff_overview_side;
  std::string compress = "COMPRESS=";
  compress += compression_name(options.compression);
  const char* const cog_options[] = {compress.c_str(),
                                     "LEVEL=1",
                                     "PREDICTOR=YES",
                                     "NUM_THREADS=ALL_CPUS",
                                     overviews ? "OVERVIEWS=AUTO" : "OVERVIEWS=NONE",
                                     nullptr};
  int overview_levels = 0;
  write_atomically(path, [&](const std::string& temporary) {
    GDALDatasetUniquePtr file(
        driver("COG", path)
            ->CreateCopy(temporary.c_str(), raster, FALSE, const_cast<char**>(cog_options), nullptr, nullptr));
    if (!file) throw OutputError(path + ": GDAL could not write the GeoTIFF: " + gdal_message());
    overview_levels = file->GetRasterBand(1)->GetOverviewCount();
    file.reset();  // closed (and flushed) before the rename
    if (CPLGetLastErrorType() >= CE_Failure)
      throw OutputError(path + ": GDAL could not write the GeoTIFF: " + gdal_message());
  });
  return {raster->GetRasterXSize(), raster->GetRasterYSize(), overview_levels};
}

}  // namespace sage::output
