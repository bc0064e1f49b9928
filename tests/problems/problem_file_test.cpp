// Problem files through the library, as a program that embeds sage reads
// them: the bundled heat plate and bracket become Poisson and elasticity
// problems that solve; bad files name the file and the place.
#include <sage/problems/problem_file.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

namespace sage::problems {
namespace {

std::string bundled(const std::string& name) { return std::string(SAGE_SOURCE_DIR) + "/examples/problems/" + name; }

/// The part called `name` (parts come in the JSON object's key order).
template <class Part>
const Part& part(const std::vector<Part>& parts, const std::string& name) {
  for (const Part& p : parts)
    if (p.name == name) return p;
  throw std::runtime_error("no part " + name);
}

TEST(ProblemFile, HeatPlateIsAPoissonProblem) {
  const ProblemFile file = read_problem_file(bundled("plate_heat.json"));
  ASSERT_TRUE(std::holds_alternative<solver::PoissonProblem>(file.physics));
  const solver::PoissonProblem& p = std::get<solver::PoissonProblem>(file.physics);
  EXPECT_EQ(file.domain().dimension, 2);
  EXPECT_EQ(p.domain.dimension, 2);
  ASSERT_EQ(p.parts.size(), 3u);
  EXPECT_EQ(part(p.parts, "left_hole").kind, solver::BoundaryKind::Robin);
  EXPECT_EQ(part(p.parts, "plate").kind, solver::BoundaryKind::Dirichlet);
  solver::SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.1;
  const auto solution = solver::solve_poisson<2>(p, options);
  EXPECT_GT(solution.report.unknowns, 100u);
}

TEST(ProblemFile, BracketIsAnElasticityProblem) {
  const ProblemFile file = read_problem_file(bundled("bracket.json"));
  ASSERT_TRUE(std::holds_alternative<solver::ElasticityProblem>(file.physics));
  const solver::ElasticityProblem& p = std::get<solver::ElasticityProblem>(file.physics);
  EXPECT_EQ(p.material.plane, solver::PlaneMode::Stress);
  EXPECT_DOUBLE_EQ(p.material.young, 70000.0);
  ASSERT_EQ(p.parts.size(), 3u);
  const solver::ElasticPart& bolt = part(p.parts, "lower_bolt");
  EXPECT_TRUE(bolt.fixes(0) && bolt.fixes(1) && !bolt.loaded);
  EXPECT_TRUE(part(p.parts, "load_hole").loaded);
  solver::SolverOptions options;
  options.degree = 2;
  options.cell_width = 4.0;
  const auto solution = solver::solve_elasticity<2>(p, options);
  ASSERT_TRUE(solution.report.elasticity);
  EXPECT_EQ(solution.report.elasticity->free_rigid_motions, 0);
  EXPECT_GT(solution.report.elasticity->max_von_mises, 0.0);
}

TEST(ProblemFile, BadFilesNameFileAndPlace) {
  const auto path = sage::test::scratch_dir() / "problem.json";
  std::ofstream(path) << R"({ "physics": "elasticity", "domain": { "dimension": 2,
      "bounds": { "min": [-1, -1], "max": [1, 1] },
      "field": { "name": "disk", "primitive": "disk", "center": [0, 0], "radius": 1 } },
      "E": 100, "nu": 0.3, "boundary": { "disk": { "pressure": "x +" } } })";
  try {
    read_problem_file(path.string());
    FAIL() << "no error";
  } catch (const ProblemError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("/boundary/disk/pressure"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace sage::problems
