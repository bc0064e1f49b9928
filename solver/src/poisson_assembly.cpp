#include "poisson_assembly.hpp"

#include <sage/solver/local_splines.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include "cell_loop.hpp"
#include "message_text.hpp"

#include <cmath>
#include <stdexcept>

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
                       Eigen::Ref<Eigen::VectorXd> rhs) {
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

/// Poisson's kernel of the cell loop (cell_loop.hpp): blocks P (and Q,
/// the Robin structure's second function), right sides the load (and,
/// pure Neumann, (v_i, 1)).
template <int D>
class PoissonKernel {
 public:
  PoissonKernel(const PoissonAssemblyInput<D>& in, const AssemblyTapes& tapes)
      : in_(in),
        structured_(in.structured),
        second_(in.second),
        pure_neumann_(in.structure.pure_neumann),
        local_count_(in.basis.grid.local_count()),
        local_rows_(second_ ? 2 * local_count_ : local_count_),
        selector_tolerance_(kSelectorTolerance * in.basis.grid.h),
        nitsche_weight_(in.weak_dirichlet ? in.nitsche_penalty / in.basis.grid.h : 0.0),
        // With a constant conductivity and no weight (w = 1: Nitsche's route and
        // the weak route's Neumann problems), every inside cell has the same
        // stiffness matrix: computed once per thread, then copied.
        same_inside_stiffness_(!structured_ && in.problem.conductivity.is_constant() &&
                               in.structure.dirichlet_weight.is_constant() &&
                               in.structure.dirichlet_weight.constant_value() == 1.0),
        structure_eval_(tapes.structure),
        coefficient_eval_(tapes.coefficients),
        surface_eval_(tapes.surface),
        gradients_(local_rows_, 0),
        trial_values_(local_rows_),
        tensor_(in.basis.grid.degree, in.inside_points, in.basis.grid.h),
        c0_(static_cast<std::size_t>(tensor_.point_count())),
        c2_(c0_.size()),
        c1_{c0_, c0_, c0_} {}

  int blocks() const { return second_ ? 2 : 1; }
  int right_sides() const { return pure_neumann_ ? 2 : 1; }

  int cell(const CellView<D>& cell, Eigen::MatrixXd& stiffness, Eigen::MatrixXd& right) {
    right.setZero();
    const bool reused = same_inside_stiffness_ && cell.tabulated && inside_stiffness_.size() > 0;
    const bool factorized = D == 3 && cell.tabulated && !structured_ && !reused;
    const auto columns = static_cast<Eigen::Index>(cell.volume.size() * D);
    if (gradients_.cols() < columns) gradients_.resize(local_rows_, columns);
    const bool meets_second = structured_ ? structured_volume(cell, right) : false;
    if (!structured_) plain_volume(cell, right, factorized || reused, factorized);
    if (reused) {
      stiffness = inside_stiffness_;
    } else if (factorized) {
      tensor_.compute(c0_.data(), {c1_[0].data(), c1_[1].data(), c1_[2].data()}, c2_.data(), stiffness);
    } else {
      stiffness.setZero();
      stiffness.template selfadjointView<Eigen::Lower>().rankUpdate(gradients_.leftCols(columns));
    }
    if (same_inside_stiffness_ && cell.tabulated && !reused) inside_stiffness_ = stiffness;
    const bool surface_meets_second = surface_terms(cell, stiffness, right);
    return meets_second || surface_meets_second ? 2 : 1;
  }

  void merge(const PoissonKernel& other) {
    data_size += other.data_size;
    offset_mean += other.offset_mean;
    if (other.unclaimed && !unclaimed) unclaimed = other.unclaimed;
  }

  double data_size = 0.0;                          // pure Neumann: (|f|, 1) + <|h|, 1>
  double offset_mean = 0.0;                        // pure Neumann: (u0, 1); the structure's u0 = -V h / k is not 0
  std::optional<std::array<double, D>> unclaimed;  // a surface point on no named part, if any

 private:
  /// The Robin structure's volume terms: v_j = w B_j - t . grad B_j (and
  /// Q's M B_j), their gradients scaled into `gradients_`, the load.
  /// True when M != 0 at a point of the cell.
  bool structured_volume(const CellView<D>& cell, Eigen::MatrixXd& right) {
    const BackgroundGrid<D>& grid = in_.basis.grid;
    const int local_count = local_count_;
    bool meets_second = false;
    for (std::size_t p = 0; p < cell.volume.size(); ++p) {
      const auto& q = cell.volume[p];
      structure_eval_.evaluate(q.x.data());
      coefficient_eval_.evaluate(q.x.data());
      const double conductivity = coefficient_eval_.result(0), source = coefficient_eval_.result(1);
      local_.evaluate(grid, cell.index, q.x.data(), true);
      const auto& w = structure_eval_.result(0);
      const auto gw = w.gradient(), gg = structure_eval_.result(1).gradient();
      const double scale = std::sqrt(conductivity * q.weight);  // k > 0: check_data
      // v_j = w B_j - t . grad B_j; d v_j / dx_a = dw/dx_a B_j + w dB_j/dx_a
      //       - sum_b (dt_b/dx_a dB_j/dx_b + t_b d2B_j/dx_a dx_b).
      const Eigen::Map<const Eigen::VectorXd> values(local_.value.data(), local_count);
      auto p_values = trial_values_.head(local_count);
      p_values = w.value() * values;
      for (int b = 0; b < D; ++b)
        p_values -= structure_eval_.result(2 + static_cast<std::size_t>(b)).value() *
                    Eigen::Map<const Eigen::VectorXd>(local_.gradient[b].data(), local_count);
      // Q's trial functions M B_j and their gradients.
      const Tuple<D, 1>* m = second_ ? &structure_eval_.result(2 + D) : nullptr;
      if (m) {
        trial_values_.tail(local_count) = m->value() * values;
        meets_second = meets_second || m->value() != 0.0;
      }
      right.col(0) += (q.weight * source) * trial_values_;
      if (pure_neumann_) {
        right.col(1) += q.weight * trial_values_;
        offset_mean += q.weight * structure_eval_.result(1).value();
        data_size += q.weight * std::abs(source);
      }
      for (int a = 0; a < D; ++a) {
        auto full_column = gradients_.col(static_cast<Eigen::Index>(p * D + static_cast<std::size_t>(a)));
        auto column = full_column.head(local_count);
        const Eigen::Map<const Eigen::VectorXd> slopes(local_.gradient[a].data(), local_count);
        column = gw[a] * values + w.value() * slopes;
        for (int b = 0; b < D; ++b) {
          const auto& t = structure_eval_.result(2 + static_cast<std::size_t>(b));
          column -= t.gradient()[a] * Eigen::Map<const Eigen::VectorXd>(local_.gradient[b].data(), local_count) +
                    t.value() * Eigen::Map<const Eigen::VectorXd>(
                                    local_.hessian[LocalSplines<D>::hessian_index(a, b)].data(), local_count);
        }
        if (m) full_column.tail(local_count) = m->gradient()[a] * values + m->value() * slopes;
        right.col(0) -= (q.weight * conductivity * gg[a]) * full_column;
        full_column *= scale;
      }
    }
    return meets_second;
  }

  /// The volume terms of v_j = w B_j: the load, and the scaled gradients
  /// into `gradients_` (`skip_gradients`: the stiffness comes otherwise),
  /// or the sum factorization's coefficients (`factorized`).
  void plain_volume(const CellView<D>& cell, Eigen::MatrixXd& right, bool skip_gradients, bool factorized) {
    const BackgroundGrid<D>& grid = in_.basis.grid;
    const int local_count = local_count_;
    for (std::size_t p = 0; p < cell.volume.size(); ++p) {
      const auto& q = cell.volume[p];
      structure_eval_.evaluate(q.x.data());
      coefficient_eval_.evaluate(q.x.data());
      const auto& w = structure_eval_.result(0);
      const auto& g = structure_eval_.result(1);
      const auto gw = w.gradient(), gg = g.gradient();
      const double conductivity = coefficient_eval_.result(0), source = coefficient_eval_.result(1);
      const double* value_data = nullptr;
      std::array<const double*, D> slope_data{};
      if (cell.tabulated) {
        value_data = cell.table.value.data() + p * static_cast<std::size_t>(local_count);
        for (int a = 0; a < D; ++a) slope_data[a] = cell.table.gradient[a].data() + p * local_count;
      } else {
        local_.evaluate(grid, cell.index, q.x.data());
        value_data = local_.value.data();
        for (int a = 0; a < D; ++a) slope_data[a] = local_.gradient[a].data();
      }
      const double scale = std::sqrt(conductivity * q.weight);
      // Column a of point p: scale * d v_j / dx_a for every j, with
      // grad v_j = B_j grad w + w grad B_j (contiguous, vectorizable).
      // The load (f, v_j) - (k grad g, grad v_j) is alpha B_j + beta . grad B_j.
      const Eigen::Map<const Eigen::VectorXd> values(value_data, local_count);
      double alpha = source * w.value();
      for (int a = 0; a < D; ++a) alpha -= conductivity * gg[a] * gw[a];
      right.col(0) += (q.weight * alpha) * values;
      if (pure_neumann_) {
        right.col(1) += (q.weight * w.value()) * values;
        offset_mean += q.weight * g.value();
        data_size += q.weight * std::abs(source);
      }
      for (int a = 0; a < D; ++a) {
        const Eigen::Map<const Eigen::VectorXd> slopes(slope_data[a], local_count);
        right.col(0) -= (q.weight * conductivity * gg[a] * w.value()) * slopes;
        if (skip_gradients) continue;
        gradients_.col(static_cast<Eigen::Index>(p * D + static_cast<std::size_t>(a))) =
            (scale * gw[a]) * values + (scale * w.value()) * slopes;
      }
      if (!factorized) continue;
      const double scale2 = scale * scale;
      double slope2 = 0.0;
      for (int a = 0; a < D; ++a) {
        slope2 += gw[a] * gw[a];
        c1_[static_cast<std::size_t>(a)][p] = scale2 * w.value() * gw[a];
      }
      c0_[p] = scale2 * slope2;
      c2_[p] = scale2 * w.value() * w.value();
    }
  }

  /// The boundary terms: Nitsche's on weak Dirichlet parts, the Neumann and
  /// Robin integrals. True when M != 0 at a surface point of the cell.
  bool surface_terms(const CellView<D>& cell, Eigen::MatrixXd& stiffness, Eigen::MatrixXd& right) {
    const BackgroundGrid<D>& grid = in_.basis.grid;
    const int local_count = local_count_;
    bool meets_second = false;
    for (const auto& s : cell.surface) {
      surface_eval_.evaluate(s.x.data());
      const SurfaceData data = surface_data(in_.problem, surface_eval_, selector_tolerance_, in_.weak_dirichlet,
                                            in_.structure.rest_must_be_empty);
      if (data.role == SurfaceData::Role::Unclaimed && !unclaimed) unclaimed = s.x;
      if (data.role == SurfaceData::Role::None || data.role == SurfaceData::Role::Unclaimed) continue;
      if (data.role == SurfaceData::Role::Nitsche) {
        coefficient_eval_.evaluate(s.x.data());
        add_nitsche_terms<D>(grid, cell.index, s, coefficient_eval_.result(0), data.value, nitsche_weight_, local_,
                             stiffness, right.col(0));
        continue;
      }
      structure_eval_.evaluate(s.x.data());
      const double w = structure_eval_.result(0).value(), g = structure_eval_.result(1).value();
      local_.evaluate(grid, cell.index, s.x.data());
      const Eigen::Map<const Eigen::VectorXd> values(local_.value.data(), local_count);
      auto p_values = trial_values_.head(local_count);
      p_values = w * values;
      for (int b = 0; b < D && structured_; ++b)  // transport vanishes on the boundary up to round-off
        p_values -= structure_eval_.result(2 + static_cast<std::size_t>(b)).value() *
                    Eigen::Map<const Eigen::VectorXd>(local_.gradient[b].data(), local_count);
      if (second_) {  // M vanishes on the structured parts, not on the rest's weak boundary
        const double m = structure_eval_.result(2 + D).value();
        trial_values_.tail(local_count) = m * values;
        meets_second = meets_second || m != 0.0;
      }
      data_size += pure_neumann_ ? s.weight * std::abs(data.flux) : 0.0;
      for (int j = 0; j < local_rows_; ++j) {
        const double vj = trial_values_[j];
        right(j, 0) += s.weight * (data.flux - data.beta * g) * vj;
        if (data.beta == 0.0) continue;
        for (int l = 0; l <= j; ++l) stiffness(j, l) += s.weight * data.beta * vj * trial_values_[l];
      }
    }
    return meets_second;
  }

  const PoissonAssemblyInput<D>& in_;
  const bool structured_, second_, pure_neumann_;
  const int local_count_, local_rows_;
  const double selector_tolerance_, nitsche_weight_;
  const bool same_inside_stiffness_;
  Evaluator<Tuple<D, 1>> structure_eval_;
  Evaluator<double> coefficient_eval_, surface_eval_;
  LocalSplines<D> local_;
  Eigen::MatrixXd gradients_;
  Eigen::VectorXd trial_values_;
  // 3D inside cells: stiffness by sum factorization, from these per-point coefficients.
  TensorCellStiffness tensor_;
  std::vector<double> c0_, c2_;
  std::array<std::vector<double>, 3> c1_;
  Eigen::MatrixXd inside_stiffness_;  // same_inside_stiffness_: the first inside cell's, lower triangle
};

}  // namespace

template <int D>
PoissonAssembly assemble_poisson(const PoissonAssemblyInput<D>& in) {
  const PoissonProblem& problem = in.problem;
  // Dirichlet data on the boundary: the caller's extension when given (its
  // boundary values are the data), else each part's value.
  std::vector<Expr> surface_roots = in.structure.selectors;
  for (const BoundaryPart* part : all_parts(problem)) {
    surface_roots.push_back(part->beta);
    surface_roots.push_back(part->flux);
    surface_roots.push_back(problem.dirichlet_extension ? *problem.dirichlet_extension : part->value);
  }
  const AssemblyTapes tapes{in.trial, Tape(std::vector<Expr>{problem.conductivity, problem.source}, D),
                            Tape(surface_roots, D)};
  PoissonKernel<D> kernel(in, tapes);
  CellSums sums = assemble_cells<D>(in.basis, in.candidates, in.kinds, in.rules, in.inside_points, kernel);
  if (kernel.unclaimed)
    throw std::invalid_argument(
        "the boundary at " + point_text<D>(*kernel.unclaimed) +
        " belongs to no named part, and the problem gives no default condition: name that part, or give a "
        "\"default\" (with --dirichlet structure beside Neumann or Robin parts, the default must be one of those)");
  PoissonAssembly out;
  const int blocks = kernel.blocks();
  out.band = std::move(sums.bands[block_pair(0, 0)]);
  out.load = std::move(sums.right_sides[0]);
  if (in.structure.pure_neumann) out.mean_load = std::move(sums.right_sides[static_cast<std::size_t>(blocks)]);
  if (in.second) {
    out.coupling_band = std::move(sums.bands[block_pair(1, 0)]);
    out.second_band = std::move(sums.bands[block_pair(1, 1)]);
    out.second_load = std::move(sums.right_sides[1]);
    if (in.structure.pure_neumann) out.second_mean_load = std::move(sums.right_sides[3]);
  }
  out.data_size = kernel.data_size;
  out.offset_mean = kernel.offset_mean;
  return out;
}

template PoissonAssembly assemble_poisson<2>(const PoissonAssemblyInput<2>&);
template PoissonAssembly assemble_poisson<3>(const PoissonAssemblyInput<3>&);

}  // namespace sage::solver
