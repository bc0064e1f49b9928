// GeoTIFF output: files written by sage read back with GDAL, pixels centred
// on the grid points and north-up, one named band per array, the CRS as
// given, NaN nodata, Float32 or Float64, a tiled ZSTD- or DEFLATE-compressed
// COG, overviews for large rasters only.

#include <sage/expression/formula.hpp>
#include <sage/output/geotiff_writer.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/sampling/field_samples.hpp>

#include <gtest/gtest.h>
#include <geotiff_file.hpp>
#include <test_files.hpp>

#include <cmath>
#include <limits>

namespace {

using sage::test::read_geotiff;

// 5 x 7 points over [-1, 1] x [-2, 2]: spacing 0.5 x 2/3.
sage::FieldSamples samples_of(const std::string& formula, int order) {
  sage::Grid grid;
  grid.lo = {-1, -2, 0};
  grid.hi = {1, 2, 0};
  grid.points = {5, 7, 1};
  const sage::Tape tape(sage::parse_formula(formula, 2), 2);
  return sage::sample_field(tape, grid, order);
}

std::string temp_path(const std::string& name) { return (sage::test::scratch_dir() / name).string(); }

std::string utm33_wkt() {
  OGRSpatialReference srs;
  srs.importFromEPSG(32633);
  char* text = nullptr;
  srs.exportToWkt(&text);
  std::string wkt = text;
  CPLFree(text);
  return wkt;
}

TEST(GeoTiffWriter, PixelsAreCentredOnTheGridPointsNorthUp) {
  const auto s = samples_of("x^2 * y + 3 * y", 2);
  const std::string path = temp_path("field.tif");
  sage::output::write_geotiff(path, s, {utm33_wkt(), false, "", sage::output::GeoTiffCompression::zstd});
  const auto tif = read_geotiff(path);
  ASSERT_EQ(tif.width, 5);
  ASSERT_EQ(tif.height, 7);
  const double dx = 0.5, dy = 4.0 / 6.0;
  EXPECT_DOUBLE_EQ(tif.transform[0], -1 - dx / 2);  // the first point minus half a pixel
  EXPECT_DOUBLE_EQ(tif.transform[1], dx);
  EXPECT_DOUBLE_EQ(tif.transform[3], 2 + dy / 2);  // the top: the largest y plus half a pixel
  EXPECT_DOUBLE_EQ(tif.transform[5], -dy);
  EXPECT_EQ(tif.transform[2], 0.0);
  EXPECT_EQ(tif.transform[4], 0.0);
  // Row 0 is the grid's last row (y = 2): omega = x^2 y + 3 y is odd in y.
  EXPECT_FLOAT_EQ(tif.at(0, 0, 0), 1 * 2 + 3 * 2);
  EXPECT_FLOAT_EQ(tif.at(0, 0, 6), -(1 * 2 + 3 * 2));
  for (int row = 0; row < 7; ++row)
    for (int column = 0; column < 5; ++column) {
      // The pixel's centre, from the geotransform, is where the value was
      // sampled (to rounding in the centre and in Float32).
      const double x = tif.transform[0] + (column + 0.5) * tif.transform[1];
      const double y = tif.transform[3] + (row + 0.5) * tif.transform[5];
      EXPECT_NEAR(tif.at(0, column, row), x * x * y + 3 * y, 1e-6) << x << ", " << y;
      EXPECT_NEAR(tif.at(1, column, row), 2 * x * y, 1e-6);
      EXPECT_NEAR(tif.at(2, column, row), x * x + 3, 1e-6);
      EXPECT_NEAR(tif.at(5, column, row), 2 * x, 1e-6);  // xy
    }
}

TEST(GeoTiffWriter, BandsAreNamedAsTheVtiArrays) {
  const auto tif = [&] {
    const std::string path = temp_path("bands.tif");
    sage::output::write_geotiff(path, samples_of("x * y", 3));
    return read_geotiff(path);
  }();
  const std::vector<std::string> expected{"omega",        "grad_omega_x", "grad_omega_y", "grad_norm",
                                          "d2_omega_xx",  "d2_omega_xy",  "d2_omega_yy",  "d3_omega_xxx",
                                          "d3_omega_xxy", "d3_omega_xyy", "d3_omega_yyy"};
  ASSERT_EQ(tif.bands.size(), expected.size());
  for (std::size_t b = 0; b < expected.size(); ++b) EXPECT_EQ(tif.bands[b].description, expected[b]);
  EXPECT_EQ(sage::output::geotiff_band_names(samples_of("x", 0)), std::vector<std::string>{"omega"});
}

TEST(GeoTiffWriter, Float32TiledZstdCogByDefaultFloat64AndDeflateOnRequest) {
  const auto s = samples_of("exp(x) * sin(y)", 1);
  const std::string single = temp_path("single.tif"), twice = temp_path("double.tif");
  sage::output::write_geotiff(single, s);
  sage::output::write_geotiff(twice, s, {"", true, "", sage::output::GeoTiffCompression::deflate});
  const auto a = read_geotiff(single), b = read_geotiff(twice);
  EXPECT_EQ(a.bands[0].type, GDT_Float32);
  EXPECT_EQ(b.bands[0].type, GDT_Float64);
  EXPECT_EQ(a.layout, "COG");
  EXPECT_EQ(a.compression, "ZSTD");
  EXPECT_EQ(b.compression, "DEFLATE");
  EXPECT_EQ(a.block_width, 512);  // tiles, not strips of a row
  EXPECT_EQ(a.block_height, 512);
  EXPECT_FALSE(a.crs) << "no CRS given, none written";
  EXPECT_EQ(a.metadata.at("evaluation"), "exact");  // how the samples were made, as in the .vti
  EXPECT_EQ(a.metadata.at("far_field_tolerance"), "0");
  const int nx = 5, ny = 7;
  for (int row = 0; row < ny; ++row)
    for (int column = 0; column < nx; ++column) {
      const std::size_t i = static_cast<std::size_t>(ny - 1 - row) * nx + column;  // north-up
      EXPECT_EQ(b.at(0, column, row), s.omega[i]);
      EXPECT_EQ(a.at(0, column, row), static_cast<double>(static_cast<float>(s.omega[i])));
    }
}

// Overviews only for rasters with a side past geotiff_overview_side pixels
// (they double the writing time and small rasters draw fast without).
TEST(GeoTiffWriter, OverviewsOnlyForLargeRasters) {
  auto strip = [](int width) {  // a strip one row too thin to matter
    sage::Grid grid;
    grid.lo = {0, 0, 0};
    grid.hi = {1, 0.01, 0};
    grid.points = {width, 4, 1};
    return sage::sample_field(sage::Tape(sage::parse_formula("x", 2), 2), grid, 0);
  };
  const int side = sage::output::geotiff_overview_side;
  const std::string small = temp_path("small.tif"), large = temp_path("large.tif");
  const auto small_layout = sage::output::write_geotiff(small, strip(side));
  const auto large_layout = sage::output::write_geotiff(large, strip(side + 1));
  EXPECT_EQ(small_layout.overview_levels, 0);
  EXPECT_EQ(read_geotiff(small).overviews, 0);
  EXPECT_GE(large_layout.overview_levels, 1);
  EXPECT_EQ(read_geotiff(large).overviews, large_layout.overview_levels);
  EXPECT_EQ(large_layout.width, side + 1);
  EXPECT_EQ(large_layout.height, 4);
  EXPECT_EQ(read_geotiff(large).layout, "COG");
}

TEST(GeoTiffWriter, NonFiniteValuesAreNanNodata) {
  auto s = samples_of("x + y", 1);
  s.omega[0] = std::numeric_limits<double>::infinity();  // the grid's first point: bottom left
  s.gradient_norm[4] = std::numeric_limits<double>::quiet_NaN();
  const std::string path = temp_path("holes.tif");
  sage::output::write_geotiff(path, s);
  const auto tif = read_geotiff(path);
  for (const auto& band : tif.bands) {
    EXPECT_TRUE(band.has_nodata);
    EXPECT_TRUE(std::isnan(band.nodata));
  }
  EXPECT_TRUE(std::isnan(tif.at(0, 0, 6)));
  EXPECT_TRUE(std::isnan(tif.at(3, 4, 6)));
  EXPECT_FALSE(std::isnan(tif.at(0, 1, 6)));
}

TEST(GeoTiffWriter, RefusesThreeDimensionsAndUnwritablePaths) {
  sage::Grid grid;
  grid.dimension = 3;
  grid.points = {3, 3, 3};
  const sage::Tape tape(sage::parse_formula("x + y + z", 3), 3);
  const auto solid = sage::sample_field(tape, grid, 1);
  EXPECT_THROW(sage::output::write_geotiff(temp_path("solid.tif"), solid), sage::output::OutputError);
  try {
    sage::output::write_geotiff("/nonexistent-folder/out.tif", samples_of("x", 1));
    FAIL();
  } catch (const sage::output::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/out.tif"), std::string::npos);
  }
  EXPECT_TRUE(sage::output::is_geotiff_path("a.tif"));
  EXPECT_TRUE(sage::output::is_geotiff_path("a.tiff"));
  EXPECT_FALSE(sage::output::is_geotiff_path("a.vti"));
}

TEST(GeoTiffWriter, KeepsTheCoordinateReferenceSystem) {
  const std::string path = temp_path("utm.tif");
  sage::output::write_geotiff(path, samples_of("x", 0),
                              {utm33_wkt(), false, "", sage::output::GeoTiffCompression::zstd});
  const auto tif = read_geotiff(path);
  ASSERT_TRUE(tif.crs);
  EXPECT_STREQ(tif.crs->GetAuthorityCode(nullptr), "32633");
  EXPECT_EQ(sage::output::crs_name(utm33_wkt()), "WGS 84 / UTM zone 33N");
  EXPECT_EQ(sage::output::crs_name(""), "");
}

// --crs-out: the raster warped into another CRS keeps its bands' names,
// nodata and metadata; a field without a CRS or an unknown CRS is refused.
TEST(GeoTiffWriter, WarpsIntoAnotherCrs) {
  sage::Grid grid;  // 2 km around a point of southern Sweden in UTM 33N
  grid.lo = {400000, 6500000, 0};
  grid.hi = {402000, 6502000, 0};
  grid.points = {21, 21, 1};
  const sage::Tape tape(sage::parse_formula("x - 400000", 2), 2);
  const auto s = sage::sample_field(tape, grid, 1);
  const std::string path = temp_path("warped.tif");
  sage::output::write_geotiff(
      path, s, {utm33_wkt(), false, sage::output::crs_wkt_from("EPSG:4326"), sage::output::GeoTiffCompression::zstd});
  const auto tif = read_geotiff(path);
  ASSERT_TRUE(tif.crs);
  EXPECT_STREQ(tif.crs->GetAuthorityCode(nullptr), "4326");
  EXPECT_NEAR(tif.transform[0], 13.3, 0.1);   // degrees east
  EXPECT_NEAR(tif.transform[3], 58.65, 0.1);  // degrees north
  ASSERT_EQ(tif.bands.size(), 4u);
  EXPECT_EQ(tif.bands[3].description, "grad_norm");
  EXPECT_TRUE(tif.bands[0].has_nodata && std::isnan(tif.bands[0].nodata));
  EXPECT_EQ(tif.metadata.at("evaluation"), "exact");
  // omega = x - 400000 grows eastward, from 0 to 2000 m.
  const double west = tif.at(0, tif.width / 4, tif.height / 2), east = tif.at(0, 3 * tif.width / 4, tif.height / 2);
  EXPECT_GT(west, 0.0);
  EXPECT_LT(east, 2000.0);
  EXPECT_GT(east - west, 500.0);
  EXPECT_THROW(
      sage::output::write_geotiff(
          path, s, {"", false, sage::output::crs_wkt_from("EPSG:4326"), sage::output::GeoTiffCompression::zstd}),
      sage::output::OutputError);
  EXPECT_THROW(sage::output::crs_wkt_from("EPSG:99999"), sage::output::OutputError);
}

}  // namespace
