// sage solve PROBLEM.json -o OUT.vtu [--degree 3] [--cells 64 | --h 0.01]
//            [--basis web|weighted] [--robin weak|structure [--robin-band F] [--robin-band-power M]]
//            [--solver auto|direct|cg|jacobi] [--tolerance T]
//            [--grid RES]
//            [--quadrature-points FILE.vtu] [--condition] [--quiet]

#include "commands.hpp"
#include "field_job.hpp"
#include "solve_output.hpp"

#include <sage/output/output_file.hpp>
#include <sage/solver/bspline.hpp>
#include <sage/solver/default_grid.hpp>
#include <sage/solver/poisson.hpp>

#include <boost/program_options.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <variant>

namespace po = boost::program_options;

namespace sage::cli {

namespace {

template <int D>
void solve_and_write(const SolveCommand& command, const solver::PoissonProblem& problem) {
  solver::PoissonSolution<D> solution;
  try {
    solution = solver::solve_poisson<D>(problem, command.options);
  } catch (const std::exception& e) {
    throw std::runtime_error(command.problem_path + ": " + e.what());
  }
  const solver::SolveReport& r = solution.report;

  const auto start = std::chrono::steady_clock::now();
  const WrittenSolution written = write_solution<D>(command, problem.domain, solution, problem.exact);
  write_quadrature(command, solution.quadrature);
  const double output_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (command.quiet) return;
  const auto& s = r.seconds;
  std::printf("%s: %dD Poisson, degree %d, %s basis, Dirichlet by %s, %s Robin/Neumann route, h = %g\n",
              command.problem_path.c_str(), D, command.options.degree, command.basis.c_str(), r.dirichlet_route.c_str(),
              command.options.robin == solver::RobinRoute::Structure ? "structure" : "weak",
              command.options.cell_width);
  std::fputs(command.grid_note.c_str(), stdout);
  std::fputs(command.geometry_note.c_str(), stdout);
  if (r.nitsche_penalty) std::printf("  Nitsche penalty %g / h\n", *r.nitsche_penalty);
  if (r.robin_band) {
    if (*r.robin_band > 0.0)
      std::printf(
          "  structure multiplier cut off at distance %g (--robin-band %g), power %d; second function on %zu "
          "unknowns\n",
          *r.robin_band, command.options.robin_band, command.options.robin_band_power, r.second_unknowns);
    else
      std::printf("  structure multiplier: the global distance field (--robin-band 0)\n");
  }
  print_solve_report(r, solution.domain, solution.mesh != nullptr);
  if (r.neumann_compatibility)
    std::printf("  pure Neumann: compatibility defect %.1e (relative), mean of u fixed to 0\n",
                *r.neumann_compatibility);
  if (r.l2_error && r.h1_error) std::printf("  relative errors: L2 %.3e, H1 seminorm %.3e\n", *r.l2_error, *r.h1_error);
  std::printf(
      "  seconds: field %.3f, classification %.3f, quadrature %.3f, assembly %.3f, solve %.3f, condition %.3f, "
      "errors %.3f, output %.3f\n",
      s.field, s.classification, s.quadrature, s.assembly, s.solve, s.condition, s.errors, output_seconds);
  print_written(command.output_path, written);
}

constexpr double kFinestDeflection = 3e-4;

/// A tessellated CAD domain's deflection for the grid, when the file sets
/// none and the default is coarser: the geometry's error below the
/// discretization's, L (h / L)^(p + 1) for the domain's longest side L,
/// but not below 3e-4 of the diagonal. Cut cells cost with their
/// triangles: on gmsh_t20_data.step (B-splines, degree 2, 48 cells) a
/// deflection of 4e-4 of the diagonal costs 1.4 times the default's
/// solve, 1e-4 of it 3.6 times.
std::optional<double> deflection_for_grid(const ProblemFile& file, const solver::SolverOptions& options) {
  const geometry::Model& model = file.model;
  if (model.faces.empty() || !model.field_follows_surface || file.deflection || !model.bounds) return std::nullopt;
  const auto& b = *model.bounds;
  const double diagonal = std::hypot(b.max[0] - b.min[0], b.max[1] - b.min[1], b.max[2] - b.min[2]);
  const double side = file.domain().longest_side();
  const double wanted =
      std::max(side * std::pow(options.cell_width / side, options.degree + 1), kFinestDeflection * diagonal);
  if (!(wanted < 0.99 * model.deflection)) return std::nullopt;
  return wanted;
}

/// What a CAD domain's cut cells follow: the exact faces, or their
/// tessellation (and why).
std::string geometry_note(const ProblemFile& file, bool chosen_for_grid) {
  const geometry::Model& model = file.model;
  if (model.faces.empty()) return {};
  if (!model.field_follows_surface) return "  geometry: the exact CAD faces (sage info tells how)\n";
  std::ostringstream s;
  s << "  geometry: the CAD faces' tessellation, within " << model.deflection << " " << model.unit
    << (file.deflection   ? " (the file's deflection)"
        : chosen_for_grid ? " (chosen for the grid: L (h/L)^(p+1), at least 3e-4 of the diagonal)"
                          : " (the default, 1e-3 of the diagonal, is below L (h/L)^(p+1))");
  for (const std::string& note : model.notes)
    if (note.rfind("no exact field: ", 0) == 0) s << " (" << note << ")";
  s << "\n";
  return s.str();
}

/// The options of `sage solve`, writing into `command` (and `cells`, `h`,
/// which are optional in the command).
po::options_description solve_options(SolveCommand& command, int& cells, double& h) {
  po::options_description options(
      "Usage: sage solve PROBLEM.json -o OUT.vtu [options]\n"
      "Solves -div(k grad u) = f with Dirichlet, Neumann and Robin conditions on the\n"
      "domain of PROBLEM.json (see README.md, \"Solving boundary value problems\"),\n"
      "with B-splines on a background grid: no mesh of the domain. Writes point\n"
      "arrays u, grad_u, omega (and u_exact, error) on the cells covering the domain.\n"
      "With \"physics\": \"elasticity\", solves linear elasticity and writes displacement,\n"
      "stress (xx, yy, zz, xy, yz, xz), von_mises and omega (the --robin options do not apply).\n\n"
      "Options");
  auto add = options.add_options();
  add("help,h", "show this help");
  add("output,o", po::value(&command.output_path)->required(), "output file (.vtu)");
  add("degree", po::value(&command.options.degree)->default_value(3), "B-spline degree, 1 to 5");
  add("cells", po::value(&cells),
      "cells across the longest side of the box (default 64 in 2D; 20 in 3D, more for thin walls)");
  add("h", po::value(&h), "cell width (instead of --cells)");
  add("basis", po::value(&command.basis)->default_value("web"), "web (stable WEB-splines) or weighted");
  add("robin", po::value(&command.robin),
      "weak (Neumann and Robin conditions by boundary integrals; default) or structure (Rvachev's solution "
      "structure as well, degree >= 2; overrides the problem file's \"robin\")");
  add("dirichlet", po::value(&command.dirichlet)->default_value(command.dirichlet),
      "auto (weak, except with --robin structure or --basis weighted), weak (Nitsche's method) or structure "
      "(u = omega_D Phi + g~, the R-function structure)");
  add("nitsche-penalty", po::value(&command.options.nitsche_penalty),
      "weak Dirichlet conditions: the penalty sigma h (default 4 (degree + 1)^2)");
  add("robin-band", po::value(&command.options.robin_band)->default_value(command.options.robin_band),
      "structure route: the multiplier is cut off at distance F L (h/L)^(2/3) from the Robin parts, L the "
      "box's longest side, where the structure's second function lives (0: no cut-off and no second function, "
      "the global distance field)");
  add("robin-band-power", po::value(&command.options.robin_band_power)->default_value(command.options.robin_band_power),
      "structure route: the power M of the cut-off (1 - omega_R / band)^M, M >= 2");
  add("solver", po::value(&command.linear_solver)->default_value("auto"),
      "auto (cg in 2D; in 3D jacobi, then schwarz when jacobi would take longer; direct for --robin "
      "structure), direct (sparse LDLT), cg (conjugate "
      "gradients, incomplete Cholesky), jacobi (conjugate gradients, Jacobi) or "
      "schwarz (conjugate gradients, multilevel Schwarz on cell blocks)");
  add("tolerance", po::value(&command.options.cg_tolerance),
      "relative residual of conjugate gradients (default (h/L)^(degree+3) within [1e-12, 1e-6], L the "
      "box's longest side: below the discretization error)");
  add("grid", po::value(&command.grid), "output points per axis, e.g. 200x200 (default: 4 per cell)");
  add("quadrature-points", po::value(&command.quadrature_path), "also write the quadrature points to this .vtu");
  add("condition", "also estimate the condition number (two sparse factorizations: slow on large problems)");
  add("quiet,q", "no summary");
  return options;
}

/// Checks the parsed options and turns their texts into the solver's
/// enums; `robin` is --robin when given. Throws UsageError (exit 2).
void check_options(SolveCommand& command, const po::variables_map& vm, int cells, double h,
                   std::optional<solver::RobinRoute>& robin) {
  if (vm.count("cells")) command.cells = cells;
  if (vm.count("h")) command.h = h;
  command.quiet = vm.count("quiet") > 0;
  command.options.keep_quadrature = !command.quadrature_path.empty();
  if (!command.output_path.ends_with(".vtu")) throw UsageError{"-o " + command.output_path + ": must end in .vtu"};
  if (!command.quadrature_path.empty() && !command.quadrature_path.ends_with(".vtu"))
    throw UsageError{"--quadrature-points " + command.quadrature_path + ": must end in .vtu"};
  if (command.cells && command.h) throw UsageError{"give --cells or --h, not both"};
  if (command.options.degree < 1 || command.options.degree > solver::kMaxDegree)
    throw UsageError{"--degree must be from 1 to " + std::to_string(solver::kMaxDegree)};
  if (command.cells && *command.cells < 1) throw UsageError{"--cells must be positive"};
  if (command.h && !(*command.h > 0.0)) throw UsageError{"--h must be positive"};
  if (vm.count("tolerance") && !(command.options.cg_tolerance > 0.0 && command.options.cg_tolerance < 1.0))
    throw UsageError{"--tolerance must be in (0, 1)"};
  if (!(command.options.robin_band >= 0.0) || !std::isfinite(command.options.robin_band))
    throw UsageError{"--robin-band must be 0 or positive"};
  if (command.options.robin_band_power < 2) throw UsageError{"--robin-band-power must be 2 or more"};
  try {
    command.options.basis = solver::parse_basis_kind(command.basis);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--basis: ") + e.what()};
  }
  if (command.linear_solver == "auto") {
    command.options.linear_solver = solver::LinearSolverKind::Automatic;
  } else if (command.linear_solver == "direct") {
    command.options.linear_solver = solver::LinearSolverKind::Direct;
  } else if (command.linear_solver == "cg") {
    command.options.linear_solver = solver::LinearSolverKind::ConjugateGradient;
  } else if (command.linear_solver == "jacobi") {
    command.options.linear_solver = solver::LinearSolverKind::JacobiConjugateGradient;
  } else if (command.linear_solver == "schwarz") {
    command.options.linear_solver = solver::LinearSolverKind::Schwarz;
  } else {
    throw UsageError{"--solver must be auto, direct, cg, jacobi or schwarz, not '" + command.linear_solver + "'"};
  }

  try {
    command.options.dirichlet = solver::parse_dirichlet_route(command.dirichlet);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--dirichlet: ") + e.what()};
  }
  if (vm.count("nitsche-penalty") && !(command.options.nitsche_penalty > 0.0))
    throw UsageError{"--nitsche-penalty must be positive"};

  if (!command.robin.empty()) {
    try {
      robin = solver::parse_robin_route(command.robin);
    } catch (const std::invalid_argument& e) {
      throw UsageError{std::string("--robin: ") + e.what()};
    }
  }
}

}  // namespace

int run_solve(const std::vector<std::string>& args) {
  SolveCommand command;
  int cells = 0;
  double h = 0.0;
  const po::options_description options = solve_options(command, cells, h);
  po::variables_map vm;
  if (!parse_model_command(args, options, command.problem_path, vm)) return 0;
  std::optional<solver::RobinRoute> robin;
  check_options(command, vm, cells, h, robin);

  // Before the work, not after it.
  output::check_writable(command.output_path);
  if (!command.quadrature_path.empty()) output::check_writable(command.quadrature_path);
  ProblemFile file = problems::read_problem_file(command.problem_path);
  const solver::ProblemDomain* domain = &file.domain();
  command.options.robin = robin.value_or(file.robin.value_or(solver::RobinRoute::Weak));
  command.options.estimate_condition = vm.count("condition") > 0;
  if (command.h) {
    command.options.cell_width = *command.h;
  } else if (command.cells || domain->dimension == 2) {
    command.options.cell_width = domain->longest_side() / command.cells.value_or(domain->dimension == 2 ? 64 : 20);
  } else {
    const solver::DefaultGrid grid = solver::default_grid(*domain);
    command.options.cell_width = domain->longest_side() / grid.cells;
    if (grid.refined())
      command.grid_note = "  grid: " + std::to_string(grid.cells) + " cells across (not " +
                          std::to_string(grid.preferred) + "): the domain's walls are thin; " +
                          std::to_string(grid.cells_inside) + " cells inside, " + std::to_string(grid.cells_cut) +
                          " cut (--cells or --h to choose)\n";
  }
  const std::optional<double> finer = deflection_for_grid(file, command.options);
  if (finer) {
    geometry::LoadOptions options;
    options.deflection = *finer;
    file = problems::read_problem_file(command.problem_path, options);
    domain = &file.domain();
  }
  command.geometry_note = geometry_note(file, finer.has_value());
  std::visit(
      [&](const auto& problem) {
        if (domain->dimension == 2)
          solve_and_write<2>(command, problem);
        else
          solve_and_write<3>(command, problem);
      },
      file.physics);
  return 0;
}

}  // namespace sage::cli
