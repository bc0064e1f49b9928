#pragma once
// A GeoTIFF read back whole with GDAL's C++ API, for the tests of sage's
// GeoTIFF output: size, geotransform, CRS, bands (description, type,
// nodata, values in raster order: row 0 is the top, north).

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <array>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage::test {

struct GeoTiffBand {
  std::string description;
  GDALDataType type = GDT_Unknown;
  bool has_nodata = false;
  double nodata = 0;
  std::vector<double> values;  // width * height, row by row from the top
};

struct GeoTiffFile {
  int width = 0, height = 0;
  std::array<double, 6> transform{};         // GDAL's geotransform
  std::unique_ptr<OGRSpatialReference> crs;  // null when the file has none
  std::vector<GeoTiffBand> bands;
  std::string layout, compression;              // IMAGE_STRUCTURE metadata: "COG", "DEFLATE"
  std::map<std::string, std::string> metadata;  // the default domain's items
  int block_width = 0, block_height = 0;
  int overviews = 0;  // the first band's overview levels

  double at(std::size_t band, int column, int row) const {
    return bands.at(band).values.at(static_cast<std::size_t>(row) * width + column);
  }
};

inline GeoTiffFile read_geotiff(const std::string& path) {
  GDALAllRegister();
  GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!dataset) throw std::runtime_error(path + ": GDAL cannot open it: " + CPLGetLastErrorMsg());
  GeoTiffFile file;
  file.width = dataset->GetRasterXSize();
  file.height = dataset->GetRasterYSize();
  if (dataset->GetGeoTransform(file.transform.data()) != CE_None) throw std::runtime_error(path + ": no geotransform");
  if (const OGRSpatialReference* crs = dataset->GetSpatialRef()) file.crs.reset(crs->Clone());
  auto item = [&](const char* name) {
    const char* v = dataset->GetMetadataItem(name, "IMAGE_STRUCTURE");
    return std::string(v ? v : "");
  };
  for (char** entry = dataset->GetMetadata(); entry && *entry; ++entry) {
    char* key = nullptr;
    const char* value = CPLParseNameValue(*entry, &key);
    if (key && value) file.metadata[key] = value;
    CPLFree(key);
  }
  file.layout = item("LAYOUT");
  file.compression = item("COMPRESSION");
  for (int b = 1; b <= dataset->GetRasterCount(); ++b) {
    GDALRasterBand* band = dataset->GetRasterBand(b);
    GeoTiffBand out;
    out.description = band->GetDescription();
    out.type = band->GetRasterDataType();
    int has = 0;
    out.nodata = band->GetNoDataValue(&has);
    out.has_nodata = has != 0;
    if (b == 1) {
      band->GetBlockSize(&file.block_width, &file.block_height);
      file.overviews = band->GetOverviewCount();
    }
    out.values.resize(static_cast<std::size_t>(file.width) * file.height);
    if (band->RasterIO(GF_Read, 0, 0, file.width, file.height, out.values.data(), file.width, file.height, GDT_Float64,
                       0, 0, nullptr) != CE_None)
      throw std::runtime_error(path + ": cannot read band " + std::to_string(b));
    file.bands.push_back(std::move(out));
  }
  return file;
}

}  // namespace sage::test
