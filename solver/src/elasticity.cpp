#include "cell_loop.hpp"
#include "data_check.hpp"
#include "discretization.hpp"
#include "elasticity_assembly.hpp"
#include "linear_solve.hpp"
#include "message_text.hpp"
#include "stage_timer.hpp"

#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/extended_system.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sage::solver {

namespace {

constexpr const char* kAxisName[3] = {"x", "y", "z"};

std::string part_label(const ElasticPart& part, bool rest) {
  return rest ? std::string("the default part") : "part '" + part.name + "'";
}

void check_problem(const ElasticityProblem& problem) {
  problem.material.check();
  for (std::size_t k = 0; k <= problem.parts.size(); ++k) {
    const bool rest = k == problem.parts.size();
    const ElasticPart& part = rest ? problem.rest : problem.parts[k];
    if (part.fixed() && part.loaded)
      throw std::invalid_argument(part_label(part, rest) +
                                  " is both fixed (displacement) and loaded (traction or pressure): split it into two "
                                  "parts, or give the load on the components it leaves free by a separate part");
  }
}

/// Component c's boundary split for the structure route: the parts that
/// fix c prescribe its value, the others are weak.
BoundarySplit component_split(const ElasticityProblem& problem, int c) {
  BoundarySplit split;
  split.dimension = problem.domain.dimension;
  split.field = problem.domain.field;
  auto part = [c](const ElasticPart& given) {
    return BoundarySplit::Part{given.name, given.selector, given.displacement[static_cast<std::size_t>(c)]};
  };
  for (const ElasticPart& given : problem.parts) split.parts.push_back(part(given));
  split.rest = part(problem.rest);
  return split;
}

/// The rigid motions about `centre`: D translations, then the rotations
/// (one in 2D, three in 3D), as the displacement at x.
template <int D>
constexpr int kRigidMotions = D == 2 ? 3 : 6;

template <int D>
std::array<double, D> rigid_motion(int mode, const double* x, const std::array<double, 3>& centre) {
  std::array<double, D> u{};
  if (mode < D) {
    u[static_cast<std::size_t>(mode)] = 1.0;
    return u;
  }
  std::array<double, 3> d{};
  for (int a = 0; a < D; ++a) d[static_cast<std::size_t>(a)] = x[a] - centre[static_cast<std::size_t>(a)];
  if constexpr (D == 2) {
    u = {-d[1], d[0]};
  } else {
    const int axis = mode - D;  // omega = e_axis, u = omega x d
    const std::array<std::array<double, 3>, 3> rotations{{{0.0, -d[2], d[1]}, {d[2], 0.0, -d[0]}, {-d[1], d[0], 0.0}}};
    for (int a = 0; a < 3; ++a) u[static_cast<std::size_t>(a)] = rotations[static_cast<std::size_t>(axis)][a];
  }
  return u;
}

/// The strain energy density sigma : eps of a displacement gradient.
template <int D>
double energy_density(const ElasticMaterial& material, const double* g) {
  const std::array<double, 6> s = material.stress<D>(g);
  double e = 0.0;
  for (int a = 0; a < D; ++a) e += s[static_cast<std::size_t>(a)] * g[a * D + a];
  e += s[3] * (g[1] + g[D]);
  if constexpr (D == 3) e += s[4] * (g[5] + g[7]) + s[5] * (g[2] + g[6]);
  return e;
}

}  // namespace

template <int D>
ElasticitySolution<D>::Probe::Probe(const ElasticitySolution& solution)
    : solution_(&solution), domain_(solution.domain, solution.mesh, solution.basis.grid.h) {
  if (solution.structure) structure_.emplace(*solution.structure);
}

template <int D>
void ElasticitySolution<D>::Probe::at(const double* x, double* displacement, double* gradient) {
  const auto& grid = solution_->basis.grid;
  const auto cell = grid.cell_of(x);
  local_.evaluate(grid, cell, x);
  std::array<double, D> s{};
  std::array<std::array<double, D>, D> grad_s{};
  for (int k = 0; k < grid.local_count(); ++k) {
    const long long r =
        solution_->basis.relevant_of[grid.spline_linear(LocalSplines<D>::global_index(cell, grid.degree, k))];
    if (r < 0) continue;
    for (int c = 0; c < D; ++c) {
      const double coefficient = solution_->spline_coefficients(r, c);
      s[c] += coefficient * local_.value[k];
      for (int a = 0; a < D; ++a) grad_s[c][a] += coefficient * local_.gradient[a][k];
    }
  }
  if (structure_) structure_->evaluate(x);
  for (int c = 0; c < D; ++c) {
    double u = s[c];
    std::array<double, D> g = grad_s[c];
    if (structure_) {  // u_c = w_c s_c + g~_c
      const auto& w = structure_->result(2 * static_cast<std::size_t>(c));
      const auto& offset = structure_->result(2 * static_cast<std::size_t>(c) + 1);
      const auto gw = w.gradient(), go = offset.gradient();
      u = w.value() * s[c] + offset.value();
      for (int a = 0; a < D; ++a) g[a] = gw[a] * s[c] + w.value() * grad_s[c][a] + go[a];
    }
    displacement[c] = u;
    if (gradient)
      for (int a = 0; a < D; ++a) gradient[c * D + a] = g[a];
  }
}

template <int D>
std::array<double, 6> ElasticitySolution<D>::Probe::stress(const double* x) {
  double u[D], g[D * D];
  at(x, u, g);
  return solution_->material.template stress<D>(g);
}

namespace {

/// The structure route's trial functions, per component c: the roots w_c,
/// g~_c (boundary_structure.hpp) of the parts that fix c.
template <int D>
std::shared_ptr<const Tape> displacement_structure(const ElasticityProblem& problem,
                                                   const std::array<double, 3>& interior) {
  std::vector<Expr> roots;
  for (int c = 0; c < D; ++c) {
    try {
      const BoundaryStructure s = boundary_structure(component_split(problem, c), interior, true);
      roots.push_back(s.dirichlet_weight);
      roots.push_back(s.dirichlet_extension);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("the structure of displacement component ") + kAxisName[c] + ": " +
                                  e.what());
    }
  }
  return std::make_shared<Tape>(roots, D);
}

/// The system of the unknowns (lower triangle), component-major: the
/// diagonal blocks by extended_system, the blocks below them E^T A_cd E;
/// the bands are released as they are used. Its right side into `right`.
template <int D>
Eigen::SparseMatrix<double> elastic_system(const SplineBasis<D>& basis, ElasticityAssembly& assembled,
                                           Eigen::VectorXd& right) {
  const Eigen::SparseMatrix<double>& E = basis.extension;
  const Eigen::Index N = E.cols();
  const auto relevant = static_cast<Eigen::Index>(basis.relevant.size());
  right.resize(D * N);
  for (int c = 0; c < D; ++c)
    right.segment(c * N, N) = E.transpose() * Eigen::Map<const Eigen::VectorXd>(assembled.loads[c].data(), relevant);
  // Column-major: the columns of component d are those of the blocks (c, d),
  // c >= d, one above the other; built a component at a time and appended
  // in order, so that only that component's blocks exist beside the system.
  Eigen::SparseMatrix<double> system(D * N, D * N);
  for (int d = 0; d < D; ++d) {
    // Swapped in: Eigen 3.4's SparseMatrix has no move constructor, and a copy would double each block.
    std::vector<Eigen::SparseMatrix<double>> blocks;
    blocks.reserve(D);
    for (int c = d; c < D; ++c) {
      std::vector<double>& band = assembled.bands[block_pair(c, d)];
      Eigen::SparseMatrix<double> block = c == d ? extended_system(basis, band) : extended_product(basis, band);
      blocks.emplace_back().swap(block);
      std::vector<double>().swap(band);
    }
    // Reserved once, for D times the first component's columns: the blocks
    // share one pattern, so that bounds the whole (the lower triangle's
    // later components have fewer blocks), and growing the arrays would
    // copy them beside the new. Pages never written cost no memory.
    if (d == 0) {
      std::size_t entries = 0;
      for (const auto& block : blocks) entries += static_cast<std::size_t>(block.nonZeros());
      system.reserve(static_cast<Eigen::Index>(D * entries));
    }
    for (Eigen::Index col = 0; col < N; ++col) {
      system.startVec(d * N + col);
      for (int c = d; c < D; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator e(blocks[static_cast<std::size_t>(c - d)], col); e; ++e)
          system.insertBack(c * N + e.row(), d * N + col) = e.value();
    }
  }
  system.finalize();
  return system;
}

/// The rigid motions no displacement condition holds, about `centre`.
struct FreeMotions {
  int count = 0;
  Eigen::MatrixXd combination;  // motions x count: the free ones among the rigid motions
  Eigen::MatrixXd unknowns;     // unknowns x count: their coefficients
  std::array<double, 3> centre{};
};

/// Free rigid motions: those of energy 0 (the rest is held by the
/// displacement conditions), from the generalized eigenproblem of the
/// motions' energies against their diagonal scale. Throws when the loads
/// do work on them; else removes the quadrature-level remainder from
/// `right` and pins one unknown per free motion.
template <int D>
FreeMotions hold_free_motions(const ElasticityProblem& problem, const SplineBasis<D>& basis,
                              Eigen::SparseMatrix<double>& system, Eigen::VectorXd& right, ElasticityResults& results) {
  const BackgroundGrid<D>& grid = basis.grid;
  const Eigen::Index N = basis.extension.cols();
  FreeMotions free;
  for (int a = 0; a < D; ++a) free.centre[a] = 0.5 * (problem.domain.min[a] + problem.domain.max[a]);
  const int motions = kRigidMotions<D>;
  // Rigid motions are linear: their coefficients are their values at the B-splines' Greville points.
  Eigen::MatrixXd rigid(D * N, motions);
  for (Eigen::Index p = 0; p < N; ++p) {
    const auto x = grid.greville(grid.spline_index(basis.relevant[basis.unknown_spline[static_cast<std::size_t>(p)]]));
    for (int m = 0; m < motions; ++m) {
      const auto u = rigid_motion<D>(m, x.data(), free.centre);
      for (int c = 0; c < D; ++c) rigid(c * N + p, m) = u[c];
    }
  }
  const Eigen::MatrixXd energy = rigid.transpose() * (system.template selfadjointView<Eigen::Lower>() * rigid);
  const Eigen::MatrixXd scale = rigid.transpose() * system.diagonal().asDiagonal() * rigid;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(energy, scale);
  while (free.count < motions && modes.eigenvalues()[free.count] < 1e-8) ++free.count;
  results.free_rigid_motions = free.count;
  if (free.count == 0) return free;
  free.combination = modes.eigenvectors().leftCols(free.count);
  free.unknowns = rigid * free.combination;
  const Eigen::VectorXd net = free.unknowns.transpose() * right;
  const Eigen::VectorXd size = free.unknowns.cwiseAbs().transpose() * right.cwiseAbs();
  double defect = 0.0;
  for (int m = 0; m < free.count; ++m) defect = std::max(defect, std::abs(net[m]) / std::max(size[m], 1e-300));
  results.load_balance = defect;
  if (size.maxCoeff() > 0.0 && defect > kLoadBalanceTolerance) {
    const Eigen::VectorXd resultant = rigid.transpose() * right;  // net force, then moment(s)
    std::string force = "(", moment = D == 2 ? "" : "(";
    for (int a = 0; a < D; ++a) force += (a ? ", " : "") + scientific(resultant[a]);
    for (int m = D; m < motions; ++m) moment += (m > D ? ", " : "") + scientific(resultant[m]);
    std::array<double, D> box_centre{};
    for (int a = 0; a < D; ++a) box_centre[a] = free.centre[a];
    throw std::invalid_argument("unbalanced loads on a free body: the displacement conditions leave " +
                                std::to_string(free.count) + " rigid motion" + (free.count == 1 ? "" : "s") +
                                " free, and the loads do work on them (net force " + force + "), moment " + moment +
                                (D == 2 ? "" : ")") + " about " + point_text<D>(box_centre) + "; relative defect " +
                                scientific(defect) + "): balance the loads or fix the body somewhere");
  }
  // Remove the quadrature-level remainder, then pin one unknown per
  // free motion (column-pivoted QR picks unknowns that determine them).
  right -= free.unknowns * (free.unknowns.transpose() * free.unknowns).ldlt().solve(free.unknowns.transpose() * right);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> pivots(free.unknowns.transpose());
  for (int m = 0; m < free.count; ++m) {
    const Eigen::Index pinned = pivots.colsPermutation().indices()[m];
    system.coeffRef(pinned, pinned) *= 2.0;
  }
  return free;
}

/// The relevant B-splines' coefficients, per component, from the unknowns'.
template <int D>
void spread_coefficients(ElasticitySolution<D>& solution, const Eigen::VectorXd& coefficients) {
  const Eigen::SparseMatrix<double>& E = solution.basis.extension;
  const Eigen::Index N = E.cols();
  solution.spline_coefficients.resize(static_cast<Eigen::Index>(solution.basis.relevant.size()), D);
  for (int c = 0; c < D; ++c) solution.spline_coefficients.col(c) = E * coefficients.segment(c * N, N);
}

/// Makes u_h L2-orthogonal to the free motions. Their functions are the
/// rigid motions combined, exactly (linear functions are in the basis).
template <int D>
void orthogonalize(ElasticitySolution<D>& solution, const FreeMotions& free,
                   const std::vector<std::vector<VolumePoint<D>>>& volume, Eigen::VectorXd& coefficients) {
  const int motions = kRigidMotions<D>;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(motions, motions);
  Eigen::VectorXd moments = Eigen::VectorXd::Zero(motions);
  typename ElasticitySolution<D>::Probe probe(solution);
  for (const auto& points : volume)
    for (const auto& q : points) {
      double u[D];
      probe.at(q.x.data(), u);
      std::array<std::array<double, D>, kRigidMotions<D>> r{};
      for (int m = 0; m < motions; ++m) r[m] = rigid_motion<D>(m, q.x.data(), free.centre);
      for (int m = 0; m < motions; ++m)
        for (int c = 0; c < D; ++c) {
          moments[m] += q.weight * r[m][c] * u[c];
          for (int l = 0; l < motions; ++l) gram(m, l) += q.weight * r[m][c] * r[l][c];
        }
    }
  const Eigen::MatrixXd& combination = free.combination;
  const Eigen::VectorXd amount =
      (combination.transpose() * gram * combination).ldlt().solve(combination.transpose() * moments);
  coefficients -= free.unknowns * amount;
  spread_coefficients(solution, coefficients);
}

/// The strain energy, the largest von Mises stress, and the errors against
/// the exact solution, at the volume points.
template <int D>
void elastic_results(ElasticitySolution<D>& solution, const ElasticityProblem& problem,
                     const std::vector<std::vector<VolumePoint<D>>>& volume) {
  const ElasticMaterial& material = problem.material;
  SolveReport& report = solution.report;
  ElasticityResults& results = *report.elasticity;
  std::optional<Tape> exact_tape;
  if (problem.exact) exact_tape.emplace(std::vector<Expr>(problem.exact->begin(), problem.exact->begin() + D), D);
  double energy_sum = 0.0, error2 = 0.0, norm2 = 0.0, energy_error2 = 0.0, energy_norm2 = 0.0;
  double peak = -1.0;
  std::array<double, 3> peak_at{};
#pragma omp parallel reduction(+ : energy_sum, error2, norm2, energy_error2, energy_norm2)
  {
    typename ElasticitySolution<D>::Probe probe(solution);
    std::optional<Evaluator<Tuple<D, 1>>> exact;
    if (exact_tape) exact.emplace(*exact_tape);
    double own_peak = -1.0;
    std::array<double, 3> own_at{};
#pragma omp for schedule(dynamic, 16)
    for (std::size_t k = 0; k < volume.size(); ++k) {
      for (const auto& q : volume[k]) {
        double u[D], g[D * D];
        probe.at(q.x.data(), u, g);
        energy_sum += 0.5 * q.weight * energy_density<D>(material, g);
        const double mises = von_mises(material.stress<D>(g));
        if (mises > own_peak) {
          own_peak = mises;
          for (int a = 0; a < D; ++a) own_at[a] = q.x[a];
        }
        if (!exact) continue;
        exact->evaluate(q.x.data());
        double ge[D * D], gd[D * D];
        for (int c = 0; c < D; ++c) {
          const auto& e = exact->result(static_cast<std::size_t>(c));
          const auto grad = e.gradient();
          error2 += q.weight * (u[c] - e.value()) * (u[c] - e.value());
          norm2 += q.weight * e.value() * e.value();
          for (int a = 0; a < D; ++a) {
            ge[c * D + a] = grad[a];
            gd[c * D + a] = g[c * D + a] - grad[a];
          }
        }
        energy_error2 += q.weight * energy_density<D>(material, gd);
        energy_norm2 += q.weight * energy_density<D>(material, ge);
      }
    }
#pragma omp critical
    if (own_peak > peak || (own_peak == peak && own_at < peak_at)) {
      peak = own_peak;
      peak_at = own_at;
    }
  }
  results.strain_energy = energy_sum;
  results.max_von_mises = peak;
  results.max_von_mises_at = peak_at;
  if (exact_tape) {
    report.l2_error = std::sqrt(error2 / norm2);
    report.energy_error = std::sqrt(energy_error2 / energy_norm2);
  }
}

}  // namespace

template <int D>
ElasticitySolution<D> solve_elasticity(const ElasticityProblem& problem, const SolverOptions& options) {
  const ProblemDomain& domain = problem.domain;
  if (domain.dimension != D) throw std::invalid_argument("problem dimension does not match the solver");
  check_solver_options(options, domain.min, domain.max, D);
  check_problem(problem);
  ElasticitySolution<D> solution;
  solution.material = problem.material;
  SolveReport& report = solution.report;
  report.elasticity.emplace();
  StageTimer timer(report);
  const int n = options.degree;

  // Setup: cells, their rules, the basis, the displacement route, the data checked.
  DomainCells<D> cells(domain.field, domain.boundary_mesh);
  timer.lap(&StageSeconds::field);
  const ClassifiedGrid<D> classified =
      classify_grid<D>(cells, domain.min, domain.max, options.cell_width, n,
                       {options.linear_solver == LinearSolverKind::Direct, D, options.memory_limit_mb}, report);
  // Gauss with n + 1 nodes per direction (poisson.cpp says why one more where a curved piece is active).
  const int inside_points = options.quadrature_points > 0 ? options.quadrature_points : n + 1;
  const QuadratureOptions quadrature{inside_points, inside_points, options.max_subdivision, 1};
  timer.lap(&StageSeconds::classification);
  CellRules<D> rules = integrate_cells(cells, classified, quadrature, quadrature, {}, true);
  report_fallbacks(rules.counts, report);
  timer.lap(&StageSeconds::quadrature);
  solution.basis = basis_on_cells(cells, classified, rules, options.basis, report);
  if (options.keep_quadrature) solution.quadrature = quadrature_dump(rules);
  report.unknowns = D * solution.basis.unknowns();
  bool has_fixed = problem.rest.fixed();
  for (const ElasticPart& part : problem.parts) has_fixed = has_fixed || part.fixed();
  DirichletRoute route = options.dirichlet;
  if (route == DirichletRoute::Automatic)
    route = options.basis == BasisKind::Weighted ? DirichletRoute::Structure : DirichletRoute::Weak;
  const bool structured = route == DirichletRoute::Structure && has_fixed;
  const bool weak = route == DirichletRoute::Weak && has_fixed;
  report.dirichlet_route = route == DirichletRoute::Weak ? "weak (Nitsche)" : "structure";
  if (weak) report.nitsche_penalty = nitsche_penalty(options.nitsche_penalty, n);
  if (structured) solution.structure = displacement_structure<D>(problem, classified.interior);
  check_data(elasticity_data_rules(problem, structured), rules, classified.grid.h);
  solution.mesh = cells.mesh();
  if (!solution.mesh) solution.domain = std::make_shared<Tape>(domain.field, D);

  // Assembly by the shared cell loop, one band per pair of components, then the system.
  ElasticityAssembly assembled =
      assemble_elasticity<D>({problem, solution.basis, classified.candidates, cells.kinds(), rules,
                              solution.structure.get(), weak, inside_points, report.nitsche_penalty.value_or(0.0)});
  Eigen::VectorXd right;
  Eigen::SparseMatrix<double> system = elastic_system(solution.basis, assembled, right);
  report.nonzeros = 2 * static_cast<std::size_t>(system.nonZeros()) - static_cast<std::size_t>(system.rows());
  const FreeMotions free = hold_free_motions(problem, solution.basis, system, right, *report.elasticity);
  timer.lap(&StageSeconds::assembly);

  // Solve.
  LinearSolverKind kind = options.linear_solver;
  if (kind == LinearSolverKind::Automatic && D == 2) kind = LinearSolverKind::ConjugateGradient;
  const double tolerance = options.cg_tolerance > 0.0
                               ? options.cg_tolerance
                               : automatic_cg_tolerance(classified.grid.h, domain.longest_side(), n);
  const SplinePlacement placement = spline_placement(solution.basis, D);
  Eigen::VectorXd coefficients = solve_symmetric(system, right, kind, tolerance, report, &placement);
  spread_coefficients(solution, coefficients);
  timer.lap(&StageSeconds::solve);

  // Post-processing.
  if (free.count > 0) orthogonalize(solution, free, rules.volume, coefficients);
  elastic_results(solution, problem, rules.volume);
  timer.lap(&StageSeconds::errors);
  return solution;
}

template class ElasticitySolution<2>;
template class ElasticitySolution<3>;
template ElasticitySolution<2> solve_elasticity<2>(const ElasticityProblem&, const SolverOptions&);
template ElasticitySolution<3> solve_elasticity<3>(const ElasticityProblem&, const SolverOptions&);

}  // namespace sage::solver
