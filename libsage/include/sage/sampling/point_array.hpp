#pragma once
// A named array of values at points, `components` numbers per point: what
// samplers produce and writers write (output/point_arrays.hpp,
// output/clipped_grid.hpp).

#include <string>
#include <vector>

namespace sage {

struct PointArray {
  std::string name;
  int components = 1;
  std::vector<double> values;  // components per point, in the points' order
};

}  // namespace sage
