// sage.solve(): a problem file (or the same as a dict) solved as `sage
// solve` solves it, the solution evaluated at numpy points, the report as
// a dict.

#include "bindings.hpp"

#include <sage/problems/problem_file.hpp>
#include <sage/solver/default_grid.hpp>
#include <sage/solver/elastic_material.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <pybind11/stl.h>

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <optional>

namespace sage::python {

namespace {

solver::LinearSolverKind solver_kind(const std::string& name) {
  if (name == "auto") return solver::LinearSolverKind::Automatic;
  if (name == "direct") return solver::LinearSolverKind::Direct;
  if (name == "cg") return solver::LinearSolverKind::ConjugateGradient;
  if (name == "jacobi") return solver::LinearSolverKind::JacobiConjugateGradient;
  if (name == "schwarz") return solver::LinearSolverKind::Schwarz;
  throw py::value_error("solver must be 'auto', 'direct', 'cg', 'jacobi' or 'schwarz', not '" + name + "'");
}

/// The options `sage solve` would take: the grid from h, cells or the
/// default (2D: 64 cells across; 3D: solver::default_grid).
solver::SolverOptions options_for(const problems::ProblemFile& file, std::optional<int> degree,
                                  std::optional<int> cells, std::optional<double> h, const std::string& kind) {
  solver::SolverOptions options;
  if (degree) options.degree = *degree;
  options.linear_solver = solver_kind(kind);
  options.robin = file.robin.value_or(solver::RobinRoute::Weak);
  const solver::ProblemDomain& domain = file.domain();
  if (h && cells) throw py::value_error("give cells or h, not both");
  if (h)
    options.cell_width = *h;
  else if (cells || domain.dimension == 2)
    options.cell_width = domain.longest_side() / cells.value_or(domain.dimension == 2 ? 64 : 20);
  else
    options.cell_width = domain.longest_side() / solver::default_grid(domain).cells;
  return options;
}

py::dict report_of(const solver::SolveReport& r) {
  py::dict out;
  out["unknowns"] = r.unknowns;
  out["cells_inside"] = r.cells_inside;
  out["cells_cut"] = r.cells_cut;
  out["linear_solver"] = r.linear_solver;
  out["iterations"] = r.iterations;
  out["memory_estimate_mb"] = r.memory_estimate_mb;
  py::dict seconds;
  seconds["classification"] = r.seconds.classification;
  seconds["quadrature"] = r.seconds.quadrature;
  seconds["assembly"] = r.seconds.assembly;
  seconds["solve"] = r.seconds.solve;
  out["seconds"] = seconds;
  if (r.l2_error) out["l2_error"] = *r.l2_error;
  if (r.h1_error) out["h1_error"] = *r.h1_error;
  if (r.energy_error) out["energy_error"] = *r.energy_error;
  if (r.elasticity) {
    out["strain_energy"] = r.elasticity->strain_energy;
    out["max_von_mises"] = r.elasticity->max_von_mises;
    out["max_von_mises_at"] = r.elasticity->max_von_mises_at;
  }
  return out;
}

template <int D>
py::dict solve_in(const solver::PoissonProblem& problem, const solver::SolverOptions& options,
                  const std::vector<std::array<double, 3>>& at) {
  py::dict out;
  std::vector<double> u(at.size()), gradient(at.size() * D), omega(at.size());
  {
    py::gil_scoped_release unlocked;
    const solver::PoissonSolution<D> solution = solver::solve_poisson<D>(problem, options);
    typename solver::PoissonSolution<D>::Probe probe(solution);
    for (std::size_t p = 0; p < at.size(); ++p) {
      u[p] = probe.at(at[p].data(), gradient.data() + p * D);
      omega[p] = probe.omega(at[p].data());
    }
    py::gil_scoped_acquire locked;
    out["report"] = report_of(solution.report);
  }
  const auto n = static_cast<py::ssize_t>(at.size());
  out["u"] = array_of({n}, u.data());
  out["grad_u"] = array_of({n, D}, gradient.data());
  out["omega"] = array_of({n}, omega.data());
  return out;
}

template <int D>
py::dict solve_in(const solver::ElasticityProblem& problem, const solver::SolverOptions& options,
                  const std::vector<std::array<double, 3>>& at) {
  py::dict out;
  std::vector<double> displacement(at.size() * D), stress(at.size() * 6), mises(at.size()), omega(at.size());
  {
    py::gil_scoped_release unlocked;
    const solver::ElasticitySolution<D> solution = solver::solve_elasticity<D>(problem, options);
    typename solver::ElasticitySolution<D>::Probe probe(solution);
    for (std::size_t p = 0; p < at.size(); ++p) {
      probe.at(at[p].data(), displacement.data() + p * D);
      const std::array<double, 6> s = probe.stress(at[p].data());
      std::copy(s.begin(), s.end(), stress.begin() + static_cast<std::ptrdiff_t>(6 * p));
      mises[p] = solver::von_mises(s);
      omega[p] = probe.omega(at[p].data());
    }
    py::gil_scoped_acquire locked;
    out["report"] = report_of(solution.report);
  }
  const auto n = static_cast<py::ssize_t>(at.size());
  out["displacement"] = array_of({n, D}, displacement.data());
  out["stress"] = array_of({n, 6}, stress.data());
  out["von_mises"] = array_of({n}, mises.data());
  out["omega"] = array_of({n}, omega.data());
  return out;
}

/// A problem given as a dict: written as JSON to a temporary file (its
/// relative "domain" path made absolute from the current directory first).
std::string problem_file_of(const py::dict& problem) {
  py::dict copy = py::module_::import("copy").attr("deepcopy")(problem);
  if (copy.contains("domain") && py::isinstance<py::str>(copy["domain"]))
    copy["domain"] = py::module_::import("os.path").attr("abspath")(copy["domain"]);
  const std::string text = py::module_::import("json").attr("dumps")(copy).cast<std::string>();
  static std::atomic<int> made{0};
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("sage-problem-" + std::to_string(::getpid()) + "-" + std::to_string(made++) + ".json");
  std::ofstream(path) << text;
  return path.string();
}

/// The message of `e` naming "the problem dict" in place of its temporary file.
std::string renamed(const std::exception& e, const std::string& path) {
  std::string message = e.what();
  for (auto at = message.find(path); at != std::string::npos; at = message.find(path))
    message.replace(at, path.size(), "the problem dict");
  return message;
}

py::dict solve(const py::object& problem,
               const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& points,
               std::optional<int> degree, std::optional<int> cells, std::optional<double> h, const std::string& kind) {
  const bool from_dict = py::isinstance<py::dict>(problem);
  const std::string path = from_dict ? problem_file_of(problem.cast<py::dict>()) : problem.cast<std::string>();
  std::optional<problems::ProblemFile> file;
  try {
    py::gil_scoped_release unlocked;
    file = problems::read_problem_file(path);
  } catch (const problems::ProblemError& e) {
    if (!from_dict) throw;
    std::filesystem::remove(path);
    throw problems::ProblemError(renamed(e, path));
  } catch (const geometry::ModelError& e) {
    if (!from_dict) throw;
    std::filesystem::remove(path);
    throw geometry::ModelError(renamed(e, path));
  } catch (...) {
    if (from_dict) std::filesystem::remove(path);
    throw;
  }
  if (from_dict) std::filesystem::remove(path);
  const int d = file->domain().dimension;
  const solver::SolverOptions options = options_for(*file, degree, cells, h, kind);
  const std::vector<std::array<double, 3>> at =
      points ? points_of(*points, d, "points") : std::vector<std::array<double, 3>>{};
  return std::visit(
      [&](const auto& physics) {
        return d == 2 ? solve_in<2>(physics, options, at) : solve_in<3>(physics, options, at);
      },
      file->physics);
}

}  // namespace

void bind_solve(py::module_& m) {
  m.def("solve", &solve, py::arg("problem"), py::arg("points") = py::none(), py::kw_only(),
        py::arg("degree") = py::none(), py::arg("cells") = py::none(), py::arg("h") = py::none(),
        py::arg("solver") = "auto",
        "solve(problem, points=None, *, degree=None, cells=None, h=None, solver='auto') -> dict\n\n"
        "Solves a problem file (a path, or the same JSON as a dict; a dict's relative 'domain' path is\n"
        "read from the current directory) as `sage solve` does, with its defaults: degree 2, 64 cells\n"
        "across in 2D, the part-fitted default grid in 3D. Returns 'report' (unknowns, iterations,\n"
        "errors when the problem has an exact solution, seconds, ...) and, at points ((n, dimension)\n"
        "array): heat problems 'u', 'grad_u', 'omega'; elasticity 'displacement', 'stress' (n, 6:\n"
        "xx, yy, zz, xy, yz, xz), 'von_mises', 'omega'. Raises ProblemError, ModelError, ValueError,\n"
        "RuntimeError (the grid cannot carry the problem, the solve failed).");
}

}  // namespace sage::python
