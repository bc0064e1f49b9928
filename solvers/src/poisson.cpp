#include "discretization.hpp"
#include "linear_solve.hpp"
#include "stage_timer.hpp"

#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/condition.hpp>
#include <sage/solver/extended_system.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/poisson.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

namespace {

/// Everything the assembly of one cell reads, compiled once.
struct AssemblyTapes {
  Tape structure;     // omega_D, g~
  Tape coefficients;  // k, f
  Tape surface;       // selectors..., then beta, flux, g per named part, then beta, flux, g of the rest
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

/// The structure route's own conditions (trial_structure.hpp): the field
/// of the structured parts must not vanish inside the domain (W = 0 would
/// impose the Robin condition there too), and the structured parts must not
/// meet a Dirichlet part (W is singular where omega_D and omega_R vanish
/// together). Checked at the quadrature points; throws std::invalid_argument.
template <int D>
void check_robin_structure(const BoundaryStructure& structure, const TrialStructure& trial, double h,
                           const std::vector<std::vector<VolumePoint<D>>>& volume,
                           const std::vector<std::vector<SurfacePoint<D>>>& surface) {
  const Tape tape(std::vector<Expr>{trial.robin_field, structure.dirichlet_weight}, D);
  const bool has_dirichlet = trial.joined_with_dirichlet;
  double lowest = 0.0;
  std::array<double, D> lowest_at{}, junction{};
  bool meets = false;
#pragma omp parallel
  {
    Evaluator<Tuple<D, 1>> eval(tape);
    double own_lowest = 0.0;
    std::array<double, D> own_at{};
#pragma omp for schedule(dynamic, 64) nowait
    for (std::size_t k = 0; k < volume.size(); ++k) {
      for (const auto& q : volume[k]) {
        eval.evaluate(q.x.data());
        if (eval.result(0).value() < own_lowest) {
          own_lowest = eval.result(0).value();
          own_at = q.x;
        }
      }
      if (!has_dirichlet) continue;
      for (const auto& q : surface[k]) {
        eval.evaluate(q.x.data());
        if (std::abs(eval.result(0).value()) > 1e-6 * h) continue;  // not on a structured part
        const auto& omega_d = eval.result(1);
        double slope = 0.0;
        for (double g : omega_d.gradient()) slope += g * g;
        if (omega_d.value() > 0.5 * h * std::sqrt(slope)) continue;
#pragma omp critical
        {
          meets = true;
          junction = q.x;
        }
      }
    }
#pragma omp critical
    if (own_lowest < lowest) {
      lowest = own_lowest;
      lowest_at = own_at;
    }
  }
  if (lowest < -1e-9 * h)
    throw std::invalid_argument(
        "Robin structure: the field of the Neumann and Robin parts is negative inside the domain "
        "(at " +
        point_text<D>(lowest_at) +
        "), so its zero set crosses the domain; the structure route needs fields that vanish "
        "on the boundary only (use the weak route)");
  if (meets)
    throw std::invalid_argument("Robin structure: a Neumann or Robin part meets a Dirichlet part (near " +
                                point_text<D>(junction) + "), where the structure is singular; use the weak route");
}

/// Gauss points per direction added in the cells of the Robin structure's
/// band (degree 3: 4 + 7; with 4 + 4 the errors stall at h = 0.0125).
constexpr int kBandExtraPoints = 7;

/// The unknowns that the structure's second function keeps: those whose
/// function M b_j (M = V omega_R, b_j = sum_i E_ij B_i) carries energy, by the diagonal
/// of E^T A_QQ E; as an unknowns x kept matrix of ones.
Eigen::SparseMatrix<double> second_function_unknowns(const Eigen::SparseMatrix<double>& own) {
  const Eigen::VectorXd diagonal = own.diagonal();
  const double least = 1e-14 * diagonal.maxCoeff();
  std::vector<Eigen::Triplet<double>> ones;
  for (Eigen::Index j = 0; j < diagonal.size(); ++j)
    if (diagonal[j] > least) ones.emplace_back(j, static_cast<Eigen::Index>(ones.size()), 1.0);
  Eigen::SparseMatrix<double> select(diagonal.size(), static_cast<Eigen::Index>(ones.size()));
  select.setFromTriplets(ones.begin(), ones.end());
  return select;
}

/// The lower triangle of [S_PP, S_QP^T; S_QP, S_QQ] from S_PP's lower
/// triangle, the coupling S_QP (Q rows, P columns) and S_QQ.
Eigen::SparseMatrix<double> joined_system(const Eigen::SparseMatrix<double>& pp_lower,
                                          const Eigen::SparseMatrix<double>& qp,
                                          const Eigen::SparseMatrix<double>& qq) {
  const Eigen::Index p = pp_lower.rows(), total = p + qq.rows();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(pp_lower.nonZeros() + qp.nonZeros() + qq.nonZeros()));
  for (Eigen::Index c = 0; c < p; ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator e(pp_lower, c); e; ++e) entries.emplace_back(e.row(), c, e.value());
  for (Eigen::Index c = 0; c < qp.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator e(qp, c); e; ++e) entries.emplace_back(p + e.row(), c, e.value());
  for (Eigen::Index c = 0; c < qq.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator e(qq, c); e; ++e)
      if (e.row() >= c) entries.emplace_back(p + e.row(), p + c, e.value());
  Eigen::SparseMatrix<double> joined(total, total);
  joined.setFromTriplets(entries.begin(), entries.end());
  return joined;
}

}  // namespace

// The second function absorbs the Robin defect within the band, so P needs
// no layer, and V D1(P) costs O(band^1.5 h^(n-1)) in H1: below h^n for
// band ~ h^(2/3). A band of a few cells (~ h) would do as well in exact
// arithmetic, but its cut-offs would then vary within a cell at every h,
// and Gauss rules would leave a relative error that does not fall with h
// (README, Robin structure; bench/robin_structure_study).
double robin_band_width(double fraction, double cell_width, double longest_side) {
  if (fraction <= 0.0) return 0.0;
  return fraction * longest_side * std::pow(cell_width / longest_side, 2.0 / 3.0);
}

double nitsche_penalty(double requested, int degree) {
  return requested > 0.0 ? requested : kNitschePenaltyFactor * (degree + 1) * (degree + 1);
}

DirichletRoute parse_dirichlet_route(const std::string& text) {
  if (text == "auto") return DirichletRoute::Automatic;
  if (text == "weak") return DirichletRoute::Weak;
  if (text == "structure") return DirichletRoute::Structure;
  throw std::invalid_argument("expected auto, weak or structure, not '" + text + "'");
}

double automatic_cg_tolerance(double cell_width, double longest_side, int degree) {
  const double tolerance = std::pow(cell_width / longest_side, degree + 3);
  return std::min(std::max(tolerance, 1e-12), 1e-6);
}

template <int D>
PoissonSolution<D>::Probe::Probe(const PoissonSolution& solution)
    : solution_(&solution),
      structure_(*solution.structure),
      domain_(solution.domain, solution.mesh, solution.basis.grid.h) {}

template <int D>
double PoissonSolution<D>::Probe::at(const double* x, double* gradient) {
  const auto& grid = solution_->basis.grid;
  const auto cell = grid.cell_of(x);
  const bool structured = solution_->structure->results().size() > 2;
  const bool second = solution_->second_coefficients.size() > 0;
  LocalSplines<D>& local = local_;
  local.evaluate(grid, cell, x, structured);
  // Phi = sum c B, its gradient and (structure route) its Hessian; Q = sum q B and its gradient.
  double s = 0.0, q = 0.0;
  std::array<double, D> grad_s{}, grad_q{};
  std::array<double, LocalSplines<D>::kHessianEntries> hess_s{};
  for (int k = 0; k < grid.local_count(); ++k) {
    const auto i = LocalSplines<D>::global_index(cell, grid.degree, k);
    const long long r = solution_->basis.relevant_of[grid.spline_linear(i)];
    if (r < 0) continue;
    const double c = solution_->spline_coefficients[r];
    s += c * local.value[k];
    for (int a = 0; a < D; ++a) grad_s[a] += c * local.gradient[a][k];
    if (structured)
      for (int e = 0; e < LocalSplines<D>::kHessianEntries; ++e) hess_s[e] += c * local.hessian[e][k];
    if (!second) continue;
    const double d = solution_->second_coefficients[r];
    q += d * local.value[k];
    for (int a = 0; a < D; ++a) grad_q[a] += d * local.gradient[a][k];
  }
  structure_.evaluate(x);
  const auto& w = structure_.result(0);
  const auto& g = structure_.result(1);
  double u = w.value() * s + g.value();
  std::array<double, D> grad_u{};
  const auto gw = w.gradient(), gg = g.gradient();
  for (int a = 0; a < D; ++a) grad_u[a] = gw[a] * s + w.value() * grad_s[a] + gg[a];
  if (structured) {
    // u -= transport . grad Phi, and its gradient.
    for (int b = 0; b < D; ++b) {
      const auto& t = structure_.result(2 + static_cast<std::size_t>(b));
      const auto gt = t.gradient();
      u -= t.value() * grad_s[b];
      for (int a = 0; a < D; ++a)
        grad_u[a] -= gt[a] * grad_s[b] + t.value() * hess_s[LocalSplines<D>::hessian_index(a, b)];
    }
  }
  if (second) {  // u += M Q, M = V omega_R
    const auto& m = structure_.result(2 + D);
    const auto gm = m.gradient();
    u += m.value() * q;
    for (int a = 0; a < D; ++a) grad_u[a] += gm[a] * q + m.value() * grad_q[a];
  }
  if (gradient)
    for (int a = 0; a < D; ++a) gradient[a] = grad_u[a];
  return u;
}

template <int D>
PoissonSolution<D> solve_poisson(const PoissonProblem& problem, const SolverOptions& options) {
  if (problem.dimension != D) throw std::invalid_argument("problem dimension does not match the solver");
  check_solver_options(options, problem.min, problem.max, D);
  PoissonSolution<D> solution;
  SolveReport& report = solution.report;
  StageTimer timer(report);
  const int n = options.degree;

  // Field: the domain's pieces and their Boolean formula, compiled (not for
  // mesh domains, whose cells come from the triangles).
  DomainCells<D> cells(problem.domain, problem.boundary_mesh);
  timer.lap(&StageSeconds::field);

  // Classification of the background cells.
  const bool direct = options.linear_solver == LinearSolverKind::Direct ||
                      (options.linear_solver == LinearSolverKind::Automatic && options.robin == RobinRoute::Structure);
  const ClassifiedGrid<D> classified = classify_grid<D>(cells, problem.min, problem.max, options.cell_width, n,
                                                        {direct, 1, options.memory_limit_mb}, report);
  const BackgroundGrid<D>& grid = classified.grid;
  const std::vector<std::size_t>& candidates = classified.candidates;
  const std::vector<CellKind>& kinds = cells.kinds();
  const std::array<double, 3>& interior = classified.interior;
  // Gauss with n + 1 nodes per direction, in inside cells and on every
  // piece of a cut cell whose active pieces are planar: exact for the
  // polynomial part (degree 2n + 1). One more where a curved piece is
  // active: weak terms on a sphere need it (the ball's Robin patch test:
  // L2 1.8e-5 with n + 1, 8e-7 with n + 2).
  const int inside_points = options.quadrature_points > 0 ? options.quadrature_points : n + 1;
  const QuadratureOptions quadrature{inside_points, inside_points, options.max_subdivision, 1};
  timer.lap(&StageSeconds::classification);

  bool has_dirichlet = problem.rest.kind == BoundaryKind::Dirichlet, has_weak = !has_dirichlet;
  for (const BoundaryPart& part : problem.parts) {
    has_dirichlet = has_dirichlet || part.kind == BoundaryKind::Dirichlet;
    has_weak = has_weak || part.kind != BoundaryKind::Dirichlet;
  }
  const bool structured = options.robin == RobinRoute::Structure && has_weak;
  if (structured && n < 2)
    throw std::invalid_argument(
        "the Robin structure needs second derivatives of the B-splines: use degree 2 or more (or the weak route)");
  DirichletRoute route = options.dirichlet;
  // Nitsche's method leans on the WEB extension for its stability (plain
  // B-splines with slivers of support need no penalty bound); the Robin
  // structure is built on the Dirichlet structure.
  if (route == DirichletRoute::Automatic)
    route = structured || options.basis == BasisKind::Weighted ? DirichletRoute::Structure : DirichletRoute::Weak;
  if (route == DirichletRoute::Weak && structured)
    throw std::invalid_argument(
        "the Robin structure is built on the Dirichlet structure: impose Dirichlet conditions by the structure too "
        "(--dirichlet structure), or Neumann and Robin conditions weakly");
  const bool weak_dirichlet = route == DirichletRoute::Weak && has_dirichlet;
  const BoundaryStructure structure = boundary_structure(problem, interior, route == DirichletRoute::Structure);
  report.dirichlet_route = route == DirichletRoute::Weak ? "weak (Nitsche)" : "structure";
  if (weak_dirichlet) report.nitsche_penalty = nitsche_penalty(options.nitsche_penalty, n);
  const bool needs_surface = structure.has_weak_parts || weak_dirichlet;
  double longest = 0.0;
  for (int a = 0; a < D; ++a) longest = std::max(longest, problem.max[a] - problem.min[a]);
  if (structured) report.robin_band = robin_band_width(options.robin_band, grid.h, longest);
  // Nitsche's trial functions are the WEB B-splines themselves: the
  // structure's omega_D = 1 and g~ = 0 then (boundary_structure()).
  const TrialStructure trial = structured
                                   ? robin_trial(problem, structure, *report.robin_band, options.robin_band_power)
                                   : dirichlet_trial(structure);
  const bool second = trial.second_function();
  // Cells that may meet the structure's band (omega_R < band over the cell,
  // by intervals) hold its cut-offs, polynomials of degree power + 2 or so in
  // omega_R times the splines, and their C^(power - 1) edge: a finer rule
  // there (with n + 1 points, degree 3, h = 0.0125: H1 error 7.8e-4 against 3.6e-9).
  std::vector<char> in_band(candidates.size(), 0);
  if (second) {
    const Tape field(trial.robin_field, D);
    Evaluator<Interval> eval(field);
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const Box<D> box = cell_box(grid, candidates[k]);
      std::array<Interval, 3> x{Interval(0.0), Interval(0.0), Interval(0.0)};
      for (int a = 0; a < D; ++a) x[static_cast<std::size_t>(a)] = Interval(box.lo[a], box.hi[a]);
      eval.evaluate_with(x.data());
      in_band[k] = !(eval.result().lo >= *report.robin_band) ? 1 : 0;  // NaN: may meet it
    }
  }
  const int band_points = inside_points + kBandExtraPoints;
  const QuadratureOptions band_quadrature{band_points + 1, band_points, options.max_subdivision, 0};

  // Quadrature: volume rules of inside and cut cells, surface rules where
  // a weak condition may hold.
  CellRules<D> rules = integrate_cells(cells, classified, quadrature, band_quadrature, in_band, needs_surface, report);
  const auto& volume = rules.volume;
  const auto& surface = rules.surface;
  timer.lap(&StageSeconds::quadrature);

  // Basis and assembly.
  solution.basis = basis_on_cells(cells, classified, rules, options.basis, report);
  if (options.keep_quadrature) solution.quadrature = quadrature_dump(rules);
  const SplineBasis<D>& basis = solution.basis;

  // Dirichlet data on the boundary: the caller's extension when given (its
  // boundary values are the data), else each part's value.
  std::vector<Expr> surface_roots = structure.selectors;
  for (const BoundaryPart* part : all_parts(problem)) {
    surface_roots.push_back(part->beta);
    surface_roots.push_back(part->flux);
    surface_roots.push_back(problem.dirichlet_extension ? *problem.dirichlet_extension : part->value);
  }
  std::vector<Expr> trial_roots{trial.scale, trial.offset};
  for (const Expr& t : trial.transport) trial_roots.push_back(t);
  if (second) trial_roots.push_back(trial.second_weight);
  auto structure_tape = std::make_shared<Tape>(trial_roots, D);
  if (structured) check_robin_structure(structure, trial, grid.h, volume, surface);
  const AssemblyTapes tapes{*structure_tape, Tape(std::vector<Expr>{problem.conductivity, problem.source}, D),
                            Tape(surface_roots, D)};
  solution.structure = structure_tape;
  solution.mesh = cells.mesh();
  if (!solution.mesh) solution.domain = std::make_shared<Tape>(problem.domain, D);

  const StencilLayout<D> layout(n);
  const int stencil = layout.size;
  const std::size_t relevant = basis.relevant.size();
  std::vector<double> band(relevant * static_cast<std::size_t>(stencil), 0.0);
  std::vector<double> load(relevant, 0.0);
  // The structure's second function Q: its rows of the Galerkin matrix
  // (against P's trial functions and its own), in the band's layout, and
  // its load; per relevant B-spline, extended below like P's.
  std::vector<double> second_band(second ? band.size() : 0, 0.0), coupling_band(second_band.size(), 0.0);
  std::vector<double> second_load(second ? relevant : 0, 0.0);
  // Pure Neumann: (v_i, 1) per relevant spline, and (|f|, 1) + <|h|, 1>.
  const bool pure_neumann = structure.pure_neumann;
  std::vector<double> mean_load(pure_neumann ? relevant : 0, 0.0);
  std::vector<double> second_mean_load(pure_neumann && second ? relevant : 0, 0.0);
  double data_size = 0.0;
  double offset_mean = 0.0;                        // (u0, 1), pure Neumann only: the structure's u0 = -V h / k is not 0
  std::optional<std::array<double, D>> unclaimed;  // a surface point on no named part, where the rest must be empty
  const int local_count = grid.local_count();
  // Local trial functions per cell: P's, then (second function) Q's.
  const int local_rows = second ? 2 * local_count : local_count;
  const std::vector<int>& stencil_of_local = layout.position;
  const int stencil_centre = layout.centre;
  const double selector_tolerance = 1e-6 * grid.h;
  const double nitsche_weight = weak_dirichlet ? *report.nitsche_penalty / grid.h : 0.0;
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
        const double scale = std::sqrt(std::max(conductivity, 0.0) * q.weight);
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
        const double scale = std::sqrt(std::max(conductivity, 0.0) * q.weight);
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
  Eigen::SparseMatrix<double> system = extended_system(basis, band);  // lower triangle
  band = std::vector<double>();
  const Eigen::SparseMatrix<double>& E = basis.extension;
  Eigen::VectorXd right =
      E.transpose() * Eigen::Map<const Eigen::VectorXd>(load.data(), static_cast<Eigen::Index>(relevant));
  Eigen::VectorXd mean_row;  // (v_i, 1) per unknown, pure Neumann only
  double neumann_shift = 0.0;
  if (pure_neumann) {
    mean_row = E.transpose() * Eigen::Map<const Eigen::VectorXd>(mean_load.data(), static_cast<Eigen::Index>(relevant));
    const double total = right.sum();  // (f, 1) + <h, 1>: the test function 1 is the vector of ones
    const double defect = std::abs(total) / std::max(data_size, std::numeric_limits<double>::min());
    report.neumann_compatibility = defect;
    if (data_size > 0.0 && defect > kNeumannCompatibilityTolerance)
      throw std::invalid_argument(
          "incompatible Neumann data: a pure Neumann problem needs (integral of f over the domain) + (integral of h "
          "over the boundary) = 0, but it is " +
          scientific(total) + " (relative to the integrals of |f| and |h|: " + scientific(defect) +
          "); fix the data or give a part a Dirichlet or Robin condition");
    neumann_shift = total / mean_row.sum();
    right -= neumann_shift * mean_row;
    Eigen::Index pinned = 0;
    system.diagonal().maxCoeff(&pinned);
    system.coeffRef(pinned, pinned) *= 2.0;
  }
  // The second function's unknowns after P's (the constant, P's vector of
  // ones, is still the null space of a pure Neumann problem).
  Eigen::SparseMatrix<double> second_select;
  if (second) {
    auto extended = [&](const std::vector<double>& b) {
      return Eigen::SparseMatrix<double>(E.transpose() * band_matrix(basis, b) * E);
    };
    const Eigen::SparseMatrix<double> own = extended(second_band);
    second_select = second_function_unknowns(own);
    const Eigen::SparseMatrix<double> select_t = second_select.transpose();
    const Eigen::SparseMatrix<double> qp = select_t * extended(coupling_band);
    const Eigen::SparseMatrix<double> qq = select_t * own * second_select;
    system = joined_system(system, qp, qq);
    auto rows_of = [&](const std::vector<double>& v) {
      return Eigen::VectorXd(select_t * (E.transpose() * Eigen::Map<const Eigen::VectorXd>(
                                                             v.data(), static_cast<Eigen::Index>(relevant))));
    };
    const Eigen::Index p = right.size(), q = second_select.cols();
    Eigen::VectorXd joined_right(p + q);
    joined_right << right, rows_of(second_load);
    if (pure_neumann) {
      Eigen::VectorXd joined_mean(p + q);
      joined_mean << mean_row, rows_of(second_mean_load);
      joined_right.tail(q) -= neumann_shift * joined_mean.tail(q);
      mean_row = joined_mean;
    }
    right = joined_right;
    report.unknowns += static_cast<std::size_t>(q);
    report.second_unknowns = static_cast<std::size_t>(q);
  }
  std::size_t diagonal_entries = 0;
  for (Eigen::Index p = 0; p < system.outerSize(); ++p) {
    const Eigen::SparseMatrix<double>::InnerIterator first(system, p);
    diagonal_entries += first && first.row() == p ? 1 : 0;
  }
  report.nonzeros = 2 * static_cast<std::size_t>(system.nonZeros()) - diagonal_entries;  // of the whole matrix
  timer.lap(&StageSeconds::assembly);

  // Solve.
  LinearSolverKind kind = options.linear_solver;
  // The structure's second function has functions of very different energy near the band's edge
  // (diagonal entries over 1e14 apart), where incomplete Cholesky needs 1e4 iterations and more.
  // Automatic in 3D: Jacobi, then incomplete Cholesky when Jacobi is too slow (linear_solve.hpp).
  if (kind == LinearSolverKind::Automatic && (second || D == 2))
    kind = second ? LinearSolverKind::Direct : LinearSolverKind::ConjugateGradient;
  const double tolerance =
      options.cg_tolerance > 0.0 ? options.cg_tolerance : automatic_cg_tolerance(grid.h, longest, n);
  Eigen::VectorXd coefficients = solve_symmetric(system, right, kind, tolerance, report);
  const Eigen::Index p_unknowns = E.cols();
  if (pure_neumann)  // zero mean of u = u0 + sum c v: the constant is P's vector of ones
    coefficients.head(p_unknowns).array() -=
        (mean_row.dot(coefficients) + offset_mean) / mean_row.head(p_unknowns).sum();
  solution.spline_coefficients = E * coefficients.head(p_unknowns);
  if (second) solution.second_coefficients = E * (second_select * coefficients.tail(second_select.cols()));
  timer.lap(&StageSeconds::solve);

  if (options.estimate_condition) {
    const ConditionEstimate estimate =
        estimate_condition(Eigen::SparseMatrix<double>(system.selfadjointView<Eigen::Lower>()));
    report.condition = estimate.condition;
    report.scaled_condition = estimate.scaled_condition;
    timer.lap(&StageSeconds::condition);
  }

  if (problem.exact) {
    const Tape exact_tape(*problem.exact, D);
    double error2 = 0, norm2 = 0, grad_error2 = 0, grad_norm2 = 0;
#pragma omp parallel reduction(+ : error2, norm2, grad_error2, grad_norm2)
    {
      typename PoissonSolution<D>::Probe probe(solution);
      Evaluator<Tuple<D, 1>> exact(exact_tape);
#pragma omp for schedule(dynamic, 16)
      for (std::size_t k = 0; k < candidates.size(); ++k) {
        for (const auto& q : volume[k]) {
          double grad[D];
          const double u = probe.at(q.x.data(), grad);
          exact.evaluate(q.x.data());
          const auto& e = exact.result();
          const auto ge = e.gradient();
          error2 += q.weight * (u - e.value()) * (u - e.value());
          norm2 += q.weight * e.value() * e.value();
          for (int a = 0; a < D; ++a) {
            grad_error2 += q.weight * (grad[a] - ge[a]) * (grad[a] - ge[a]);
            grad_norm2 += q.weight * ge[a] * ge[a];
          }
        }
      }
    }
    report.l2_error = std::sqrt(error2 / norm2);
    report.h1_error = std::sqrt(grad_error2 / grad_norm2);
    timer.lap(&StageSeconds::errors);
  }
  return solution;
}

template class PoissonSolution<2>;
template class PoissonSolution<3>;
template PoissonSolution<2> solve_poisson<2>(const PoissonProblem&, const SolverOptions&);
template PoissonSolution<3> solve_poisson<3>(const PoissonProblem&, const SolverOptions&);

}  // namespace sage::solver
