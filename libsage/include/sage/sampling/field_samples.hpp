#pragma once
// Sampling a field and its derivatives on a grid, ready to write out.
//
// omega:     value at each point
// gradient:  3 components per point (z = 0 in 2D, so viewers can draw
//            glyphs), in point order; empty at order 0 (values only)
// gradient_norm: |grad omega|; empty at order 0
// higher:    one array per order 2..K; components are the partials of that
//            order in the graded layout of multi_index.hpp, named by the
//            variables they differentiate ("xx", "xy", "yy", ...).
//            Values are derivatives, not Taylor coefficients.

#include <sage/sampling/grid.hpp>
#include <sage/tape/tape.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <array>
#include <string>
#include <vector>

namespace sage {

struct DerivativeArray {
  int order = 2;
  std::vector<std::string> components;
  std::vector<double> values;  // components.size() per point
};

struct FieldSamples {
  Grid grid;
  int order = 1;
  // How the samples were made, written beside them as field data: 0 for
  // exact evaluation, else the far-field tolerance (field units).
  double far_field_tolerance = 0;
  // Whether mesh faces far from the points ran in single precision
  // (far_faces.hpp), and the largest deviation from exact evaluation
  // measured at sample points, relative to the grid box's diagonal; if it
  // was beyond the limit, far_faces is false again (the samples are
  // exact) and far_faces_rejected true.
  bool far_faces = false;
  bool far_faces_rejected = false;
  double far_faces_deviation = 0;
  std::vector<double> omega;
  std::vector<double> gradient;
  std::vector<double> gradient_norm;
  std::vector<DerivativeArray> higher;
};

constexpr int kMaxSampleOrder = 6;

/// The far-field tolerance `sage field` samples with where patches pay
/// (far_field_pays in tape/far_field.hpp; plan_sampling in
/// sampling_plan.hpp decides), as a fraction of the grid box's diagonal.
/// far_field_bench measures it: up to 6 times faster at 1000^2 on
/// polygons, the whole field within 3.2e-10, no sign changed.
constexpr double kDefaultFarFieldTolerance = 1e-10;

/// Evaluates root 0 of `tape` with tuples of `order` (0..kMaxSampleOrder)
/// at every point of `grid`, on all cores: exactly (interval pruning keeps
/// every bit), or with far-field patches when `approximation` is given
/// with a positive tolerance (pruned_grid.hpp).
FieldSamples sample_field(const Tape& tape, const Grid& grid, int order, const Progress& progress = {},
                          const Approximation* approximation = nullptr);

/// The same arrays at a list of points (the tape's dimension of
/// coordinates each, the rest ignored), in their order, on all cores:
/// groups of nearby points run the tape pruned to their box
/// (pruned_points.hpp). Exactly without `approximation` (the numbers
/// sample_field gives exactly at a grid point that is one of them, bit for
/// bit); with one, far-field patches as sample_field's (plan them with
/// plan_points in sampling_plan.hpp). Far mesh faces run exactly. `grid`
/// is left empty.
FieldSamples sample_points(const Tape& tape, const std::vector<std::array<double, 3>>& points, int order,
                           const Approximation* approximation = nullptr);

}  // namespace sage
