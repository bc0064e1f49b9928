#include <sage/solver/default_grid.hpp>

#include "discretization.hpp"

#include <algorithm>
#include <cmath>

namespace sage::solver {

DefaultGrid default_grid(const ProblemDomain& domain, int preferred, int most) {
  DefaultGrid choice;
  choice.preferred = preferred;
  choice.cells = preferred;
  if (domain.dimension != 3) return choice;
  DomainCells<3> cells(domain.field, domain.boundary_mesh);
  const std::array<double, 3> lo = domain.min, hi = domain.max;
  for (int n = preferred;; n = std::max(n + 1, static_cast<int>(std::ceil(1.25 * n)))) {
    choice.cells = std::min(n, most);
    const auto grid = BackgroundGrid<3>::covering(lo, hi, domain.longest_side() / choice.cells, 1);
    cells.classify(grid);
    choice.cells_inside =
        static_cast<std::size_t>(std::count(cells.kinds().begin(), cells.kinds().end(), CellKind::Inside));
    choice.cells_cut = static_cast<std::size_t>(std::count(cells.kinds().begin(), cells.kinds().end(), CellKind::Cut));
    if (choice.cells >= most || choice.cells_cut == 0 ||
        static_cast<double>(choice.cells_inside) >= kDefaultInsideShare * static_cast<double>(choice.cells_cut))
      return choice;
  }
}

}  // namespace sage::solver
