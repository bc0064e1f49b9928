#pragma once
// The part of a regular grid where omega >= 0, for solution files that
// hold values only in the domain: the grid's cells clipped at omega = 0 by
// VTK's table-based clip of the point field omega (linear on each cell's
// edges). Its points are the grid points inside and the points where cell
// edges cross omega = 0; callers sample their fields there (the solution
// at each point, never an extrapolation from outside) and write them.
// ParaView's colour ranges, Warp By Vector and integrals then see the part
// only.

#include <sage/output/point_arrays.hpp>
#include <sage/sampling/grid.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace sage::output {

class ClippedGrid {
 public:
  /// `omega`: one value per grid point, in grid order.
  ClippedGrid(const Grid& grid, const std::vector<double>& omega);
  ~ClippedGrid();
  ClippedGrid(ClippedGrid&&) noexcept;
  ClippedGrid& operator=(ClippedGrid&&) noexcept;

  std::size_t point_count() const;
  std::size_t cell_count() const;
  /// The points, in order (x, y, z; z = 0 in 2D).
  std::vector<std::array<double, 3>> points() const;
  /// omega at the points: the grid's values, 0 (to rounding) on the cut.
  std::vector<double> omega() const;

  /// Writes a .vtu of the clipped cells with `arrays` (values per clipped
  /// point, in point order) and omega. Throws OutputError naming the path.
  void write(const std::string& path, const std::vector<PointArray>& arrays) const;

 private:
  struct Data;
  std::unique_ptr<Data> data_;
};

}  // namespace sage::output
