#pragma once
// Problems shared by the solver benchmarks on real shapes.

#include <sage/geometry/model.hpp>
#include <sage/solver/poisson.hpp>

namespace sage::bench {

/// u = 0 on the boundary of a model read from a file (mesh or GIS), f = 1.
inline solver::PoissonProblem zero_dirichlet(const geometry::Model& model) {
  solver::PoissonProblem p;
  p.domain.dimension = model.dimension;
  p.domain.field = model.field;
  if (model.field_follows_surface) p.domain.boundary_mesh = model.surface;
  for (int a = 0; a < 3; ++a) {
    p.domain.min[a] = model.bounds->min[a];
    p.domain.max[a] = model.bounds->max[a];
  }
  p.source = 1.0;
  return p;
}

}  // namespace sage::bench
