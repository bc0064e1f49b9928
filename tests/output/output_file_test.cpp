// Output files are written whole or not at all (output_file.hpp), and
// solution files hold the domain only (clipped_grid.hpp).

#include <sage/output/clipped_grid.hpp>
#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkCell.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using sage::output::OutputError;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The files of a folder, for checking that no temporary file stays behind.
std::size_t files_in(const fs::path& folder) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(folder), {}));
}

void expect_output_error(const std::function<void()>& f, const std::string& piece) {
  try {
    f();
    ADD_FAILURE() << "no OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what();
  }
}

TEST(OutputFile, UnwritablePathsFailBeforeTheWork) {
  const fs::path folder = sage::test::scratch_dir() / "checks";
  fs::create_directories(folder);
  expect_output_error([&] { sage::output::check_writable((folder / "missing" / "x.vtu").string()); }, "does not exist");
  expect_output_error([&] { sage::output::check_writable(folder.string()); }, "is a folder");
  const fs::path existing = folder / "previous.vtu";
  std::ofstream(existing) << "the user's previous result";
  sage::output::check_writable(existing.string());
  EXPECT_EQ(read_text(existing), "the user's previous result") << "the check must not truncate";
  EXPECT_EQ(files_in(folder), 1u);
}

TEST(OutputFile, FailedWriteLeavesThePreviousFileAndNoTemporary) {
  const fs::path folder = sage::test::scratch_dir() / "atomic";
  fs::create_directories(folder);
  const fs::path path = folder / "result.vtu";
  std::ofstream(path) << "old";
  EXPECT_THROW(sage::output::write_atomically(path.string(),
                                              [](const std::string& temporary) {
                                                std::ofstream(temporary) << "half a fi";
                                                throw std::runtime_error("interrupted");
                                              }),
               std::runtime_error);
  EXPECT_EQ(read_text(path), "old");
  EXPECT_EQ(files_in(folder), 1u);
  sage::output::write_atomically(path.string(),
                                 [](const std::string& temporary) { std::ofstream(temporary) << "new"; });
  EXPECT_EQ(read_text(path), "new");
  EXPECT_EQ(files_in(folder), 1u);
}

/// The unit disk's field 1 - x^2 - y^2 on a grid over [-1.3, 1.3]^2.
sage::Grid disk_grid(int n, std::vector<double>& omega) {
  sage::Grid grid;
  grid.dimension = 2;
  grid.lo = {-1.3, -1.3, 0};
  grid.hi = {1.3, 1.3, 0};
  grid.points = {n, n, 1};
  omega.resize(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const auto p = grid.point(i);
    omega[i] = 1 - p[0] * p[0] - p[1] * p[1];
  }
  return grid;
}

TEST(ClippedGrid, HoldsTheDiskOnlyAndItsAreaConverges) {
  double previous_error = 0.0;
  for (const int n : {33, 65}) {
    std::vector<double> omega;
    const sage::Grid grid = disk_grid(n, omega);
    const sage::output::ClippedGrid disk(grid, omega);
    const auto points = disk.points();
    ASSERT_EQ(points.size(), disk.point_count());
    for (const auto& p : points) EXPECT_LE(p[0] * p[0] + p[1] * p[1], 1.0 + 1e-12);
    // The cut points lie on the circle's chords: within h^2 of the circle.
    const double h = 2.6 / (n - 1);
    double outermost = 0.0;
    for (const auto& p : points) outermost = std::max(outermost, std::hypot(p[0], p[1]));
    EXPECT_GT(outermost, 1.0 - h * h);
    // The clipped cells' area is the inscribed polygon's: pi - O(h^2).
    std::vector<sage::output::PointArray> arrays{{"x", 1, std::vector<double>(points.size())}};
    for (std::size_t i = 0; i < points.size(); ++i) arrays[0].values[i] = points[i][0];
    const fs::path path = sage::test::scratch_dir() / ("disk" + std::to_string(n) + ".vtu");
    disk.write(path.string(), arrays);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    ASSERT_EQ(static_cast<std::size_t>(g->GetNumberOfPoints()), points.size());
    vtkDataArray* x = g->GetPointData()->GetArray("x");
    vtkDataArray* written_omega = g->GetPointData()->GetArray("omega");
    ASSERT_TRUE(x && written_omega);
    double area = 0.0;
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
      vtkCell* cell = g->GetCell(c);
      const vtkIdType m = cell->GetNumberOfPoints();
      // Clipped pixels are whole pixels, or triangles and quads whose
      // points go round them: the shoelace formula.
      double a = 0.0;
      if (cell->GetCellType() == VTK_PIXEL) {
        a = h * h;
      } else {
        for (vtkIdType k = 0; k < m; ++k) {
          double p[3], q[3];
          g->GetPoint(cell->GetPointId(k), p);
          g->GetPoint(cell->GetPointId((k + 1) % m), q);
          a += 0.5 * (p[0] * q[1] - q[0] * p[1]);
        }
      }
      area += std::abs(a);
    }
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
      double p[3];
      g->GetPoint(i, p);
      EXPECT_EQ(x->GetTuple1(i), p[0]) << "arrays follow the points' order";
      EXPECT_NEAR(written_omega->GetTuple1(i), 1 - p[0] * p[0] - p[1] * p[1], 2 * h * h);
      EXPECT_GE(written_omega->GetTuple1(i), -1e-15);
    }
    const double error = std::abs(area - M_PI);
    EXPECT_LT(error, 2 * h * h) << n;
    if (previous_error > 0) {
      EXPECT_LT(error, 0.4 * previous_error) << "second order";
    }
    previous_error = error;
  }
}

}  // namespace
