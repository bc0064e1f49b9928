// The Python module `sage`: normalized fields of models (GIS polygons, CSG
// models, meshes) at numpy points and on grids, and solves of problem
// files, through the same code as the `sage` program.
//
//     import sage
//     lake = sage.load("lake.geojson")
//     r = lake.evaluate(points)          # points: (n, 2) array in the model's plane
//     r["omega"], r["grad"], r["grad_norm"]
//     grid = lake.sample(resolution=100.0)   # arrays (ny, nx), axes, geotransform, crs

#include "bindings.hpp"

#include <sage/geometry/model.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/problems/problem_file.hpp>

namespace sage::python {

std::vector<std::array<double, 3>> points_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                                             int dimension, const std::string& what) {
  if (a.ndim() != 2 || a.shape(1) != dimension)
    throw py::value_error(what + ": expected an array of shape (n, " + std::to_string(dimension) + "), got " +
                          std::to_string(a.ndim()) + " dimension(s)" +
                          (a.ndim() == 2
                               ? " of shape (" + std::to_string(a.shape(0)) + ", " + std::to_string(a.shape(1)) + ")"
                               : std::string()));
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(a.shape(0)), {0.0, 0.0, 0.0});
  const auto view = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (int d = 0; d < dimension; ++d) points[static_cast<std::size_t>(i)][d] = view(i, d);
  return points;
}

py::array_t<double> array_of(const std::vector<py::ssize_t>& shape, const double* values) {
  py::array_t<double> a(shape);
  std::copy(values, values + a.size(), a.mutable_data());
  return a;
}

std::vector<py::ssize_t> grid_shape(const Grid& grid) {
  std::vector<py::ssize_t> shape;
  for (int a = grid.dimension - 1; a >= 0; --a) shape.push_back(grid.points[a]);
  return shape;
}

void add_axes(py::dict& out, const Grid& grid) {
  for (int a = 0; a < grid.dimension; ++a) {
    std::vector<double> axis(static_cast<std::size_t>(grid.points[a]));
    for (std::size_t i = 0; i < axis.size(); ++i) axis[i] = grid.lo[a] + static_cast<double>(i) * grid.spacing(a);
    out[py::str(std::string(1, "xyz"[a]))] = array_of({grid.points[a]}, axis.data());
  }
}

}  // namespace sage::python

PYBIND11_MODULE(sage, m) {
  namespace py = pybind11;
  m.doc() =
      "sage: meshfree engineering analysis with R-functions.\n\n"
      "load(path) reads a model (JSON CSG model, GIS polygons GDAL reads, or a closed\n"
      "triangle mesh) into a Model, whose evaluate() and sample() give its normalized\n"
      "field omega and derivatives as numpy arrays; solve(problem) solves a problem\n"
      "file (heat or elasticity) and evaluates the solution at points.\n"
      "Errors: ModelError, ProblemError (bad input, with the file and place), ValueError.";
  py::register_exception<sage::geometry::ModelError>(m, "ModelError", PyExc_ValueError);
  py::register_exception<sage::problems::ProblemError>(m, "ProblemError", PyExc_ValueError);
  py::register_exception<sage::output::OutputError>(m, "OutputError", PyExc_OSError);
  sage::python::bind_models(m);
  sage::python::bind_solve(m);
}
