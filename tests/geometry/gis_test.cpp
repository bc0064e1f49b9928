// GIS reading and validation: real files load with the right projection
// and area; harmless defects are fixed and counted; every fault gives a
// ModelError naming the file, feature, ring and vertex.

#include <sage/geometry/gis_model.hpp>
#include <sage/geometry/gis_reader.hpp>
#include <sage/geometry/polygon_validation.hpp>
#include <sage/tape/evaluator.hpp>

#include <ogr_spatialref.h>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace sage::geometry {
namespace {

std::string data(const std::string& name) { return sage::test::test_data("gis/" + name); }

double ring_area(const Ring& r) {
  double a = 0;
  const std::size_t n = r.points.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = r.points[i];
    const auto& q = r.points[(i + 1) % n];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * a;
}

double area(const PolygonSet& set) {
  double a = 0;
  for (const auto& p : set.polygons) {
    a += ring_area(p.outer);
    for (const auto& h : p.holes) a += ring_area(h);  // clockwise: negative
  }
  return a;
}

/// Writes a GeoJSON FeatureCollection with the given features' geometries,
/// in a projected CRS (UTM 33N) so that coordinates are used as written.
std::string write_geojson(const std::string& name, const std::vector<std::string>& geometries) {
  const auto path = sage::test::scratch_dir() / (name + ".geojson");
  std::ofstream out(path);
  out << R"({"type": "FeatureCollection",
             "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}}, "features": [)";
  for (std::size_t i = 0; i < geometries.size(); ++i)
    out << (i ? "," : "") << R"({"type": "Feature", "properties": {"NAME": "f)" << i << R"("}, "geometry": )"
        << geometries[i] << "}";
  out << "]}";
  return path.string();
}

std::string polygon(const std::string& rings) { return R"({"type": "Polygon", "coordinates": [)" + rings + "]}"; }

void expect_fault(const std::string& path, std::initializer_list<std::string> pieces, LoadOptions options = {}) {
  try {
    load_gis(path, options);
    FAIL() << "no error for " << path;
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    for (const auto& p : pieces) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  }
}

TEST(GisReader, LonLatIsProjectedAndAreasMatchTheDataSheet) {
  // Planar areas from the data sheet (their own transverse Mercator
  // projections); a local azimuthal equidistant projection agrees to < 0.2%.
  struct Expect {
    const char* file;
    double km2;
  };
  for (const Expect& e :
       {Expect{"washington_island_wi_osm.geojson", 64.276}, Expect{"lake_vanern_se_osm.geojson", 5432.221},
        Expect{"wisconsin_us-atlas.geojson", 145390.623}}) {
    GisPolygons g = read_gis_polygons(data(e.file), {});
    EXPECT_NE(g.crs.find("azimuthal equidistant"), std::string::npos) << g.crs;
    validate_polygons(g.polygons, e.file);
    EXPECT_NEAR(area(g.polygons) / 1e6, e.km2, 2e-3 * e.km2) << e.file;
  }
}

TEST(GisReader, ProjectedDataIsUsedAsIs) {
  GisPolygons g = read_gis_polygons(data("washington_island_wi_osm_EPSG3070.geojson"), {});
  EXPECT_NE(g.crs.find("used as is"), std::string::npos) << g.crs;
  validate_polygons(g.polygons, "wi");
  EXPECT_NEAR(area(g.polygons) / 1e6, 64.276, 1e-3);
  EXPECT_GT(g.polygons.polygons[0].outer.points[0][0], 7e5);  // EPSG:3070 eastings
}

TEST(GisReader, ShapefileFeaturesByIndexAndAttributeAreUnited) {
  LoadOptions one;
  one.where = "NAME = 'Ashe'";
  const Model ashe = load_gis(data("shapefile_nc/nc.shp"), one);
  EXPECT_NE(ashe.name.find("1 polygon"), std::string::npos);
  LoadOptions three;
  three.features = {0, 1, 2};  // Ashe, Alleghany, Surry: neighbours
  const Model united = load_gis(data("shapefile_nc/nc.shp"), three);
  bool noted = false;
  for (const auto& n : united.notes) noted = noted || n.find("united 3 features") != std::string::npos;
  EXPECT_TRUE(noted);
  // Their shared borders are gone: one polygon.
  EXPECT_NE(united.name.find("1 polygon"), std::string::npos) << united.name;
}

TEST(GisReader, GreeceHasOneCrossingAndRepairFixesIt) {
  // The data sheet lists one proper crossing in Greece.
  expect_fault(data("greece_ne10m.geojson"), {"edges cross", "vertex", "--repair"});
  LoadOptions repair;
  repair.repair = true;
  const Model m = load_gis(data("greece_ne10m.geojson"), repair);
  bool noted = false;
  for (const auto& n : m.notes) noted = noted || n.find("repaired") != std::string::npos;
  EXPECT_TRUE(noted);
}

/// Writes a GeoJSON without a "crs" member: WGS84 longitude/latitude.
std::string write_lon_lat_geojson(const std::string& name, const std::string& geometry) {
  const auto path = sage::test::scratch_dir() / (name + ".geojson");
  std::ofstream(path) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},
      "geometry": )" << geometry
                      << "}]}";
  return path.string();
}

// A multipolygon spanning the globe (parts near both poles and the
// equator) whose holes touch their shells at a point in the middle of a
// shell edge: valid in longitude/latitude, but the projected shell edge is
// a chord, not the image of the parallel, so the holes cross it in the
// plane where the field is built. --repair repairs in that plane.
TEST(GisReader, RepairHappensInTheProjectedPlane) {
  const std::string path = write_lon_lat_geojson("globe", R"({"type": "MultiPolygon", "coordinates": [
      [[[0, 70], [40, 70], [40, 85], [0, 85], [0, 70]], [[20, 70], [25, 78], [15, 78], [20, 70]],
       [[20, 85], [15, 80], [25, 80], [20, 85]]],
      [[[0, 0], [10, 0], [5, 5], [10, 10], [0, 10], [5, 5], [0, 0]]],
      [[[20, -85], [60, -85], [60, -70], [20, -70], [20, -85]], [[40, -70], [45, -78], [35, -78], [40, -70]],
       [[40, -85], [35, -80], [45, -80], [40, -85]]]]})");
  expect_fault(path, {"edges cross", "use --repair"});
  LoadOptions repair;
  repair.repair = true;
  const Model m = load_gis(path, repair);
  bool noted = false;
  for (const auto& n : m.notes) noted = noted || n.find("repaired in the projected plane") != std::string::npos;
  EXPECT_TRUE(noted);
  // Shells less holes, before and after repair: only the slivers beyond
  // the projected chords differ (0.1% here); losing a part or a hole would
  // change the area by 2% or more.
  GisPolygons raw = read_gis_polygons(path, {});
  GisPolygons repaired = read_gis_polygons(path, repair);
  validate_polygons(repaired.polygons, path, true);
  auto net_area = [](const PolygonSet& set) {
    double a = 0;
    for (const auto& p : set.polygons) {
      a += std::abs(ring_area(p.outer));
      for (const auto& h : p.holes) a -= std::abs(ring_area(h));
    }
    return a;
  };
  EXPECT_NEAR(net_area(repaired.polygons), net_area(raw.polygons), 5e-3 * net_area(raw.polygons));
}

// Faults left after --repair never suggest --repair again.
TEST(GisValidation, FaultsAfterRepairSuggestLeavingTheFeatureOut) {
  PolygonSet set;
  PolygonWithHoles bowtie;
  bowtie.outer.points = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  bowtie.outer.source_vertex = {0, 1, 2, 3};
  set.polygons.push_back(bowtie);
  for (const bool repaired : {false, true}) {
    PolygonSet copy = set;
    try {
      validate_polygons(copy, "data.geojson", repaired);
      FAIL() << "no error";
    } catch (const ModelError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("edges cross"), std::string::npos) << what;
      EXPECT_EQ(what.find("use --repair") != std::string::npos, !repaired) << what;
      if (repaired) {
        EXPECT_NE(what.find("--feature"), std::string::npos) << what;
      }
    }
  }
}

// A shapefile without its .prj: coordinates within longitude/latitude
// ranges give a warning; --crs names the system and the data is projected.
TEST(GisReader, MissingCoordinateSystemWarnsAndCrsOptionProjects) {
  const auto folder = sage::test::scratch_dir() / "noprj";
  std::filesystem::create_directories(folder);
  for (const char* ext : {".shp", ".shx", ".dbf"})
    std::filesystem::copy_file(data(std::string("shapefile_nc/nc") + ext), folder / (std::string("nc") + ext),
                               std::filesystem::copy_options::overwrite_existing);
  const std::string path = (folder / "nc.shp").string();
  LoadOptions ashe;
  ashe.where = "NAME = 'Ashe'";
  GisPolygons planar = read_gis_polygons(path, ashe);
  ASSERT_EQ(planar.warnings.size(), 1u);
  EXPECT_NE(planar.warnings[0].find("--crs EPSG:4326"), std::string::npos) << planar.warnings[0];
  EXPECT_NE(planar.crs.find("assumed planar"), std::string::npos);
  ashe.crs = "EPSG:4267";  // NAD27, what the missing .prj said
  GisPolygons projected = read_gis_polygons(path, ashe);
  EXPECT_TRUE(projected.warnings.empty());
  EXPECT_NE(projected.crs.find("NAD27"), std::string::npos) << projected.crs;
  EXPECT_NE(projected.crs.find("azimuthal equidistant"), std::string::npos) << projected.crs;
  // The same county as read with its .prj: the same area (Ashe: 1,100 km^2).
  LoadOptions with_prj;
  with_prj.where = "NAME = 'Ashe'";
  GisPolygons original = read_gis_polygons(data("shapefile_nc/nc.shp"), with_prj);
  validate_polygons(projected.polygons, path);
  validate_polygons(original.polygons, "nc.shp");
  EXPECT_NEAR(area(projected.polygons), area(original.polygons), 1e-9 * area(original.polygons));
  ashe.crs = "EPSG:99999";
  expect_fault(path, {"--crs EPSG:99999", "PROJ does not know"}, ashe);
}

TEST(GisValidation, DuplicateAndCollinearVerticesAreRemovedAndOrientationFixed) {
  // Clockwise square with a repeated vertex and a collinear middle vertex.
  const auto path = write_geojson("clean", {polygon("[[0,0],[0,2],[0,2],[2,2],[2,1],[2,0],[0,0]]")});
  GisPolygons g = read_gis_polygons(path, {});
  const ValidationReport r = validate_polygons(g.polygons, path);
  EXPECT_EQ(r.duplicate_vertices, 1u);
  EXPECT_EQ(r.collinear_vertices, 1u);
  EXPECT_EQ(r.reoriented_rings, 1u);
  EXPECT_EQ(g.polygons.polygons[0].outer.points.size(), 4u);
  EXPECT_GT(ring_area(g.polygons.polygons[0].outer), 0);
}

TEST(GisValidation, TouchingRingsAreToleratedAndCounted) {
  // Two squares of one multipolygon meeting at the corner (1, 1).
  const auto path =
      write_geojson("touch", {R"({"type": "MultiPolygon", "coordinates": [[[[0,0],[1,0],[1,1],[0,1],[0,0]]],
                                                           [[[1,1],[2,1],[2,2],[1,2],[1,1]]]]})"});
  GisPolygons g = read_gis_polygons(path, {});
  EXPECT_GE(validate_polygons(g.polygons, path).touchings, 1u);
}

TEST(GisValidation, Faults) {
  expect_fault(write_geojson("bowtie", {polygon("[[0,0],[2,2],[2,0],[0,2],[0,0]]")}),
               {"feature 0", "ring 0", "vertex", "edges cross"});
  expect_fault(write_geojson("spike", {polygon("[[0,0],[2,0],[2,2],[3,2],[2,2],[0,2],[0,0]]")}),
               {"feature 0", "vertex", "doubles back"});
  expect_fault(write_geojson("two", {polygon("[[0,0],[1,0],[0,0]]")}), {"feature 0", "fewer than 3"});
  expect_fault(write_geojson("flat", {polygon("[[0,0],[1,0],[2,0],[0,0]]")}), {"feature 0"});
  expect_fault(write_geojson("hole_outside", {polygon("[[0,0],[4,0],[4,4],[0,4],[0,0]],[[5,5],[6,5],[6,6],[5,5]]")}),
               {"ring 1 (hole)", "outside its exterior"});
  expect_fault(write_geojson("hole_in_hole", {polygon("[[0,0],[9,0],[9,9],[0,9],[0,0]],"
                                                      "[[1,1],[8,1],[8,8],[1,8],[1,1]],"
                                                      "[[3,3],[5,3],[5,5],[3,5],[3,3]]")}),
               {"inside another hole"});
  expect_fault(
      write_geojson("crossing_rings", {polygon("[[0,0],[4,0],[4,4],[0,4],[0,0]],[[1,1],[5,1],[5,2],[1,2],[1,1]]")}),
      {"edges cross", "ring 1"});
  expect_fault(write_geojson("nested", {R"({"type": "MultiPolygon", "coordinates": [[[[0,0],[9,0],[9,9],[0,9],[0,0]]],
                                                                                  [[[1,1],[2,1],[2,2],[1,2],[1,1]]]]})"}),
               {"inside another"});
  expect_fault(write_geojson("overlap", {polygon("[[0,0],[4,0],[4,4],[0,4],[0,0]],[[0,1],[0,3],[1,2],[0,1]]")}),
               {"overlap"});
  expect_fault(write_geojson("line", {R"({"type": "LineString", "coordinates": [[0,0],[1,1]]})"}),
               {"feature 0", "Line String", "expected Polygon"});
}

TEST(GisValidation, SelectionAndFileErrors) {
  const auto path = write_geojson("sel", {polygon("[[0,0],[1,0],[1,1],[0,0]]")});
  LoadOptions far;
  far.features = {5};
  expect_fault(path, {"--feature 5", "1 feature"}, far);
  LoadOptions bad_where;
  bad_where.where = "NAME = ";
  expect_fault(path, {"--where"}, bad_where);
  LoadOptions none;
  none.where = "NAME = 'nothing'";
  expect_fault(path, {"no polygon features"}, none);
  const auto garbage = sage::test::scratch_dir() / "garbage.geojson";
  std::ofstream(garbage) << "{\"type\": \"FeatureCollection\", \"features\": [ {oops";
  expect_fault(garbage.string(), {"GDAL cannot read"});
  expect_fault("/nonexistent/x.shp", {"GDAL cannot read"});
}

// The model carries the plane its field is built in as WKT, for
// georeferenced output: the data's own projected system, the local
// projection sage chose for longitude/latitude, or nothing.
TEST(GisModel, ModelCarriesTheCoordinateSystemOfItsPlane) {
  OGRSpatialReference srs;
  const Model utm = load_gis(data("washington_island_wi_osm_EPSG3070.geojson"), {});
  ASSERT_EQ(srs.importFromWkt(utm.crs_wkt.c_str()), OGRERR_NONE) << utm.crs_wkt;
  EXPECT_STREQ(srs.GetAuthorityCode(nullptr), "3070");
  const Model island = load_gis(data("washington_island_wi_osm.geojson"), {});
  ASSERT_EQ(srs.importFromWkt(island.crs_wkt.c_str()), OGRERR_NONE) << island.crs_wkt;
  // Centred where the notes say: "... centred on lat 45.38..., lon -86.9..."
  std::string note;
  for (const auto& n : island.notes)
    if (n.find("centred on lat") != std::string::npos) note = n;
  const double lat = std::stod(note.substr(note.find("lat ") + 4)), lon = std::stod(note.substr(note.find("lon ") + 4));
  EXPECT_STREQ(srs.GetAttrValue("PROJECTION"), "Azimuthal_Equidistant");
  EXPECT_NEAR(srs.GetNormProjParm(SRS_PP_LATITUDE_OF_CENTER, 0), lat, 1e-6);
  EXPECT_NEAR(srs.GetNormProjParm(SRS_PP_LONGITUDE_OF_CENTER, 0), lon, 1e-6);
  EXPECT_TRUE(load_model(std::string(SAGE_SOURCE_DIR) + "/examples/models/plate_with_holes.json").crs_wkt.empty());
}

TEST(GisModel, GeoJsonWithJsonExtensionIsGisData) {
  const auto path = sage::test::scratch_dir() / "plain.json";
  std::ofstream(path) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},
      "geometry": {"type": "Polygon", "coordinates": [[[0,0],[3,0],[3,3],[0,3],[0,0]]]}}]})";
  EXPECT_TRUE(is_gis_path(path.string()));
  const Model m = load_model(path.string(), {});
  const Tape tape(m.field, 2);
  Evaluator<double> eval(tape);
  // No CRS member: GeoJSON means WGS84 lon/lat, so the square is projected
  // (about 333 km wide); its centre is inside, far outside is outside.
  EXPECT_GT(eval.at({0, 0, 0}), 0.0);
  EXPECT_LT(eval.at({1e6, 0, 0}), 0.0);
}

}  // namespace
}  // namespace sage::geometry
