// JSON CSG models: the bundled examples load and mean what they say, and
// every kind of bad input gives a ModelError naming the file and the place.

#include <sage/expression/primitives.hpp>
#include <sage/geometry/csg_model.hpp>
#include <sage/tape/evaluator.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace {

using sage::geometry::Model;
using sage::geometry::ModelError;
using sage::geometry::parse_model;

double value_at(const Model& m, std::array<double, 3> p) {
  const sage::Tape tape(m.field, m.dimension);
  sage::Evaluator<double> eval(tape);
  return eval.at(p);
}

// Expects parse_model(text) to fail with a message containing every piece.
void expect_error(const std::string& text, std::initializer_list<std::string> pieces) {
  try {
    parse_model(text, "bad.json");
    FAIL() << "no error for: " << text;
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("bad.json: ", 0), 0u) << what;
    for (const auto& piece : pieces)
      EXPECT_NE(what.find(piece), std::string::npos) << "'" << piece << "' not in: " << what;
  }
}

TEST(CsgModel, DiskHasTheDistanceFieldNearItsBoundary) {
  const Model m =
      parse_model(R"({"dimension": 2, "field": {"primitive": "disk", "center": [1, 2], "radius": 0.5}})", "t");
  EXPECT_NEAR(value_at(m, {1, 2, 0}), 0.25, 1e-15);  // (r^2 - 0) / 2r
  EXPECT_NEAR(value_at(m, {1.5, 2, 0}), 0.0, 1e-15);
  EXPECT_LT(value_at(m, {3, 3, 0}), 0.0);
}

TEST(CsgModel, OperatorsFollowSetSemantics) {
  const Model m = parse_model(R"({
    "dimension": 2, "rfunction": "r0",
    "field": {"op": "difference", "args": [
      {"primitive": "rectangle", "min": [-2, -1], "max": [2, 1]},
      {"name": "hole", "primitive": "disk", "center": [0, 0], "radius": 0.5}]}})",
                              "t");
  EXPECT_GT(value_at(m, {1.5, 0, 0}), 0.0);           // plate
  EXPECT_LT(value_at(m, {0.1, 0, 0}), 0.0);           // hole
  EXPECT_LT(value_at(m, {3, 0, 0}), 0.0);             // outside
  EXPECT_NEAR(value_at(m, {0.5, 0, 0}), 0.0, 1e-12);  // hole boundary
  EXPECT_TRUE(m.named.count("hole"));
  ASSERT_EQ(m.primitives.size(), 2u);
  EXPECT_EQ(m.primitives[1].pointer, "/field/args/1");
}

TEST(CsgModel, NodeRFunctionOverridesTheDefaultAndOptionsOverrideTheModel) {
  const std::string text = R"({"dimension": 2, "rfunction": "minmax",
    "field": {"op": "intersection", "args": [{"formula": "x"}, {"formula": "y"}]}})";
  const Model minmax = parse_model(text, "t");
  EXPECT_DOUBLE_EQ(value_at(minmax, {1, 2, 0}), 1.0);
  sage::geometry::ModelOptions options;
  options.rfunction = sage::RSystem::r0();
  const Model r0 = parse_model(text, "t", options);
  EXPECT_NEAR(value_at(r0, {1, 2, 0}), 3.0 - std::sqrt(5.0), 1e-15);
}

TEST(CsgModel, FormulaInsideNegativeFlipsTheSign) {
  const Model m =
      parse_model(R"({"dimension": 3, "field": {"formula": "x^2 + y^2 + z^2 - 1", "inside": "negative"}})", "t");
  EXPECT_DOUBLE_EQ(value_at(m, {0, 0, 0}), 1.0);
}

TEST(CsgModel, RefReusesANamedNode) {
  const Model m = parse_model(R"({"dimension": 2, "field": {"op": "union", "args": [
      {"name": "a", "primitive": "disk", "center": [0, 0], "radius": 1},
      {"ref": "a"}]}})",
                              "t");
  EXPECT_EQ(m.field.arg(0).id(), m.field.arg(1).id());
}

TEST(CsgModel, EveryBundledExampleLoadsAndIsFiniteOverItsBounds) {
  const std::filesystem::path folder = std::filesystem::path(SAGE_SOURCE_DIR) / "examples" / "models";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const Model m = sage::geometry::read_model(entry.path().string());
    ASSERT_TRUE(m.bounds.has_value()) << entry.path();
    const auto& b = *m.bounds;
    const std::array<double, 3> centre{(b.min[0] + b.max[0]) / 2, (b.min[1] + b.max[1]) / 2, (b.min[2] + b.max[2]) / 2};
    EXPECT_TRUE(std::isfinite(value_at(m, centre))) << entry.path();
  }
  EXPECT_GE(count, 8);
}

TEST(CsgModel, Figure9SolidContainsItsCoreAndExcludesTheBore) {
  const Model m =
      sage::geometry::read_model(std::string(SAGE_SOURCE_DIR) + "/examples/models/paper004_fig9_solid.json");
  EXPECT_GT(value_at(m, {0.6, 0.0, 0.3}), 0.0);
  EXPECT_LT(value_at(m, {0.0, 0.0, 0.3}), 0.0);   // in the bore
  EXPECT_LT(value_at(m, {0.6, 0.0, -0.1}), 0.0);  // below the bottom plane
  EXPECT_LT(value_at(m, {0.6, 0.0, 1.3}), 0.0);   // above the slanted top
}

// ---- bad input ---------------------------------------------------------------

TEST(CsgModelErrors, MalformedJsonNamesLineAndColumn) {
  expect_error("{\n  \"dimension\": 2,\n  \"field\": {\"formula\": \"x\",}\n}", {"line 3", "malformed JSON"});
}

TEST(CsgModelErrors, UnknownPrimitive) {
  expect_error(R"({"dimension": 2, "field": {"op": "union", "args": [{"primitive": "blob"}]}})",
               {"/field/args/0/primitive", "unknown primitive \"blob\""});
}

TEST(CsgModelErrors, MissingParameter) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0]}})", {"/field", "\"radius\""});
}

TEST(CsgModelErrors, WrongParameterType) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0], "radius": "big"}})",
               {"/field/radius", "expected a number"});
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0, 0], "radius": 1}})",
               {"/field/center", "array of 2 numbers"});
}

TEST(CsgModelErrors, NonPositiveRadius) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0], "radius": -1}})",
               {"/field/radius", "positive"});
}

TEST(CsgModelErrors, InfiniteAndNanNumbers) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [1e999, 0], "radius": 1}})",
               {"line 1", "not finite", "1e999"});
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [NaN, 0], "radius": 1}})",
               {"malformed JSON"});
}

TEST(CsgModelErrors, MisspelledKey) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0], "radius": 1, "radus": 2}})",
               {"/field/radus", "unknown parameter"});
}

TEST(CsgModelErrors, BadFormulaNamesTheColumn) {
  expect_error(R"({"dimension": 2, "field": {"formula": "x^2 + * y"}})", {"/field/formula", "column 7"});
  expect_error(R"({"dimension": 2, "field": {"formula": "x + z"}})", {"'z' is not a variable of a 2D model"});
}

TEST(CsgModelErrors, ThreeDimensionalPrimitiveInTwoD) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "torus", "center": [0,0,0], "axis": [0,0,1],
               "major_radius": 1, "minor_radius": 0.2}})",
               {"3D primitive"});
}

TEST(CsgModelErrors, BadRFunctionAndOperator) {
  expect_error(R"({"dimension": 2, "rfunction": "rp:3", "field": {"formula": "x"}})", {"/rfunction", "even"});
  expect_error(R"({"dimension": 2, "field": {"op": "xor", "args": [{"formula": "x"}]}})",
               {"/field/op", "unknown operator"});
  expect_error(R"({"dimension": 2, "field": {"op": "difference", "args": [{"formula": "x"}]}})",
               {"/field/args", "at least 2"});
}

TEST(CsgModelErrors, MissingTopLevelPieces) {
  expect_error(R"({"field": {"formula": "x"}})", {"dimension"});
  expect_error(R"({"dimension": 4, "field": {"formula": "x"}})", {"/dimension", "2 or 3"});
  expect_error(R"({"dimension": 2})", {"missing \"field\""});
  expect_error(R"([1, 2])", {"JSON object"});
}

TEST(CsgModelErrors, UnknownReferenceAndDuplicateName) {
  expect_error(R"({"dimension": 2, "field": {"ref": "nothing"}})", {"/field/ref", "no node named"});
  expect_error(R"({"dimension": 2, "field": {"op": "union", "args": [
      {"name": "a", "formula": "x"}, {"name": "a", "formula": "y"}]}})",
               {"/field/args/1/name", "used twice"});
}

TEST(CsgModelErrors, MissingFileIsNamed) {
  try {
    sage::geometry::read_model("/nonexistent/model.json");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.json"), std::string::npos);
  }
}

}  // namespace

namespace {

TEST(CsgModelErrors, DeepNestingIsAnErrorNotACrash) {
  std::string text = R"({"dimension": 2, "field": )";
  for (int i = 0; i < 5000; ++i) text += R"({"op": "complement", "args": [)";
  text += R"({"formula": "x"})";
  for (int i = 0; i < 5000; ++i) text += "]}";
  text += "}";
  expect_error(text, {"nested more than"});
}

TEST(CsgModelErrors, RFunctionWhereNothingUsesIt) {
  expect_error(R"({"dimension": 2, "field": {"primitive": "disk", "center": [0, 0], "radius": 1, "rfunction": "r0"}})",
               {"/field/rfunction", "unknown parameter"});
  expect_error(R"({"dimension": 2, "field": {"op": "trim", "entity": {"formula": "y"}, "region": {"formula": "x"},
               "rfunction": "r0"}})",
               {"/field/rfunction", "simple"});
}

}  // namespace
