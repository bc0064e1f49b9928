// `sage solve` on problems whose data have a mistake, as a new user writes
// them: every case ends with exit 1 and a message naming the file, the
// datum's JSON pointer, its value and (for formulas) the point; nothing is
// written, and a previous result is left as it was. And solution files
// that hold only the part: no point outside the domain, the colour range
// of von Mises stress that of the material.

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <regex>
#include <string>

namespace {

using namespace sage_cli_test;

/// The unit disk, u = 0 on the circle, with the given conductivity and source.
std::string disk(const std::string& name, const std::string& conductivity, const std::string& source,
                 const std::string& boundary = R"({ "disk": { "type": "dirichlet", "value": 0 } })") {
  return write_file(name, R"({
  "domain": { "dimension": 2, "bounds": { "min": [-1, -1], "max": [1, 1] },
              "field": { "name": "disk", "primitive": "disk", "center": [0, 0], "radius": 1 } },
  "conductivity": )" + conductivity +
                              R"(,
  "source": )" + source + R"(,
  "boundary": )" + boundary + "\n}");
}

/// The 3D bracket of examples/problems with the load hole's traction given.
std::string bracket_3d(const std::string& name, const std::string& traction) {
  std::ifstream in(std::string(SAGE_SOURCE_DIR) + "/examples/problems/bracket_3d.json");
  std::string text(std::istreambuf_iterator<char>(in), {});
  text = std::regex_replace(text, std::regex(R"("traction": \[0, 0, -20\])"), R"("traction": )" + traction);
  return write_file(name, text);
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliSolveBadData, EveryMistakeNamesFileKeyValueAndPointAndWritesNothing) {
  struct Case {
    std::string problem, pointer, value;  // the value, then "everywhere" or the point
  };
  const Case cases[] = {
      {disk("k_zero.json", "0", "1"), "/conductivity", "is 0 everywhere"},
      {disk("k_sign.json", "\"x\"", "1"), "/conductivity", "is -"},  // then the point where x < 0
      {disk("k_negative.json", "\"-1\"", "1"), "/conductivity", "is -1 everywhere"},
      {disk("f_infinite.json", "1", "\"1/0\""), "/source", "is inf everywhere"},
      {disk("f_nan.json", "1", "\"sqrt(x - 2)\""), "/source", "is NaN at ("},
      {disk("beta.json", "1", "1", R"({ "disk": { "type": "robin", "beta": -5, "flux": 0 } })"), "/boundary/disk/beta",
       "is -5 everywhere"},
      {disk("flux.json", "1", "1", R"j({ "disk": { "type": "robin", "beta": 1, "flux": "log(y)" } })j"),
       "/boundary/disk/flux", "is NaN at ("},
      {bracket_3d("traction.json", R"j([0, 0, "log(0)"])j"), "/boundary/load_hole/traction/2", "is -inf everywhere"},
      {bracket_3d("traction_point.json", R"j([0, "sqrt(z - 5)", 0])j"), "/boundary/load_hole/traction/1",
       "is NaN at ("},
  };
  const fs::path previous = scratch("previous.vtu");
  for (const Case& c : cases) {
    std::ofstream(previous) << "the user's previous result";
    const fs::path fresh = scratch("fresh.vtu");
    const Result r = run("solve " + c.problem + " -o " + fresh.string() + " --cells 10 --degree 2");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(c.problem + ": " + c.pointer + " " + c.value), std::string::npos) << r.output;
    if (c.value == "is -") {
      EXPECT_NE(r.output.find(" at ("), std::string::npos) << r.output;
    }
    EXPECT_FALSE(fs::exists(fresh)) << c.pointer;
    const Result again = run("solve " + c.problem + " -o " + previous.string() + " --cells 10 --degree 2");
    EXPECT_EQ(again.exit_code, 1);
    EXPECT_EQ(read_text(previous), "the user's previous result") << c.pointer;
  }
}

TEST(CliSolveBadData, MissingOutputFolderFailsBeforeTheWork) {
  const std::string problem = disk("fine.json", "1", "1");
  const Result r = run("solve " + problem + " -o " + scratch("no/such/folder/u.vtu").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no/such/folder"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("solver:"), std::string::npos) << "nothing was solved: " << r.output;
}

/// The range of a point array of a .vtu, and the lowest omega of its points.
struct FileRange {
  double lowest = 1e300, highest = -1e300, lowest_omega = 1e300;
};

FileRange range_of(const fs::path& path, const char* array) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  vtkDataArray* values = g->GetPointData()->GetArray(array);
  vtkDataArray* omega = g->GetPointData()->GetArray("omega");
  FileRange out;
  if (!values || !omega) return out;
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
    out.lowest = std::min(out.lowest, values->GetTuple1(i));
    out.highest = std::max(out.highest, values->GetTuple1(i));
    out.lowest_omega = std::min(out.lowest_omega, omega->GetTuple1(i));
  }
  return out;
}

double printed_number_after(const std::string& output, const std::string& label) {
  const auto at = output.find(label);
  return at == std::string::npos ? -1.0 : std::stod(output.substr(at + label.size()));
}

TEST(CliSolveBadData, SolutionFilesHoldThePartOnly) {
  // The bracket's stresses: the file's largest von Mises stress is the
  // material's (the summary's, at the quadrature points), not that of the
  // B-spline solution extrapolated beyond the part (1,202 MPa there before).
  const fs::path out = scratch("bracket.vtu");
  const Result r = run("solve " + std::string(SAGE_SOURCE_DIR) + "/examples/problems/bracket.json -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double summary = printed_number_after(r.output, "largest von Mises stress ");
  ASSERT_GT(summary, 0.0) << r.output;
  const FileRange stress = range_of(out, "von_mises");
  EXPECT_NEAR(stress.highest, summary, 0.05 * summary);
  EXPECT_GE(stress.lowest_omega, -1e-12) << "a point outside the part";
  // The plate's temperature: u = 0 on the outer edge, a positive source, so
  // u >= 0 in the plate (to the weak condition's error); outside it went to -0.079.
  const fs::path plate = scratch("plate.vtu");
  const Result heat =
      run("solve " + std::string(SAGE_SOURCE_DIR) + "/examples/problems/plate_heat.json -o " + plate.string());
  ASSERT_EQ(heat.exit_code, 0) << heat.output;
  const FileRange u = range_of(plate, "u");
  EXPECT_GT(u.lowest, -1e-4 * u.highest);
  EXPECT_GE(u.lowest_omega, -1e-12);
}

}  // namespace
