// sage.solve(): a problem file (or the same as a dict) solved as `sage
// solve` solves it, the solution evaluated at numpy points, the report as
// a dict.

#include "bindings.hpp"

#include <sage/problems/problem_file.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/solver/default_grid.hpp>
#include <sage/solver/elastic_material.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <pybind11/stl.h>

#include <unistd.h>

#include <atomic>
#include <cmath>
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

/// Where the solution is wanted: points in the order given (`shape` {n}),
/// or a grid's points, x fastest (`shape` {ny, nx} or {nz, ny, nx}), where
/// the values outside the domain (omega < 0) become NaN.
struct Places {
  std::vector<std::array<double, 3>> points;
  std::vector<py::ssize_t> shape;
  bool grid = false;
};

/// `shape` followed by `trailing` (none for 0).
std::vector<py::ssize_t> shaped(const Places& at, py::ssize_t trailing) {
  std::vector<py::ssize_t> shape = at.shape;
  if (trailing > 0) shape.push_back(trailing);
  return shape;
}

/// NaN in every `width` values of a point outside the domain, on a grid.
void mask_outside(const Places& at, const std::vector<double>& omega, std::vector<double>& values, std::size_t width) {
  if (!at.grid) return;
  for (std::size_t p = 0; p < omega.size(); ++p)
    if (!(omega[p] >= 0.0)) std::fill_n(values.begin() + static_cast<std::ptrdiff_t>(p * width), width, std::nan(""));
}

template <int D>
py::dict solve_in(const solver::PoissonProblem& problem, const solver::SolverOptions& options, const Places& at) {
  const std::size_t n = at.points.size();
  std::vector<double> u(n), gradient(n * D), omega(n);
  py::dict out;
  {
    py::gil_scoped_release unlocked;
    const solver::PoissonSolution<D> solution = solver::solve_poisson<D>(problem, options);
#pragma omp parallel
    {
      typename solver::PoissonSolution<D>::Probe probe(solution);  // one per thread
#pragma omp for schedule(dynamic, 256)
      for (std::size_t p = 0; p < n; ++p) {
        u[p] = probe.at(at.points[p].data(), gradient.data() + p * D);
        omega[p] = probe.omega(at.points[p].data());
      }
    }
    py::gil_scoped_acquire locked;
    out["report"] = report_of(solution.report);
  }
  mask_outside(at, omega, u, 1);
  mask_outside(at, omega, gradient, D);
  out["u"] = array_of(shaped(at, 0), u.data());
  out["grad_u"] = array_of(shaped(at, D), gradient.data());
  out["omega"] = array_of(shaped(at, 0), omega.data());
  return out;
}

template <int D>
py::dict solve_in(const solver::ElasticityProblem& problem, const solver::SolverOptions& options, const Places& at) {
  const std::size_t n = at.points.size();
  std::vector<double> displacement(n * D), stress(n * 6), mises(n), omega(n);
  py::dict out;
  {
    py::gil_scoped_release unlocked;
    const solver::ElasticitySolution<D> solution = solver::solve_elasticity<D>(problem, options);
#pragma omp parallel
    {
      typename solver::ElasticitySolution<D>::Probe probe(solution);  // one per thread
#pragma omp for schedule(dynamic, 256)
      for (std::size_t p = 0; p < n; ++p) {
        probe.at(at.points[p].data(), displacement.data() + p * D);
        const std::array<double, 6> s = probe.stress(at.points[p].data());
        std::copy(s.begin(), s.end(), stress.begin() + static_cast<std::ptrdiff_t>(6 * p));
        mises[p] = solver::von_mises(s);
        omega[p] = probe.omega(at.points[p].data());
      }
    }
    py::gil_scoped_acquire locked;
    out["report"] = report_of(solution.report);
  }
  mask_outside(at, omega, displacement, D);
  mask_outside(at, omega, stress, 6);
  mask_outside(at, omega, mises, 1);
  out["displacement"] = array_of(shaped(at, D), displacement.data());
  out["stress"] = array_of(shaped(at, 6), stress.data());
  out["von_mises"] = array_of(shaped(at, 0), mises.data());
  out["omega"] = array_of(shaped(at, 0), omega.data());
  return out;
}

/// A grid over the problem's box: `counts` points per axis, or points `resolution` apart.
Places grid_places(const solver::ProblemDomain& domain, const std::optional<std::vector<int>>& counts,
                   std::optional<double> resolution, py::dict& axes) {
  const int d = domain.dimension;
  Grid grid;
  grid.dimension = d;
  for (int a = 0; a < d; ++a) {
    grid.lo[a] = domain.min[a];
    grid.hi[a] = domain.max[a];
  }
  // Bad counts or spacings throw std::invalid_argument: ValueError in Python.
  if (counts)
    grid.points = Grid::checked_points({counts->begin(), counts->end()}, d, "grid");
  else
    grid.space_points(*resolution);
  Places at;
  at.grid = true;
  at.shape = grid_shape(grid);
  at.points.resize(grid.size());
  for (std::size_t p = 0; p < grid.size(); ++p) at.points[p] = grid.point(p);
  add_axes(axes, grid);
  return at;
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

/// A problem dict's temporary file, removed however the solve ends.
struct TemporaryFile {
  std::string path;  // empty: none
  ~TemporaryFile() {
    std::error_code ignored;
    if (!path.empty()) std::filesystem::remove(path, ignored);
  }
};

/// Inside a handler of `e`: rethrows it, for a dict as the same error
/// naming "the problem dict" in place of its temporary file.
template <class Error>
[[noreturn]] void rethrow_naming_the_dict(const Error& e, const TemporaryFile& temporary) {
  if (temporary.path.empty()) throw;
  std::string message = e.what();
  for (auto at = message.find(temporary.path); at != std::string::npos; at = message.find(temporary.path))
    message.replace(at, temporary.path.size(), "the problem dict");
  throw Error(message);
}

py::dict solve(const py::object& problem,
               const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& points,
               std::optional<int> degree, std::optional<int> cells, std::optional<double> h, const std::string& kind,
               const std::optional<std::vector<int>>& grid, std::optional<double> resolution) {
  if (points && (grid || resolution)) throw py::value_error("give points, or grid or resolution, not both");
  if (grid && resolution) throw py::value_error("give grid or resolution, not both");
  const bool from_dict = py::isinstance<py::dict>(problem);
  const std::string path = from_dict ? problem_file_of(problem.cast<py::dict>()) : problem.cast<std::string>();
  std::optional<problems::ProblemFile> file;
  {
    const TemporaryFile temporary{from_dict ? path : std::string()};
    try {
      py::gil_scoped_release unlocked;
      file = problems::read_problem_file(path);
    } catch (const problems::ProblemError& e) {
      rethrow_naming_the_dict(e, temporary);
    } catch (const geometry::ModelError& e) {
      rethrow_naming_the_dict(e, temporary);
    }
  }
  const int d = file->domain().dimension;
  const solver::SolverOptions options = options_for(*file, degree, cells, h, kind);
  py::dict axes;
  Places at;
  if (grid || resolution) {
    at = grid_places(file->domain(), grid, resolution, axes);
  } else if (points) {
    at.points = points_of(*points, d, "points");
    at.shape = {static_cast<py::ssize_t>(at.points.size())};
  } else {
    at.shape = {0};
  }
  py::dict out = std::visit(
      [&](const auto& physics) {
        return d == 2 ? solve_in<2>(physics, options, at) : solve_in<3>(physics, options, at);
      },
      file->physics);
  for (const auto& [name, axis] : axes) out[name] = axis;
  return out;
}

}  // namespace

void bind_solve(py::module_& m) {
  m.def("solve", &solve, py::arg("problem"), py::arg("points") = py::none(), py::kw_only(),
        py::arg("degree") = py::none(), py::arg("cells") = py::none(), py::arg("h") = py::none(),
        py::arg("solver") = "auto", py::arg("grid") = py::none(), py::arg("resolution") = py::none(),
        "Solves a problem file (a path, or the same JSON as a dict; a dict's relative 'domain' path is\n"
        "read from the current directory) as `sage solve` does, with its defaults: degree 2, 64 cells\n"
        "across in 2D, the part-fitted default grid in 3D. Returns 'report' (unknowns, iterations,\n"
        "errors when the problem has an exact solution, seconds, ...) and the solution at points\n"
        "((n, dimension) array), or on a grid over the problem's box (grid=(nx, ny[, nz]) points per\n"
        "axis, or resolution=R), shaped (ny, nx) or (nz, ny, nx) with the axes 'x', 'y' ('z') and NaN\n"
        "outside the domain: heat problems 'u', 'grad_u', 'omega'; elasticity 'displacement', 'stress'\n"
        "(xx, yy, zz, xy, yz, xz), 'von_mises', 'omega'. Raises ProblemError, ModelError, ValueError,\n"
        "RuntimeError (the grid cannot carry the problem, the solve failed).");
}

}  // namespace sage::python
