#include <sage/output/point_arrays.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <fstream>

namespace sage::output {

namespace {

void write_unstructured(const std::string& path, vtkUnstructuredGrid* grid) {
  {
    std::ofstream probe(path, std::ios::binary | std::ios::trunc);
    if (!probe) throw OutputError(path + ": cannot open for writing (does the folder exist? permissions?)");
  }
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToLZ4();
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
    throw OutputError(path + ": VTK could not write the file (disk full or no permission?)");
}

/// Adds the arrays, taking the values of the grid points listed in `used`.
void add_arrays(vtkUnstructuredGrid* grid, const std::vector<PointArray>& arrays, const std::vector<vtkIdType>& used) {
  for (const PointArray& a : arrays) {
    vtkNew<vtkDoubleArray> data;
    data->SetName(a.name.c_str());
    data->SetNumberOfComponents(a.components);
    data->SetNumberOfTuples(static_cast<vtkIdType>(used.size()));
    for (std::size_t i = 0; i < used.size(); ++i)
      for (int c = 0; c < a.components; ++c)
        data->SetComponent(static_cast<vtkIdType>(i), c,
                           a.values[static_cast<std::size_t>(used[i]) * static_cast<std::size_t>(a.components) +
                                    static_cast<std::size_t>(c)]);
    grid->GetPointData()->AddArray(data);
  }
  if (!arrays.empty()) grid->GetPointData()->SetActiveScalars(arrays.front().name.c_str());
}

}  // namespace

void write_point_arrays(const std::string& path, const Grid& g, const std::vector<PointArray>& arrays,
                        const std::vector<char>& keep_cell) {
  const vtkIdType nx = g.points[0], ny = g.points[1], nz = g.points[2];
  auto id = [&](vtkIdType i, vtkIdType j, vtkIdType k) { return i + nx * (j + ny * k); };
  std::vector<vtkIdType> new_id(g.size(), -1), used;
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  auto point = [&](vtkIdType old) {
    if (new_id[static_cast<std::size_t>(old)] < 0) {
      new_id[static_cast<std::size_t>(old)] = static_cast<vtkIdType>(used.size());
      used.push_back(old);
      points->InsertNextPoint(g.point(static_cast<std::size_t>(old)).data());
    }
    return new_id[static_cast<std::size_t>(old)];
  };
  std::size_t cell = 0;
  const vtkIdType kz = g.dimension == 3 ? nz - 1 : 1;
  for (vtkIdType k = 0; k < kz; ++k)
    for (vtkIdType j = 0; j + 1 < ny; ++j)
      for (vtkIdType i = 0; i + 1 < nx; ++i, ++cell) {
        if (!keep_cell.empty() && !keep_cell[cell]) continue;
        if (g.dimension == 2) {
          const vtkIdType quad[4] = {point(id(i, j, 0)), point(id(i + 1, j, 0)), point(id(i + 1, j + 1, 0)),
                                     point(id(i, j + 1, 0))};
          cells->InsertNextCell(4, quad);
        } else {
          const vtkIdType hex[8] = {point(id(i, j, k)),
                                    point(id(i + 1, j, k)),
                                    point(id(i + 1, j + 1, k)),
                                    point(id(i, j + 1, k)),
                                    point(id(i, j, k + 1)),
                                    point(id(i + 1, j, k + 1)),
                                    point(id(i + 1, j + 1, k + 1)),
                                    point(id(i, j + 1, k + 1))};
          cells->InsertNextCell(8, hex);
        }
      }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(g.dimension == 2 ? VTK_QUAD : VTK_HEXAHEDRON, cells);
  add_arrays(grid, arrays, used);
  write_unstructured(path, grid);
}

void write_scattered_points(const std::string& path, const std::vector<double>& coordinates,
                            const std::vector<PointArray>& arrays) {
  const std::size_t n = coordinates.size() / 3;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  std::vector<vtkIdType> used(n);
  for (std::size_t i = 0; i < n; ++i) {
    const vtkIdType v = points->InsertNextPoint(&coordinates[3 * i]);
    cells->InsertNextCell(1, &v);
    used[i] = static_cast<vtkIdType>(i);
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(VTK_VERTEX, cells);
  add_arrays(grid, arrays, used);
  write_unstructured(path, grid);
}

}  // namespace sage::output
