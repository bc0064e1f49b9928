#include "elasticity_assembly.hpp"

#include "cell_loop.hpp"

#include <sage/solver/local_splines.hpp>

#include <Eigen/Cholesky>

#include <cmath>
#include <optional>

namespace sage::solver {

namespace {

/// The cell's strain-displacement matrix in Voigt order (elastic_material.hpp)
/// from the gradients of the local trial functions of each component:
/// gradient[c][a] holds d(w_c B_j)/dx_a for the local splines j; local
/// unknown (c, j) is column c * local + j.
template <int D>
void strain_matrix(const std::array<std::array<const double*, D>, D>& gradient, int local, Eigen::MatrixXd& strain) {
  strain.setZero();
  for (int v = 0; v < voigt_size(D); ++v) {
    const auto [a, b] = voigt_axes(D, v);
    for (int j = 0; j < local; ++j) {
      strain(v, a * local + j) += gradient[a][b][j];
      if (a != b) strain(v, b * local + j) += gradient[b][a][j];
    }
  }
}

/// The traction sigma n in terms of Voigt stresses: t = N sigma_v.
template <int D>
Eigen::MatrixXd traction_map(const std::array<double, D>& n) {
  Eigen::MatrixXd map = Eigen::MatrixXd::Zero(D, voigt_size(D));
  for (int v = 0; v < voigt_size(D); ++v) {
    const auto [a, b] = voigt_axes(D, v);
    map(a, v) += n[b];
    if (a != b) map(b, v) += n[a];
  }
  return map;
}

/// Elasticity's kernel of the cell loop (cell_loop.hpp): one block per
/// displacement component, one right side.
template <int D>
class ElasticityKernel {
 public:
  ElasticityKernel(const ElasticityAssemblyInput<D>& in, const Tape& force_tape, const Tape& surface_tape)
      : in_(in),
        local_(in.basis.grid.local_count()),
        dofs_(D * local_),
        voigt_(voigt_size(D)),
        elastic_(in.problem.material.voigt(D)),
        elastic_root_(Eigen::LLT<Eigen::MatrixXd>(elastic_).matrixL()),  // C = R R^T
        selector_tolerance_(kSelectorTolerance * in.basis.grid.h),
        penalty_(in.weak ? in.nitsche_penalty * in.problem.material.stiffness_scale(D) / in.basis.grid.h : 0.0),
        force_eval_(force_tape),
        surface_eval_(surface_tape),
        columns_(dofs_, 0),
        strain_(voigt_, dofs_),
        trial_(dofs_),
        traction_row_(dofs_),
        trial_gradient_(static_cast<std::size_t>(D * D * local_)) {
    if (in.structure) structure_eval_.emplace(*in.structure);
  }

  int blocks() const { return D; }
  int right_sides() const { return 1; }

  int cell(const CellView<D>& cell, Eigen::MatrixXd& stiffness, Eigen::MatrixXd& right) {
    const bool structured = structure_eval_.has_value();
    // Without the structure every inside cell has the same stiffness (constant material).
    const bool reused = !structured && cell.tabulated && inside_stiffness_.size() > 0;
    const auto needed = static_cast<Eigen::Index>(cell.volume.size()) * voigt_;
    if (!reused && columns_.cols() < needed) columns_.resize(dofs_, needed);
    right.setZero();
    volume_terms(cell, right, reused);
    if (reused) {
      stiffness = inside_stiffness_;
    } else {
      stiffness.setZero();
      stiffness.template selfadjointView<Eigen::Lower>().rankUpdate(columns_.leftCols(needed));
      if (!structured && cell.tabulated) inside_stiffness_ = stiffness;
    }
    surface_terms(cell, stiffness, right);
    return D;
  }

  void merge(const ElasticityKernel&) {}

 private:
  /// The load (f, v) - (sigma(g~), eps(v)) and (unless `reused`) the columns
  /// sqrt(w) eps^T R of every volume point.
  void volume_terms(const CellView<D>& cell, Eigen::MatrixXd& right, bool reused) {
    const BackgroundGrid<D>& grid = in_.basis.grid;
    const int local = local_, voigt = voigt_;
    for (std::size_t p = 0; p < cell.volume.size(); ++p) {
      const auto& q = cell.volume[p];
      const double* value = nullptr;
      std::array<const double*, D> slope{};
      if (cell.tabulated) {
        value = cell.table.value.data() + p * static_cast<std::size_t>(local);
        for (int a = 0; a < D; ++a) slope[a] = cell.table.gradient[a].data() + p * static_cast<std::size_t>(local);
      } else {
        splines_.evaluate(grid, cell.index, q.x.data());
        value = splines_.value.data();
        for (int a = 0; a < D; ++a) slope[a] = splines_.gradient[a].data();
      }
      force_eval_.evaluate(q.x.data());
      const Eigen::Map<const Eigen::VectorXd> values(value, local);
      // Trial gradients d(w_c B_j)/dx_a, and the load (f, v) - (sigma(g~), eps(v)).
      std::array<std::array<const double*, D>, D> gradient{};
      if (structure_eval_) {
        structure_eval_->evaluate(q.x.data());
        Eigen::VectorXd offset_strain = Eigen::VectorXd::Zero(voigt);
        for (int c = 0; c < D; ++c) {
          const auto& w = structure_eval_->result(2 * static_cast<std::size_t>(c));
          const auto gw = w.gradient();
          const auto go = structure_eval_->result(2 * static_cast<std::size_t>(c) + 1).gradient();
          for (int a = 0; a < D; ++a) {
            double* out = trial_gradient_.data() + static_cast<std::size_t>((c * D + a) * local);
            for (int j = 0; j < local; ++j) out[j] = gw[a] * value[j] + w.value() * slope[a][j];
            gradient[c][a] = out;
          }
          right.col(0).segment(c * local, local) += (q.weight * force_eval_.result(c) * w.value()) * values;
          for (int v = 0; v < voigt; ++v) {
            const auto [a, b] = voigt_axes(D, v);
            if (a == c) offset_strain[v] += go[b];
            if (b == c && a != b) offset_strain[v] += go[a];
          }
        }
        strain_matrix<D>(gradient, local, strain_);
        right.col(0) -= q.weight * (strain_.transpose() * (elastic_ * offset_strain));
      } else {
        for (int c = 0; c < D; ++c) {
          for (int a = 0; a < D; ++a) gradient[c][a] = slope[a];
          right.col(0).segment(c * local, local) += (q.weight * force_eval_.result(c)) * values;
        }
        if (!reused) strain_matrix<D>(gradient, local, strain_);
      }
      if (!reused)
        columns_.middleCols(static_cast<Eigen::Index>(p) * voigt, voigt) =
            std::sqrt(q.weight) * (strain_.transpose() * elastic_root_);
    }
  }

  /// The loads <t - p n, w_c B_j> of loaded parts and Nitsche's terms of
  /// fixed components (w = 1: the B-splines themselves).
  void surface_terms(const CellView<D>& cell, Eigen::MatrixXd& stiffness, Eigen::MatrixXd& right) {
    const ElasticityProblem& problem = in_.problem;
    const std::size_t part_count = problem.parts.size(), part_stride = 2 * D + 1;
    const int local = local_;
    for (const auto& s : cell.surface) {
      surface_eval_.evaluate(s.x.data());
      const std::size_t part = nearest_part(surface_eval_, part_count, selector_tolerance_);
      const ElasticPart& data = part < part_count ? problem.parts[part] : problem.rest;
      const std::size_t at = part_count + part * part_stride;
      const bool nitsche = in_.weak && data.fixed();
      if (!data.loaded && !nitsche) continue;
      splines_.evaluate(in_.basis.grid, cell.index, s.x.data());
      const Eigen::Map<const Eigen::VectorXd> values(splines_.value.data(), local);
      if (data.loaded) {
        if (structure_eval_) structure_eval_->evaluate(s.x.data());
        const double pressure = surface_eval_.result(at + D);
        for (int c = 0; c < D; ++c) {
          const double t = surface_eval_.result(at + static_cast<std::size_t>(c)) - pressure * s.normal[c];
          const double w = structure_eval_ ? structure_eval_->result(2 * static_cast<std::size_t>(c)).value() : 1.0;
          right.col(0).segment(c * local, local) += (s.weight * t * w) * values;
        }
        continue;
      }
      std::array<std::array<const double*, D>, D> gradient{};
      for (int c = 0; c < D; ++c)
        for (int a = 0; a < D; ++a) gradient[c][a] = splines_.gradient[a].data();
      strain_matrix<D>(gradient, local, strain_);
      const Eigen::MatrixXd traction = traction_map<D>(s.normal) * elastic_ * strain_;  // D x dofs
      auto lower = stiffness.template selfadjointView<Eigen::Lower>();
      for (int c = 0; c < D; ++c) {
        if (!data.fixes(c)) continue;
        const double g = surface_eval_.result(at + D + 1 + static_cast<std::size_t>(c));
        trial_.setZero();
        trial_.segment(c * local, local) = values;
        traction_row_ = traction.row(c).transpose();
        lower.rankUpdate(trial_, s.weight * penalty_);
        lower.rankUpdate(trial_, traction_row_, -s.weight);
        right.col(0) += (s.weight * g) * (penalty_ * trial_ - traction_row_);
      }
    }
  }

  const ElasticityAssemblyInput<D>& in_;
  const int local_, dofs_, voigt_;
  const Eigen::MatrixXd elastic_, elastic_root_;
  const double selector_tolerance_, penalty_;
  std::optional<Evaluator<Tuple<D, 1>>> structure_eval_;
  Evaluator<double> force_eval_, surface_eval_;
  LocalSplines<D> splines_;
  Eigen::MatrixXd columns_, inside_stiffness_, strain_;
  Eigen::VectorXd trial_, traction_row_;
  std::vector<double> trial_gradient_;
};

}  // namespace

template <int D>
ElasticityAssembly assemble_elasticity(const ElasticityAssemblyInput<D>& in) {
  const ElasticityProblem& problem = in.problem;
  // Surface data: the selectors, then per part (named, then the rest) the
  // traction (D), the pressure, and the displacement data (D, 0 where free).
  std::vector<Expr> surface_roots;
  for (const ElasticPart& part : problem.parts) surface_roots.push_back(part.selector);
  const std::size_t part_count = problem.parts.size();
  for (std::size_t k = 0; k <= part_count; ++k) {
    const ElasticPart& part = k < part_count ? problem.parts[k] : problem.rest;
    for (int c = 0; c < D; ++c) surface_roots.push_back(part.traction[static_cast<std::size_t>(c)]);
    surface_roots.push_back(part.pressure);
    for (int c = 0; c < D; ++c)
      surface_roots.push_back(part.fixes(c) ? *part.displacement[static_cast<std::size_t>(c)] : Expr(0.0));
  }
  const Tape surface_tape(surface_roots, D);
  const Tape force_tape(std::vector<Expr>(problem.body_force.begin(), problem.body_force.begin() + D), D);
  ElasticityKernel<D> kernel(in, force_tape, surface_tape);
  CellSums sums = assemble_cells<D>(in.basis, in.candidates, in.kinds, in.rules, in.inside_points, kernel);
  return {std::move(sums.bands), std::move(sums.right_sides)};
}

template ElasticityAssembly assemble_elasticity<2>(const ElasticityAssemblyInput<2>&);
template ElasticityAssembly assemble_elasticity<3>(const ElasticityAssemblyInput<3>&);

}  // namespace sage::solver
