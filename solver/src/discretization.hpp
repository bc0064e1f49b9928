#pragma once
// The stages every solver shares (poisson.cpp, elasticity.cpp), before
// its own assembly:
//
//   1. classify_grid: the background grid against the domain, by the
//      domain's Boolean pieces and interval arithmetic or by a mesh's
//      triangles; refuses, with an estimate, a job too large for memory;
//   2. integrate_cells: the volume and surface rules of inside and cut
//      cells (domain_quadrature.hpp, mesh_domain.hpp), on all cores;
//   3. basis_on_cells: the WEB basis of the cells that carry weight
//      (web_basis.hpp).
//
// Also: the B-splines of the inside cells' common Gauss rule, tabulated
// once for every assembly.

#include "schwarz_preconditioner.hpp"

#include <sage/solver/domain_quadrature.hpp>
#include <sage/solver/mesh_domain.hpp>
#include <sage/solver/problem.hpp>
#include <sage/solver/solver_options.hpp>
#include <sage/solver/web_basis.hpp>

#include <sage/tape/evaluator.hpp>

#include <array>
#include <memory>
#include <optional>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

/// Throws std::invalid_argument for options no solver takes (degree, cell
/// width, tolerance) and an empty box.
void check_solver_options(const SolverOptions& options, const std::array<double, 3>& min,
                          const std::array<double, 3>& max, int dimension);

template <int D>
Box<D> cell_box(const BackgroundGrid<D>& grid, std::size_t linear);

/// The cells of the background grid against the domain, and their
/// quadrature: from the Boolean pieces of omega, or, for 3D domains read
/// from meshes, from the triangles.
template <int D>
class DomainCells {
 public:
  /// Compiles the pieces (an implicit domain; not for a mesh in 3D).
  DomainCells(const Expr& domain, std::shared_ptr<const TriangleSurface> mesh);
  /// Classifies the cells of `grid`.
  void classify(const BackgroundGrid<D>& grid);
  const std::vector<CellKind>& kinds() const { return kinds_; }
  std::shared_ptr<const MeshDomain> mesh() const { return mesh_; }

  /// The cut-cell rule; one per thread.
  class Rule {
   public:
    Rule(const DomainCells& cells, QuadratureOptions options);
    void append(std::size_t cell, const Box<D>& box, std::vector<VolumePoint<D>>& volume,
                std::vector<SurfacePoint<D>>* surface);
    const QuadratureCounts& counts() const;

   private:
    const DomainCells& cells_;
    std::optional<ImplicitCellQuadrature<D>> rule_;
    std::optional<MeshCellQuadrature> mesh_rule_;
  };

 private:
  std::shared_ptr<const TriangleSurface> surface_;
  std::optional<DomainPieces> pieces_;
  std::vector<ClassifiedCell> cells_;
  std::shared_ptr<MeshDomain> mesh_;
  std::vector<CellKind> kinds_;
};

/// What the memory estimate needs beyond the grid (memory_estimate.hpp).
struct MemoryNeeds {
  bool direct_solve = false;
  int components = 1;     // unknowns per B-spline
  double limit_mb = 0.0;  // 0: what the machine has available
};

template <int D>
struct ClassifiedGrid {
  BackgroundGrid<D> grid;
  std::vector<std::size_t> candidates;  // the cells that are not outside, increasing
  std::array<double, 3> interior{};     // the centre of the inside cell farthest from the others
};

/// Stage 1. Fills the report's cell counts and memory estimate. Throws
/// std::runtime_error for an empty domain, a grid too coarse to hold an
/// inside cell, or a job estimated above the memory limit.
template <int D>
ClassifiedGrid<D> classify_grid(DomainCells<D>& cells, const std::array<double, 3>& min,
                                const std::array<double, 3>& max, double cell_width, int degree,
                                const MemoryNeeds& memory, SolveReport& report);

/// The rules per candidate cell, and their fallbacks.
template <int D>
struct CellRules {
  std::vector<std::vector<VolumePoint<D>>> volume;
  std::vector<std::vector<SurfacePoint<D>>> surface;
  QuadratureCounts counts;
};

/// Stage 2. Cells with in_band[k] (when in_band is not empty) get
/// `band_rule`, the others `rule`; surface rules only `with_surface`.
template <int D>
CellRules<D> integrate_cells(const DomainCells<D>& cells, const ClassifiedGrid<D>& classified,
                             const QuadratureOptions& rule, const QuadratureOptions& band_rule,
                             const std::vector<char>& in_band, bool with_surface);

/// Adds the rules' fallbacks to the report.
void report_fallbacks(const QuadratureCounts& counts, SolveReport& report);

/// The surface points of `rules` that no named part of `problem` claims
/// (the rest's), by the parts' selectors as the assembly reads them.
template <int D>
std::size_t rest_points(const PoissonProblem& problem, const CellRules<D>& rules, double cell_width);

/// Stage 3. Drops the volume points of cells that touch the domain in a
/// face or an edge only (no weight: their B-splines must not become
/// unknowns), counts the points in the report, and builds the basis.
template <int D>
SplineBasis<D> basis_on_cells(const DomainCells<D>& cells, const ClassifiedGrid<D>& classified, CellRules<D>& rules,
                              BasisKind kind, SolveReport& report);

/// Where the unknowns sit on the grid, for the Schwarz preconditioner:
/// `components` copies of the basis' unknowns (component-major), then
/// `without_place` unknowns with no B-spline of their own.
template <int D>
SplinePlacement spline_placement(const SplineBasis<D>& basis, int components, std::size_t without_place = 0);

/// The rules' points, for display (SolverOptions::keep_quadrature).
template <int D>
QuadratureDump quadrature_dump(const CellRules<D>& rules);

/// Local B-splines and their gradients at the points of the tensor Gauss
/// rule of an inside cell, in the order of ImplicitCellQuadrature::append_rule
/// (x fastest): value[p * local + k], gradient[a][p * local + k]. Inside
/// cells all carry this rule relative to the cell, so these values serve
/// them all.
struct InsideSplineTable {
  std::size_t points = 0;
  std::vector<double> value;
  std::array<std::vector<double>, 3> gradient;
};

template <int D>
InsideSplineTable inside_spline_table(const BackgroundGrid<D>& grid, int rule_points);

/// The band layout of a Galerkin matrix (extended_system.hpp): the
/// position of local spline k of a cell in the (2n + 1)^D stencil, and the
/// stencil's centre; row j of a cell adds column l at slot
/// centre - position[j] + position[l].
template <int D>
struct StencilLayout {
  explicit StencilLayout(int degree);
  int size = 1, centre = 0;
  std::vector<int> position;
};

/// The boundary part at a surface point: of the first `parts` results of
/// `eval` (the parts' selectors there), the one nearest zero within
/// `tolerance` (kSelectorTolerance cell widths), or `parts` (the rest) when
/// none is.
std::size_t nearest_part(const Evaluator<double>& eval, std::size_t parts, double tolerance);
constexpr double kSelectorTolerance = 1e-6;

/// Calls add() on each thread of the enclosing parallel region in turn,
/// thread 0 first: sums of per-thread arrays taken in this fixed order give
/// the same bits on every run with the same number of threads.
template <class Add>
void in_thread_order(Add&& add) {
#ifdef _OPENMP
  const int thread = omp_get_thread_num(), threads = omp_get_num_threads();
#else
  const int thread = 0, threads = 1;
#endif
  for (int turn = 0; turn < threads; ++turn) {
#pragma omp barrier
    if (turn == thread) add();
  }
}

}  // namespace sage::solver
