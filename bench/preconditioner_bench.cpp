// preconditioner_bench: the 3D linear solve before and after the
// multilevel Schwarz preconditioner (issue 44), side by side in one run.
//
// Per case, degree and grid: unknowns, then for the old path (conjugate
// gradients with Jacobi; when Jacobi stagnates, incomplete Cholesky, as
// the former automatic solver did) and for Schwarz (the default now):
// iterations, the preconditioner's set-up seconds, the whole solve's
// seconds (set-up and iterations, wall clock), the peak resident MB of the
// whole run, the relative L2 error; the ratio of the two solve times; and
// what `--solver auto` chose (Jacobi, or Jacobi then Schwarz when Jacobi
// would take longer than Schwarz's whole solve) with its solve seconds.
// All solve to the same automatic tolerance.
//
// Cases: the unit ball and the lattice-aligned cube (Dirichlet data that
// differ from u inside), the plate with a hole (Dirichlet, Neumann, Robin
// faces), a mesh part (joint.off), a thin-walled part (occt_sh1.stl, walls
// a few cells thick), and elasticity: the bracket of
// examples/problems/bracket_3d.json and Lame's thick sphere.
//
//   preconditioner_bench [CASE...]   (ball cube plate joint thin bracket sphere; default: all)
//   preconditioner_bench big         (the plate at degree 2 and 128 cells, about 1e6 unknowns, Schwarz only)

#include <sage/expression/primitives.hpp>
#include <sage/geometry/model.hpp>
#include <sage/problems/problem_file.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/manufactured.hpp>
#include <sage/solver/poisson.hpp>

#include "bench_problems.hpp"
#include "bench_support.hpp"

#include <elastic_benchmarks.hpp>
#include <solver_fixtures.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace sage;
using namespace sage::solver;
using sage::bench::peak_megabytes;
using sage::bench::reset_peak;

constexpr double kPi = 3.14159265358979323846;

/// One solve's figures.
struct Figures {
  std::size_t unknowns = 0;
  int iterations = 0;
  double setup = 0.0, solve = 0.0, peak = 0.0, l2 = -1.0;
  std::string failure, solver;
};

/// Runs `solve` (which returns the report) with the kind given, measuring the peak.
Figures measure(const std::function<SolveReport(const SolverOptions&)>& solve, SolverOptions options,
                LinearSolverKind kind) {
  options.linear_solver = kind;
  Figures f;
  reset_peak();
  try {
    const SolveReport r = solve(options);
    f.unknowns = r.unknowns;
    f.iterations = r.iterations;
    f.setup = r.preconditioner_seconds;
    f.solve = r.seconds.solve;
    f.l2 = r.l2_error.value_or(-1.0);
    f.solver = r.linear_solver;
  } catch (const std::exception& e) {
    f.failure = e.what();
  }
  f.peak = peak_megabytes();
  return f;
}

void print_header(const char* title) {
  std::printf("\n%s\n%6s %5s %9s | %6s %7s %8s %8s %10s | %6s %7s %8s %8s %10s | %7s | %15s %8s\n", title, "degree",
              "cells", "unknowns", "iter.", "set-up", "solve s", "peak MB", "L2", "iter.", "set-up", "solve s",
              "peak MB", "L2", "speed-up", "auto", "solve s");
}

void print_side(const Figures& f) {
  if (!f.failure.empty()) {
    std::printf(" | failed: %.60s", f.failure.c_str());
    return;
  }
  std::printf(" | %6d %7.2f %8.2f %8.0f ", f.iterations, f.setup, f.solve, f.peak);
  if (f.l2 >= 0.0)
    std::printf("%10.3e", f.l2);
  else
    std::printf("%10s", "-");
}

/// The old path: Jacobi, or incomplete Cholesky when Jacobi stagnates.
Figures old_path(const std::function<SolveReport(const SolverOptions&)>& solve, const SolverOptions& options) {
  Figures jacobi = measure(solve, options, LinearSolverKind::JacobiConjugateGradient);
  if (jacobi.failure.empty()) return jacobi;
  Figures ic = measure(solve, options, LinearSolverKind::ConjugateGradient);
  ic.solve += jacobi.solve;  // the Jacobi iterations spent first
  return ic;
}

void compare(const std::function<SolveReport(const SolverOptions&)>& solve, int degree, int cells, double longest,
             bool with_old = true) {
  SolverOptions options;
  options.degree = degree;
  options.cell_width = longest / cells;
  options.estimate_condition = false;
  const Figures schwarz = measure(solve, options, LinearSolverKind::Schwarz);
  const Figures old = with_old ? old_path(solve, options) : Figures{};
  std::printf("%6d %5d %9zu", degree, cells, schwarz.unknowns);
  if (with_old)
    print_side(old);
  else
    std::printf(" | %50s", "(not run)");
  print_side(schwarz);
  if (with_old && old.failure.empty() && schwarz.failure.empty()) std::printf(" | %6.1fx", old.solve / schwarz.solve);
  const Figures automatic = measure(solve, options, LinearSolverKind::Automatic);
  const bool switched = automatic.solver.find("then multilevel Schwarz") != std::string::npos;
  const bool schwarz_only = !switched && automatic.solver.find("Schwarz") != std::string::npos;
  std::printf(" | %15s %8.2f\n", switched ? "Jacobi, Schwarz" : schwarz_only ? "Schwarz" : "Jacobi", automatic.solve);
  std::fflush(stdout);
}

/// The table of one problem: `solve(problem, options)` returns the report.
template <class Problem, class Solve>
void solve_case(const char* title, const Problem& problem, const std::vector<int>& degrees,
                const std::vector<int>& cells, Solve&& solve) {
  print_header(title);
  const double longest = problem.domain.longest_side();
  for (const int degree : degrees)
    for (const int n : cells) compare([&](const SolverOptions& o) { return solve(problem, o); }, degree, n, longest);
}

void poisson_case(const char* title, const PoissonProblem& problem, const std::vector<int>& degrees,
                  const std::vector<int>& cells) {
  solve_case(title, problem, degrees, cells,
             [](const PoissonProblem& p, const SolverOptions& o) { return solve_poisson<3>(p, o).report; });
}

void elasticity_case(const char* title, const ElasticityProblem& problem, const std::vector<int>& degrees,
                     const std::vector<int>& cells) {
  solve_case(title, problem, degrees, cells,
             [](const ElasticityProblem& p, const SolverOptions& o) { return solve_elasticity<3>(p, o).report; });
}

PoissonProblem unit_ball() {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr exact = sin(kPi * x) * sin(kPi * y) * sin(kPi * z) + x;
  PoissonProblem p;
  p.domain.dimension = 3;
  p.domain.field = ball({0, 0, 0}, 1.0, 3);
  p.domain.min = {-1, -1, -1};
  p.domain.max = {1, 1, 1};
  p.source = manufactured_source(exact, p.conductivity, 3);
  p.exact = exact;
  p.rest.value = exact + 0.5 * (1.0 - square(x) - square(y) - square(z));  // not u inside
  return p;
}

bool wanted(const std::vector<std::string>& cases, const std::string& name) {
  if (cases.empty()) return true;
  for (const std::string& c : cases)
    if (c == name) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> cases(argv + 1, argv + argc);
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  std::printf(
      "preconditioner_bench: %d thread(s); old = CG with Jacobi (incomplete Cholesky when Jacobi stagnates), "
      "new = CG with multilevel Schwarz; seconds are wall clock\n",
      threads);
  if (cases.size() == 1 && cases[0] == "big") {
    print_header("Plate (-1,1)^2 x (0,1) minus cylinder, about 1e6 unknowns (Schwarz only)");
    const PoissonProblem plate = plate_with_hole();
    compare([&](const SolverOptions& o) { return solve_poisson<3>(plate, o).report; }, 2, 128, 2.0, false);
    return 0;
  }
  if (wanted(cases, "ball")) poisson_case("Unit ball, Dirichlet", unit_ball(), {2, 3}, {16, 24, 32});
  if (wanted(cases, "cube"))
    poisson_case("Cube (-1,1)^3 on the lattice, Dirichlet", dirichlet_box(3), {2, 3}, {16, 24, 32});
  if (wanted(cases, "plate"))
    poisson_case("Plate (-1,1)^2 x (0,1) minus cylinder r = 0.4: Dirichlet, Neumann, Robin", plate_with_hole(), {2, 3},
                 {16, 32, 48});
  if (wanted(cases, "joint"))
    poisson_case("joint.off (CAD part, mesh), u = 0, f = 1",
                 sage::bench::zero_dirichlet(geometry::load_model(sage::bench::shared_data("meshes/joint.off"))),
                 {2, 3}, {16, 24, 32});
  if (wanted(cases, "thin"))
    poisson_case("occt_sh1.stl (thin-walled part, mesh), u = 0, f = 1",
                 sage::bench::zero_dirichlet(geometry::load_model(sage::bench::shared_data("meshes/occt_sh1.stl"))),
                 {2}, {48, 64, 96});
  if (wanted(cases, "bracket")) {
    const problems::ProblemFile file =
        problems::read_problem_file(std::string(SAGE_SOURCE_DIR) + "/examples/problems/bracket_3d.json");
    elasticity_case("bracket_3d.json (elasticity)", std::get<ElasticityProblem>(file.physics), {2, 3}, {20, 30, 40});
  }
  if (wanted(cases, "sphere"))
    elasticity_case("Lame's thick sphere (elasticity)", elastic_benchmarks::thick_sphere(false), {2}, {8, 12, 16});
  return 0;
}
