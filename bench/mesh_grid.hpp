#pragma once
// The N^3 grid over a mesh model's bounding box that the mesh benchmarks
// sample (sage field's grid for `--grid NxNxN`).

#include <sage/geometry/model.hpp>
#include <sage/sampling/grid.hpp>

namespace sage::bench {

inline Grid mesh_grid(const geometry::Model& model, int n) {
  Grid grid;
  grid.dimension = 3;
  grid.lo = model.bounds->min;
  grid.hi = model.bounds->max;
  grid.points = {n, n, n};
  return grid;
}

}  // namespace sage::bench
