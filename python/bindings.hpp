#pragma once
// The parts of the Python module `sage` (module.cpp), one file each:
// models and their fields (model_bindings.cpp), solves (solve_bindings.cpp),
// and the numpy conversions they share.

#include <sage/geometry/model.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/tape/tape.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sage::python {

namespace py = pybind11;

void bind_models(py::module_& m);
void bind_solve(py::module_& m);

/// A model and its tape, compiled once for all its evaluations.
struct PyModel {
  geometry::Model model;
  std::shared_ptr<const Tape> tape;
};

/// Models from memory (memory_sources.cpp): GeoJSON (a dict or its text;
/// RFC 7946 means longitude/latitude unless `crs` says otherwise), a WKB
/// geometry (planar unless `crs` is given), vertex and triangle arrays.
geometry::Model model_from_geojson(const py::object& geojson, const std::optional<std::string>& crs,
                                   const std::string& method, bool repair);
geometry::Model model_from_wkb(const py::bytes& wkb, const std::optional<std::string>& crs, const std::string& method,
                               bool repair);
geometry::Model model_from_mesh(const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                                const py::array_t<long long, py::array::c_style | py::array::forcecast>& triangles,
                                const std::string& method);

/// An (n, dimension) float64 array's rows as points (z = 0 in 2D); throws
/// ValueError naming `what` for another shape.
std::vector<std::array<double, 3>> points_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                                             int dimension, const std::string& what);

/// A new float64 array of `shape`, filled from values (C order).
py::array_t<double> array_of(const std::vector<py::ssize_t>& shape, const double* values);

/// The numpy shape of a grid's points, x fastest: (ny, nx) or (nz, ny, nx).
std::vector<py::ssize_t> grid_shape(const Grid& grid);

/// The grid's axes as arrays 'x', 'y' ('z') in `out`.
void add_axes(py::dict& out, const Grid& grid);

}  // namespace sage::python
