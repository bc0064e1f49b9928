#pragma once
// Writing a 2D field's samples as a GeoTIFF that QGIS and GDAL open
// directly, with GDAL's COG driver (Cloud Optimized GeoTIFF: tiled,
// compressed, with overviews past geotiff_overview_side pixels). One band per array component,
// named by its band description as the .vti arrays are named: omega, grad_omega_x,
// grad_omega_y, grad_norm, then d<k>_omega_<partial> (d2_omega_xx, ...).
//
// Georeferencing: sage's samples are values at grid points, a raster
// pixel's value is at its centre (GeoTIFF's PixelIsArea, GDAL's default).
// So each pixel is centred on its grid point: the geotransform's origin is
// the first grid point minus half a pixel, and rows run north-up (the
// first row holds the grid's largest y).
//
// Another CRS on request (warp_to_wkt): the raster above is warped with
// GDAL (bilinear) into it. The field is still evaluated in the plane where
// it was built: values are resampled, and grad_omega_x/y stay that
// plane's components.

#include <sage/sampling/field_samples.hpp>

#include <string>
#include <vector>

namespace sage::output {

/// How the tiles are compressed. ZSTD is twice as fast as DEFLATE for the
/// same size and every GDAL since 2.3 (QGIS, rasterio) reads it; DEFLATE
/// is for readers built on an older libtiff.
enum class GeoTiffCompression { zstd, deflate, none };

struct GeoTiffOptions {
  std::string crs_wkt;      // the plane's coordinate reference system (WKT); empty: none is written
  bool float64 = false;     // Float64 bands in place of Float32
  std::string warp_to_wkt;  // non-empty: write the raster warped into this CRS (needs crs_wkt)
  GeoTiffCompression compression = GeoTiffCompression::zstd;
};

/// GDAL's name of a compression: "ZSTD", "DEFLATE", "NONE".
const char* compression_name(GeoTiffCompression compression);

/// What write_geotiff wrote: the raster's size (after a warp, GDAL's) and
/// its overview levels.
struct GeoTiffLayout {
  int width = 0;
  int height = 0;
  int overview_levels = 0;
};

/// Rasters with a side longer than this get overviews (halved copies for
/// zoomed-out views); smaller ones draw fast without.
inline constexpr int geotiff_overview_side = 2048;

/// True if `path` ends in .tif or .tiff.
bool is_geotiff_path(const std::string& path);

/// The band descriptions write_geotiff gives `samples`, in band order.
std::vector<std::string> geotiff_band_names(const FieldSamples& samples);

/// The WKT of a CRS as users write it (EPSG:XXXX, a PROJ string, WKT).
/// Throws OutputError when PROJ does not know it.
std::string crs_wkt_from(const std::string& text);

/// The name GDAL gives a coordinate reference system written as WKT (for
/// summaries); empty when `wkt` is empty or not understood.
std::string crs_name(const std::string& wkt);

/// Writes the samples of a 2D grid to `path` (atomically, as every
/// writer): one band per array component, non-finite values as nodata (NaN). Throws
/// OutputError naming the path for a 3D grid or when GDAL cannot write.
GeoTiffLayout write_geotiff(const std::string& path, const FieldSamples& samples, const GeoTiffOptions& options = {});

}  // namespace sage::output
