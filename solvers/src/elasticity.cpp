#include "cell_loop.hpp"
#include "data_check.hpp"
#include "discretization.hpp"
#include "elasticity_assembly.hpp"
#include "linear_solve.hpp"
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

/// Component c as a Poisson problem for the structure route: the parts
/// that fix c are Dirichlet parts with c's data, the others Neumann.
PoissonProblem component_problem(const ElasticityProblem& problem, int c) {
  PoissonProblem p;
  p.dimension = problem.dimension;
  p.domain = problem.domain;
  p.min = problem.min;
  p.max = problem.max;
  auto convert = [c](const ElasticPart& part) {
    BoundaryPart b;
    b.name = part.name;
    b.selector = part.selector;
    b.kind = part.fixes(c) ? BoundaryKind::Dirichlet : BoundaryKind::Neumann;
    if (part.fixes(c)) b.value = *part.displacement[static_cast<std::size_t>(c)];
    return b;
  };
  for (const ElasticPart& part : problem.parts) p.parts.push_back(convert(part));
  p.rest = convert(problem.rest);
  return p;
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

template <int D>
ElasticitySolution<D> solve_elasticity(const ElasticityProblem& problem, const SolverOptions& options) {
  if (problem.dimension != D) throw std::invalid_argument("problem dimension does not match the solver");
  check_solver_options(options, problem.min, problem.max, D);
  check_problem(problem);
  ElasticitySolution<D> solution;
  solution.material = problem.material;
  SolveReport& report = solution.report;
  ElasticityResults& results = solution.results;
  StageTimer timer(report);
  const int n = options.degree;
  const ElasticMaterial& material = problem.material;

  DomainCells<D> cells(problem.domain, problem.boundary_mesh);
  timer.lap(&StageSeconds::field);

  const ClassifiedGrid<D> classified =
      classify_grid<D>(cells, problem.min, problem.max, options.cell_width, n,
                       {options.linear_solver == LinearSolverKind::Direct, D, options.memory_limit_mb}, report);
  const BackgroundGrid<D>& grid = classified.grid;
  const std::vector<std::size_t>& candidates = classified.candidates;
  const std::vector<CellKind>& kinds = cells.kinds();
  // Gauss with n + 1 nodes per direction (poisson.cpp says why one more where a curved piece is active).
  const int inside_points = options.quadrature_points > 0 ? options.quadrature_points : n + 1;
  const QuadratureOptions quadrature{inside_points, inside_points, options.max_subdivision, 1};
  timer.lap(&StageSeconds::classification);

  CellRules<D> rules = integrate_cells(cells, classified, quadrature, quadrature, {}, true);
  report_fallbacks(rules.counts, report);
  const auto& volume = rules.volume;
  timer.lap(&StageSeconds::quadrature);

  solution.basis = basis_on_cells(cells, classified, rules, options.basis, report);
  if (options.keep_quadrature) solution.quadrature = quadrature_dump(rules);
  const SplineBasis<D>& basis = solution.basis;
  report.unknowns = D * basis.unknowns();

  // Displacement conditions: weak (Nitsche) or by the structure per component.
  bool has_fixed = problem.rest.fixed();
  for (const ElasticPart& part : problem.parts) has_fixed = has_fixed || part.fixed();
  DirichletRoute route = options.dirichlet;
  if (route == DirichletRoute::Automatic)
    route = options.basis == BasisKind::Weighted ? DirichletRoute::Structure : DirichletRoute::Weak;
  const bool structured = route == DirichletRoute::Structure && has_fixed;
  const bool weak = route == DirichletRoute::Weak && has_fixed;
  report.dirichlet_route = route == DirichletRoute::Weak ? "weak (Nitsche)" : "structure";
  if (weak) report.nitsche_penalty = nitsche_penalty(options.nitsche_penalty, n);
  if (structured) {
    std::vector<Expr> roots;
    for (int c = 0; c < D; ++c) {
      try {
        const BoundaryStructure s = boundary_structure(component_problem(problem, c), classified.interior, true);
        roots.push_back(s.dirichlet_weight);
        roots.push_back(s.dirichlet_extension);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("the structure of displacement component ") + kAxisName[c] + ": " +
                                    e.what());
      }
    }
    solution.structure = std::make_shared<Tape>(roots, D);
  }
  check_data(elasticity_data_rules(problem, structured), rules, grid.h);
  solution.mesh = cells.mesh();
  if (!solution.mesh) solution.domain = std::make_shared<Tape>(problem.domain, D);

  // Assembly by the shared cell loop, one band per pair of components.
  const std::size_t relevant = basis.relevant.size();
  ElasticityAssembly assembled =
      assemble_elasticity<D>({problem, basis, candidates, kinds, rules, solution.structure.get(), weak, inside_points,
                              report.nitsche_penalty.value_or(0.0)});
  std::vector<std::vector<double>>& bands = assembled.bands;
  const std::vector<std::vector<double>>& loads = assembled.loads;

  // The system of the unknowns, component-major: the diagonal blocks by
  // extended_system, the blocks below them E^T A_cd E.
  const Eigen::SparseMatrix<double>& E = basis.extension;
  const Eigen::Index N = E.cols();
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd right(D * N);
  for (int c = 0; c < D; ++c) {
    right.segment(c * N, N) =
        E.transpose() * Eigen::Map<const Eigen::VectorXd>(loads[c].data(), static_cast<Eigen::Index>(relevant));
    for (int d = 0; d <= c; ++d) {
      const Eigen::SparseMatrix<double> block =
          c == d ? extended_system(basis, bands[block_pair(c, d)])
                 : Eigen::SparseMatrix<double>(E.transpose() * band_matrix(basis, bands[block_pair(c, d)]) * E);
      std::vector<double>().swap(bands[block_pair(c, d)]);
      for (Eigen::Index col = 0; col < block.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator e(block, col); e; ++e)
          entries.emplace_back(c * N + e.row(), d * N + col, e.value());
    }
  }
  Eigen::SparseMatrix<double> system(D * N, D * N);
  system.setFromTriplets(entries.begin(), entries.end());
  entries = {};
  report.nonzeros = 2 * static_cast<std::size_t>(system.nonZeros()) - static_cast<std::size_t>(D * N);

  // Free rigid motions: those of energy 0 (the rest is held by the
  // displacement conditions), from the generalized eigenproblem of the
  // motions' energies against their diagonal scale.
  double longest = 0.0;
  std::array<double, 3> centre{};
  for (int a = 0; a < D; ++a) {
    longest = std::max(longest, problem.max[a] - problem.min[a]);
    centre[a] = 0.5 * (problem.min[a] + problem.max[a]);
  }
  const int motions = kRigidMotions<D>;
  Eigen::MatrixXd rigid(D * N, motions);
  for (Eigen::Index p = 0; p < N; ++p) {
    const auto x = grid.greville(grid.spline_index(basis.relevant[basis.unknown_spline[static_cast<std::size_t>(p)]]));
    for (int m = 0; m < motions; ++m) {
      const auto u = rigid_motion<D>(m, x.data(), centre);
      for (int c = 0; c < D; ++c) rigid(c * N + p, m) = u[c];
    }
  }
  std::array<double, D> box_centre{};
  for (int a = 0; a < D; ++a) box_centre[a] = centre[a];
  const Eigen::MatrixXd energy = rigid.transpose() * (system.template selfadjointView<Eigen::Lower>() * rigid);
  const Eigen::MatrixXd scale = rigid.transpose() * system.diagonal().asDiagonal() * rigid;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(energy, scale);
  int free = 0;
  while (free < motions && modes.eigenvalues()[free] < 1e-8) ++free;
  results.free_rigid_motions = free;
  Eigen::MatrixXd free_motions;  // unknowns x free
  if (free > 0) {
    const Eigen::MatrixXd combination = modes.eigenvectors().leftCols(free);
    free_motions = rigid * combination;
    const Eigen::VectorXd net = free_motions.transpose() * right;
    const Eigen::VectorXd size = free_motions.cwiseAbs().transpose() * right.cwiseAbs();
    double defect = 0.0;
    for (int m = 0; m < free; ++m) defect = std::max(defect, std::abs(net[m]) / std::max(size[m], 1e-300));
    results.load_balance = defect;
    if (size.maxCoeff() > 0.0 && defect > kLoadBalanceTolerance) {
      const Eigen::VectorXd resultant = rigid.transpose() * right;  // net force, then moment(s)
      std::string force = "(", moment = D == 2 ? "" : "(";
      for (int a = 0; a < D; ++a) force += (a ? ", " : "") + scientific(resultant[a]);
      for (int m = D; m < motions; ++m) moment += (m > D ? ", " : "") + scientific(resultant[m]);
      throw std::invalid_argument("unbalanced loads on a free body: the displacement conditions leave " +
                                  std::to_string(free) + " rigid motion" + (free == 1 ? "" : "s") +
                                  " free, and the loads do work on them (net force " + force + "), moment " + moment +
                                  (D == 2 ? "" : ")") + " about " + point_text<D>(box_centre) + "; relative defect " +
                                  scientific(defect) + "): balance the loads or fix the body somewhere");
    }
    // Remove the quadrature-level remainder, then pin one unknown per
    // free motion (column-pivoted QR picks unknowns that determine them).
    right -= free_motions * (free_motions.transpose() * free_motions).ldlt().solve(free_motions.transpose() * right);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> pivots(free_motions.transpose());
    for (int m = 0; m < free; ++m) {
      const Eigen::Index pinned = pivots.colsPermutation().indices()[m];
      system.coeffRef(pinned, pinned) *= 2.0;
    }
  }
  timer.lap(&StageSeconds::assembly);

  LinearSolverKind kind = options.linear_solver;
  if (kind == LinearSolverKind::Automatic && D == 2) kind = LinearSolverKind::ConjugateGradient;
  const double tolerance =
      options.cg_tolerance > 0.0 ? options.cg_tolerance : automatic_cg_tolerance(grid.h, longest, n);
  Eigen::VectorXd coefficients = solve_symmetric(system, right, kind, tolerance, report);
  auto spline_coefficients = [&] {
    solution.spline_coefficients.resize(static_cast<Eigen::Index>(relevant), D);
    for (int c = 0; c < D; ++c) solution.spline_coefficients.col(c) = E * coefficients.segment(c * N, N);
  };
  spline_coefficients();
  timer.lap(&StageSeconds::solve);

  // Free motions: make u_h L2-orthogonal to them. Their functions are the
  // rigid motions combined, exactly (linear functions are in the basis).
  if (free > 0) {
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(motions, motions);
    Eigen::VectorXd moments = Eigen::VectorXd::Zero(motions);
    typename ElasticitySolution<D>::Probe probe(solution);
    for (const auto& points : volume)
      for (const auto& q : points) {
        double u[D];
        probe.at(q.x.data(), u);
        std::array<std::array<double, D>, kRigidMotions<D>> r{};
        for (int m = 0; m < motions; ++m) r[m] = rigid_motion<D>(m, q.x.data(), centre);
        for (int m = 0; m < motions; ++m)
          for (int c = 0; c < D; ++c) {
            moments[m] += q.weight * r[m][c] * u[c];
            for (int l = 0; l < motions; ++l) gram(m, l) += q.weight * r[m][c] * r[l][c];
          }
      }
    const Eigen::MatrixXd combination = modes.eigenvectors().leftCols(free);
    const Eigen::VectorXd amount =
        (combination.transpose() * gram * combination).ldlt().solve(combination.transpose() * moments);
    coefficients -= free_motions * amount;
    spline_coefficients();
  }

  // Energies, the largest von Mises stress, and errors against the exact solution.
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
    for (std::size_t k = 0; k < candidates.size(); ++k) {
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
    results.l2_error = std::sqrt(error2 / norm2);
    results.energy_error = std::sqrt(energy_error2 / energy_norm2);
  }
  timer.lap(&StageSeconds::errors);
  return solution;
}

template class ElasticitySolution<2>;
template class ElasticitySolution<3>;
template ElasticitySolution<2> solve_elasticity<2>(const ElasticityProblem&, const SolverOptions&);
template ElasticitySolution<3> solve_elasticity<3>(const ElasticityProblem&, const SolverOptions&);

}  // namespace sage::solver
