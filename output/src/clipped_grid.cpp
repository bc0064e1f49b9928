#include "unstructured_writer.hpp"

#include <sage/output/clipped_grid.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkTableBasedClipDataSet.h>
#include <vtkUnstructuredGrid.h>

#include <stdexcept>

namespace sage::output {

struct ClippedGrid::Data {
  vtkSmartPointer<vtkUnstructuredGrid> cells;
};

ClippedGrid::ClippedGrid(const Grid& grid, const std::vector<double>& omega) : data_(std::make_unique<Data>()) {
  if (omega.size() != grid.size()) throw std::invalid_argument("ClippedGrid: one omega per grid point");
  vtkNew<vtkImageData> image;
  image->SetDimensions(grid.points[0], grid.points[1], grid.dimension == 3 ? grid.points[2] : 1);
  image->SetOrigin(grid.lo[0], grid.lo[1], grid.dimension == 3 ? grid.lo[2] : 0.0);
  image->SetSpacing(grid.spacing(0), grid.spacing(1), grid.dimension == 3 ? grid.spacing(2) : 1.0);
  vtkNew<vtkDoubleArray> values;
  values->SetName("omega");
  values->SetNumberOfTuples(static_cast<vtkIdType>(omega.size()));
  for (std::size_t i = 0; i < omega.size(); ++i) values->SetValue(static_cast<vtkIdType>(i), omega[i]);
  image->GetPointData()->SetScalars(values);
  // Keeps the points where omega > 0 (and the cut at 0), interpolating
  // omega linearly along the cells' edges.
  vtkNew<vtkTableBasedClipDataSet> clip;
  clip->SetInputData(image);
  clip->SetValue(0.0);
  clip->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  clip->Update();
  data_->cells = clip->GetOutput();
}

ClippedGrid::~ClippedGrid() = default;
ClippedGrid::ClippedGrid(ClippedGrid&&) noexcept = default;
ClippedGrid& ClippedGrid::operator=(ClippedGrid&&) noexcept = default;

std::size_t ClippedGrid::point_count() const { return static_cast<std::size_t>(data_->cells->GetNumberOfPoints()); }

std::size_t ClippedGrid::cell_count() const { return static_cast<std::size_t>(data_->cells->GetNumberOfCells()); }

std::vector<std::array<double, 3>> ClippedGrid::points() const {
  std::vector<std::array<double, 3>> out(point_count());
  for (std::size_t i = 0; i < out.size(); ++i) data_->cells->GetPoint(static_cast<vtkIdType>(i), out[i].data());
  return out;
}

std::vector<double> ClippedGrid::omega() const {
  vtkDataArray* values = data_->cells->GetPointData()->GetArray("omega");
  std::vector<double> out(point_count(), 0.0);
  for (std::size_t i = 0; i < out.size() && values; ++i) out[i] = values->GetTuple1(static_cast<vtkIdType>(i));
  return out;
}

void ClippedGrid::write(const std::string& path, const std::vector<PointArray>& arrays) const {
  for (const PointArray& a : arrays)
    if (a.values.size() != point_count() * static_cast<std::size_t>(a.components))
      throw std::invalid_argument("ClippedGrid::write: array " + a.name + " has the wrong size");
  vtkNew<vtkUnstructuredGrid> out;
  out->ShallowCopy(data_->cells);
  out->GetPointData()->Initialize();
  add_arrays(out, arrays);
  vtkNew<vtkDoubleArray> omega_values;
  omega_values->DeepCopy(data_->cells->GetPointData()->GetArray("omega"));
  out->GetPointData()->AddArray(omega_values);
  write_unstructured(path, out);
}

}  // namespace sage::output
