// The solver on exact CAD fields: the STEP block with a channel as
// accurate as the same block written as CSG, and a curved part (a
// spherical shell, Neumann data on its inner sphere) converging at the
// optimal rate. A tessellated field stalls at its chordal error instead.
#include <sage/problems/problem_file.hpp>
#include <sage/solver/poisson.hpp>

#include <gtest/gtest.h>
#include <cad_fixtures.hpp>
#include <test_files.hpp>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <variant>

namespace sage::problems {
namespace {

using test::write_scratch;

double l2_error(const std::string& problem, int degree, double cell_width) {
  const ProblemFile file = read_problem_file(problem);
  solver::SolverOptions options;
  options.degree = degree;
  options.cell_width = cell_width;
  options.estimate_condition = false;
  const auto solution = solver::solve_poisson<3>(std::get<solver::PoissonProblem>(file.physics), options);
  return solution.report.l2_error.value();
}

// u = e^x sin y + z^2: -laplace u = -2. Dirichlet data differ from the
// solution inside; the front and back carry its flux.
const char* const kExact = R"("exact": "exp(x)*sin(y) + z^2", "source": -2)";
const char* const kFlux = "\"flux\": \"exp(x)*cos(y)\"";
const char* const kMinusFlux = "\"flux\": \"-exp(x)*cos(y)\"";

TEST(CadExactSolve, StepBlockAsAccurateAsItsCsgAtDegree3) {
  const std::string step = (test::scratch_dir() / "block_solve.step").string();
  test::write_step(test::block_with_channel(), step);
  const std::string d = R"("type": "dirichlet", "value": "exp(x)*sin(y) + z^2")";
  const std::string from_step = write_scratch("block_step.json", std::string(R"({ "domain": ")") + step + R"(",
    "bounds": { "min": [-1, -1, 0], "max": [1, 1, 1] }, )" + kExact + R"(,
    "boundary": {
      "left": { )" + d + R"(, "faces": "plane normal -1 0 0" },
      "right": { )" + d + R"(, "faces": "plane normal 1 0 0" },
      "top": { )" + d + R"(, "faces": "plane normal 0 0 1" },
      "bottom": { )" + d + R"(, "faces": "plane normal 0 0 -1" },
      "channel": { )" + d + R"(, "faces": "cylinder radius 0.4" },
      "front": { "type": "neumann", )" + kMinusFlux + R"(, "faces": "plane normal 0 -1 0" },
      "back": { "type": "neumann", )" + kFlux + R"(, "faces": "plane normal 0 1 0" } } })");
  const std::string from_csg = write_scratch("block_csg.json", std::string(R"({ "domain": {
    "dimension": 3, "bounds": { "min": [-1, -1, 0], "max": [1, 1, 1] },
    "field": { "op": "difference", "args": [
      { "op": "intersection", "args": [
        { "name": "left", "primitive": "halfspace", "point": [-1, 0, 0], "normal": [-1, 0, 0] },
        { "name": "right", "primitive": "halfspace", "point": [1, 0, 0], "normal": [1, 0, 0] },
        { "name": "front", "primitive": "halfspace", "point": [0, -1, 0], "normal": [0, -1, 0] },
        { "name": "back", "primitive": "halfspace", "point": [0, 1, 0], "normal": [0, 1, 0] },
        { "name": "bottom", "primitive": "halfspace", "point": [0, 0, 0], "normal": [0, 0, -1] },
        { "name": "top", "primitive": "halfspace", "point": [0, 0, 1], "normal": [0, 0, 1] } ] },
      { "name": "channel", "primitive": "cylinder", "point": [0, 0, 0], "axis": [0, 0, 1], "radius": 0.4 } ] } },
    )") + kExact + R"(,
    "boundary": {
      "left": { )" + d + R"( }, "right": { )" + d + R"( }, "top": { )" +
                                                                   d + R"( },
      "bottom": { )" + d + R"( }, "channel": { )" + d + R"( },
      "front": { "type": "neumann", )" + kMinusFlux + R"( },
      "back": { "type": "neumann", )" + kFlux + R"( } } })");
  for (const int cells : {20, 32}) {
    const double h = 2.0 / cells;
    const double e_step = l2_error(from_step, 3, h), e_csg = l2_error(from_csg, 3, h);
    std::printf("block, degree 3, %d cells: L2 %.4e (STEP), %.4e (CSG)\n", cells, e_step, e_csg);
    EXPECT_LT(std::abs(e_step - e_csg), 0.1 * e_csg) << cells << " cells: STEP " << e_step << ", CSG " << e_csg;
    EXPECT_LT(e_csg, 2e-7) << cells << " cells";
  }
}

const char* const kInnerFlux = "\"-2*(x*exp(x)*sin(y) + y*exp(x)*cos(y) + 2*z^2)\"";

TEST(CadExactSolve, SphericalShellConvergesAtTheOptimalRate) {
  // The shell 0.5 < r < 1: u given on the outer sphere, its flux on the
  // inner one, whose outward normal (out of the solid) is -x/r.
  const std::string step = (test::scratch_dir() / "shell.step").string();
  test::write_step(BRepAlgoAPI_Cut(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 1.0).Shape(),
                                   BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 0.5).Shape())
                       .Shape(),
                   step);
  const std::string problem = write_scratch("shell.json", std::string(R"({ "domain": ")") + step + R"(",
    "bounds": { "min": [-1, -1, -1], "max": [1, 1, 1] }, )" + kExact +
                                                              R"(,
    "boundary": {
      "outer": { "type": "dirichlet", "value": "exp(x)*sin(y) + z^2", "faces": "sphere radius 1" },
      "inner": { "type": "neumann", "faces": "sphere radius 0.5",
                 "flux": )" + std::string(kInnerFlux) + " } } }");
  for (const int degree : {2, 3}) {
    const double coarse = l2_error(problem, degree, 2.0 / 8), fine = l2_error(problem, degree, 2.0 / 16);
    const double rate = std::log2(coarse / fine);
    std::printf("shell, degree %d: L2 %.3e (8 cells), %.3e (16 cells), rate %.2f\n", degree, coarse, fine, rate);
    EXPECT_GT(rate, degree + 1 - 0.3) << "degree " << degree << ": " << coarse << " -> " << fine;
  }
}

}  // namespace
}  // namespace sage::problems
