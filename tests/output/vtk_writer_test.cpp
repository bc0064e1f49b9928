// VTK output: files written by sage read back with VTK's own readers, with
// the named arrays, the grid geometry and the sampled values.

#include <sage/expression/formula.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/sampling/field_samples.hpp>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <gtest/gtest.h>
#include <test_files.hpp>

#include <filesystem>

namespace {

sage::FieldSamples samples_of(const std::string& formula, int dimension, int order) {
  sage::Grid grid;
  grid.dimension = dimension;
  grid.lo = {-1, -2, -0.5};
  grid.hi = {1, 2, 0.5};
  grid.points = dimension == 2 ? std::array<int, 3>{5, 7, 1} : std::array<int, 3>{4, 3, 5};
  const sage::Tape tape(sage::parse_formula(formula, dimension), dimension);
  return sage::sample_field(tape, grid, order);
}

std::string temp_path(const std::string& name) { return (sage::test::scratch_dir() / name).string(); }

TEST(VtkWriter, UnstructuredGridRoundTrip2D) {
  const auto s = samples_of("x^2 * y + 3 * y", 2, 3);
  const std::string path = temp_path("2d.vtu");
  sage::output::write_field(path, s);

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  ASSERT_EQ(g->GetNumberOfPoints(), 35);
  EXPECT_EQ(g->GetNumberOfCells(), 4 * 6);
  vtkPointData* pd = g->GetPointData();
  vtkDataArray* omega = pd->GetArray("omega");
  vtkDataArray* grad = pd->GetArray("grad_omega");
  vtkDataArray* norm = pd->GetArray("grad_norm");
  vtkDataArray* d2 = pd->GetArray("d2_omega");
  vtkDataArray* d3 = pd->GetArray("d3_omega");
  ASSERT_TRUE(omega && grad && norm && d2 && d3);
  EXPECT_EQ(grad->GetNumberOfComponents(), 3);
  ASSERT_EQ(d2->GetNumberOfComponents(), 3);
  EXPECT_STREQ(d2->GetComponentName(1), "xy");
  ASSERT_EQ(d3->GetNumberOfComponents(), 4);
  EXPECT_STREQ(d3->GetComponentName(1), "xxy");
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
    double p[3];
    g->GetPoint(i, p);
    const double x = p[0], y = p[1];
    EXPECT_NEAR(omega->GetTuple1(i), x * x * y + 3 * y, 1e-12);
    EXPECT_NEAR(grad->GetComponent(i, 0), 2 * x * y, 1e-12);
    EXPECT_NEAR(grad->GetComponent(i, 1), x * x + 3, 1e-12);
    EXPECT_EQ(grad->GetComponent(i, 2), 0.0);
    EXPECT_NEAR(d2->GetComponent(i, 0), 2 * y, 1e-12);  // xx
    EXPECT_NEAR(d2->GetComponent(i, 1), 2 * x, 1e-12);  // xy
    EXPECT_NEAR(d2->GetComponent(i, 2), 0.0, 1e-12);    // yy
    EXPECT_NEAR(d3->GetComponent(i, 1), 2.0, 1e-12);    // xxy
  }
  std::filesystem::remove(path);
}

TEST(VtkWriter, ImageDataRoundTrip3D) {
  const auto s = samples_of("x + 2*y*z", 3, 1);
  const std::string path = temp_path("3d.vti");
  sage::output::write_field(path, s);

  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  EXPECT_EQ(dims[0], 4);
  EXPECT_EQ(dims[1], 3);
  EXPECT_EQ(dims[2], 5);
  vtkDataArray* omega = img->GetPointData()->GetArray("omega");
  ASSERT_TRUE(omega);
  for (vtkIdType i = 0; i < img->GetNumberOfPoints(); ++i) {
    double p[3];
    img->GetPoint(i, p);
    EXPECT_NEAR(omega->GetTuple1(i), p[0] + 2 * p[1] * p[2], 1e-12);
  }
  std::filesystem::remove(path);
}

TEST(VtkWriter, UnwritablePathIsReportedWithThePath) {
  const auto s = samples_of("x", 2, 1);
  try {
    sage::output::write_field("/nonexistent-folder/out.vtu", s);
    FAIL();
  } catch (const sage::output::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/out.vtu"), std::string::npos);
  }
  EXPECT_THROW(sage::output::write_field(temp_path("out.txt"), s), sage::output::OutputError);
}

}  // namespace
