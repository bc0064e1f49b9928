#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/condition.hpp>
#include <sage/solver/extended_system.hpp>
#include <sage/solver/gauss.hpp>
#include <sage/solver/local_splines.hpp>
#include <sage/solver/memory_estimate.hpp>
#include <sage/solver/mesh_domain.hpp>
#include <sage/solver/poisson.hpp>
#include <sage/solver/tensor_cell_stiffness.hpp>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

namespace {

/// Wall-clock and process CPU seconds per stage (CPU time is what a
/// one-thread benchmark on a shared machine can compare).
class StageTimer {
 public:
  explicit StageTimer(SolveReport& report) : report_(report) {}
  void lap(double StageSeconds::*stage) {
    const auto now = std::chrono::steady_clock::now();
    const std::clock_t cpu_now = std::clock();
    report_.seconds.*stage = std::chrono::duration<double>(now - start_).count();
    report_.cpu_seconds.*stage = static_cast<double>(cpu_now - cpu_start_) / CLOCKS_PER_SEC;
    start_ = now;
    cpu_start_ = cpu_now;
  }

 private:
  SolveReport& report_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::clock_t cpu_start_ = std::clock();
};

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
                  const SolverOptions& options, double limit_mb) {
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
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  const bool direct = options.linear_solver == LinearSolverKind::Direct ||
                      (options.linear_solver == LinearSolverKind::Automatic && options.robin == RobinRoute::Structure);
  const MemoryEstimate estimate =
      estimate_memory(D, grid.degree, report.cells_inside, report.cells_cut, relevant_count, threads, direct);
  report.memory_estimate_mb = estimate.megabytes;
  if (limit_mb > 0.0 && estimate.megabytes > limit_mb)
    throw std::runtime_error("the problem is too large for this machine: it needs " + estimate.summary() + ", and " +
                             std::to_string(static_cast<long long>(limit_mb)) +
                             " MB are available (use fewer cells or a lower degree)");
}

/// The cells of the background grid against the domain, and their
/// quadrature: from the Boolean pieces of omega (domain_quadrature.hpp), or,
/// for domains read from meshes, from the triangles (mesh_domain.hpp).
template <int D>
class DomainCells {
 public:
  /// Compiles the pieces (an implicit domain).
  explicit DomainCells(const PoissonProblem& problem) : problem_(problem) {
    if (D == 2 || !problem.boundary_mesh) pieces_.emplace(problem.domain, D);
  }
  /// Classifies the cells of `grid`.
  void classify(const BackgroundGrid<D>& grid) {
    if constexpr (D == 3) {
      if (problem_.boundary_mesh) {
        mesh_ = std::make_shared<MeshDomain>(problem_.boundary_mesh, grid);
        kinds_ = mesh_->kinds();
        return;
      }
    }
    cells_ = classify_cells<D>(*pieces_, grid);
    kinds_.resize(cells_.size());
    for (std::size_t c = 0; c < cells_.size(); ++c) kinds_[c] = cells_[c].kind;
  }
  const std::vector<CellKind>& kinds() const { return kinds_; }
  std::shared_ptr<const MeshDomain> mesh() const { return mesh_; }

  /// One per thread.
  class Rule {
   public:
    Rule(const DomainCells& cells, QuadratureOptions options) : cells_(cells) {
      if (cells.mesh_) {
        mesh_rule_.emplace(*cells.mesh_, options);
      } else {
        rule_.emplace(*cells.pieces_, options);
      }
    }
    void append(std::size_t cell, const Box<D>& box, std::vector<VolumePoint<D>>& volume,
                std::vector<SurfacePoint<D>>* surface) {
      if constexpr (D == 3) {
        if (mesh_rule_) return mesh_rule_->append_rule(cell, box, volume, surface);
      }
      rule_->append_rule(box, cells_.cells_[cell], volume, surface);
    }
    const QuadratureCounts& counts() const { return mesh_rule_ ? mesh_rule_->counts() : rule_->counts(); }

   private:
    const DomainCells& cells_;
    std::optional<CellQuadrature<D>> rule_;
    std::optional<MeshCellQuadrature> mesh_rule_;
  };

 private:
  const PoissonProblem& problem_;
  std::optional<DomainPieces> pieces_;
  std::vector<CellDomain> cells_;
  std::shared_ptr<MeshDomain> mesh_;
  std::vector<CellKind> kinds_;
};

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
  std::size_t nearest = parts;
  double distance = tolerance;
  for (std::size_t k = 0; k < parts; ++k) {
    const double d = std::abs(eval.result(k));
    if (d <= distance) {
      distance = d;
      nearest = k;
    }
  }
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

template <int D>
void check_options(const PoissonProblem& problem, const SolverOptions& options) {
  if (problem.dimension != D) throw std::invalid_argument("problem dimension does not match the solver");
  if (options.degree < 1 || options.degree > kMaxDegree)
    throw std::invalid_argument("degree must be 1.." + std::to_string(kMaxDegree) + ", not " +
                                std::to_string(options.degree));
  if (!(options.cell_width > 0.0) || !std::isfinite(options.cell_width))
    throw std::invalid_argument("cell width h must be positive");
  if (!(options.cg_tolerance >= 0.0 && options.cg_tolerance < 1.0))
    throw std::invalid_argument("the conjugate gradients tolerance must be in [0, 1) (0: automatic)");
  for (int a = 0; a < D; ++a)
    if (!(problem.max[a] > problem.min[a])) throw std::invalid_argument("the domain's bounding box is empty");
}

/// What conjugate gradients reached.
struct CgResult {
  Eigen::VectorXd x;
  bool converged = false;
  double residual = 1.0;  // relative
};

/// Conjugate gradients from `guess` (or 0), for at most `budget`
/// iterations; without a budget, throws when they do not converge.
template <class Preconditioner>
CgResult conjugate_gradients(const Eigen::SparseMatrix<double>& system, const Eigen::VectorXd& right, double tolerance,
                             SolveReport& report, int budget = 0, const Eigen::VectorXd* guess = nullptr) {
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower, Preconditioner> cg;
  cg.setTolerance(tolerance);
  report.cg_tolerance = tolerance;
  cg.setMaxIterations(budget > 0 ? budget : 10 * system.rows() + 100);
  cg.compute(system);
  if (cg.info() != Eigen::Success) throw std::runtime_error("the preconditioner could not be set up");
  CgResult result;
  if (guess) {
    result.x = cg.solveWithGuess(right, *guess);
  } else {
    result.x = cg.solve(right);
  }
  report.iterations += static_cast<int>(cg.iterations());
  result.converged = cg.info() == Eigen::Success;
  result.residual = cg.error();
  if (!result.converged && budget == 0)
    throw std::runtime_error("conjugate gradients did not converge in " + std::to_string(cg.iterations()) +
                             " iterations (relative residual " + std::to_string(cg.error()) + ")");
  return result;
}

/// 3D, automatic: Jacobi's preconditioner is set up for free and enough
/// for most domains (a few hundred to 1,400 iterations), but domains with
/// features a few cells wide (a mesh's thin ears) make the WEB system's
/// condition reach 1e8 after scaling, where Jacobi needs 8,000 iterations
/// and incomplete Cholesky 23 (its set-up costs several times a hundred
/// Jacobi iterations). So Jacobi in legs, while they promise convergence
/// within kJacobiBudget iterations.
constexpr int kJacobiProbe = 200;
constexpr int kJacobiBudget = 4000;

/// Local B-splines and their gradients at the points of the tensor Gauss
/// rule of an inside cell, in the order of CellQuadrature::append_rule
/// (x fastest): value[p * local + k], gradient[a][p * local + k].
struct InsideSplineTable {
  std::size_t points = 0;
  std::vector<double> value;
  std::array<std::vector<double>, 3> gradient;
};

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

std::string scientific(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", x);
  return text;
}

template <int D>
std::string point_text(const std::array<double, D>& x) {
  std::string text = "(";
  for (int a = 0; a < D; ++a) text += (a ? ", " : "") + std::to_string(x[a]);
  return text + ")";
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
    : solution_(&solution), structure_(*solution.structure) {
  if (solution.domain) domain_.emplace(*solution.domain);
}

template <int D>
double PoissonSolution<D>::Probe::omega(const double* x) {
  if constexpr (D == 3) {
    if (solution_->mesh) {
      std::array<double, 3> p{x[0], x[1], x[2]};
      return solution_->mesh->signed_distance(p, kMeshDistanceBand * solution_->basis.grid.h);
    }
  }
  domain_->evaluate(x);
  return domain_->result();
}

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
  check_options<D>(problem, options);
  PoissonSolution<D> solution;
  SolveReport& report = solution.report;
  StageTimer timer(report);
  const int n = options.degree;

  // Field: the domain's pieces and their Boolean formula, compiled (not for
  // mesh domains, whose cells come from the triangles).
  DomainCells<D> cells(problem);
  timer.lap(&StageSeconds::field);

  // Classification of the background cells: by the domain's pieces and
  // interval arithmetic, or by a mesh's triangles.
  std::array<double, D> min{}, max{};
  for (int a = 0; a < D; ++a) {
    min[a] = problem.min[a];
    max[a] = problem.max[a];
  }
  const auto grid = BackgroundGrid<D>::covering(min, max, options.cell_width, n);
  if (grid.spline_count() > 50'000'000ull)
    throw std::invalid_argument("the grid is too fine: " + std::to_string(grid.spline_count()) + " B-splines");
  // Gauss with n + 1 nodes per direction, in inside cells and on every
  // piece of a cut cell whose active pieces are planar: exact for the
  // polynomial part (degree 2n + 1). One more where a curved piece is
  // active: weak terms on a sphere need it (the ball's Robin patch test:
  // L2 1.8e-5 with n + 1, 8e-7 with n + 2).
  const int inside_points = options.quadrature_points > 0 ? options.quadrature_points : n + 1;
  QuadratureOptions quadrature{inside_points, inside_points, options.max_subdivision, 1};
  const std::size_t cell_count = grid.cell_count();
  const double memory_limit = options.memory_limit_mb > 0.0 ? options.memory_limit_mb : available_megabytes();
  // The classification's own arrays, before it allocates them.
  const double classification_mb =
      static_cast<double>(cell_count) * (sizeof(CellDomain) + sizeof(CellKind) + 8) / (1024.0 * 1024.0);
  if (memory_limit > 0.0 && classification_mb > memory_limit)
    throw std::runtime_error("the grid is too large for this machine: classifying its " + std::to_string(cell_count) +
                             " cells needs about " + std::to_string(static_cast<long long>(classification_mb)) +
                             " MB, " + std::to_string(static_cast<long long>(memory_limit)) +
                             " MB are available (use fewer cells or a lower degree)");
  cells.classify(grid);
  const std::vector<CellKind>& kinds = cells.kinds();
  std::vector<std::size_t> candidates;
  for (std::size_t c = 0; c < cell_count; ++c) {
    if (kinds[c] == CellKind::Outside) continue;
    candidates.push_back(c);
    if (kinds[c] == CellKind::Inside) ++report.cells_inside;
  }
  report.cells = cell_count;
  report.cells_cut = candidates.size() - report.cells_inside;
  if (candidates.empty()) throw std::runtime_error("the domain is empty: omega < 0 on every grid cell");
  if (report.cells_inside == 0)
    throw std::runtime_error("the grid is too coarse: no grid cell lies entirely inside the domain (use more cells)");
  const std::array<double, 3> interior = deepest_inside_centre(grid, kinds);
  check_memory<D>(grid, candidates, report, options, memory_limit);
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
  std::vector<std::vector<VolumePoint<D>>> volume(candidates.size());
  std::vector<std::vector<SurfacePoint<D>>> surface(candidates.size());
#pragma omp parallel
  {
    typename DomainCells<D>::Rule rule(cells, quadrature), band_rule(cells, band_quadrature);
#pragma omp for schedule(dynamic, 16) nowait
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const std::size_t c = candidates[k];
      (in_band[k] ? band_rule : rule).append(c, cell_box(grid, c), volume[k], needs_surface ? &surface[k] : nullptr);
    }
#pragma omp critical
    for (const QuadratureCounts* counts : {&rule.counts(), &band_rule.counts()}) {
      report.masked_boxes += counts->masked_boxes;
      report.masked_points += counts->masked_points;
      report.unresolved_surface_boxes += counts->unresolved_surface;
      report.unbroken_boxes += counts->unbroken_boxes;
    }
  }
  std::vector<char> active(cell_count, 0), inside(cell_count, 0);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    // A cell touching the domain in a face or an edge only carries no
    // weight: its B-splines must not become unknowns.
    double weight = 0.0;
    for (const auto& q : volume[k]) weight += q.weight;
    active[candidates[k]] = weight > 1e-13 * std::pow(grid.h, D) ? 1 : 0;
    if (!active[candidates[k]]) volume[k].clear();
    inside[candidates[k]] = kinds[candidates[k]] == CellKind::Inside ? 1 : 0;
    report.volume_points += volume[k].size();
    if (kinds[candidates[k]] == CellKind::Cut) report.cut_volume_points += volume[k].size();
    report.surface_points += surface[k].size();
  }
  if (options.keep_quadrature) {
    QuadratureDump& dump = solution.quadrature;
    auto add = [&](const std::array<double, D>& x, double weight, double on_surface) {
      for (int a = 0; a < 3; ++a) dump.coordinates.push_back(a < D ? x[a] : 0.0);
      dump.weights.push_back(weight);
      dump.on_surface.push_back(on_surface);
    };
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      for (const auto& q : volume[k]) add(q.x, q.weight, 0.0);
      for (const auto& q : surface[k]) add(q.x, q.weight, 1.0);
    }
  }
  timer.lap(&StageSeconds::quadrature);

  // Basis and assembly.
  solution.basis = build_basis(grid, active, inside, options.basis);
  const SplineBasis<D>& basis = solution.basis;
  report.relevant_splines = basis.relevant.size();
  report.inner_splines = basis.inner_count;
  report.outer_splines = basis.outer_count;
  report.unknowns = basis.unknowns();

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

  int stencil = 1;
  for (int a = 0; a < D; ++a) stencil *= 2 * n + 1;
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
  // Band position of the pair (j, l) of local splines: their offset
  // difference, numbered in the (2n + 1)^D stencil.
  std::vector<int> stencil_of_local(static_cast<std::size_t>(local_count));
  int stencil_centre = 0;
  for (int k = 0; k < local_count; ++k) {
    const auto m = LocalSplines<D>::global_index({}, n, k);
    int position = 0;
    for (int a = D - 1; a >= 0; --a) position = position * (2 * n + 1) + m[a];
    stencil_of_local[static_cast<std::size_t>(k)] = position;
  }
  for (int a = D - 1; a >= 0; --a) stencil_centre = stencil_centre * (2 * n + 1) + n;
  const double selector_tolerance = 1e-6 * grid.h;
  const double nitsche_weight = weak_dirichlet ? *report.nitsche_penalty / grid.h : 0.0;
  // Inside cells all carry the same tensor Gauss rule relative to the
  // cell, so their local B-splines and gradients at the rule's points are
  // the same too: tabulated once (point p, spline k at p * local_count + k).
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
    const int thread = omp_get_thread_num(), threads = omp_get_num_threads();
#else
    const int thread = 0, threads = 1;
#endif
    const bool first_thread = thread == 0;
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
    for (int turn = 0; turn < threads; ++turn) {
#pragma omp barrier
      if (turn != thread) continue;
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
    }
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
  if (kind == LinearSolverKind::Automatic)
    kind = second   ? LinearSolverKind::Direct
           : D == 2 ? LinearSolverKind::ConjugateGradient
                    : LinearSolverKind::JacobiConjugateGradient;
  const double tolerance =
      options.cg_tolerance > 0.0 ? options.cg_tolerance : automatic_cg_tolerance(grid.h, longest, n);
  Eigen::VectorXd coefficients;
  if (kind == LinearSolverKind::Direct) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(system);
    if (factor.info() != Eigen::Success)
      throw std::runtime_error(
          "the sparse factorization failed: the system is singular (is the basis stable? try --basis web)");
    coefficients = factor.solve(right);
    report.linear_solver = "sparse LDLT (AMD ordering)";
    report.iterations = 1;
  } else if (kind == LinearSolverKind::ConjugateGradient) {
    coefficients = conjugate_gradients<Eigen::IncompleteCholesky<double>>(system, right, tolerance, report).x;
    report.linear_solver = "conjugate gradients, incomplete Cholesky";
  } else if (options.linear_solver == LinearSolverKind::Automatic) {
    report.linear_solver = "conjugate gradients, Jacobi";
    // Jacobi in legs: after each, the rate of the last leg says how many
    // more iterations it needs (CG's residual falls about geometrically
    // once past its first fast phase); beyond the budget, incomplete Cholesky.
    CgResult leg =
        conjugate_gradients<Eigen::DiagonalPreconditioner<double>>(system, right, tolerance, report, kJacobiProbe);
    int spent = kJacobiProbe, length = kJacobiProbe;
    double start = 1.0;
    while (!leg.converged) {
      const double per_iteration = std::log(leg.residual / start) / length;
      const double more = per_iteration < 0.0 ? std::log(tolerance / leg.residual) / per_iteration
                                              : std::numeric_limits<double>::infinity();
      if (spent + more > kJacobiBudget) break;
      start = leg.residual;
      length = std::max(kJacobiProbe, static_cast<int>(1.2 * more));
      leg =
          conjugate_gradients<Eigen::DiagonalPreconditioner<double>>(system, right, tolerance, report, length, &leg.x);
      spent += length;
    }
    if (leg.converged) {
      coefficients = leg.x;
    } else {
      coefficients = conjugate_gradients<Eigen::IncompleteCholesky<double>>(system, right, tolerance, report).x;
      report.linear_solver =
          "conjugate gradients, Jacobi (" + std::to_string(spent) + " iterations, too slow), then incomplete Cholesky";
    }
  } else {
    coefficients = conjugate_gradients<Eigen::DiagonalPreconditioner<double>>(system, right, tolerance, report).x;
    report.linear_solver = "conjugate gradients, Jacobi";
  }
  if (!coefficients.allFinite()) throw std::runtime_error("the solve produced non-finite coefficients");
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
