#pragma once
// Where a boundary value problem lives, whatever its physics
// (PoissonProblem, ElasticityProblem): the domain {field >= 0}, a box
// holding it, and for domains read from a mesh its triangles.

#include <sage/expression/expression.hpp>
#include <sage/expression/triangle_surface.hpp>

#include <algorithm>
#include <array>
#include <memory>

namespace sage::solver {

struct ProblemDomain {
  int dimension = 2;
  Expr field;                          // omega >= 0 inside
  std::array<double, 3> min{}, max{};  // a box holding the domain
  /// 3D domains read from a mesh: its triangles (the boundary of {field >=
  /// 0}). The solvers then classify cells and integrate cut cells from the
  /// triangles (mesh_domain.hpp); `field` still serves the Dirichlet
  /// structure when asked for.
  std::shared_ptr<const TriangleSurface> boundary_mesh;

  double longest_side() const {
    double longest = 0.0;
    for (int a = 0; a < dimension; ++a) longest = std::max(longest, max[a] - min[a]);
    return longest;
  }
};

}  // namespace sage::solver
