#include "poisson_assembly.hpp"

#include <sage/solver/local_splines.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include "stage_timer.hpp"

#include <cmath>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

namespace {

/// Everything the assembly of one cell reads, compiled once.
struct AssemblyTapes {
  const Tape& structure;  // the trial structure (trial_structure.hpp)
  Tape coefficients;      // k, f
  Tape surface;           // selectors..., then beta, flux, g per named part, then beta, flux, g of the rest
};

/// Which boundary condition holds at a surface point (the part whose
/// selector is nearest zero, or the rest) and how it enters: by the
/// boundary integrals of a Neumann or Robin part, by Nitsche's terms of a
/// weak Dirichlet part, or not at all (a Dirichlet part in the trial
/// functions). Unclaimed: on no named part, where the rest must be empty.
struct SurfaceData {
  enum class Role { None, NeumannRobin, Nitsche, Unclaimed } role = Role::None;
  double beta = 0.0, flux = 0.0, value = 0.0;
};

SurfaceData surface_data(const PoissonProblem& problem, const Evaluator<double>& eval, double tolerance,
                         bool weak_dirichlet, bool rest_must_be_empty) {
  const std::size_t parts = problem.parts.size();
  const std::size_t nearest = nearest_part(eval, parts, tolerance);
  if (nearest == parts && rest_must_be_empty) return {SurfaceData::Role::Unclaimed};
  const BoundaryPart& part = nearest < parts ? problem.parts[nearest] : problem.rest;
  const std::size_t data = parts + 3 * nearest;
  if (part.kind != BoundaryKind::Dirichlet)
    return {SurfaceData::Role::NeumannRobin, eval.result(data), eval.result(data + 1), 0.0};
  if (weak_dirichlet) return {SurfaceData::Role::Nitsche, 0.0, 0.0, eval.result(data + 2)};
  return {};
}

/// The named parts, then the rest: the order of the surface tape's data.
std::vector<const BoundaryPart*> all_parts(const PoissonProblem& problem) {
  std::vector<const BoundaryPart*> parts;
  for (const BoundaryPart& part : problem.parts) parts.push_back(&part);
  parts.push_back(&problem.rest);
  return parts;
}

/// Nitsche's terms of a weak Dirichlet condition u = g at the surface
/// point s (outward normal n, weight w), for the trial functions B_j:
///
///     a_jl += w [ sigma k B_j B_l - k (dn B_j B_l + B_j dn B_l) ]
///     f_j  += w [ sigma k g B_j - k g dn B_j ]
///
/// (the symmetric method; sigma = penalty / h). Lower triangle of a_jl.
template <int D>
void add_nitsche_terms(const BackgroundGrid<D>& grid, const std::array<int, D>& cell, const SurfacePoint<D>& s,
                       double conductivity, double g, double sigma, LocalSplines<D>& local, Eigen::MatrixXd& stiffness,
                       Eigen::VectorXd& rhs) {
  local.evaluate(grid, cell, s.x.data());
  const int count = grid.local_count();
  const Eigen::Map<const Eigen::VectorXd> values(local.value.data(), count);
  Eigen::VectorXd dn = Eigen::VectorXd::Zero(count);
  for (int a = 0; a < D; ++a) dn += s.normal[a] * Eigen::Map<const Eigen::VectorXd>(local.gradient[a].data(), count);
  const double wk = s.weight * conductivity;
  rhs.head(count) += (wk * g) * (sigma * values - dn);
  auto lower = stiffness.topLeftCorner(count, count).template selfadjointView<Eigen::Lower>();
  lower.rankUpdate(values, wk * sigma);
  lower.rankUpdate(values, dn, -wk);
}

}  // namespace

template <int D>
PoissonAssembly assemble_poisson(const PoissonAssemblyInput<D>& in) {
  const PoissonProblem& problem = in.problem;
  const BoundaryStructure& structure = in.structure;
  const SplineBasis<D>& basis = in.basis;
  const BackgroundGrid<D>& grid = basis.grid;
  const std::vector<std::size_t>& candidates = in.candidates;
  const std::vector<CellKind>& kinds = in.kinds;
  const auto& volume = in.rules.volume;
  const auto& surface = in.rules.surface;
  const bool structured = in.structured, second = in.second, weak_dirichlet = in.weak_dirichlet;
  const int n = grid.degree, inside_points = in.inside_points;
  // Dirichlet data on the boundary: the caller's extension when given (its
  // boundary values are the data), else each part's value.
  std::vector<Expr> surface_roots = structure.selectors;
  for (const BoundaryPart* part : all_parts(problem)) {
    surface_roots.push_back(part->beta);
    surface_roots.push_back(part->flux);
    surface_roots.push_back(problem.dirichlet_extension ? *problem.dirichlet_extension : part->value);
  }
  const AssemblyTapes tapes{in.trial, Tape(std::vector<Expr>{problem.conductivity, problem.source}, D),
                            Tape(surface_roots, D)};

  const StencilLayout<D> layout(n);
  const int stencil = layout.size;
  const std::size_t relevant = basis.relevant.size();
  PoissonAssembly out;
  std::vector<double>& band = out.band;
  std::vector<double>& load = out.load;
  band.assign(relevant * static_cast<std::size_t>(stencil), 0.0);
  load.assign(relevant, 0.0);
  // The structure's second function Q: its rows of the Galerkin matrix
  // (against P's trial functions and its own), in the band's layout, and
  // its load; per relevant B-spline, extended below like P's.
  std::vector<double>& second_band = out.second_band;
  std::vector<double>& coupling_band = out.coupling_band;
  std::vector<double>& second_load = out.second_load;
  second_band.assign(second ? band.size() : 0, 0.0);
  coupling_band.assign(second_band.size(), 0.0);
  second_load.assign(second ? relevant : 0, 0.0);
  // Pure Neumann: (v_i, 1) per relevant spline, and (|f|, 1) + <|h|, 1>.
  const bool pure_neumann = structure.pure_neumann;
  std::vector<double>& mean_load = out.mean_load;
  std::vector<double>& second_mean_load = out.second_mean_load;
  mean_load.assign(pure_neumann ? relevant : 0, 0.0);
  second_mean_load.assign(pure_neumann && second ? relevant : 0, 0.0);
  double& data_size = out.data_size;
  double& offset_mean = out.offset_mean;           // (u0, 1), pure Neumann only: the structure's u0 = -V h / k is not 0
  std::optional<std::array<double, D>> unclaimed;  // a surface point on no named part, where the rest must be empty
  const int local_count = grid.local_count();
  // Local trial functions per cell: P's, then (second function) Q's.
  const int local_rows = second ? 2 * local_count : local_count;
  const std::vector<int>& stencil_of_local = layout.position;
  const int stencil_centre = layout.centre;
  const double selector_tolerance = kSelectorTolerance * grid.h;
  const double nitsche_weight = weak_dirichlet ? in.nitsche_penalty / grid.h : 0.0;
  // The local B-splines at the inside cells' common rule, tabulated once.
  const InsideSplineTable inside_table = inside_spline_table<D>(grid, inside_points);
  // With a constant conductivity and no weight (w = 1: Nitsche's route and
  // the weak route's Neumann problems), every inside cell has the same
  // stiffness matrix: computed once per thread, then copied.
  const bool same_inside_stiffness = !structured && problem.conductivity.is_constant() &&
                                     structure.dirichlet_weight.is_constant() &&
                                     structure.dirichlet_weight.constant_value() == 1.0;

#pragma omp parallel
  {
    Evaluator<Tuple<D, 1>> structure_eval(tapes.structure);
    Evaluator<double> coefficient_eval(tapes.coefficients);
    Evaluator<double> surface_eval(tapes.surface);
    LocalSplines<D> local;
    Eigen::MatrixXd gradients(local_rows, 0), stiffness(local_rows, local_rows);
    Eigen::VectorXd rhs(local_rows), trial_values(local_rows);
    std::vector<long long> rows(static_cast<std::size_t>(local_count));
    // Each thread adds into its own band (no atomics), summed below; the
    // first thread adds into `band` itself (one thread: no copy at all).
    // Cells go to threads in a fixed pattern and the sums are taken in
    // thread order, so the same run gives the same bits every time.
#ifdef _OPENMP
    const bool first_thread = omp_get_thread_num() == 0;
#else
    const bool first_thread = true;
#endif
    std::vector<double> own_band_storage(first_thread ? 0 : band.size(), 0.0);
    std::vector<double>& own_band = first_thread ? band : own_band_storage;
    std::vector<double> own_load(load.size(), 0.0), own_mean(mean_load.size(), 0.0);
    std::vector<double> own_second_band(second_band.size(), 0.0), own_coupling_band(second_band.size(), 0.0);
    std::vector<double> own_second_load(second_load.size(), 0.0), own_second_mean(second_mean_load.size(), 0.0);
    Eigen::VectorXd mean_rhs(local_rows);
    double own_data_size = 0.0, own_offset_mean = 0.0;
    std::optional<std::array<double, D>> own_unclaimed;  // a surface point on no named part, if any
    // 3D inside cells: stiffness by sum factorization, from these per-point coefficients.
    TensorCellStiffness tensor(n, inside_points, grid.h);
    Eigen::MatrixXd inside_stiffness;  // same_inside_stiffness: the first inside cell's, lower triangle
    std::vector<double> c0(static_cast<std::size_t>(tensor.point_count())), c2(c0.size());
    std::array<std::vector<double>, 3> c1{c0, c0, c0};
#pragma omp for schedule(static, 8) nowait
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const auto& points = volume[k];
      if (points.empty()) continue;
      const auto cell = grid.cell_index(candidates[k]);
      const bool tabulated = kinds[candidates[k]] == CellKind::Inside && points.size() == inside_table.points;
      const bool reused = same_inside_stiffness && tabulated && inside_stiffness.size() > 0;
      const bool factorized = D == 3 && tabulated && !structured && !reused;
      const auto columns = static_cast<Eigen::Index>(points.size() * D);
      if (gradients.cols() < columns) gradients.resize(local_rows, columns);
      rhs.setZero();
      mean_rhs.setZero();
      bool meets_second = false;  // M != 0 at a point of the cell
      for (std::size_t p = 0; p < points.size() && structured; ++p) {
        const auto& q = points[p];
        structure_eval.evaluate(q.x.data());
        coefficient_eval.evaluate(q.x.data());
        const double conductivity = coefficient_eval.result(0), source = coefficient_eval.result(1);
        local.evaluate(grid, cell, q.x.data(), true);
        const auto& w = structure_eval.result(0);
        const auto gw = w.gradient(), gg = structure_eval.result(1).gradient();
        const double scale = std::sqrt(conductivity * q.weight);  // k > 0: check_data
        // v_j = w B_j - t . grad B_j; d v_j / dx_a = dw/dx_a B_j + w dB_j/dx_a
        //       - sum_b (dt_b/dx_a dB_j/dx_b + t_b d2B_j/dx_a dx_b).
        const Eigen::Map<const Eigen::VectorXd> values(local.value.data(), local_count);
        auto p_values = trial_values.head(local_count);
        p_values = w.value() * values;
        for (int b = 0; b < D; ++b)
          p_values -= structure_eval.result(2 + static_cast<std::size_t>(b)).value() *
                      Eigen::Map<const Eigen::VectorXd>(local.gradient[b].data(), local_count);
        // Q's trial functions M B_j and their gradients.
        const Tuple<D, 1>* m = second ? &structure_eval.result(2 + D) : nullptr;
        if (m) {
          trial_values.tail(local_count) = m->value() * values;
          meets_second = meets_second || m->value() != 0.0;
        }
        rhs += (q.weight * source) * trial_values;
        if (pure_neumann) {
          mean_rhs += q.weight * trial_values;
          own_offset_mean += q.weight * structure_eval.result(1).value();
          own_data_size += q.weight * std::abs(source);
        }
        for (int a = 0; a < D; ++a) {
          auto full_column = gradients.col(static_cast<Eigen::Index>(p * D + static_cast<std::size_t>(a)));
          auto column = full_column.head(local_count);
          const Eigen::Map<const Eigen::VectorXd> slopes(local.gradient[a].data(), local_count);
          column = gw[a] * values + w.value() * slopes;
          for (int b = 0; b < D; ++b) {
            const auto& t = structure_eval.result(2 + static_cast<std::size_t>(b));
            column -= t.gradient()[a] * Eigen::Map<const Eigen::VectorXd>(local.gradient[b].data(), local_count) +
                      t.value() * Eigen::Map<const Eigen::VectorXd>(
                                      local.hessian[LocalSplines<D>::hessian_index(a, b)].data(), local_count);
          }
          if (m) full_column.tail(local_count) = m->gradient()[a] * values + m->value() * slopes;
          rhs -= (q.weight * conductivity * gg[a]) * full_column;
          full_column *= scale;
        }
      }
      for (std::size_t p = 0; p < points.size() && !structured; ++p) {
        const auto& q = points[p];
        structure_eval.evaluate(q.x.data());
        coefficient_eval.evaluate(q.x.data());
        const auto& w = structure_eval.result(0);
        const auto& g = structure_eval.result(1);
        const auto gw = w.gradient(), gg = g.gradient();
        const double conductivity = coefficient_eval.result(0), source = coefficient_eval.result(1);
        const double* value_data = nullptr;
        std::array<const double*, D> slope_data{};
        if (tabulated) {
          value_data = inside_table.value.data() + p * static_cast<std::size_t>(local_count);
          for (int a = 0; a < D; ++a) slope_data[a] = inside_table.gradient[a].data() + p * local_count;
        } else {
          local.evaluate(grid, cell, q.x.data());
          value_data = local.value.data();
          for (int a = 0; a < D; ++a) slope_data[a] = local.gradient[a].data();
        }
        const double scale = std::sqrt(conductivity * q.weight);
        // Column a of point p: scale * d v_j / dx_a for every j, with
        // grad v_j = B_j grad w + w grad B_j (contiguous, vectorizable).
        // The load (f, v_j) - (k grad g, grad v_j) is alpha B_j + beta . grad B_j.
        const Eigen::Map<const Eigen::VectorXd> values(value_data, local_count);
        double alpha = source * w.value();
        for (int a = 0; a < D; ++a) alpha -= conductivity * gg[a] * gw[a];
        rhs += (q.weight * alpha) * values;
        if (pure_neumann) {
          mean_rhs += (q.weight * w.value()) * values;
          own_offset_mean += q.weight * g.value();
          own_data_size += q.weight * std::abs(source);
        }
        for (int a = 0; a < D; ++a) {
          const Eigen::Map<const Eigen::VectorXd> slopes(slope_data[a], local_count);
          rhs -= (q.weight * conductivity * gg[a] * w.value()) * slopes;
          if (factorized || reused) continue;
          gradients.col(static_cast<Eigen::Index>(p * D + static_cast<std::size_t>(a))) =
              (scale * gw[a]) * values + (scale * w.value()) * slopes;
        }
        if (!factorized) continue;
        const double scale2 = scale * scale;
        double slope2 = 0.0;
        for (int a = 0; a < D; ++a) {
          slope2 += gw[a] * gw[a];
          c1[static_cast<std::size_t>(a)][p] = scale2 * w.value() * gw[a];
        }
        c0[p] = scale2 * slope2;
        c2[p] = scale2 * w.value() * w.value();
      }
      if (reused) {
        stiffness = inside_stiffness;
      } else if (factorized) {
        tensor.compute(c0.data(), {c1[0].data(), c1[1].data(), c1[2].data()}, c2.data(), stiffness);
      } else {
        stiffness.setZero();
        stiffness.template selfadjointView<Eigen::Lower>().rankUpdate(gradients.leftCols(columns));
      }
      if (same_inside_stiffness && tabulated && !reused) inside_stiffness = stiffness;
      for (const auto& s : surface[k]) {
        surface_eval.evaluate(s.x.data());
        const SurfaceData data =
            surface_data(problem, surface_eval, selector_tolerance, weak_dirichlet, structure.rest_must_be_empty);
        if (data.role == SurfaceData::Role::Unclaimed && !own_unclaimed) own_unclaimed = s.x;
        if (data.role == SurfaceData::Role::None || data.role == SurfaceData::Role::Unclaimed) continue;
        if (data.role == SurfaceData::Role::Nitsche) {
          coefficient_eval.evaluate(s.x.data());
          add_nitsche_terms<D>(grid, cell, s, coefficient_eval.result(0), data.value, nitsche_weight, local, stiffness,
                               rhs);
          continue;
        }
        structure_eval.evaluate(s.x.data());
        const double w = structure_eval.result(0).value(), g = structure_eval.result(1).value();
        local.evaluate(grid, cell, s.x.data());
        const Eigen::Map<const Eigen::VectorXd> values(local.value.data(), local_count);
        auto p_values = trial_values.head(local_count);
        p_values = w * values;
        for (int b = 0; b < D && structured; ++b)  // transport vanishes on the boundary up to round-off
          p_values -= structure_eval.result(2 + static_cast<std::size_t>(b)).value() *
                      Eigen::Map<const Eigen::VectorXd>(local.gradient[b].data(), local_count);
        if (second) {  // M vanishes on the structured parts, not on the rest's weak boundary
          const double m = structure_eval.result(2 + D).value();
          trial_values.tail(local_count) = m * values;
          meets_second = meets_second || m != 0.0;
        }
        own_data_size += pure_neumann ? s.weight * std::abs(data.flux) : 0.0;
        for (int j = 0; j < local_rows; ++j) {
          const double vj = trial_values[j];
          rhs[j] += s.weight * (data.flux - data.beta * g) * vj;
          if (data.beta == 0.0) continue;
          for (int l = 0; l <= j; ++l) stiffness(j, l) += s.weight * data.beta * vj * trial_values[l];
        }
      }
      for (int j = 0; j < local_count; ++j)
        rows[j] = basis.relevant_of[grid.spline_linear(LocalSplines<D>::global_index(cell, n, j))];
      // Fill the upper triangle: column j is then row j, read contiguously.
      stiffness.template triangularView<Eigen::StrictlyUpper>() = stiffness.transpose();
      for (int j = 0; j < local_count; ++j) {
        own_load[static_cast<std::size_t>(rows[j])] += rhs[j];
        if (pure_neumann) own_mean[static_cast<std::size_t>(rows[j])] += mean_rhs[j];
        double* row = own_band.data() + static_cast<std::size_t>(rows[j]) * static_cast<std::size_t>(stencil) +
                      stencil_centre - stencil_of_local[j];
        const double* column = stiffness.col(j).data();
        for (int l = 0; l < local_count; ++l) row[stencil_of_local[l]] += column[l];
      }
      if (!meets_second) continue;
      // Q's rows: against P's trial functions (coupling) and against Q's own.
      for (int j = 0; j < local_count; ++j) {
        const auto r = static_cast<std::size_t>(rows[j]);
        own_second_load[r] += rhs[local_count + j];
        if (pure_neumann) own_second_mean[r] += mean_rhs[local_count + j];
        const std::size_t slot = r * static_cast<std::size_t>(stencil) + stencil_centre - stencil_of_local[j];
        for (int l = 0; l < local_count; ++l) {
          own_coupling_band[slot + stencil_of_local[l]] += stiffness(local_count + j, l);
          own_second_band[slot + stencil_of_local[l]] += stiffness(local_count + j, local_count + l);
        }
      }
    }
    in_thread_order([&] {
      if (!first_thread)
        for (std::size_t i = 0; i < band.size(); ++i) band[i] += own_band[i];
      for (std::size_t i = 0; i < load.size(); ++i) load[i] += own_load[i];
      for (std::size_t i = 0; i < mean_load.size(); ++i) mean_load[i] += own_mean[i];
      for (std::size_t i = 0; i < second_band.size(); ++i) {
        second_band[i] += own_second_band[i];
        coupling_band[i] += own_coupling_band[i];
      }
      for (std::size_t i = 0; i < second_load.size(); ++i) second_load[i] += own_second_load[i];
      for (std::size_t i = 0; i < second_mean_load.size(); ++i) second_mean_load[i] += own_second_mean[i];
      data_size += own_data_size;
      offset_mean += own_offset_mean;
      if (own_unclaimed && !unclaimed) unclaimed = own_unclaimed;
    });
  }
  if (unclaimed)
    throw std::invalid_argument(
        "the boundary at " + point_text<D>(*unclaimed) +
        " belongs to no named part, and the problem gives no default condition: name that part, or give a "
        "\"default\" (with --dirichlet structure beside Neumann or Robin parts, the default must be one of those)");
  return out;
}

template PoissonAssembly assemble_poisson<2>(const PoissonAssemblyInput<2>&);
template PoissonAssembly assemble_poisson<3>(const PoissonAssemblyInput<3>&);

}  // namespace sage::solver
