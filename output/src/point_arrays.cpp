#include "unstructured_writer.hpp"

#include <sage/output/point_arrays.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

namespace sage::output {

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
