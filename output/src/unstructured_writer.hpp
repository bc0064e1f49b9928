#pragma once
// Point arrays onto a vtkUnstructuredGrid and its .vtu file, shared by the
// writers of grids' cells, clipped grids and scattered points.

#include <sage/output/point_arrays.hpp>

#include <vtkType.h>

#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace sage::output {

/// Writes `grid` as .vtu (binary, appended, LZ4), whole or not at all
/// (output_file.hpp). Throws OutputError naming the path.
void write_unstructured(const std::string& path, vtkUnstructuredGrid* grid);

/// Adds the arrays to the grid's points, point i taking the values of entry
/// used[i] of each array (every entry in order when `used` is empty).
void add_arrays(vtkUnstructuredGrid* grid, const std::vector<PointArray>& arrays,
                const std::vector<vtkIdType>& used = {});

}  // namespace sage::output
