// `sage field MODEL -o OUT.tif`: a GeoTIFF that GDAL reads back in the CRS
// the field was built in, with the .vti's values at the same points,
// north-up, pixels centred on the grid points; --resolution sets the
// pixel size; misuse exits with 2.

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>
#include <geotiff_file.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace sage_cli_test;
using sage::test::read_geotiff;
using sage::test::test_data;

/// Component `c` of the .vti's array `name` at grid point (i, j).
double vti_value(vtkImageData* image, const char* name, int c, int i, int j) {
  int dims[3];
  image->GetDimensions(dims);
  vtkDataArray* array = image->GetPointData()->GetArray(name);
  if (!array) throw std::runtime_error(std::string("no array ") + name);
  return array->GetComponent(static_cast<vtkIdType>(i) + static_cast<vtkIdType>(dims[0]) * j, c);
}

// The lake in UTM 33N: the .tif keeps EPSG:32633, its pixels sit on the
// .vti's points (first point minus half a pixel, rows from the north), and
// its bands hold the .vti's arrays: rounded to Float32, or exact in Float64.
TEST(CliGeoTiff, ProjectedLakeKeepsItsCrsAndTheVtiValues) {
  const std::string lake = test_data("gis/lake_vanern_se_osm_EPSG32633.geojson") + " --grid 60x40 --exact --order 2";
  const fs::path vti = scratch("lake.vti"), tif = scratch("lake.tif"), tif64 = scratch("lake64.tif");
  ASSERT_EQ(run("field " + lake + " -q -o " + vti.string()).exit_code, 0);
  const Result r = run("field " + lake + " -o " + tif.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("GeoTIFF: 7 Float32 band(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("coordinate reference system WGS 84 / UTM zone 33N"), std::string::npos) << r.output;
  ASSERT_EQ(run("field " + lake + " -q --float64 -o " + tif64.string()).exit_code, 0);

  const auto image = read_vti(vti);
  const auto single = read_geotiff(tif.string()), twice = read_geotiff(tif64.string());
  ASSERT_TRUE(single.crs);
  EXPECT_STREQ(single.crs->GetAuthorityCode(nullptr), "32633");
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  ASSERT_EQ(single.width, 60);
  ASSERT_EQ(single.height, 40);
  EXPECT_NEAR(single.transform[0], origin[0] - spacing[0] / 2, 1e-6);
  EXPECT_NEAR(single.transform[1], spacing[0], 1e-9);
  EXPECT_NEAR(single.transform[3], origin[1] + 39 * spacing[1] + spacing[1] / 2, 1e-6);
  EXPECT_NEAR(single.transform[5], -spacing[1], 1e-9);

  const std::vector<std::string> names{"omega",       "grad_omega_x", "grad_omega_y", "grad_norm",
                                       "d2_omega_xx", "d2_omega_xy",  "d2_omega_yy"};
  struct Source {
    const char* array;
    int component;
  };
  const std::vector<Source> sources{{"omega", 0},    {"grad_omega", 0}, {"grad_omega", 1}, {"grad_norm", 0},
                                    {"d2_omega", 0}, {"d2_omega", 1},   {"d2_omega", 2}};
  ASSERT_EQ(single.bands.size(), names.size());
  ASSERT_EQ(twice.bands.size(), names.size());
  for (std::size_t b = 0; b < names.size(); ++b) {
    EXPECT_EQ(single.bands[b].description, names[b]);
    EXPECT_EQ(twice.bands[b].type, GDT_Float64);
    for (int row = 0; row < 40; ++row)
      for (int column = 0; column < 60; ++column) {
        const double v = vti_value(image, sources[b].array, sources[b].component, column, 39 - row);
        ASSERT_EQ(twice.at(b, column, row), v) << names[b] << " at pixel " << column << ", " << row;
        ASSERT_EQ(single.at(b, column, row), static_cast<double>(static_cast<float>(v))) << names[b];
      }
  }
}

// Longitude/latitude data: the .tif's CRS is the local azimuthal
// equidistant projection the loader chose, centred where `sage info` says.
TEST(CliGeoTiff, LonLatLakeGetsTheLoadersProjection) {
  const std::string lake = test_data("gis/lake_vanern_se_osm.geojson");
  const Result info = run("info " + lake);
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const fs::path tif = scratch("lake_aeqd.tif");
  const Result r = run("field " + lake + " --grid 30x30 -o " + tif.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("coordinate reference system sage local azimuthal equidistant, lat "), std::string::npos)
      << r.output;
  const auto file = read_geotiff(tif.string());
  ASSERT_TRUE(file.crs);
  EXPECT_STREQ(file.crs->GetAttrValue("PROJECTION"), "Azimuthal_Equidistant");
  EXPECT_NEAR(file.crs->GetNormProjParm(SRS_PP_LATITUDE_OF_CENTER, 0), number_after(info.output, "centred on lat "),
              1e-6);
  EXPECT_NEAR(file.crs->GetNormProjParm(SRS_PP_LONGITUDE_OF_CENTER, 0), number_after(info.output, ", lon "), 1e-6);
  EXPECT_EQ(file.crs->GetLinearUnits(), 1.0);  // metres
}

// A JSON model has no CRS, and the summary says so. omega = x + 10 y tells
// the corners apart: the top-left pixel is the grid's point (0, 2).
TEST(CliGeoTiff, JsonModelIsNorthUpWithoutCrs) {
  const std::string m = write_file("ramp.json", R"({"dimension": 2, "field": {"formula": "x + 10*y"}})");
  const fs::path tif = scratch("ramp.tif");
  const Result r = run("field " + m + " --bounds 0,4,0,2 --grid 5x3 -o " + tif.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no coordinate reference system: " + m + " has none"), std::string::npos) << r.output;
  const auto file = read_geotiff(tif.string());
  EXPECT_FALSE(file.crs);
  EXPECT_EQ(file.transform[0], -0.5);
  EXPECT_EQ(file.transform[3], 2.5);
  EXPECT_EQ(file.at(0, 0, 0), 20.0);  // (0, 2)
  EXPECT_EQ(file.at(0, 4, 0), 24.0);  // (4, 2)
  EXPECT_EQ(file.at(0, 0, 2), 0.0);   // (0, 0)
  EXPECT_EQ(file.at(0, 4, 2), 4.0);   // (4, 0)
  EXPECT_TRUE(std::isnan(file.bands[0].nodata) && file.bands[0].has_nodata);
  EXPECT_EQ(file.compression, "ZSTD");
  EXPECT_NE(r.output.find("5 x 3 pixels in 512-pixel ZSTD tiles, no overviews"), std::string::npos) << r.output;

  // --compression deflate for readers on an older libtiff: the same pixels.
  const fs::path deflated = scratch("ramp_deflate.tif");
  const Result d = run("field " + m + " --bounds 0,4,0,2 --grid 5x3 --compression deflate -o " + deflated.string());
  ASSERT_EQ(d.exit_code, 0) << d.output;
  const auto other = read_geotiff(deflated.string());
  EXPECT_EQ(other.compression, "DEFLATE");
  EXPECT_EQ(other.bands[0].values, file.bands[0].values);
}

// --resolution R: points R apart from the bounds' minimum on, up to the
// first at or past the maximum; for every output format.
TEST(CliGeoTiff, ResolutionSetsThePixelSize) {
  const std::string m = write_file("plane.json", R"({"dimension": 2, "field": {"formula": "x - y"}})");
  const std::string args = "field " + m + " --bounds 0,10,0,4.2 --resolution 0.5 -q -o ";
  const fs::path tif = scratch("plane.tif"), vti = scratch("plane.vti");
  ASSERT_EQ(run(args + tif.string()).exit_code, 0);
  ASSERT_EQ(run(args + vti.string()).exit_code, 0);
  const auto file = read_geotiff(tif.string());
  EXPECT_EQ(file.width, 21);   // 10 / 0.5 steps
  EXPECT_EQ(file.height, 10);  // 4.2 / 0.5 = 8.4: 9 steps, up to y = 4.5
  EXPECT_DOUBLE_EQ(file.transform[1], 0.5);
  EXPECT_DOUBLE_EQ(file.transform[5], -0.5);
  EXPECT_DOUBLE_EQ(file.transform[0], -0.25);
  EXPECT_DOUBLE_EQ(file.transform[3], 4.75);
  EXPECT_EQ(file.at(0, 0, 0), -4.5);  // x - y at (0, 4.5)
  const auto image = read_vti(vti);
  int dims[3];
  double spacing[3];
  image->GetDimensions(dims);
  image->GetSpacing(spacing);
  EXPECT_EQ(dims[0], 21);
  EXPECT_EQ(dims[1], 10);
  EXPECT_DOUBLE_EQ(spacing[0], 0.5);
  EXPECT_DOUBLE_EQ(spacing[1], 0.5);
}

/// The smallest and largest values of `band` at the pixels whose centres
/// are within `reach` pixels of (x, y) in `file`'s CRS; NaN when one of
/// them is outside or nodata.
std::pair<double, double> neighbour_range(const sage::test::GeoTiffFile& file, std::size_t band, double x, double y,
                                          int reach) {
  const double u = (x - file.transform[0]) / file.transform[1] - 0.5;
  const double v = (y - file.transform[3]) / file.transform[5] - 0.5;
  const int i0 = static_cast<int>(std::floor(u)), j0 = static_cast<int>(std::floor(v));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int j = j0 - reach + 1; j <= j0 + reach; ++j)
    for (int i = i0 - reach + 1; i <= i0 + reach; ++i) {
      const double value = i >= 0 && j >= 0 && i < file.width && j < file.height ? file.at(band, i, j) : std::nan("");
      if (std::isnan(value)) return {std::nan(""), std::nan("")};
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
  return {lo, hi};
}

// --crs-out EPSG:4326: the lake's raster warped into longitude/latitude.
// Each pixel's value is a bilinear blend of the UTM raster's pixels around
// the same place (GDAL's warp places its samples within a pixel, so the
// check allows the 4 x 4 pixels around it; most are blends, not copies of
// one pixel as the nearest neighbour's would be), and the summary says the
// field was evaluated in UTM and resampled.
TEST(CliGeoTiff, CrsOutWarpsTheRasterBilinearly) {
  const std::string lake =
      test_data("gis/lake_vanern_se_osm_EPSG32633.geojson") + " --grid 80x60 --exact --float64 --order 0";
  const fs::path utm = scratch("lake_utm.tif"), lonlat = scratch("lake_lonlat.tif");
  ASSERT_EQ(run("field " + lake + " -q -o " + utm.string()).exit_code, 0);
  const Result r = run("field " + lake + " --crs-out EPSG:4326 -o " + lonlat.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warped (bilinear) into WGS 84: the field was evaluated in the plane where it was built, "
                          "WGS 84 / UTM zone 33N, and resampled"),
            std::string::npos)
      << r.output;
  const auto source = read_geotiff(utm.string()), target = read_geotiff(lonlat.string());
  ASSERT_TRUE(target.crs);
  EXPECT_STREQ(target.crs->GetAuthorityCode(nullptr), "4326");
  ASSERT_EQ(target.bands.size(), 1u);
  EXPECT_EQ(target.bands[0].description, "omega");
  OGRSpatialReference from, to;
  from.importFromEPSG(4326);
  to.importFromEPSG(32633);
  from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  const std::unique_ptr<OGRCoordinateTransformation> transform(OGRCreateCoordinateTransformation(&from, &to));
  ASSERT_TRUE(transform);
  const std::set<double> source_values(source.bands[0].values.begin(), source.bands[0].values.end());
  int checked = 0, inside = 0, copies = 0;
  for (int row = 0; row < target.height; ++row)
    for (int column = 0; column < target.width; ++column) {
      const double value = target.at(0, column, row);
      double x = target.transform[0] + (column + 0.5) * target.transform[1];
      double y = target.transform[3] + (row + 0.5) * target.transform[5];
      ASSERT_TRUE(transform->Transform(1, &x, &y));
      const auto [lo, hi] = neighbour_range(source, 0, x, y, 2);
      if (std::isnan(value) || std::isnan(lo)) continue;  // at the edge of the UTM raster's footprint
      ++checked;
      inside += value > 0;
      copies += source_values.count(value) > 0;
      EXPECT_GE(value, lo - 1e-9 * std::abs(lo)) << "pixel " << column << ", " << row;
      EXPECT_LE(value, hi + 1e-9 * std::abs(hi)) << "pixel " << column << ", " << row;
    }
  EXPECT_GT(checked, 80 * 60 / 2);
  EXPECT_GT(inside, 0);  // the lake is there
  EXPECT_LT(copies, checked / 2);
}

TEST(CliGeoTiff, MisuseExitsWithTwo) {
  const std::string plane =
      write_file("plane2.json", R"({"dimension": 2, "field": {"formula": "x"}})") + " --bounds 0,1,0,1 -q -o ";
  auto expect_usage = [](const std::string& args, const std::string& piece) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(piece), std::string::npos) << "'" << piece << "' not in: " << r.output;
  };
  const fs::path solid = scratch("solid.tif");
  expect_usage("field " + std::string(SAGE_SOURCE_DIR) + "/examples/models/primitives_3d.json -q -o " + solid.string(),
               "is 3D: write .vti or .vtu");
  EXPECT_FALSE(fs::exists(solid));
  expect_usage("field " + plane + scratch("a.tif").string() + " --grid 10x10 --resolution 0.1", "not both");
  expect_usage("field " + plane + scratch("a.vti").string() + " --float64", "--float64 is for GeoTIFF");
  expect_usage("field " + plane + scratch("a.tif").string() + " --resolution 0", "--resolution 0");
  expect_usage("field " + plane + scratch("a.tif").string() + " --resolution 1e-6", "over 100000 points");
  expect_usage("field " + plane + scratch("a.png").string(), ".vtu, .vti or .tif");
  expect_usage("field " + plane + scratch("a.vti").string() + " --crs-out EPSG:4326", "--crs-out is for GeoTIFF");
  expect_usage("field " + plane + scratch("a.vti").string() + " --compression none", "--compression is for GeoTIFF");
  expect_usage("field " + plane + scratch("a.tif").string() + " --compression lzw", "use zstd, deflate or none");
  expect_usage("field " + plane + scratch("a.tif").string() + " --crs-out EPSG:4326", "no coordinate reference system");
  expect_usage("field " + test_data("gis/lake_vanern_se_osm.geojson") + " -q --crs-out EPSG:99999 -o " +
                   scratch("a.tif").string(),
               "--crs-out EPSG:99999");
}

}  // namespace
