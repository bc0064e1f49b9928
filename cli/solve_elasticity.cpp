// `sage solve` for problem files with "physics": "elasticity": solves,
// writes displacement, stress (VTK's symmetric tensor layout), von_mises
// and omega (and the exact displacement and the error when given), and
// prints the summary.

#include "solve_output.hpp"

#include <sage/solver/elasticity.hpp>

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace sage::cli {

template <int D>
void solve_and_write(const SolveCommand& command, const solver::ElasticityProblem& problem) {
  solver::ElasticitySolution<D> solution;
  try {
    solution = solver::solve_elasticity<D>(problem, command.options);
  } catch (const std::exception& e) {
    throw std::runtime_error(command.problem_path + ": " + e.what());
  }
  const solver::SolveReport& r = solution.report;
  const solver::ElasticityResults& results = *r.elasticity;

  const auto start = std::chrono::steady_clock::now();
  const WrittenSolution written = write_solution<D>(command, problem.domain, solution, problem.exact);
  write_quadrature(command, solution.quadrature);
  const double output_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (command.quiet) return;
  const solver::ElasticMaterial& m = problem.material;
  std::printf("%s: %dD linear elasticity%s, E = %g, nu = %g, degree %d, %s basis, displacements by %s, h = %g\n",
              command.problem_path.c_str(), D,
              D == 3 ? "" : (m.plane == solver::PlaneMode::Stress ? " (plane stress)" : " (plane strain)"), m.young,
              m.poisson, command.options.degree, command.basis.c_str(), r.dirichlet_route.c_str(),
              command.options.cell_width);
  std::fputs(command.grid_note.c_str(), stdout);
  std::fputs(command.geometry_note.c_str(), stdout);
  if (r.nitsche_penalty) std::printf("  Nitsche penalty %g (2 mu + lambda) / h\n", *r.nitsche_penalty);
  print_solve_report(r, solution.domain, solution.mesh != nullptr);
  if (results.free_rigid_motions > 0)
    std::printf(
        "  free body: %d rigid motion%s held by no displacement condition; loads balance to %.1e (relative); the "
        "solution is L2-orthogonal to %s\n",
        results.free_rigid_motions, results.free_rigid_motions == 1 ? "" : "s", *results.load_balance,
        results.free_rigid_motions == 1 ? "it" : "them");
  if (r.l2_error) std::printf("  relative errors: L2 %.3e, energy norm %.3e\n", *r.l2_error, *r.energy_error);
  std::printf("  strain energy %.6g; largest von Mises stress %.6g at (", results.strain_energy, results.max_von_mises);
  for (int a = 0; a < D; ++a) std::printf("%s%g", a ? ", " : "", results.max_von_mises_at[static_cast<std::size_t>(a)]);
  std::printf(") (at the quadrature points)\n");
  const auto& s = r.seconds;
  std::printf(
      "  seconds: field %.3f, classification %.3f, quadrature %.3f, assembly %.3f, solve %.3f, errors %.3f, output "
      "%.3f\n",
      s.field, s.classification, s.quadrature, s.assembly, s.solve, s.errors, output_seconds);
  print_written(command.output_path, written);
}

template void solve_and_write<2>(const SolveCommand&, const solver::ElasticityProblem&);
template void solve_and_write<3>(const SolveCommand&, const solver::ElasticityProblem&);

}  // namespace sage::cli
