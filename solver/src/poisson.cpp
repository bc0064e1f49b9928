#include "data_check.hpp"
#include "discretization.hpp"
#include "linear_solve.hpp"
#include "message_text.hpp"
#include "poisson_assembly.hpp"
#include "stage_timer.hpp"

#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/condition.hpp>
#include <sage/solver/extended_system.hpp>
#include <sage/solver/poisson.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sage::solver {

namespace {

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

/// The system of the unknowns (lower triangle) and its right side, from
/// the assembly of the relevant B-splines: E^T A E and E^T b; for pure
/// Neumann problems the compatibility check, the load's shift and one
/// pinned unknown (poisson.hpp); the second function's unknowns after P's.
struct PoissonSystem {
  Eigen::SparseMatrix<double> matrix;
  Eigen::VectorXd right;
  Eigen::VectorXd mean_row;                   // (v_i, 1) per unknown, pure Neumann only
  Eigen::SparseMatrix<double> second_select;  // the second function's unknowns kept (second_function_unknowns)
};

template <int D>
PoissonSystem poisson_system(const SplineBasis<D>& basis, PoissonAssembly& assembly, bool pure_neumann, bool second,
                             SolveReport& report) {
  const std::size_t relevant = basis.relevant.size();
  PoissonSystem out;
  Eigen::SparseMatrix<double>& system = out.matrix;
  {
    Eigen::SparseMatrix<double> lower = extended_system(basis, assembly.band);
    system.swap(lower);  // Eigen 3.4's SparseMatrix has no move assignment: a copy would double it
  }
  assembly.band = std::vector<double>();
  const Eigen::SparseMatrix<double>& E = basis.extension;
  Eigen::VectorXd& right = out.right;
  right = E.transpose() * Eigen::Map<const Eigen::VectorXd>(assembly.load.data(), static_cast<Eigen::Index>(relevant));
  Eigen::VectorXd& mean_row = out.mean_row;
  double neumann_shift = 0.0;
  if (pure_neumann) {
    mean_row = E.transpose() *
               Eigen::Map<const Eigen::VectorXd>(assembly.mean_load.data(), static_cast<Eigen::Index>(relevant));
    const double total = right.sum();  // (f, 1) + <h, 1>: the test function 1 is the vector of ones
    const double defect = std::abs(total) / std::max(assembly.data_size, std::numeric_limits<double>::min());
    report.neumann_compatibility = defect;
    if (assembly.data_size > 0.0 && defect > kNeumannCompatibilityTolerance)
      throw std::invalid_argument(
          "incompatible Neumann data: no part of the boundary (/boundary) is Dirichlet or Robin with beta != 0, and "
          "such a pure Neumann problem needs (integral of f over the domain) + (integral of h over the boundary) = "
          "0, but it is " +
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
  Eigen::SparseMatrix<double>& second_select = out.second_select;
  if (second) {
    const Eigen::SparseMatrix<double> own = extended_product(basis, assembly.second_band);
    second_select = second_function_unknowns(own);
    const Eigen::SparseMatrix<double> select_t = second_select.transpose();
    const Eigen::SparseMatrix<double> qp = select_t * extended_product(basis, assembly.coupling_band);
    const Eigen::SparseMatrix<double> qq = select_t * own * second_select;
    system = joined_system(system, qp, qq);
    auto rows_of = [&](const std::vector<double>& v) {
      return Eigen::VectorXd(select_t * (E.transpose() * Eigen::Map<const Eigen::VectorXd>(
                                                             v.data(), static_cast<Eigen::Index>(relevant))));
    };
    const Eigen::Index p = right.size(), q = second_select.cols();
    Eigen::VectorXd joined_right(p + q);
    joined_right << right, rows_of(assembly.second_load);
    if (pure_neumann) {
      Eigen::VectorXd joined_mean(p + q);
      joined_mean << mean_row, rows_of(assembly.second_mean_load);
      joined_right.tail(q) -= neumann_shift * joined_mean.tail(q);
      mean_row = joined_mean;
    }
    right = joined_right;
    report.unknowns += static_cast<std::size_t>(q);
    report.second_unknowns = static_cast<std::size_t>(q);
  }
  return out;
}

/// Relative L2 and H1-seminorm errors against the exact solution, at the volume points.
template <int D>
void poisson_errors(const PoissonSolution<D>& solution, const Expr& exact_solution,
                    const std::vector<std::vector<VolumePoint<D>>>& volume, SolveReport& report) {
  const Tape exact_tape(exact_solution, D);
  double error2 = 0, norm2 = 0, grad_error2 = 0, grad_norm2 = 0;
#pragma omp parallel reduction(+ : error2, norm2, grad_error2, grad_norm2)
  {
    typename PoissonSolution<D>::Probe probe(solution);
    Evaluator<Tuple<D, 1>> exact(exact_tape);
#pragma omp for schedule(dynamic, 16)
    for (std::size_t k = 0; k < volume.size(); ++k) {
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
}

}  // namespace

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

namespace {

/// Named Neumann and Robin parts and no default: the rest is Dirichlet
/// u = 0 where it exists, but the named parts may claim the whole boundary,
/// and then the problem is a Neumann or Robin problem (pure Neumann
/// without Robin parts). The surface points tell: the problem as posed,
/// and (when they were needed) the rules that told, into `early_rules`.
template <int D>
PoissonProblem posed_problem(const PoissonProblem& given, const DomainCells<D>& cells,
                             const ClassifiedGrid<D>& classified, const QuadratureOptions& quadrature,
                             std::optional<CellRules<D>>& early_rules) {
  PoissonProblem problem = given;
  bool named_dirichlet = false, named_weak = false;
  for (const BoundaryPart& part : given.parts) {
    named_dirichlet = named_dirichlet || part.kind == BoundaryKind::Dirichlet;
    named_weak = named_weak || part.kind != BoundaryKind::Dirichlet;
  }
  if (given.rest_given || !named_weak || named_dirichlet) return problem;
  early_rules = integrate_cells(cells, classified, quadrature, quadrature, {}, true);
  if (rest_points(given, *early_rules, classified.grid.h) == 0) {
    problem.rest.kind = BoundaryKind::Neumann;
    problem.rest.flux = 0.0;
    problem.rest_given = true;
  }
  return problem;
}

/// How the conditions enter: the Robin structure or not, the Dirichlet route.
struct PoissonRoutes {
  bool structured = false;  // the Robin structure
  DirichletRoute dirichlet = DirichletRoute::Weak;
  bool weak_dirichlet = false;  // Nitsche's terms on Dirichlet parts
};

PoissonRoutes poisson_routes(const PoissonProblem& problem, const SolverOptions& options) {
  bool has_dirichlet = problem.rest.kind == BoundaryKind::Dirichlet, has_weak = !has_dirichlet;
  for (const BoundaryPart& part : problem.parts) {
    has_dirichlet = has_dirichlet || part.kind == BoundaryKind::Dirichlet;
    has_weak = has_weak || part.kind != BoundaryKind::Dirichlet;
  }
  PoissonRoutes routes;
  routes.structured = options.robin == RobinRoute::Structure && has_weak;
  if (routes.structured && options.degree < 2)
    throw std::invalid_argument(
        "the Robin structure needs second derivatives of the B-splines: use degree 2 or more (or the weak route)");
  routes.dirichlet = options.dirichlet;
  // Nitsche's method leans on the WEB extension for its stability (plain
  // B-splines with slivers of support need no penalty bound); the Robin
  // structure is built on the Dirichlet structure.
  if (routes.dirichlet == DirichletRoute::Automatic)
    routes.dirichlet =
        routes.structured || options.basis == BasisKind::Weighted ? DirichletRoute::Structure : DirichletRoute::Weak;
  if (routes.dirichlet == DirichletRoute::Weak && routes.structured)
    throw std::invalid_argument(
        "the Robin structure is built on the Dirichlet structure: impose Dirichlet conditions by the structure too "
        "(--dirichlet structure), or Neumann and Robin conditions weakly");
  routes.weak_dirichlet = routes.dirichlet == DirichletRoute::Weak && has_dirichlet;
  return routes;
}

/// Cells that may meet the structure's band (omega_R < band over the cell,
/// by intervals) hold its cut-offs, polynomials of degree power + 2 or so in
/// omega_R times the splines, and their C^(power - 1) edge: a finer rule
/// there (with n + 1 points, degree 3, h = 0.0125: H1 error 7.8e-4 against 3.6e-9).
template <int D>
std::vector<char> band_cells(const TrialStructure& trial, const ClassifiedGrid<D>& classified, double band) {
  const std::vector<std::size_t>& candidates = classified.candidates;
  std::vector<char> in_band(candidates.size(), 0);
  if (!trial.second_function()) return in_band;
  const Tape field(trial.robin_field, D);
  Evaluator<Interval> eval(field);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const Box<D> box = cell_box(classified.grid, candidates[k]);
    std::array<Interval, 3> x{Interval(0.0), Interval(0.0), Interval(0.0)};
    for (int a = 0; a < D; ++a) x[static_cast<std::size_t>(a)] = Interval(box.lo[a], box.hi[a]);
    eval.evaluate_with(x.data());
    in_band[k] = !(eval.result().lo >= band) ? 1 : 0;  // NaN: may meet it
  }
  return in_band;
}

/// The trial structure's roots, compiled: scale, offset, transport per axis, second weight.
template <int D>
std::shared_ptr<const Tape> trial_tape(const TrialStructure& trial) {
  std::vector<Expr> roots{trial.scale, trial.offset};
  for (const Expr& t : trial.transport) roots.push_back(t);
  if (trial.second_function()) roots.push_back(trial.second_weight);
  return std::make_shared<Tape>(roots, D);
}

/// The nonzeros of the whole matrix whose lower triangle `system` holds.
std::size_t whole_nonzeros(const Eigen::SparseMatrix<double>& system) {
  std::size_t diagonal_entries = 0;
  for (Eigen::Index p = 0; p < system.outerSize(); ++p) {
    const Eigen::SparseMatrix<double>::InnerIterator first(system, p);
    diagonal_entries += first && first.row() == p ? 1 : 0;
  }
  return 2 * static_cast<std::size_t>(system.nonZeros()) - diagonal_entries;
}

/// Solves the system, fixes a pure Neumann solution's mean to 0, and
/// spreads the coefficients over the relevant B-splines (P's, then Q's).
template <int D>
void solve_and_spread(PoissonSolution<D>& solution, const PoissonSystem& poisson, const PoissonAssembly& assembly,
                      bool pure_neumann, LinearSolverKind kind, double tolerance) {
  const SplinePlacement placement =
      spline_placement(solution.basis, 1, static_cast<std::size_t>(poisson.second_select.cols()));
  Eigen::VectorXd coefficients =
      solve_symmetric(poisson.matrix, poisson.right, kind, tolerance, solution.report, &placement);
  const Eigen::SparseMatrix<double>& E = solution.basis.extension;
  const Eigen::Index p_unknowns = E.cols();
  if (pure_neumann)  // zero mean of u = u0 + sum c v: the constant is P's vector of ones
    coefficients.head(p_unknowns).array() -=
        (poisson.mean_row.dot(coefficients) + assembly.offset_mean) / poisson.mean_row.head(p_unknowns).sum();
  solution.spline_coefficients = E * coefficients.head(p_unknowns);
  const Eigen::SparseMatrix<double>& second = poisson.second_select;
  if (second.cols() > 0) solution.second_coefficients = E * (second * coefficients.tail(second.cols()));
}

}  // namespace

namespace {

/// The trial functions and what the report says of them: the Dirichlet
/// route, Nitsche's penalty, the Robin structure's band. Nitsche's trial
/// functions are the WEB B-splines themselves: the structure's omega_D = 1
/// and g~ = 0 then (boundary_structure()).
TrialStructure poisson_trial(const PoissonProblem& problem, const BoundaryStructure& structure,
                             const PoissonRoutes& routes, const SolverOptions& options, double h, SolveReport& report) {
  report.dirichlet_route = routes.dirichlet == DirichletRoute::Weak ? "weak (Nitsche)" : "structure";
  if (routes.weak_dirichlet) report.nitsche_penalty = nitsche_penalty(options.nitsche_penalty, options.degree);
  if (!routes.structured) return dirichlet_trial(structure);
  report.robin_band = robin_band_width(options.robin_band, h, problem.domain.longest_side());
  return robin_trial(problem, structure, *report.robin_band, options.robin_band_power);
}

/// The condition numbers of the system (lower triangle), plain and after Jacobi scaling.
void estimate_system_condition(const Eigen::SparseMatrix<double>& lower, SolveReport& report) {
  const ConditionEstimate estimate =
      estimate_condition(Eigen::SparseMatrix<double>(lower.selfadjointView<Eigen::Lower>()));
  report.condition = estimate.condition;
  report.scaled_condition = estimate.scaled_condition;
}

}  // namespace

template <int D>
PoissonSolution<D> solve_poisson(const PoissonProblem& given, const SolverOptions& options) {
  const ProblemDomain& domain = given.domain;
  if (domain.dimension != D) throw std::invalid_argument("problem dimension does not match the solver");
  check_solver_options(options, domain.min, domain.max, D);
  PoissonSolution<D> solution;
  SolveReport& report = solution.report;
  StageTimer timer(report);
  const int n = options.degree;

  // Setup: the domain's pieces, the cells, the routes, the rules, the basis, the data checked.
  DomainCells<D> cells(domain.field, domain.boundary_mesh);
  timer.lap(&StageSeconds::field);
  const bool direct = options.linear_solver == LinearSolverKind::Direct ||
                      (options.linear_solver == LinearSolverKind::Automatic && options.robin == RobinRoute::Structure);
  const ClassifiedGrid<D> classified = classify_grid<D>(cells, domain.min, domain.max, options.cell_width, n,
                                                        {direct, 1, options.memory_limit_mb}, report);
  const double h = classified.grid.h;
  // Gauss with n + 1 nodes per direction, in inside cells and on every
  // piece of a cut cell whose active pieces are planar: exact for the
  // polynomial part (degree 2n + 1). One more where a curved piece is
  // active: weak terms on a sphere need it (the ball's Robin patch test:
  // L2 1.8e-5 with n + 1, 8e-7 with n + 2).
  const int inside_points = options.quadrature_points > 0 ? options.quadrature_points : n + 1;
  const QuadratureOptions quadrature{inside_points, inside_points, options.max_subdivision, 1};
  timer.lap(&StageSeconds::classification);
  std::optional<CellRules<D>> early_rules;
  const PoissonProblem problem = posed_problem(given, cells, classified, quadrature, early_rules);
  const PoissonRoutes routes = poisson_routes(problem, options);
  const BoundaryStructure structure =
      boundary_structure(boundary_split(problem), classified.interior, routes.dirichlet == DirichletRoute::Structure);
  const TrialStructure trial = poisson_trial(problem, structure, routes, options, h, report);
  const bool second = trial.second_function();
  const int band_points = inside_points + kBandExtraPoints;
  const QuadratureOptions band_quadrature{band_points + 1, band_points, options.max_subdivision, 0};
  // Volume rules of inside and cut cells, surface rules where a weak condition may hold.
  CellRules<D> rules = early_rules && !second
                           ? std::move(*early_rules)
                           : integrate_cells(cells, classified, quadrature, band_quadrature,
                                             band_cells(trial, classified, report.robin_band.value_or(0.0)),
                                             structure.has_weak_parts || routes.weak_dirichlet);
  report_fallbacks(rules.counts, report);
  check_data(poisson_data_rules(problem, routes.dirichlet == DirichletRoute::Structure), rules, h);
  timer.lap(&StageSeconds::quadrature);
  solution.basis = basis_on_cells(cells, classified, rules, options.basis, report);
  if (options.keep_quadrature) solution.quadrature = quadrature_dump(rules);
  solution.structure = trial_tape<D>(trial);
  if (routes.structured) check_robin_structure(structure, trial, h, rules.volume, rules.surface);
  solution.mesh = cells.mesh();
  if (!solution.mesh) solution.domain = std::make_shared<Tape>(domain.field, D);

  // Assembly by the shared cell loop, then the system.
  PoissonAssembly assembly = assemble_poisson<D>(
      {problem, structure, solution.basis, classified.candidates, cells.kinds(), rules, *solution.structure,
       routes.structured, second, routes.weak_dirichlet, inside_points, report.nitsche_penalty.value_or(0.0)});
  const PoissonSystem poisson = poisson_system(solution.basis, assembly, structure.pure_neumann, second, report);
  report.nonzeros = whole_nonzeros(poisson.matrix);
  timer.lap(&StageSeconds::assembly);

  // Solve. The structure's second function has functions of very different
  // energy near the band's edge (diagonal entries over 1e14 apart), where
  // incomplete Cholesky needs 1e4 iterations and more. Automatic in 3D:
  // Jacobi, then incomplete Cholesky when Jacobi is too slow (linear_solve.hpp).
  LinearSolverKind kind = options.linear_solver;
  if (kind == LinearSolverKind::Automatic && (second || D == 2))
    kind = second ? LinearSolverKind::Direct : LinearSolverKind::ConjugateGradient;
  const double tolerance =
      options.cg_tolerance > 0.0 ? options.cg_tolerance : automatic_cg_tolerance(h, domain.longest_side(), n);
  solve_and_spread(solution, poisson, assembly, structure.pure_neumann, kind, tolerance);
  timer.lap(&StageSeconds::solve);

  // Post-processing.
  if (options.estimate_condition) {
    estimate_system_condition(poisson.matrix, report);
    timer.lap(&StageSeconds::condition);
  }
  if (problem.exact) {
    poisson_errors(solution, *problem.exact, rules.volume, report);
    timer.lap(&StageSeconds::errors);
  }
  return solution;
}

template class PoissonSolution<2>;
template class PoissonSolution<3>;
template PoissonSolution<2> solve_poisson<2>(const PoissonProblem&, const SolverOptions&);
template PoissonSolution<3> solve_poisson<3>(const PoissonProblem&, const SolverOptions&);

}  // namespace sage::solver
