// `sage solve` with "physics": "elasticity": Lame's cylinder written as a
// problem file gives a .vtu whose displacement, stress and von Mises
// arrays agree with the exact solution; the bundled bracket runs; bad
// input names the file and the place.

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace sage_cli_test;

/// Lame's cylinder 1 < r < 2 in plane strain (E = 1000, nu = 0.3, p = 1),
/// with `boundary` and `extra` top-level entries.
std::string cylinder_problem(const std::string& name, const std::string& boundary, const std::string& extra = "") {
  return write_file(name, R"({
  "physics": "elasticity",
  "domain": { "dimension": 2, "bounds": { "min": [-2, -2], "max": [2, 2] },
              "field": { "op": "difference", "args": [
                { "name": "outer", "primitive": "disk", "center": [0, 0], "radius": 2 },
                { "name": "inner", "primitive": "disk", "center": [0, 0], "radius": 1 } ] } },
  "E": 1000, "nu": 0.3, "plane": "strain",
  "boundary": )" + boundary + extra +
                              "\n}");
}

// u_r = A r + B / r with A = p a^2 (1 - 2 nu)(1 + nu) / (E (b^2 - a^2)), B = p a^2 b^2 (1 + nu) / (E (b^2 - a^2)).
constexpr double kA = 1.0 * 0.4 * 1.3 / (1000.0 * 3.0), kB = 4.0 * 1.3 / (1000.0 * 3.0);

TEST(CliSolveElasticity, LameCylinderMatchesItsExactSolution) {
  auto component = [](const char* axis) {
    return "\"" + std::to_string(kA) + " * " + axis + " + " + std::to_string(kB) + " * " + axis + " / (x^2 + y^2)\"";
  };
  const std::string exact = ", \"exact\": [" + component("x") + ", " + component("y") + "]";
  const std::string problem = cylinder_problem("lame.json", R"({ "inner": { "pressure": 1 } })", exact);
  const fs::path out = scratch("lame.vtu");
  const Result r = run("solve " + problem + " -o " + out.string() + " --cells 32");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* line : {"linear elasticity (plane strain)", "free body: 3 rigid motions", "energy norm",
                           "largest von Mises stress", "strain energy"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  vtkDataArray* u = g->GetPointData()->GetArray("displacement");
  vtkDataArray* stress = g->GetPointData()->GetArray("stress");
  vtkDataArray* mises = g->GetPointData()->GetArray("von_mises");
  vtkDataArray* error = g->GetPointData()->GetArray("displacement_error");
  ASSERT_TRUE(u && stress && mises && error && g->GetPointData()->GetArray("omega"));
  ASSERT_EQ(u->GetNumberOfComponents(), 3);
  ASSERT_EQ(stress->GetNumberOfComponents(), 6);
  std::size_t checked = 0;
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
    double p[3];
    g->GetPoint(i, p);
    const double r2 = p[0] * p[0] + p[1] * p[1];
    if (r2 < 1.1 * 1.1 || r2 > 1.9 * 1.9) continue;
    // sigma_rr = (1 - 4 / r^2) / 3, sigma_tt = (1 + 4 / r^2) / 3 (p a^2 / (b^2 - a^2) = 1/3).
    const double srr = (1 - 4 / r2) / 3, stt = (1 + 4 / r2) / 3, c = p[0] * p[0] / r2, s = p[1] * p[1] / r2;
    EXPECT_NEAR(stress->GetComponent(i, 0), srr * c + stt * s, 1e-3);
    EXPECT_NEAR(stress->GetComponent(i, 1), srr * s + stt * c, 1e-3);
    EXPECT_NEAR(stress->GetComponent(i, 2), 0.3 * (srr + stt), 1e-3);  // plane strain: sigma_zz = nu (srr + stt)
    EXPECT_NEAR(stress->GetComponent(i, 3), (srr - stt) * p[0] * p[1] / r2, 1e-3);
    const double ur = kA * std::sqrt(r2) + kB / std::sqrt(r2);
    EXPECT_NEAR(u->GetComponent(i, 0), ur * p[0] / std::sqrt(r2), 1e-6);
    EXPECT_NEAR(error->GetComponent(i, 1), 0.0, 1e-6);
    EXPECT_GE(mises->GetTuple1(i), 0.0);
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(CliSolveElasticity, BracketExamplesRun) {
  // The 3D angle bracket, coarse: bolted, so no free motion either.
  const Result solid = run("solve " + std::string(SAGE_SOURCE_DIR) + "/examples/problems/bracket_3d.json -o " +
                           scratch("bracket_3d.vtu").string() + " --degree 2 --cells 12");
  ASSERT_EQ(solid.exit_code, 0) << solid.output;
  EXPECT_NE(solid.output.find("3D linear elasticity"), std::string::npos) << solid.output;
  EXPECT_EQ(solid.output.find("free body"), std::string::npos) << solid.output;

  const Result r = run("solve " + std::string(SAGE_SOURCE_DIR) + "/examples/problems/bracket.json -o " +
                       scratch("bracket.vtu").string() + " --cells 48");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("plane stress"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("free body"), std::string::npos) << r.output;  // bolted: no free motion
}

TEST(CliSolveElasticity, MeshSolidUnderUniaxialTension) {
  // The cube [0,1]^3 as 12 triangles (OFF), rollers on x = 0, y = 0, z = 0
  // (selector formulas: a mesh names no parts), traction s on z = 1: the
  // uniaxial stress u = (-nu s x, -nu s y, s z) / E, linear, so reproduced
  // up to the solver's tolerance; cut cells come from the triangles.
  write_cube_off("tension_cube.off", 0, 1);
  const std::string problem = write_file("tension_cube.json", R"json({
  "physics": "elasticity",
  "domain": "tension_cube.off",
  "bounds": { "min": [-0.05, -0.05, -0.05], "max": [1.05, 1.05, 1.05] },
  "E": 200, "nu": 0.25,
  "boundary": {
    "left": { "selector": "x", "displacement": { "x": 0 } },
    "front": { "selector": "y", "displacement": { "y": 0 } },
    "bottom": { "selector": "z", "displacement": { "z": 0 } },
    "top": { "selector": "z - 1", "traction": [0, 0, 2] } },
  "exact": ["-0.0025*x", "-0.0025*y", "0.01*z"]
})json");
  const Result r = run("solve " + problem + " -o " + scratch("tension_cube.vtu").string() +
                       " --degree 2 --cells 5 --tolerance 1e-13");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto at = r.output.find("relative errors: L2 ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_LT(std::stod(r.output.substr(at + 20)), 1e-9) << r.output;
  EXPECT_NE(r.output.find("signed distance to the mesh"), std::string::npos) << r.output;
}

TEST(CliSolveElasticity, BadInputNamesFileAndPlace) {
  struct Case {
    std::string boundary, extra, expected;
  };
  const Case cases[] = {
      {R"({ "inner": { "pressure": 1 } })", R"(, "nu": 0.5)", "/nu"},
      {R"({ "inner": { "pressure": 1 } })", R"(, "E": -3)", "/E"},
      {R"({ "inner": { "pressure": 1, "displacement": { "x": 0 } } })", "", "not both"},
      {R"({ "lid": { "traction": [1, 0] } })", "", "unknown boundary part 'lid'"},
      {R"({ "outer": { "traction": [1, 0] } })", "", "unbalanced loads"},
      {R"({ "outer": { "displacement": { "w": 0 } } })", "", "/boundary/outer/displacement/w"},
      {R"({ "outer": { "traction": [1] } })", "", "/boundary/outer/traction"},
      {R"({ "inner": { "pressure": 1 } })", R"(, "plane": "membrane")", "/plane"},
      {R"({ "inner": { "pressure": 1 } })", R"(, "conductivity": 2)", "unknown key"},
  };
  int k = 0;
  for (const Case& c : cases) {
    // Later keys replace earlier ones in the JSON reader: "extra" overrides E, nu, plane.
    const std::string problem = cylinder_problem("bad_elastic_" + std::to_string(k++) + ".json", c.boundary, c.extra);
    const Result r = run("solve " + problem + " -o " + scratch("bad_elastic.vtu").string() + " --cells 8");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.expected << "\n" << r.output;
    EXPECT_NE(r.output.find(problem), std::string::npos) << r.output;
  }
}

}  // namespace
