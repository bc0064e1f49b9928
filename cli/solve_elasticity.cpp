// `sage solve` for problem files with "physics": "elasticity": solves,
// writes displacement, stress (VTK's symmetric tensor layout), von_mises
// and omega (and the exact displacement and the error when given), and
// prints the summary.

#include "solve_output.hpp"

#include <sage/output/point_arrays.hpp>
#include <sage/solver/elasticity.hpp>

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace sage::cli {

template <int D>
void solve_elasticity_and_write(const SolveCommand& command, const ProblemFile& file) {
  const solver::ElasticityProblem& problem = *file.elasticity;
  solver::ElasticitySolution<D> solution;
  try {
    solution = solver::solve_elasticity<D>(problem, command.options);
  } catch (const std::exception& e) {
    throw std::runtime_error(command.problem_path + ": " + e.what());
  }
  const solver::SolveReport& r = solution.report;
  const solver::ElasticityResults& results = solution.results;

  const auto start = std::chrono::steady_clock::now();
  const Grid grid = output_grid(command, file.problem, command.options.cell_width);
  const output::ClippedGrid part = clipped_output<D>(grid, solution.domain, solution.mesh, solution.basis.grid.h);
  const std::vector<std::array<double, 3>> points = part.points();
  const std::size_t n = points.size();
  output::PointArray displacement{"displacement", 3, std::vector<double>(3 * n, 0.0)},
      stress{"stress", 6, std::vector<double>(6 * n)}, mises{"von_mises", 1, std::vector<double>(n)};
  output::PointArray exact{"displacement_exact", 3, {}}, error{"displacement_error", 3, {}};
  std::optional<Tape> exact_tape;
  if (problem.exact) {
    exact_tape.emplace(std::vector<Expr>(problem.exact->begin(), problem.exact->begin() + D), D);
    exact.values.assign(3 * n, 0.0);
    error.values.assign(3 * n, 0.0);
  }
#pragma omp parallel
  {
    typename solver::ElasticitySolution<D>::Probe probe(solution);
    std::optional<Evaluator<double>> exact_eval;
    if (exact_tape) exact_eval.emplace(*exact_tape);
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = points[i].data();
      double u[D], g[D * D];
      probe.at(p, u, g);
      const auto s = solution.material.template stress<D>(g);
      for (int a = 0; a < D; ++a) displacement.values[3 * i + static_cast<std::size_t>(a)] = u[a];
      for (int v = 0; v < 6; ++v) stress.values[6 * i + static_cast<std::size_t>(v)] = s[static_cast<std::size_t>(v)];
      mises.values[i] = solver::von_mises(s);
      if (!exact_eval) continue;
      exact_eval->evaluate(p);
      for (int a = 0; a < D; ++a) {
        const auto at = 3 * i + static_cast<std::size_t>(a);
        exact.values[at] = exact_eval->result(static_cast<std::size_t>(a));
        error.values[at] = u[a] - exact.values[at];
      }
    }
  }
  std::vector<output::PointArray> arrays{displacement, stress, mises};
  if (problem.exact) {
    arrays.push_back(exact);
    arrays.push_back(error);
  }
  part.write(command.output_path, arrays);
  write_quadrature(command, solution.quadrature);
  const double output_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (command.quiet) return;
  const solver::ElasticMaterial& m = problem.material;
  std::printf("%s: %dD linear elasticity%s, E = %g, nu = %g, degree %d, %s basis, displacements by %s, h = %g\n",
              command.problem_path.c_str(), D,
              D == 3 ? "" : (m.plane == solver::PlaneMode::Stress ? " (plane stress)" : " (plane strain)"), m.young,
              m.poisson, command.options.degree, command.basis.c_str(), r.dirichlet_route.c_str(),
              command.options.cell_width);
  if (r.nitsche_penalty) std::printf("  Nitsche penalty %g (2 mu + lambda) / h\n", *r.nitsche_penalty);
  print_solve_report(r, solution.domain, solution.mesh != nullptr);
  if (results.free_rigid_motions > 0)
    std::printf(
        "  free body: %d rigid motion%s held by no displacement condition; loads balance to %.1e (relative); the "
        "solution is L2-orthogonal to %s\n",
        results.free_rigid_motions, results.free_rigid_motions == 1 ? "" : "s", *results.load_balance,
        results.free_rigid_motions == 1 ? "it" : "them");
  if (results.l2_error)
    std::printf("  relative errors: L2 %.3e, energy norm %.3e\n", *results.l2_error, *results.energy_error);
  std::printf("  strain energy %.6g; largest von Mises stress %.6g at (", results.strain_energy, results.max_von_mises);
  for (int a = 0; a < D; ++a) std::printf("%s%g", a ? ", " : "", results.max_von_mises_at[static_cast<std::size_t>(a)]);
  std::printf(") (at the quadrature points)\n");
  const auto& s = r.seconds;
  std::printf(
      "  seconds: field %.3f, classification %.3f, quadrature %.3f, assembly %.3f, solve %.3f, errors %.3f, output "
      "%.3f\n",
      s.field, s.classification, s.quadrature, s.assembly, s.solve, s.errors, output_seconds);
  print_written(command.output_path, part, grid);
}

template void solve_elasticity_and_write<2>(const SolveCommand&, const ProblemFile&);
template void solve_elasticity_and_write<3>(const SolveCommand&, const ProblemFile&);

}  // namespace sage::cli
