// The `sage` program end to end: it runs as a user runs it, and files it
// writes load in VTK with the named arrays and the right values. Bad input
// gives a message naming the file and place, and a non-zero exit.

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

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

TEST(Cli, FieldWritesImageDataFor3D) {
  const fs::path out = scratch("torus.vti");
  const Result r = run("field " + model("primitives_3d.json") + " -o " + out.string() + " --grid 8x8x8 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(out), 0u);
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
  EXPECT_EQ(files, 16);  // 13 fields, 2 heat solutions and the bracket's stresses
  EXPECT_TRUE(fs::exists(dir / "island_with_lake.vtu"));
  EXPECT_TRUE(fs::exists(dir / "block_with_hole.vtu"));
  EXPECT_TRUE(fs::exists(dir / "bracket.vtu"));
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
  expect_failure("field " + m + " -o " + scratch("x.png").string(), {".vtu or .vti"});
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

TEST(CliGeometry, ShapefileWhereAndBrep) {
  const Result r = run("info " + test_data("gis/shapefile_nc/nc.shp") + " --where \"NAME = 'Ashe'\" --method brep");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("trimmed-edge B-rep"), std::string::npos) << r.output;
}

TEST(CliGeometry, InvalidGisDataNamesTheVertexAndSuggestsRepair) {
  expect_failure("info " + test_data("gis/greece_ne10m.geojson"), {"greece_ne10m.geojson", "vertex", "--repair"});
}

// A mesh's trimmed-face field: far faces in single precision by default
// from 1,024 triangles up (a 3,290-triangle STL part), said and recorded
// with the deviation measured; --exact turns it off; smaller meshes run
// exactly (joint, 446).
TEST(CliGeometry, MeshField) {
  const fs::path out = scratch("joint.vti");
  const Result r = run("field " + test_data("meshes/joint.off") + " -o " + out.string() + " --grid 10x10x10 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(out), 0u);
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
  const Result fast = run("field " + part + " -o " + out.string() + " --grid 16x16x16");
  EXPECT_NE(fast.output.find("far mesh faces in single precision"), std::string::npos) << fast.output;
  double deviation = -1;
  EXPECT_NE(evaluation(out, deviation).find("far mesh faces"), std::string::npos);
  EXPECT_GE(deviation, 0.0);
  EXPECT_LT(deviation, 1e-9);
  const Result exact = run("field " + part + " -o " + out.string() + " --grid 16x16x16 --exact");
  EXPECT_NE(exact.output.find("exact evaluation"), std::string::npos) << exact.output;
  EXPECT_EQ(evaluation(out, deviation), "exact");
  EXPECT_EQ(deviation, -1);
  const Result small = run("field " + test_data("meshes/joint.off") + " -o " + out.string() + " --grid 16x16x16");
  EXPECT_NE(small.output.find("exact evaluation"), std::string::npos) << small.output;
  EXPECT_EQ(evaluation(out, deviation), "exact");
  const Result info = run("info " + part);
  EXPECT_NE(info.output.find("single precision"), std::string::npos) << info.output;
  expect_failure("field " + write_file("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n") + " -o " + out.string(), {"bad.off"});
}

// A non-convex mesh (an L-shaped prism) reaches the convex deficiency CSG
// through sage info and sage field --method csg --rfunction.
TEST(CliGeometry, NonConvexMeshCsg) {
  const std::string path = write_file("l_prism.off",
                                      "OFF\n12 8 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n"
                                      "0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n"
                                      "6 5 4 3 2 1 0\n6 6 7 8 9 10 11\n4 0 1 7 6\n4 1 2 8 7\n"
                                      "4 2 3 9 8\n4 3 4 10 9\n4 4 5 11 10\n4 5 0 6 11\n");
  const Result info = run("info " + path + " --rfunction rp:2");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("convex deficiency decomposition"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("8 face planes (each used once) and 1 bridge"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("rp:2"), std::string::npos) << info.output;
  const fs::path out = scratch("l_prism.vti");
  const Result r = run("field " + path + " -o " + out.string() + " --method csg --grid 10x10x10 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(out), 0u);
}

}  // namespace
