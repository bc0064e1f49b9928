#include "discretization.hpp"

#include "message_text.hpp"

#include <sage/solver/gauss.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/memory_estimate.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sage::solver {

namespace {

template <std::size_t D>
std::string box_text(const std::array<double, D>& lo, const std::array<double, D>& hi) {
  std::string text = "[";
  for (std::size_t a = 0; a < D; ++a) text += (a ? ", " : "") + number_text(lo[a], 6) + " .. " + number_text(hi[a], 6);
  return text + "]";
}

/// The centre of the inside cell farthest (in cells) from every cell that
/// is not inside: a point well inside the domain, where the selectors'
/// signs are read (boundary_structure.hpp).
template <int D>
std::array<double, 3> deepest_inside_centre(const BackgroundGrid<D>& grid, const std::vector<CellKind>& kinds) {
  // Multi-source breadth-first search from the cells that are not inside,
  // over the 3^D neighbourhood.
  const std::size_t count = grid.cell_count();
  std::vector<int> distance(count, -1);
  std::vector<std::size_t> queue;
  for (std::size_t c = 0; c < count; ++c) {
    if (kinds[c] == CellKind::Inside) continue;
    distance[c] = 0;
    queue.push_back(c);
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto i = grid.cell_index(queue[head]);
    for (int offset = 0; offset < (D == 2 ? 9 : 27); ++offset) {
      auto j = i;
      int rest = offset;
      bool in_grid = true;
      for (int a = 0; a < D; ++a) {
        j[a] += rest % 3 - 1;
        rest /= 3;
        in_grid = in_grid && j[a] >= 0 && j[a] < grid.cells[a];
      }
      if (!in_grid) continue;
      std::size_t linear = 0;
      for (int a = D - 1; a >= 0; --a)
        linear = linear * static_cast<std::size_t>(grid.cells[a]) + static_cast<std::size_t>(j[a]);
      const int next = distance[queue[head]] + 1;
      if (distance[linear] >= 0 && distance[linear] <= next) continue;
      distance[linear] = next;
      queue.push_back(linear);
    }
  }
  std::size_t best = 0;
  for (std::size_t c = 0; c < count; ++c)
    if (kinds[c] == CellKind::Inside && (kinds[best] != CellKind::Inside || distance[c] > distance[best])) best = c;
  std::array<double, 3> centre{};
  const auto i = grid.cell_index(best);
  for (int a = 0; a < D; ++a) centre[a] = grid.lo[a] + (i[a] + 0.5) * grid.h;
  return centre;
}

/// Refuses, with the estimate, a solve that would not fit in `limit_mb`
/// (0: unknown, no check); records the estimate in the report.
template <int D>
void check_memory(const BackgroundGrid<D>& grid, const std::vector<std::size_t>& candidates, SolveReport& report,
                  const MemoryNeeds& needs, double limit_mb) {
  // The B-splines whose support meets a candidate cell.
  std::vector<char> relevant(grid.spline_count(), 0);
  std::size_t relevant_count = 0;
  for (const std::size_t c : candidates) {
    const auto cell = grid.cell_index(c);
    for (int k = 0; k < grid.local_count(); ++k) {
      char& mark = relevant[grid.spline_linear(LocalSplines<D>::global_index(cell, grid.degree, k))];
      relevant_count += mark ? 0 : 1;
      mark = 1;
    }
  }
  const MemoryEstimate estimate = estimate_memory(D, grid.degree, report.cells_inside, report.cells_cut, relevant_count,
                                                  needs.direct_solve, needs.components);
  report.memory_estimate_mb = estimate.megabytes;
  if (limit_mb > 0.0 && estimate.megabytes > limit_mb)
    throw std::runtime_error("the problem is too large for this machine: it needs " + estimate.summary() + ", and " +
                             std::to_string(static_cast<long long>(limit_mb)) +
                             " MB are available (use fewer cells or a lower degree)");
}

}  // namespace

void check_solver_options(const SolverOptions& options, const std::array<double, 3>& min,
                          const std::array<double, 3>& max, int dimension) {
  if (options.degree < 1 || options.degree > kMaxDegree)
    throw std::invalid_argument("degree must be 1.." + std::to_string(kMaxDegree) + ", not " +
                                std::to_string(options.degree));
  if (!(options.cell_width > 0.0) || !std::isfinite(options.cell_width))
    throw std::invalid_argument("cell width h must be positive");
  if (!(options.cg_tolerance >= 0.0 && options.cg_tolerance < 1.0))
    throw std::invalid_argument("the conjugate gradients tolerance must be in [0, 1) (0: automatic)");
  for (int a = 0; a < dimension; ++a)
    if (!(max[a] > min[a])) throw std::invalid_argument("the domain's bounding box is empty");
}

std::size_t nearest_part(const Evaluator<double>& eval, std::size_t parts, double tolerance) {
  std::size_t nearest = parts;
  double distance = tolerance;
  for (std::size_t k = 0; k < parts; ++k) {
    const double d = std::abs(eval.result(k));
    if (d <= distance) {
      distance = d;
      nearest = k;
    }
  }
  return nearest;
}

template <int D>
Box<D> cell_box(const BackgroundGrid<D>& grid, std::size_t linear) {
  const auto c = grid.cell_index(linear);
  Box<D> box{};
  for (int a = 0; a < D; ++a) {
    box.lo[a] = grid.lo[a] + c[a] * grid.h;
    box.hi[a] = grid.lo[a] + (c[a] + 1) * grid.h;
  }
  return box;
}

template <int D>
DomainCells<D>::DomainCells(const Expr& domain, std::shared_ptr<const TriangleSurface> mesh)
    : surface_(std::move(mesh)) {
  if (D == 2 || !surface_) pieces_.emplace(domain, D);
}

template <int D>
void DomainCells<D>::classify(const BackgroundGrid<D>& grid) {
  if constexpr (D == 3) {
    if (surface_) {
      mesh_ = std::make_shared<MeshDomain>(surface_, grid);
      kinds_ = mesh_->kinds();
      return;
    }
  }
  cells_ = classify_cells<D>(*pieces_, grid);
  kinds_.resize(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) kinds_[c] = cells_[c].kind;
}

template <int D>
DomainCells<D>::Rule::Rule(const DomainCells& cells, QuadratureOptions options) : cells_(cells) {
  if (cells.mesh_) {
    mesh_rule_.emplace(*cells.mesh_, options);
  } else {
    rule_.emplace(*cells.pieces_, options);
  }
}

template <int D>
void DomainCells<D>::Rule::append(std::size_t cell, const Box<D>& box, std::vector<VolumePoint<D>>& volume,
                                  std::vector<SurfacePoint<D>>* surface) {
  if constexpr (D == 3) {
    if (mesh_rule_) return mesh_rule_->append_rule(cell, box, volume, surface);
  }
  rule_->append_rule(box, cells_.cells_[cell], volume, surface);
}

template <int D>
const QuadratureCounts& DomainCells<D>::Rule::counts() const {
  return mesh_rule_ ? mesh_rule_->counts() : rule_->counts();
}

template <int D>
ClassifiedGrid<D> classify_grid(DomainCells<D>& cells, const std::array<double, 3>& min,
                                const std::array<double, 3>& max, double cell_width, int degree,
                                const MemoryNeeds& memory, SolveReport& report) {
  std::array<double, D> lo{}, hi{};
  for (int a = 0; a < D; ++a) {
    lo[a] = min[a];
    hi[a] = max[a];
  }
  ClassifiedGrid<D> out;
  out.grid = BackgroundGrid<D>::covering(lo, hi, cell_width, degree);
  const BackgroundGrid<D>& grid = out.grid;
  if (grid.spline_count() > 50'000'000ull)
    throw std::invalid_argument("the grid is too fine: " + std::to_string(grid.spline_count()) + " B-splines");
  const std::size_t cell_count = grid.cell_count();
  const double memory_limit = memory.limit_mb > 0.0 ? memory.limit_mb : available_megabytes();
  // The classification's own arrays, before it allocates them.
  const double classification_mb =
      static_cast<double>(cell_count) * (sizeof(ClassifiedCell) + sizeof(CellKind) + 8) / (1024.0 * 1024.0);
  if (memory_limit > 0.0 && classification_mb > memory_limit)
    throw std::runtime_error("the grid is too large for this machine: classifying its " + std::to_string(cell_count) +
                             " cells needs about " + std::to_string(static_cast<long long>(classification_mb)) +
                             " MB, " + std::to_string(static_cast<long long>(memory_limit)) +
                             " MB are available (use fewer cells or a lower degree)");
  cells.classify(grid);
  const std::vector<CellKind>& kinds = cells.kinds();
  report.cells_inside = 0;
  for (std::size_t c = 0; c < cell_count; ++c) {
    if (kinds[c] == CellKind::Outside) continue;
    out.candidates.push_back(c);
    if (kinds[c] == CellKind::Inside) ++report.cells_inside;
  }
  report.cells = cell_count;
  report.cells_cut = out.candidates.size() - report.cells_inside;
  // The problem file's keys are named: the campaign of bench/problem_mutations.py
  // found these two to be where a wrong number in the domain's model ends.
  if (out.candidates.empty())
    throw std::runtime_error("the domain (/domain) is empty in its bounds " + box_text(lo, hi) +
                             ": omega < 0 on every grid cell");
  if (report.cells_inside == 0)
    throw std::runtime_error("the grid is too coarse: no cell of width " + number_text(grid.h, 6) +
                             " lies entirely inside the domain (/domain) in its bounds " + box_text(lo, hi) +
                             " (use more cells)");
  out.interior = deepest_inside_centre(grid, kinds);
  check_memory<D>(grid, out.candidates, report, memory, memory_limit);
  return out;
}

template <int D>
CellRules<D> integrate_cells(const DomainCells<D>& cells, const ClassifiedGrid<D>& classified,
                             const QuadratureOptions& rule_options, const QuadratureOptions& band_options,
                             const std::vector<char>& in_band, bool with_surface) {
  const std::vector<std::size_t>& candidates = classified.candidates;
  CellRules<D> rules;
  rules.volume.resize(candidates.size());
  rules.surface.resize(candidates.size());
#pragma omp parallel
  {
    typename DomainCells<D>::Rule rule(cells, rule_options), band_rule(cells, band_options);
#pragma omp for schedule(dynamic, 16) nowait
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const std::size_t c = candidates[k];
      const bool band = !in_band.empty() && in_band[k];
      (band ? band_rule : rule)
          .append(c, cell_box(classified.grid, c), rules.volume[k], with_surface ? &rules.surface[k] : nullptr);
    }
#pragma omp critical
    for (const QuadratureCounts* counts : {&rule.counts(), &band_rule.counts()}) {
      rules.counts.masked_boxes += counts->masked_boxes;
      rules.counts.masked_points += counts->masked_points;
      rules.counts.unresolved_surface += counts->unresolved_surface;
      rules.counts.unbroken_boxes += counts->unbroken_boxes;
    }
  }
  return rules;
}

void report_fallbacks(const QuadratureCounts& counts, SolveReport& report) {
  report.masked_boxes += counts.masked_boxes;
  report.masked_points += counts.masked_points;
  report.unresolved_surface_boxes += counts.unresolved_surface;
  report.unbroken_boxes += counts.unbroken_boxes;
}

template <int D>
std::size_t rest_points(const PoissonProblem& problem, const CellRules<D>& rules, double cell_width) {
  std::vector<Expr> selectors;
  for (const BoundaryPart& part : problem.parts) selectors.push_back(part.selector);
  if (selectors.empty()) selectors.push_back(Expr(1.0));  // no named part: a tape of one constant, never near 0
  const Tape tape(selectors, D);
  std::size_t rest = 0;
#pragma omp parallel reduction(+ : rest)
  {
    Evaluator<double> eval(tape);
#pragma omp for schedule(dynamic, 64)
    for (std::size_t k = 0; k < rules.surface.size(); ++k)
      for (const auto& s : rules.surface[k]) {
        eval.evaluate(s.x.data());
        rest += nearest_part(eval, problem.parts.size(), kSelectorTolerance * cell_width) == problem.parts.size();
      }
  }
  return rest;
}

template <int D>
SplineBasis<D> basis_on_cells(const DomainCells<D>& cells, const ClassifiedGrid<D>& classified, CellRules<D>& rules,
                              BasisKind kind, SolveReport& report) {
  const BackgroundGrid<D>& grid = classified.grid;
  const std::vector<CellKind>& kinds = cells.kinds();
  std::vector<char> active(grid.cell_count(), 0), inside(grid.cell_count(), 0);
  for (std::size_t k = 0; k < classified.candidates.size(); ++k) {
    const std::size_t c = classified.candidates[k];
    double weight = 0.0;
    for (const auto& q : rules.volume[k]) weight += q.weight;
    active[c] = weight > 1e-13 * std::pow(grid.h, D) ? 1 : 0;
    if (!active[c]) rules.volume[k].clear();
    inside[c] = kinds[c] == CellKind::Inside ? 1 : 0;
    report.volume_points += rules.volume[k].size();
    if (kinds[c] == CellKind::Cut) report.cut_volume_points += rules.volume[k].size();
    report.surface_points += rules.surface[k].size();
  }
  SplineBasis<D> basis = build_basis(grid, active, inside, kind);
  report.relevant_splines = basis.relevant.size();
  report.inner_splines = basis.inner_count;
  report.outer_splines = basis.outer_count;
  report.unknowns = basis.unknowns();
  return basis;
}

template <int D>
QuadratureDump quadrature_dump(const CellRules<D>& rules) {
  QuadratureDump dump;
  auto add = [&](const std::array<double, D>& x, double weight, double on_surface) {
    for (int a = 0; a < 3; ++a) dump.coordinates.push_back(a < D ? x[a] : 0.0);
    dump.weights.push_back(weight);
    dump.on_surface.push_back(on_surface);
  };
  for (std::size_t k = 0; k < rules.volume.size(); ++k) {
    for (const auto& q : rules.volume[k]) add(q.x, q.weight, 0.0);
    for (const auto& q : rules.surface[k]) add(q.x, q.weight, 1.0);
  }
  return dump;
}

template <int D>
InsideSplineTable inside_spline_table(const BackgroundGrid<D>& grid, int rule_points) {
  const GaussRule& rule = gauss_legendre(rule_points);
  InsideSplineTable table;
  table.points = 1;
  for (int a = 0; a < D; ++a) table.points *= static_cast<std::size_t>(rule_points);
  const auto local = static_cast<std::size_t>(grid.local_count());
  table.value.resize(table.points * local);
  for (int a = 0; a < D; ++a) table.gradient[a].resize(table.points * local);
  LocalSplines<D> splines;
  const std::array<int, D> cell{};  // the first cell: t = Gauss node on every axis
  for (std::size_t p = 0; p < table.points; ++p) {
    std::array<double, D> x{};
    std::size_t rest = p;
    for (int a = 0; a < D; ++a) {
      x[a] = grid.lo[a] + grid.h * rule.nodes[rest % static_cast<std::size_t>(rule_points)];
      rest /= static_cast<std::size_t>(rule_points);
    }
    splines.evaluate(grid, cell, x.data());
    std::copy(splines.value.begin(), splines.value.end(), table.value.begin() + p * local);
    for (int a = 0; a < D; ++a)
      std::copy(splines.gradient[a].begin(), splines.gradient[a].end(), table.gradient[a].begin() + p * local);
  }
  return table;
}

template <int D>
StencilLayout<D>::StencilLayout(int degree) {
  const int width = 2 * degree + 1;
  int local = 1;
  for (int a = 0; a < D; ++a) {
    size *= width;
    local *= degree + 1;
  }
  position.resize(static_cast<std::size_t>(local));
  for (int k = 0; k < local; ++k) {
    const auto m = LocalSplines<D>::global_index({}, degree, k);
    int p = 0;
    for (int a = D - 1; a >= 0; --a) p = p * width + m[a];
    position[static_cast<std::size_t>(k)] = p;
  }
  for (int a = D - 1; a >= 0; --a) centre = centre * width + degree;
}

template <int D>
SplinePlacement spline_placement(const SplineBasis<D>& basis, int components, std::size_t without_place) {
  SplinePlacement placement;
  placement.dimension = D;
  placement.degree = basis.grid.degree;
  for (int c = 0; c < components; ++c)
    for (const std::size_t spline : basis.unknown_spline) {
      const auto i = basis.grid.spline_index(basis.relevant[spline]);
      std::array<int, 3> index{};
      std::copy(i.begin(), i.end(), index.begin());
      placement.index.push_back(index);
      placement.component.push_back(c);
    }
  placement.index.resize(placement.index.size() + without_place, std::array<int, 3>{});
  placement.component.resize(placement.component.size() + without_place, -1);
  return placement;
}

#define SAGE_DISCRETIZATION(D)                                                                                         \
  template Box<D> cell_box<D>(const BackgroundGrid<D>&, std::size_t);                                                  \
  template class DomainCells<D>;                                                                                       \
  template ClassifiedGrid<D> classify_grid<D>(DomainCells<D>&, const std::array<double, 3>&,                           \
                                              const std::array<double, 3>&, double, int, const MemoryNeeds&,           \
                                              SolveReport&);                                                           \
  template CellRules<D> integrate_cells<D>(const DomainCells<D>&, const ClassifiedGrid<D>&, const QuadratureOptions&,  \
                                           const QuadratureOptions&, const std::vector<char>&, bool);                  \
  template std::size_t rest_points<D>(const PoissonProblem&, const CellRules<D>&, double);                             \
  template SplineBasis<D> basis_on_cells<D>(const DomainCells<D>&, const ClassifiedGrid<D>&, CellRules<D>&, BasisKind, \
                                            SolveReport&);                                                             \
  template QuadratureDump quadrature_dump<D>(const CellRules<D>&);                                                     \
  template InsideSplineTable inside_spline_table<D>(const BackgroundGrid<D>&, int);                                    \
  template struct StencilLayout<D>;                                                                                    \
  template SplinePlacement spline_placement<D>(const SplineBasis<D>&, int, std::size_t);
SAGE_DISCRETIZATION(2)
SAGE_DISCRETIZATION(3)
#undef SAGE_DISCRETIZATION

}  // namespace sage::solver
