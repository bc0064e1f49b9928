#pragma once
// How to sample a field: `sage field`'s decision, made here once for every
// caller (the CLI's field and info commands, examples, benches, bindings).
//
// Without a tolerance from the user, sage picks what pays: far-field
// patches within kDefaultFarFieldTolerance of the grid box's diagonal for
// 2D R-function fields (far_field_pays), far mesh faces in single
// precision, checked against exact evaluation, for meshes' trimmed-face
// fields of 1,024 faces and more at order 0 and 1 (far_faces_pay), else
// exact evaluation. A tolerance given is used as it is (0: exact), and
// turns far faces off.

#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/tape/tape.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace sage {

struct SamplingPlan {
  enum class Evaluation { Exact, FarField, FarFaces };
  Evaluation evaluation = Evaluation::Exact;
  bool by_default = true;         // no tolerance was given: sage chose
  double relative_tolerance = 0;  // far-field patches: of the grid box's diagonal; else 0
  // For sample_field: tolerance = relative_tolerance * the grid box's
  // diagonal (field units), far_faces with its check (far_faces_limit at
  // far_faces_check_points grid points).
  Approximation approximation;
  // One line saying what the plan does, e.g. "far-field approximation:
  // patches within 1e-10 of the grid box's diagonal (0.0213) each (the
  // default for 2D R-function fields)"; `sage field` and `sage info`
  // print it.
  std::string description;
};

/// The plan for sampling root 0 of `tape` on `grid` with tuples of `order`:
/// sage's default without `tolerance`, else far-field patches within
/// `tolerance` of the grid box's diagonal (0: exact evaluation). Throws
/// std::invalid_argument for a negative or non-finite tolerance.
SamplingPlan plan_sampling(const Tape& tape, const Grid& grid, int order,
                           std::optional<double> tolerance = std::nullopt);

/// The same for scattered points (sample_points): the tolerance relative to
/// the diagonal of their bounding box; far mesh faces never (exact).
SamplingPlan plan_points(const Tape& tape, const std::vector<std::array<double, 3>>& points, int order,
                         std::optional<double> tolerance = std::nullopt);

}  // namespace sage
