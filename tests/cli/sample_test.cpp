// `sage sample MODEL POINTS -o OUT`: the field at listed places, read back
// with GDAL. At grid points it equals `sage field`; longitude/latitude
// points land where the polygons' own vertices did (omega = 0 there);
// every input attribute survives; bad files get errors naming them.
#include "cli_support.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

namespace {

using namespace sage_cli_test;

/// A layer as GDAL reads it back: per feature, every attribute as text
/// and the point's coordinates.
struct Feature {
  std::map<std::string, std::string> fields;
  std::map<std::string, double> reals;  // Real attributes, whole
  double x = 0.0, y = 0.0;
};

std::vector<Feature> read_layer(const fs::path& path) {
  GDALAllRegister();
  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!dataset) throw std::runtime_error("GDAL cannot read " + path.string());
  std::vector<Feature> features;
  for (auto& feature : *dataset->GetLayer(0)) {
    Feature f;
    for (int i = 0; i < feature->GetFieldCount(); ++i) {
      const char* name = feature->GetFieldDefnRef(i)->GetNameRef();
      f.fields[name] = feature->GetFieldAsString(i);
      if (feature->GetFieldDefnRef(i)->GetType() == OFTReal) f.reals[name] = feature->GetFieldAsDouble(i);
    }
    if (const OGRGeometry* g = feature->GetGeometryRef(); g && wkbFlatten(g->getGeometryType()) == wkbPoint) {
      f.x = g->toPoint()->getX();
      f.y = g->toPoint()->getY();
    }
    features.push_back(f);
  }
  return features;
}

double number(const Feature& f, const std::string& name) {
  if (const auto real = f.reals.find(name); real != f.reals.end()) return real->second;
  const auto it = f.fields.find(name);
  return it == f.fields.end() ? std::nan("") : std::stod(it->second);
}

// At the points of a grid, the same numbers as `sage field --exact`, bit for
// bit, up to the second derivatives (a GeoPackage keeps doubles whole); by
// default within the far-field tolerance: the plate with a slot and two holes.
TEST(CliSample, EqualsTheFieldAtGridPoints) {
  const std::string model = std::string(SAGE_SOURCE_DIR) + "/examples/models/plate_with_holes.json";
  const fs::path vti = scratch("sample_plate.vti");
  const Result field = run("field " + model + " -o " + vti.string() + " --grid 23x13 --order 2 --exact");
  ASSERT_EQ(field.exit_code, 0) << field.output;
  const auto image = read_vti(vti);
  std::string csv = "id,x,y\n";
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p) {
    double at[3];
    image->GetPoint(p, at);
    char line[128];
    std::snprintf(line, sizeof line, "%lld,%.17g,%.17g\n", static_cast<long long>(p), at[0], at[1]);
    csv += line;
  }
  const std::string points = write_file("sample_plate_points.csv", csv);
  const fs::path out = scratch("sample_plate_out.gpkg");  // doubles kept whole
  const Result sample = run("sample " + model + " " + points + " -o " + out.string() + " --order 2 --exact");
  ASSERT_EQ(sample.exit_code, 0) << sample.output;
  EXPECT_NE(sample.output.find("299 points"), std::string::npos) << sample.output;
  EXPECT_NE(sample.output.find("coordinates: used as they are"), std::string::npos) << sample.output;
  EXPECT_NE(sample.output.find("exact evaluation"), std::string::npos) << sample.output;
  // By default, far-field patches (a 2D R-function field) within 1e-10 of the points' diagonal.
  const fs::path approximate = scratch("sample_plate_default.gpkg");
  const Result by_default = run("sample " + model + " " + points + " -o " + approximate.string());
  ASSERT_EQ(by_default.exit_code, 0) << by_default.output;
  EXPECT_NE(by_default.output.find("far-field approximation: patches within 1e-10 of the points' bounding box"),
            std::string::npos)
      << by_default.output;
  const std::vector<Feature> patched = read_layer(approximate);
  const std::vector<Feature> features = read_layer(out);
  ASSERT_EQ(features.size(), static_cast<std::size_t>(image->GetNumberOfPoints()));
  vtkDataArray* omega = image->GetPointData()->GetArray("omega");
  vtkDataArray* gradient = image->GetPointData()->GetArray("grad_omega");
  vtkDataArray* second = image->GetPointData()->GetArray("d2_omega");
  ASSERT_TRUE(omega && gradient && second);
  for (std::size_t p = 0; p < features.size(); ++p) {
    const Feature& f = features[p];
    const auto id = static_cast<vtkIdType>(p);
    EXPECT_EQ(f.fields.at("id"), std::to_string(p));
    EXPECT_EQ(number(f, "omega"), omega->GetComponent(id, 0)) << "point " << p;
    EXPECT_EQ(number(f, "grad_x"), gradient->GetComponent(id, 0)) << "point " << p;
    EXPECT_EQ(number(f, "grad_y"), gradient->GetComponent(id, 1)) << "point " << p;
    EXPECT_EQ(number(f, "d2_xy"), second->GetComponent(id, 1)) << "point " << p;
    EXPECT_NEAR(number(patched[p], "omega"), omega->GetComponent(id, 0), 1e-9) << "point " << p;
  }
}

// Longitude/latitude points, in a GeoJSON layer and in a CSV file told
// its CRS, go through the projection the polygons went through: the
// island's own vertices sample omega = 0, a point on the island inside,
// one at sea outside. The output keeps the names and the coordinates.
TEST(CliSample, LongitudeLatitudePointsLandOnThePolygonsPlane) {
  const std::string model = std::string(SAGE_SOURCE_DIR) + "/examples/models/island_with_lake.geojson";
  const std::string geojson = write_file("sample_island_points.geojson", R"({ "type": "FeatureCollection",
    "features": [
      { "type": "Feature", "properties": { "name": "vertex" }, "geometry": { "type": "Point", "coordinates": [11.020, 56.996] } },
      { "type": "Feature", "properties": { "name": "vertex2" }, "geometry": { "type": "Point", "coordinates": [11.058, 57.040] } },
      { "type": "Feature", "properties": { "name": "land" }, "geometry": { "type": "Point", "coordinates": [11.004, 57.030] } },
      { "type": "Feature", "properties": { "name": "sea" }, "geometry": { "type": "Point", "coordinates": [11.100, 57.100] } } ] })");
  const fs::path gpkg = scratch("sample_island.gpkg");
  const Result sample = run("sample " + model + " " + geojson + " -o " + gpkg.string());
  ASSERT_EQ(sample.exit_code, 0) << sample.output;
  EXPECT_NE(sample.output.find("transformed into the model's plane"), std::string::npos) << sample.output;
  const std::vector<Feature> features = read_layer(gpkg);
  ASSERT_EQ(features.size(), 4u);
  EXPECT_EQ(features[2].fields.at("name"), "land");
  EXPECT_NEAR(features[1].x, 11.058, 1e-12);  // the geometry as it came
  EXPECT_NEAR(features[1].y, 57.040, 1e-12);
  EXPECT_LT(std::abs(number(features[0], "omega")), 1e-6) << "a vertex of the island (metres)";
  EXPECT_LT(std::abs(number(features[1], "omega")), 1e-6) << "a vertex of the island (metres)";
  EXPECT_GT(number(features[2], "omega"), 1.0);
  EXPECT_LT(number(features[3], "omega"), -1.0);
  EXPECT_NEAR(number(features[2], "grad_norm"),
              std::hypot(number(features[2], "grad_x"), number(features[2], "grad_y")), 1e-12);

  // The same places as lon/lat columns of a CSV: told its CRS, the same numbers; not told, a warning.
  const std::string csv = write_file("sample_island_points.csv",
                                     "name,lon,lat\nvertex,11.020,56.996\nvertex2,11.058,57.040\n"
                                     "land,11.004,57.030\nsea,11.100,57.100\n");
  const fs::path from_csv = scratch("sample_island_from_csv.csv");
  const Result told = run("sample " + model + " " + csv + " -o " + from_csv.string() + " --points-crs EPSG:4326");
  ASSERT_EQ(told.exit_code, 0) << told.output;
  const std::vector<Feature> rows = read_layer(from_csv);
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(number(rows[i], "omega"), number(features[i], "omega"),
                1e-9 * (1.0 + std::abs(number(rows[i], "omega"))))
        << rows[i].fields.at("name");
  EXPECT_EQ(rows[3].fields.at("lon"), "11.1");
  const Result untold = run("sample " + model + " " + csv + " -o " + from_csv.string());
  EXPECT_EQ(untold.exit_code, 0) << untold.output;
  EXPECT_NE(untold.output.find("give --points-crs EPSG:4326"), std::string::npos) << untold.output;
}

// 3D: points with z on a 3D model, and a GeoJSON output from a CSV (the
// geometry as X, Y, Z columns is not needed: the CSV's columns are kept).
TEST(CliSample, ThreeDimensionalPointsNeedZ) {
  const std::string model = std::string(SAGE_SOURCE_DIR) + "/examples/models/primitives_3d.json";
  const std::string with_z = write_file("sample_3d.csv", "x,y,z\n0,0,0\n100,100,100\n");
  const fs::path out = scratch("sample_3d.geojson");
  const Result sample = run("sample " + model + " " + with_z + " -o " + out.string() + " --order 0");
  ASSERT_EQ(sample.exit_code, 0) << sample.output;
  const std::vector<Feature> features = read_layer(out);
  ASSERT_EQ(features.size(), 2u);
  EXPECT_LT(number(features[1], "omega"), 0.0);
  EXPECT_EQ(features[0].fields.count("grad_x"), 0u) << "order 0: omega only";
  const std::string flat = write_file("sample_flat.csv", "x,y\n0,0\n");
  const Result refused = run("sample " + model + " " + flat + " -o " + out.string());
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("sample_flat.csv: the model is 3D, and not every point has a z"), std::string::npos)
      << refused.output;
}

TEST(CliSample, BadPointFilesAreNamed) {
  const std::string model = std::string(SAGE_SOURCE_DIR) + "/examples/models/plate_with_holes.json";
  const std::string polygons = std::string(SAGE_SOURCE_DIR) + "/examples/models/island_with_lake.geojson";
  const fs::path out = scratch("sample_bad.csv");
  const Result not_points = run("sample " + model + " " + polygons + " -o " + out.string());
  EXPECT_EQ(not_points.exit_code, 1) << not_points.output;
  EXPECT_NE(not_points.output.find("island_with_lake.geojson: feature 0 is a Multi Polygon: sage sample reads points"),
            std::string::npos)
      << not_points.output;
  const std::string no_columns = write_file("sample_no_columns.csv", "a,b\n1,2\n");
  const Result columns = run("sample " + model + " " + no_columns + " -o " + out.string());
  EXPECT_EQ(columns.exit_code, 1) << columns.output;
  EXPECT_NE(columns.output.find("sample_no_columns.csv: feature 0 has no point (a CSV needs columns x and y"),
            std::string::npos)
      << columns.output;
  const std::string points = write_file("sample_ok.csv", "x,y\n0,0\n");
  const Result format = run("sample " + model + " " + points + " -o " + scratch("sample.xyz").string());
  EXPECT_EQ(format.exit_code, 1) << format.output;
  EXPECT_NE(format.output.find("sage writes points as .csv, .geojson"), std::string::npos) << format.output;
  const Result missing = run("sample " + model + " " + scratch("nowhere.csv").string() + " -o " + out.string());
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("nowhere.csv: GDAL cannot read it"), std::string::npos) << missing.output;
  const Result crs = run("sample " + model + " " + points + " -o " + out.string() + " --points-crs EPSG:999999");
  EXPECT_EQ(crs.exit_code, 1) << crs.output;
  EXPECT_NE(crs.output.find("--points-crs EPSG:999999: PROJ does not know"), std::string::npos) << crs.output;
  for (const char* misuse : {" --exact --tolerance 1e-8", " --tolerance 0.5"}) {
    const Result usage = run("sample " + model + " " + points + " -o " + out.string() + misuse);
    EXPECT_EQ(usage.exit_code, 2) << misuse << "\n" << usage.output;
    EXPECT_NE(usage.output.find("--tolerance"), std::string::npos) << usage.output;
  }
  const Result itself = run("sample " + model + " " + points + " -o " + points);
  EXPECT_EQ(itself.exit_code, 1) << itself.output;
  EXPECT_NE(itself.output.find("is the points file itself"), std::string::npos) << itself.output;
  EXPECT_TRUE(fs::exists(points));
  const std::string taken = write_file("sample_taken.csv", "x,y,omega\n0,0,1\n");
  const Result clash = run("sample " + model + " " + taken + " -o " + out.string());
  EXPECT_EQ(clash.exit_code, 1) << clash.output;
  EXPECT_NE(clash.output.find("already have an attribute named omega"), std::string::npos) << clash.output;
}

}  // namespace
