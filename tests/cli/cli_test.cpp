// The `sage` program end to end: it runs as a user runs it, and files it
// writes load in VTK with the named arrays and the right values. Bad input
// gives a message naming the file and place, and a non-zero exit. Each
// option that chooses what is read or built (--where, --feature, --layer,
// --crs, --repair, --no-certify, --orthogonalize, --rfunction) shows its
// effect in what sage prints or writes.

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

using namespace sage_cli_test;
using sage::test::test_data;

std::string model(const std::string& name) { return std::string(SAGE_SOURCE_DIR) + "/examples/models/" + name; }

TEST(Cli, HelpAndVersion) {
  const Result help = run("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("field"), std::string::npos);
  const Result version = run("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.output.rfind("sage ", 0), 0u);
  EXPECT_EQ(run("field --help").exit_code, 0);
}

TEST(Cli, FieldRoundTripThroughVtk) {
  // A disk of radius 0.5 centred at (0.25, 0): omega = (r^2 - |p - c|^2) / (2 r).
  const std::string m = write_file("disk.json", R"({"dimension": 2,
      "field": {"primitive": "disk", "center": [0.25, 0], "radius": 0.5}})");
  const fs::path out = scratch("disk.vtu");
  const Result r = run("field " + m + " -o " + out.string() + " --grid 21x11 --bounds -1,1,-0.5,0.5 --order 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  ASSERT_EQ(g->GetNumberOfPoints(), 21 * 11);
  vtkDataArray* omega = g->GetPointData()->GetArray("omega");
  vtkDataArray* grad = g->GetPointData()->GetArray("grad_omega");
  vtkDataArray* norm = g->GetPointData()->GetArray("grad_norm");
  vtkDataArray* d2 = g->GetPointData()->GetArray("d2_omega");
  ASSERT_TRUE(omega && grad && norm && d2);
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
    double p[3];
    g->GetPoint(i, p);
    const double dx = p[0] - 0.25, dy = p[1];
    EXPECT_NEAR(omega->GetTuple1(i), (0.25 - dx * dx - dy * dy) / 1.0, 1e-12);
    EXPECT_NEAR(grad->GetComponent(i, 0), -2 * dx, 1e-12);
    EXPECT_NEAR(grad->GetComponent(i, 1), -2 * dy, 1e-12);
    EXPECT_NEAR(norm->GetTuple1(i), 2 * std::hypot(dx, dy), 1e-12);
    EXPECT_NEAR(d2->GetComponent(i, 0), -2.0, 1e-12);
  }
}

// --order 0 writes values only (for contouring), the same values as
// --order 1 on the plate's R-function tree.
TEST(Cli, OrderZeroWritesValuesOnly) {
  struct Written {
    std::vector<double> omega;
    int arrays = 0;
  };
  auto sample = [](const std::string& order) {
    const fs::path out = scratch("plate_order" + order + ".vtu");
    const Result r =
        run("field " + model("plate_with_holes.json") + " -o " + out.string() + " --grid 41x31 -q --order " + order);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(out.c_str());
    reader->Update();
    Written w;
    vtkPointData* data = reader->GetOutput()->GetPointData();
    w.arrays = data->GetNumberOfArrays();
    if (vtkDataArray* omega = data->GetArray("omega"))
      for (vtkIdType i = 0; i < omega->GetNumberOfTuples(); ++i) w.omega.push_back(omega->GetTuple1(i));
    return w;
  };
  const Written zero = sample("0"), one = sample("1");
  EXPECT_EQ(zero.arrays, 1);  // omega alone
  EXPECT_EQ(one.arrays, 3);   // omega, grad_omega, grad_norm
  ASSERT_EQ(zero.omega.size(), 41u * 31u);
  ASSERT_EQ(one.omega.size(), zero.omega.size());
  for (std::size_t i = 0; i < zero.omega.size(); ++i)
    EXPECT_NEAR(zero.omega[i], one.omega[i], 1e-12 * (1 + std::abs(one.omega[i])));
}

TEST(Cli, SharpBoundedUnionHasItsLevelCOnTheCorner) {
  // G(X, Y) of the sharp bounded union with X = x, Y = y (issue 5): the
  // field G - C is 0 on the corner max(x, y) = C inside the transition zone
  // and x - C on the x axis.
  const std::string m = write_file("bounded_sharp.json", R"({"dimension": 2, "field": {"op": "iso_surface", "args": [
      {"op": "bounded_union", "sharp": true, "theta1_degrees": 20, "theta2_degrees": 70,
       "args": [{"formula": "x"}, {"formula": "y"}]}]}})");
  const fs::path out = scratch("bounded_sharp.vtu");
  const Result r = run("field " + m + " -o " + out.string() + " --grid 11x11 --bounds 0,1,0,1 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  vtkDataArray* omega = g->GetPointData()->GetArray("omega");
  ASSERT_TRUE(omega);
  int on_corner = 0;
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
    double p[3];
    g->GetPoint(i, p);
    const double theta = std::atan2(p[1], p[0]);
    const bool in_zone = theta >= 20 * M_PI / 180 && theta <= 70 * M_PI / 180;
    if (in_zone && std::abs(std::max(p[0], p[1]) - 0.5) < 1e-9) {
      EXPECT_NEAR(omega->GetTuple1(i), 0.0, 1e-12) << p[0] << ", " << p[1];
      ++on_corner;
    }
    if (p[1] == 0) {
      EXPECT_NEAR(omega->GetTuple1(i), p[0] - 0.5, 1e-12);
    }
  }
  EXPECT_EQ(on_corner, 7);  // (0.5, 0.2) ... (0.5, 0.5) ... (0.2, 0.5); (0.5, 0.1) is below 20 degrees
}

// A 3D field goes to image data (.vti): the grid of the model's bounds,
// and omega's sign is the solid's membership, (torus OR post) AND NOT
// scoop, at every grid point not within 1e-6 of a surface.
TEST(Cli, FieldWritesImageDataFor3D) {
  const fs::path out = scratch("torus.vti");
  const Result r = run("field " + model("primitives_3d.json") + " -o " + out.string() + " --grid 8x8x8 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto image = read_vti(out);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 8);
  EXPECT_EQ(dims[1], 8);
  EXPECT_EQ(dims[2], 8);
  double bounds[6];
  image->GetBounds(bounds);
  const double expected[6] = {-1.6, 1.6, -1.6, 1.6, -1.0, 1.0};  // the model's "bounds"
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(bounds[k], expected[k], 1e-12) << k;
  const std::vector<double> omega = point_values(image, "omega");
  ASSERT_EQ(omega.size(), 512u);
  ASSERT_TRUE(image->GetPointData()->GetArray("grad_omega"));
  int inside = 0, outside = 0;
  for (vtkIdType i = 0; i < 512; ++i) {
    double p[3];
    image->GetPoint(i, p);
    const double rho = std::hypot(p[0], p[1]);
    const double torus = 0.09 - (std::pow(rho - 1.1, 2) + p[2] * p[2]);   // > 0 inside
    const double post = std::min(0.25 - rho * rho, 0.64 - p[2] * p[2]);   // > 0 inside
    const double scoop = 0.2025 - (rho * rho + std::pow(p[2] - 0.9, 2));  // > 0 inside
    if (std::min({std::abs(torus), std::abs(post), std::abs(scoop)}) < 1e-6) continue;
    const bool solid = (torus > 0 || post > 0) && scoop < 0;
    EXPECT_EQ(omega[static_cast<std::size_t>(i)] > 0, solid) << p[0] << ", " << p[1] << ", " << p[2];
    (solid ? inside : outside) += 1;
  }
  EXPECT_GT(inside, 10);
  EXPECT_GT(outside, 100);
}

TEST(Cli, InfoSummarizesAModel) {
  const Result r = run("info " + model("paper004_fig9_solid.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dimension:   3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"cone\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("omega range"), std::string::npos) << r.output;
}

TEST(Cli, DemoWritesEveryFile) {
  const fs::path dir = scratch("demo");
  fs::remove_all(dir);
  const Result r = run("demo -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().extension() == ".vtu";
  // 13 fields, 2 heat solutions, the 2D bracket's stresses, and the STEP
  // bracket's where this sage reads CAD files.
  const bool cad = run("--version").output.find("OpenCASCADE") != std::string::npos;
  EXPECT_EQ(files, cad ? 17 : 16);
  // Each file holds what its job wrote: fields omega and derivatives up to
  // their order; the plate under min/max and R0 has one zero set but other
  // values; the heat solutions u; the bracket its stresses.
  for (const char* name : {"fig9_solid_r0.vtu", "island_with_lake.vtu", "plate_minmax.vtu", "plate_r0.vtu"}) {
    const auto g = read_vtu(dir / name);
    EXPECT_TRUE(g->GetPointData()->GetArray("omega") && g->GetPointData()->GetArray("grad_omega")) << name;
    double range[2] = {0, 0};
    if (vtkDataArray* omega = g->GetPointData()->GetArray("omega")) omega->GetRange(range);
    EXPECT_LT(range[0], 0.0) << name;
    EXPECT_GT(range[1], 0.0) << name;
  }
  EXPECT_TRUE(read_vtu(dir / "fig9_solid_r0.vtu")->GetPointData()->GetArray("d2_omega"));  // order 2
  const std::vector<double> minmax = point_values(read_vtu(dir / "plate_minmax.vtu"), "omega"),
                            r0 = point_values(read_vtu(dir / "plate_r0.vtu"), "omega");
  ASSERT_EQ(minmax.size(), r0.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < r0.size(); ++i) {
    differ += std::abs(minmax[i] - r0[i]) > 1e-6;
    if (std::abs(minmax[i]) > 1e-9 && std::abs(r0[i]) > 1e-9) {
      EXPECT_EQ(minmax[i] > 0, r0[i] > 0) << i;
    }
  }
  EXPECT_GT(differ, r0.size() / 10);
  for (const char* name : {"plate_heat.vtu", "block_with_hole.vtu"}) {
    const std::vector<double> u = point_values(read_vtu(dir / name), "u");
    ASSERT_FALSE(u.empty()) << name;
    EXPECT_GT(*std::max_element(u.begin(), u.end()), 0.0) << name;  // heated inside
  }
  for (const char* name : {"bracket.vtu", "cad_bracket_stress.vtu"}) {
    if (!cad && std::string(name) == "cad_bracket_stress.vtu") continue;
    const auto bracket = read_vtu(dir / name);
    for (const char* array : {"displacement", "stress", "von_mises"})
      EXPECT_TRUE(bracket->GetPointData()->GetArray(array)) << name << " " << array;
  }
}

// ---- bad input: message names the file and place, exit code non-zero ----------

void expect_failure(const std::string& args, std::initializer_list<std::string> pieces) {
  const Result r = run(args);
  EXPECT_NE(r.exit_code, 0) << args << "\n" << r.output;
  EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
  for (const auto& piece : pieces)
    EXPECT_NE(r.output.find(piece), std::string::npos) << "'" << piece << "' not in: " << r.output;
}

TEST(CliErrors, MalformedModel) {
  const std::string m = write_file("broken.json", "{\"dimension\": 2,\n \"field\": {\"formula\": }\n}");
  expect_failure("field " + m + " -o " + scratch("x.vtu").string(), {"broken.json", "line 2", "malformed JSON"});
}

TEST(CliErrors, BadSharpFlag) {
  const std::string m = write_file("bounded_bad.json", R"({"dimension": 2, "field": {"op": "bounded_union",
      "sharp": "yes", "args": [{"formula": "x"}, {"formula": "y"}]}})");
  expect_failure("field " + m + " -o " + scratch("x.vtu").string() + " --bounds 0,1,0,1",
                 {"bounded_bad.json", "/field/sharp", "true or false"});
}

TEST(CliErrors, UnknownPrimitive) {
  const std::string m = write_file("blob.json", R"({"dimension": 2, "field": {"primitive": "blob"}})");
  expect_failure("field " + m + " -o " + scratch("x.vtu").string() + " --bounds 0,1,0,1",
                 {"blob.json", "/field/primitive"});
}

TEST(CliErrors, UnknownOptionAndMissingOutput) {
  expect_failure("field " + model("plate_with_holes.json") + " -o x.vtu --colour red", {"colour"});
  expect_failure("field " + model("plate_with_holes.json"), {"output"});
  expect_failure("frobnicate", {"unknown command"});
}

TEST(CliErrors, BadOptionValues) {
  const std::string m = model("plate_with_holes.json");
  const std::string out = " -o " + scratch("x.vtu").string();
  expect_failure("field " + m + out + " --grid 20x", {"grid"});
  expect_failure("field " + m + out + " --grid 20x20x20", {"2D"});
  expect_failure("field " + m + out + " --bounds 1,0,0,1", {"max must exceed"});
  expect_failure("field " + m + out + " --bounds 0,nan,0,1", {"bounds"});
  expect_failure("field " + m + out + " --order 9", {"--order"});
  expect_failure("field " + m + out + " --order -1", {"--order"});
  expect_failure("field " + m + out + " --rfunction rp:5", {"--rfunction", "even"});
  expect_failure("field " + m + " -o " + scratch("x.png").string(), {".vtu, .vti or .tif"});
}

TEST(CliErrors, UnwritableOutput) {
  expect_failure("field " + model("plate_with_holes.json") + " -o /nonexistent-folder/x.vtu -q",
                 {"/nonexistent-folder/x.vtu"});
}

TEST(CliErrors, MissingModelFileAndBounds) {
  expect_failure("field /nonexistent/m.json -o " + scratch("x.vtu").string(), {"/nonexistent/m.json"});
  const std::string m = write_file("nobounds.json", R"({"dimension": 2, "field": {"formula": "x"}})");
  expect_failure("field " + m + " -o " + scratch("x.vtu").string(), {"nobounds.json", "--bounds"});
}

TEST(CliErrors, FieldOutsideItsDomainIsReportedNotWritten) {
  const std::string m = write_file("log.json", R"js({"dimension": 2, "field": {"formula": "log(x)"}})js");
  expect_failure("field " + m + " -o " + scratch("x.vtu").string() + " --bounds -1,1,-1,1 -q",
                 {"log.json", "not finite"});
}

}  // namespace

// ---- GIS data and meshes from the command line -----------------------------------

namespace {

TEST(CliGeometry, GeoJsonFieldAndInfoReportTheProjection) {
  const fs::path out = scratch("island.vtu");
  const Result r =
      run("field " + test_data("gis/washington_island_wi_osm.geojson") + " -o " + out.string() + " --grid 40x40 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  vtkDataArray* omega = reader->GetOutput()->GetPointData()->GetArray("omega");
  ASSERT_TRUE(omega);
  double range[2];
  omega->GetRange(range);
  EXPECT_LT(range[0], 0.0);  // the grid covers water and land
  EXPECT_GT(range[1], 0.0);
  const Result info = run("info " + test_data("gis/washington_island_wi_osm.geojson"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("azimuthal equidistant"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("certified well-formed"), std::string::npos) << info.output;
}

// sage field approximates the far field by default, says so, and records
// it in the file; --exact evaluates exactly. Both agree within the stated
// tolerance and in sign.
TEST(CliGeometry, FarFieldApproximationIsTheDefaultAndRecorded) {
  const std::string lake = test_data("gis/lake_vanern_se_osm_EPSG32633.geojson");
  struct Sampled {
    std::string evaluation;
    double tolerance = -1;
    std::vector<double> omega;
  };
  auto sample = [&](const std::string& flags, const std::string& expected_line) {
    const fs::path out = scratch("lake" + std::to_string(flags.size()) + ".vtu");
    const Result r = run("field " + lake + " -o " + out.string() + " --grid 60x60" + flags);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(expected_line), std::string::npos) << r.output;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(out.c_str());
    reader->Update();
    Sampled s;
    vtkFieldData* field = reader->GetOutput()->GetFieldData();
    if (auto* e = vtkStringArray::SafeDownCast(field->GetAbstractArray("evaluation"))) s.evaluation = e->GetValue(0);
    if (vtkDataArray* t = field->GetArray("far_field_tolerance")) s.tolerance = t->GetTuple1(0);
    vtkDataArray* omega = reader->GetOutput()->GetPointData()->GetArray("omega");
    for (vtkIdType i = 0; omega && i < omega->GetNumberOfTuples(); ++i) s.omega.push_back(omega->GetTuple1(i));
    return s;
  };
  const Sampled approximate = sample("", "far-field approximation: patches within 1e-10 of the grid box's diagonal");
  const Sampled exact = sample(" --exact", "exact evaluation");
  EXPECT_NE(approximate.evaluation.find("far-field"), std::string::npos);
  EXPECT_EQ(exact.evaluation, "exact");
  EXPECT_EQ(exact.tolerance, 0.0);
  ASSERT_GT(approximate.tolerance, 0.0);
  ASSERT_EQ(approximate.omega.size(), 3600u);
  ASSERT_EQ(exact.omega.size(), 3600u);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < exact.omega.size(); ++i) {
    EXPECT_LE(std::abs(approximate.omega[i] - exact.omega[i]), approximate.tolerance) << "point " << i;
    EXPECT_EQ(approximate.omega[i] > 0, exact.omega[i] > 0) << "point " << i;
    differ += approximate.omega[i] != exact.omega[i];
  }
  EXPECT_GT(differ, 0u);  // the patches were used
  expect_failure("field " + lake + " -o " + scratch("x.vtu").string() + " --exact --tolerance 1e-9",
                 {"--exact or --tolerance"});
  // 3D and min/max fields are exact by default (patches would not pay).
  const Result solid =
      run("field " + model("primitives_3d.json") + " -o " + scratch("solid.vti").string() + " --grid 8x8x8");
  EXPECT_NE(solid.output.find("exact evaluation"), std::string::npos) << solid.output;
}

/// Where `sage info` says longitude/latitude data was projected: the
/// centre (lat, lon) of the local azimuthal equidistant projection, the
/// middle of the selected features' longitude/latitude box; NaN when absent.
std::pair<double, double> projection_centre(const std::string& info) {
  return {number_after(info, "centred on lat "), number_after(info, ", lon ")};
}

/// The area where omega > 0 in a 2D field file: points inside times the
/// area of a grid cell (point spacing in x times in y).
double area_inside(const fs::path& file) {
  const auto g = read_vtu(file);
  const std::vector<double> omega = point_values(g, "omega");
  double b[6];
  g->GetBounds(b);
  const double n = std::sqrt(static_cast<double>(omega.size()));  // square grids only
  const double cell = (b[1] - b[0]) / (n - 1) * (b[3] - b[2]) / (n - 1);
  return static_cast<double>(std::count_if(omega.begin(), omega.end(), [](double w) { return w > 0; })) * cell;
}

// --where "NAME = 'Ashe'" selects Ashe County alone: the projection is
// centred on Ashe's box (lat 36.412, lon -81.490; its neighbour Alleghany
// lies at lon -81.13, the state's middle at lon -79.4), the model is one
// polygon, and the B-rep field's inside has Ashe's area, 1,137 km^2 (by
// the same count: Alleghany 611, Surry 1,423, all 100 counties 127,000).
TEST(CliGeometry, ShapefileWhereAndBrep) {
  const std::string nc = test_data("gis/shapefile_nc/nc.shp"), ashe = " --where \"NAME = 'Ashe'\"";
  const Result r = run("info " + nc + ashe + " --method brep");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("trimmed-edge B-rep"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(1 polygon(s), 0 hole(s), 26 edges)"), std::string::npos) << r.output;
  const auto [lat, lon] = projection_centre(r.output);
  EXPECT_NEAR(lat, 36.412, 0.005) << r.output;
  EXPECT_NEAR(lon, -81.490, 0.005) << r.output;
  const fs::path out = scratch("ashe.vtu");
  const Result field = run("field " + nc + ashe + " --method brep -o " + out.string() + " --grid 150x150 -q");
  ASSERT_EQ(field.exit_code, 0) << field.output;
  const double km2 = area_inside(out) / 1e6;
  std::cout << "[ Ashe ] " << km2 << " km^2\n";
  EXPECT_NEAR(km2, 1137, 35);
}

// --feature picks features by their 0-based index: 0 is Ashe (the same
// county as --where "NAME = 'Ashe'"), 2 is Surry (centred 0.79 degrees
// east); several are united; an index past the end names the count.
TEST(CliGeometry, FeatureSelectsFeaturesByIndex) {
  const std::string nc = test_data("gis/shapefile_nc/nc.shp");
  const Result by_name = run("info " + nc + " --where \"NAME = 'Ashe'\"");
  const Result first = run("info " + nc + " --feature 0");
  const Result third = run("info " + nc + " --feature 2");
  for (const Result* r : {&by_name, &first, &third}) ASSERT_EQ(r->exit_code, 0) << r->output;
  EXPECT_EQ(projection_centre(first.output), projection_centre(by_name.output)) << first.output;
  EXPECT_NE(first.output.find("26 edges"), std::string::npos) << first.output;
  const auto [lat, lon] = projection_centre(third.output);
  EXPECT_NEAR(lat, 36.40, 0.01) << third.output;
  EXPECT_NEAR(lon, -80.70, 0.01) << third.output;
  EXPECT_NE(third.output.find("27 edges"), std::string::npos) << third.output;
  const Result three = run("info " + nc + " --feature 0 1 2");
  ASSERT_EQ(three.exit_code, 0) << three.output;
  EXPECT_NE(three.output.find("united 3 features"), std::string::npos) << three.output;
  expect_failure("info " + nc + " --feature 100", {"nc.shp", "--feature 100", "the layer has 100 features"});
}

/// Writes a GeoPackage of one polygon per layer (UTM 33N, metres), with
/// GDAL's C++ API: each layer a name and its ring's (x, y) corners.
std::string write_geopackage(
    const std::string& name,
    const std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>>& layers) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!driver) throw std::runtime_error("GDAL has no GPKG driver");
  const fs::path path = scratch(name);
  fs::remove(path);
  GDALDatasetUniquePtr dataset(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!dataset) throw std::runtime_error("cannot create " + path.string());
  OGRSpatialReference utm;
  utm.importFromEPSG(32633);
  for (const auto& [layer_name, corners] : layers) {
    OGRLayer* layer = dataset->CreateLayer(layer_name.c_str(), &utm, wkbPolygon, nullptr);
    if (!layer) throw std::runtime_error("cannot create layer " + layer_name);
    OGRLinearRing ring;
    for (const auto& [x, y] : corners) ring.addPoint(x, y);
    ring.closeRings();
    OGRPolygon polygon;
    polygon.addRing(&ring);
    OGRFeatureUniquePtr feature(OGRFeature::CreateFeature(layer->GetLayerDefn()));
    feature->SetGeometry(&polygon);
    if (layer->CreateFeature(feature.get()) != OGRERR_NONE) throw std::runtime_error("cannot write " + layer_name);
  }
  return path.string();
}

// --layer picks a layer of a file that holds several: a GeoPackage written
// here with a square (4 edges, 1 km) in its first layer and a triangle (3
// edges, 3 km wide) in its second. Without --layer the first is read; a
// name no layer has is an error naming it.
TEST(CliGeometry, LayerSelectsALayerOfAGeoPackage) {
  const std::string gpkg = write_geopackage(
      "two_layers.gpkg", {{"square", {{500000, 6500000}, {501000, 6500000}, {501000, 6501000}, {500000, 6501000}}},
                          {"triangle", {{510000, 6500000}, {513000, 6500000}, {511500, 6502000}}}});
  const Result first = run("info " + gpkg);
  const Result square = run("info " + gpkg + " --layer square");
  const Result triangle = run("info " + gpkg + " --layer triangle");
  for (const Result* r : {&first, &square, &triangle}) ASSERT_EQ(r->exit_code, 0) << r->output;
  EXPECT_NE(first.output.find("(1 polygon(s), 0 hole(s), 4 edges)"), std::string::npos) << first.output;
  EXPECT_NE(square.output.find("(1 polygon(s), 0 hole(s), 4 edges)"), std::string::npos) << square.output;
  EXPECT_NE(triangle.output.find("(1 polygon(s), 0 hole(s), 3 edges)"), std::string::npos) << triangle.output;
  // The bounds: the triangle's box with a margin of 5% of its diagonal (3,606 m).
  // (Printed to 6 digits: to the metre here.)
  EXPECT_NEAR(number_after(triangle.output, "bounds:      ["), 510000 - 0.05 * std::hypot(3000, 2000), 1)
      << triangle.output;
  EXPECT_NEAR(number_after(square.output, "bounds:      ["), 500000 - 0.05 * std::hypot(1000, 1000), 1)
      << square.output;
  expect_failure("info " + gpkg + " --layer circle", {"two_layers.gpkg", "no layer named \"circle\""});
}

// --crs names the data's coordinate system: North Carolina's shapefile
// without its .prj is taken as planar (with a warning: the numbers look
// like degrees), its "area" then in square degrees; with --crs EPSG:4267
// (NAD27, what the .prj says) it is projected and Ashe has its area,
// 1,137 km^2. On a file with a system of its own, --crs replaces it, and says so.
TEST(CliGeometry, CrsOptionSetsTheCoordinateSystem) {
  const fs::path folder = scratch("noprj");
  fs::create_directories(folder);
  for (const char* ext : {".shp", ".shx", ".dbf"})
    fs::copy_file(test_data(std::string("gis/shapefile_nc/nc") + ext), folder / (std::string("nc") + ext),
                  fs::copy_options::overwrite_existing);
  const std::string nc = (folder / "nc.shp").string() + " --where \"NAME = 'Ashe'\"";
  const Result planar = run("info " + nc);
  const Result nad27 = run("info " + nc + " --crs EPSG:4267");
  ASSERT_EQ(planar.exit_code, 0) << planar.output;
  ASSERT_EQ(nad27.exit_code, 0) << nad27.output;
  EXPECT_NE(planar.output.find("assumed planar"), std::string::npos) << planar.output;
  EXPECT_NE(planar.output.find("give --crs EPSG:4326"), std::string::npos) << planar.output;
  EXPECT_NE(nad27.output.find("longitude/latitude (NAD27) projected to azimuthal equidistant"), std::string::npos)
      << nad27.output;
  EXPECT_EQ(nad27.output.find("assumed planar"), std::string::npos) << nad27.output;
  EXPECT_NEAR(projection_centre(nad27.output).second, -81.490, 0.005) << nad27.output;
  const fs::path degrees = scratch("ashe_degrees.vtu"), metres = scratch("ashe_metres.vtu");
  ASSERT_EQ(run("field " + nc + " -o " + degrees.string() + " --grid 150x150 -q").exit_code, 0);
  ASSERT_EQ(run("field " + nc + " --crs EPSG:4267 -o " + metres.string() + " --grid 150x150 -q").exit_code, 0);
  EXPECT_NEAR(area_inside(degrees), 0.114, 0.01);    // the shapefile's AREA attribute for Ashe
  EXPECT_NEAR(area_inside(metres) / 1e6, 1137, 35);  // km^2
  const Result replaced = run("info " + test_data("gis/washington_island_wi_osm.geojson") + " --crs EPSG:4267");
  ASSERT_EQ(replaced.exit_code, 0) << replaced.output;
  EXPECT_NE(replaced.output.find("longitude/latitude (NAD27) projected"), std::string::npos) << replaced.output;
  EXPECT_NE(replaced.output.find("--crs in place of the file's WGS 84"), std::string::npos) << replaced.output;
  expect_failure("info " + nc + " --crs EPSG:99999", {"--crs EPSG:99999", "PROJ does not know"});
}

// --repair on the command line: a bow-tie ring (its edges cross at
// (1000, 1000)) is refused without it, naming the crossing and --repair;
// with it, GEOS makes it two triangles of 1 km^2 each, and the field's
// inside has their area.
TEST(CliGeometry, RepairFlagMakesInvalidPolygonsValid) {
  const std::string bowtie = write_file("bowtie.geojson", R"({"type": "FeatureCollection",
      "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}},
      "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
        "coordinates": [[[0, 0], [2000, 2000], [2000, 0], [0, 2000], [0, 0]]]}}]})");
  expect_failure("info " + bowtie, {"bowtie.geojson", "edges cross", "--repair"});
  const Result r = run("info " + bowtie + " --repair");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("feature 0 was invalid and was repaired"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(2 polygon(s), 0 hole(s), 6 edges)"), std::string::npos) << r.output;
  const fs::path out = scratch("bowtie.vtu");
  const Result field = run("field " + bowtie + " --repair -o " + out.string() + " --grid 200x200 -q");
  ASSERT_EQ(field.exit_code, 0) << field.output;
  EXPECT_NEAR(area_inside(out), 2e6, 0.02 * 2e6);
}

// sage info certifies a polygon's CSG field well-formed by default and
// prints the certificate; --no-certify skips it.
TEST(CliGeometry, NoCertifySkipsTheCertificate) {
  const std::string island = test_data("gis/washington_island_wi_osm_EPSG3070.geojson");
  const Result certified = run("info " + island);
  const Result skipped = run("info " + island + " --no-certify");
  ASSERT_EQ(certified.exit_code, 0) << certified.output;
  ASSERT_EQ(skipped.exit_code, 0) << skipped.output;
  EXPECT_NE(certified.output.find("certified well-formed: no zeros of omega farther than"), std::string::npos)
      << certified.output;
  EXPECT_EQ(skipped.output.find("certified"), std::string::npos) << skipped.output;
  EXPECT_NE(skipped.output.find("method: well-formed CSG"), std::string::npos) << skipped.output;
}

TEST(CliGeometry, InvalidGisDataNamesTheVertexAndSuggestsRepair) {
  expect_failure("info " + test_data("gis/greece_ne10m.geojson"), {"greece_ne10m.geojson", "vertex", "--repair"});
}

// A mesh's trimmed-face field: far faces in single precision by default
// from 1,024 triangles up (a 3,290-triangle STL part), said and recorded
// with the deviation measured (at sample points), every value within 1e-9
// of the diagonal of --exact's and of the same sign; --exact turns it off;
// smaller meshes run exactly (joint, 446).
TEST(CliGeometry, MeshField) {
  const fs::path out = scratch("joint.vti");
  const Result r = run("field " + test_data("meshes/joint.off") + " -o " + out.string() + " --grid 10x10x10 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  {
    const auto joint = read_vti(out);
    int dims[3];
    joint->GetDimensions(dims);
    EXPECT_EQ(dims[0] * dims[1] * dims[2], 1000);
    const std::vector<double> omega = point_values(joint, "omega");
    ASSERT_EQ(omega.size(), 1000u);
    // The box reaches 10% of the diagonal beyond the mesh: its corners are outside.
    for (const vtkIdType corner : {0, 9, 90, 99, 900, 909, 990, 999})
      EXPECT_LT(omega[static_cast<std::size_t>(corner)], 0.0) << corner;
    EXPECT_GT(*std::max_element(omega.begin(), omega.end()), 0.0);
  }
  auto evaluation = [](const fs::path& file, double& deviation) {
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    vtkFieldData* field = reader->GetOutput()->GetFieldData();
    vtkDataArray* measured = field->GetArray("far_faces_deviation");
    deviation = measured ? measured->GetTuple1(0) : -1;
    auto* e = vtkStringArray::SafeDownCast(field->GetAbstractArray("evaluation"));
    return e ? e->GetValue(0) : std::string();
  };
  const std::string part = test_data("meshes/occt_sh1.stl");
  const fs::path fast_out = scratch("part_fast.vti"), exact_out = scratch("part_exact.vti");
  const Result fast = run("field " + part + " -o " + fast_out.string() + " --grid 16x16x16");
  EXPECT_NE(fast.output.find("far mesh faces in single precision"), std::string::npos) << fast.output;
  double deviation = -1;
  EXPECT_NE(evaluation(fast_out, deviation).find("far mesh faces"), std::string::npos);
  EXPECT_GE(deviation, 0.0);
  EXPECT_LT(deviation, 1e-9);
  const Result exact = run("field " + part + " -o " + exact_out.string() + " --grid 16x16x16 --exact");
  EXPECT_NE(exact.output.find("exact evaluation"), std::string::npos) << exact.output;
  double none = 0;
  EXPECT_EQ(evaluation(exact_out, none), "exact");
  EXPECT_EQ(none, -1);
  {
    const auto a = read_vti(fast_out), b = read_vti(exact_out);
    const std::vector<double> approximate = point_values(a, "omega"), exact_omega = point_values(b, "omega");
    ASSERT_EQ(approximate.size(), 4096u);
    ASSERT_EQ(exact_omega.size(), 4096u);
    double box[6];
    b->GetBounds(box);
    const double diagonal = std::hypot(box[1] - box[0], box[3] - box[2], box[5] - box[4]);
    int inside = 0;
    for (std::size_t i = 0; i < exact_omega.size(); ++i) {
      EXPECT_LE(std::abs(approximate[i] - exact_omega[i]), 1e-9 * diagonal) << i;
      EXPECT_EQ(approximate[i] > 0, exact_omega[i] > 0) << i;
      inside += exact_omega[i] > 0;
    }
    EXPECT_GT(inside, 20);
    EXPECT_LT(inside, 4096 - 20);
  }
  const Result small = run("field " + test_data("meshes/joint.off") + " -o " + out.string() + " --grid 16x16x16");
  EXPECT_NE(small.output.find("exact evaluation"), std::string::npos) << small.output;
  EXPECT_EQ(evaluation(out, deviation), "exact");
  const Result info = run("info " + part);
  EXPECT_NE(info.output.find("single precision"), std::string::npos) << info.output;
  expect_failure("field " + write_file("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n") + " -o " + out.string(), {"bad.off"});
}

/// An L-shaped prism, ([0, 2] x [0, 1] OR [0, 1] x [0, 2]) x [0, 1], as an OFF file.
std::string write_l_prism(const std::string& name) {
  return write_file(name,
                    "OFF\n12 8 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n"
                    "0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n"
                    "6 5 4 3 2 1 0\n6 6 7 8 9 10 11\n4 0 1 7 6\n4 1 2 8 7\n"
                    "4 2 3 9 8\n4 3 4 10 9\n4 4 5 11 10\n4 5 0 6 11\n");
}

/// Checks omega's sign in a .vti of the L-shaped prism against membership
/// at the grid points off its surface; returns how many were checked.
int expect_l_prism_signs(const fs::path& file) {
  const auto image = read_vti(file);
  const std::vector<double> omega = point_values(image, "omega");
  int checked = 0;
  for (vtkIdType i = 0; i < static_cast<vtkIdType>(omega.size()); ++i) {
    double p[3];
    image->GetPoint(i, p);
    auto within = [](double v, double lo, double hi) { return v > lo + 1e-9 && v < hi - 1e-9; };
    auto beyond = [](double v, double lo, double hi) { return v < lo - 1e-9 || v > hi + 1e-9; };
    const bool inside = within(p[2], 0, 1) &&
                        ((within(p[0], 0, 2) && within(p[1], 0, 1)) || (within(p[0], 0, 1) && within(p[1], 0, 2)));
    const bool outside =
        beyond(p[2], 0, 1) || beyond(p[0], 0, 2) || beyond(p[1], 0, 2) || (p[0] > 1 + 1e-9 && p[1] > 1 + 1e-9);
    if (!inside && !outside) continue;
    EXPECT_EQ(omega[static_cast<std::size_t>(i)] > 0, inside)
        << file.filename() << " at " << p[0] << ", " << p[1] << ", " << p[2];
    ++checked;
  }
  return checked;
}

// A non-convex mesh (an L-shaped prism) reaches the convex deficiency CSG
// through sage info and sage field --method csg --rfunction.
TEST(CliGeometry, NonConvexMeshCsg) {
  const std::string path = write_l_prism("l_prism.off");
  const Result info = run("info " + path + " --rfunction rp:2");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("convex deficiency decomposition"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("8 face planes (each used once) and 1 bridge"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("rp:2"), std::string::npos) << info.output;
  const fs::path out = scratch("l_prism.vti");
  const Result r = run("field " + path + " -o " + out.string() + " --method csg --grid 10x10x10 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The notch [1, 2] x [1, 2] is outside (a convex hull alone would fill it).
  EXPECT_GT(expect_l_prism_signs(out), 400);
}

// --orthogonalize reaches a mesh's trimmed-face (B-rep) field: info says
// so, and the field changes but keeps its sign (the L-shaped prism's
// membership at every grid point off its surface).
TEST(CliGeometry, OrthogonalizeChangesTheMeshBrepField) {
  const std::string path = write_l_prism("l_prism_brep.off");
  const Result plain_info = run("info " + path + " --method brep");
  const Result info = run("info " + path + " --method brep --orthogonalize");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_EQ(plain_info.output.find("orthogonalized"), std::string::npos) << plain_info.output;
  EXPECT_NE(info.output.find("triangle planes by their extruded regions, orthogonalized"), std::string::npos)
      << info.output;
  const fs::path plain = scratch("l_brep.vti"), orthogonal = scratch("l_brep_orthogonal.vti");
  ASSERT_EQ(run("field " + path + " --method brep -o " + plain.string() + " --grid 10x10x10 -q").exit_code, 0);
  ASSERT_EQ(run("field " + path + " --method brep --orthogonalize -o " + orthogonal.string() + " --grid 10x10x10 -q")
                .exit_code,
            0);
  EXPECT_GT(expect_l_prism_signs(plain), 400);
  EXPECT_GT(expect_l_prism_signs(orthogonal), 400);
  const std::vector<double> a = point_values(read_vti(plain), "omega"), b = point_values(read_vti(orthogonal), "omega");
  ASSERT_EQ(a.size(), b.size());
  double largest = 0;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  EXPECT_GT(largest, 1e-3);
}

// --rfunction chooses the R-function system of a model's operators: the
// intersection of the halfplanes x >= 0 and y >= 0 sampled on [0, 1]^2 is
// min(x, y) under minmax, x + y - sqrt(x^2 + y^2) under r0 (the model's
// default), that times (x^2 + y^2) under rm:2, and (x + y - sqrt(x^2 + y^2
// - x y)) / 1.5 under ralpha:0.5, at every point. info names the system,
// and render's colour map changes with it.
TEST(Cli, RFunctionOptionChoosesTheSystem) {
  const std::string m = write_file("quadrant.json", R"({"dimension": 2, "bounds": {"min": [0, 0], "max": [1, 1]},
      "field": {"op": "intersection", "args": [{"formula": "x"}, {"formula": "y"}]}})");
  struct System {
    std::string flag, name;
    double (*value)(double, double);
  };
  const System systems[] = {
      {"", "r0", [](double x, double y) { return x + y - std::hypot(x, y); }},
      {" --rfunction minmax", "minmax", [](double x, double y) { return std::min(x, y); }},
      {" --rfunction rm:2", "rm:2", [](double x, double y) { return (x + y - std::hypot(x, y)) * (x * x + y * y); }},
      {" --rfunction ralpha:0.5", "ralpha:0.5",
       [](double x, double y) { return (x + y - std::sqrt(x * x + y * y - x * y)) / 1.5; }},
  };
  for (const System& s : systems) {
    const fs::path out = scratch("quadrant.vtu");
    const Result r = run("field " + m + " -o " + out.string() + " --grid 11x11 -q --exact" + s.flag);
    ASSERT_EQ(r.exit_code, 0) << s.name << "\n" << r.output;
    const auto g = read_vtu(out);
    const std::vector<double> omega = point_values(g, "omega");
    ASSERT_EQ(omega.size(), 121u);
    for (vtkIdType i = 0; i < 121; ++i) {
      double p[3];
      g->GetPoint(i, p);
      EXPECT_NEAR(omega[static_cast<std::size_t>(i)], s.value(p[0], p[1]), 1e-12)
          << s.name << " at " << p[0] << ", " << p[1];
    }
    const Result info = run("info " + m + s.flag);
    EXPECT_NE(info.output.find("R-function:  " + s.name + " (default"), std::string::npos) << info.output;
  }
  const std::string r0_map = scratch("quadrant_r0.png").string(), minmax_map = scratch("quadrant_minmax.png").string();
  ASSERT_EQ(run("render " + m + " -o " + r0_map + " --size 40x40 -q").exit_code, 0);
  ASSERT_EQ(run("render " + m + " -o " + minmax_map + " --size 40x40 -q --rfunction minmax").exit_code, 0);
  std::ifstream a(r0_map, std::ios::binary), b(minmax_map, std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>()),
      bytes_b((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  EXPECT_GT(bytes_a.size(), 100u);
  EXPECT_TRUE(bytes_a != bytes_b) << "render ignored --rfunction";
}

}  // namespace
