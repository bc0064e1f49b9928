#pragma once
// Writing arbitrary named point arrays on a grid as .vtu, optionally
// restricted to a subset of the grid's cells (those a solution lives on).
// Points no kept cell uses are left out. Same VTK writer settings as
// vtk_writer.hpp (binary, appended, LZ4).

#include <sage/sampling/grid.hpp>
#include <sage/sampling/point_array.hpp>

#include <string>
#include <vector>

namespace sage::output {

using PointArray = sage::PointArray;  // values in grid order here

/// Writes a .vtu of the grid's quads (2D) or hexahedra (3D) for which
/// keep_cell[cell] is nonzero (every cell when keep_cell is empty), with
/// the arrays on their points. Throws OutputError naming the path.
void write_point_arrays(const std::string& path, const Grid& grid, const std::vector<PointArray>& arrays,
                        const std::vector<char>& keep_cell = {});

/// Writes scattered points as VTK vertices with point arrays (quadrature
/// points, say): `coordinates` holds 3 numbers per point.
void write_scattered_points(const std::string& path, const std::vector<double>& coordinates,
                            const std::vector<PointArray>& arrays);

}  // namespace sage::output
