#pragma once
// The background grid of a 3D solve given no cell count or width: the
// preferred count across the box's longest side (20), or more when the
// domain's walls are too thin for it. A wall thinner than a cell holds no
// cell entirely inside, and the WEB basis needs such cells; a wall one or
// two cells thick solves, but every B-spline there is cut. So the count
// grows by factors of 5/4 until the cells inside are at least a quarter
// of the cut ones (walls about two cells thick), and never beyond `most`.

#include <sage/solver/problem_domain.hpp>

#include <cstddef>

namespace sage::solver {

struct DefaultGrid {
  int cells = 0;  // across the longest side
  std::size_t cells_inside = 0, cells_cut = 0;
  int preferred = 0;
  bool refined() const { return cells > preferred; }
};

/// Inside cells per cut cell that a default grid must reach.
constexpr double kDefaultInsideShare = 0.25;

/// The cell count for `domain` (3D; a 2D domain gets `preferred`), by
/// classifying the grids in turn (interval arithmetic or the mesh's
/// triangles: no quadrature).
DefaultGrid default_grid(const ProblemDomain& domain, int preferred = 20, int most = 256);

}  // namespace sage::solver
