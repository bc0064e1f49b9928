#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/far_faces.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sage {

namespace {

std::string describe(const SamplingPlan& plan, const char* box = "the grid box") {
  std::ostringstream text;
  switch (plan.evaluation) {
    case SamplingPlan::Evaluation::FarField:
      text << "far-field approximation: patches within " << plan.relative_tolerance << " of " << box << "'s diagonal ("
           << plan.approximation.tolerance << ") each"
           << (plan.by_default ? " (the default for 2D R-function fields)" : "");
      break;
    case SamplingPlan::Evaluation::FarFaces:
      text << "far mesh faces in single precision (clusters farther from a batch of points than their size), "
           << "checked against exact evaluation at " << plan.approximation.far_faces_check_points
           << " grid points: beyond " << plan.approximation.far_faces_limit
           << " of the grid box's diagonal, sampled again exactly";
      break;
    case SamplingPlan::Evaluation::Exact:
      text << "exact evaluation" << (plan.by_default ? " (far-field patches pay only for 2D R-function fields)" : "");
      break;
  }
  return text.str();
}

}  // namespace

SamplingPlan plan_sampling(const Tape& tape, const Grid& grid, int order, std::optional<double> tolerance) {
  if (tolerance && !(*tolerance >= 0 && std::isfinite(*tolerance)))
    throw std::invalid_argument("the far-field tolerance must be finite and at least 0 (0: exact)");
  SamplingPlan plan;
  plan.by_default = !tolerance;
  plan.relative_tolerance = tolerance.value_or(far_field_pays(tape) ? kDefaultFarFieldTolerance : 0.0);
  plan.approximation.tolerance = plan.relative_tolerance * grid.diagonal();
  // Far faces run for values and gradients (order 0 and 1) only.
  plan.approximation.far_faces = !tolerance && order <= 1 && far_faces_pay(tape);
  plan.evaluation = plan.approximation.tolerance > 0 ? SamplingPlan::Evaluation::FarField
                    : plan.approximation.far_faces   ? SamplingPlan::Evaluation::FarFaces
                                                     : SamplingPlan::Evaluation::Exact;
  plan.description = describe(plan);
  return plan;
}

SamplingPlan plan_points(const Tape& tape, const std::vector<std::array<double, 3>>& points, int order,
                         std::optional<double> tolerance) {
  Grid box;
  box.dimension = tape.dimension();
  if (!points.empty()) {
    box.lo = box.hi = points.front();
    for (const auto& p : points)
      for (int a = 0; a < box.dimension; ++a) {
        box.lo[a] = std::min(box.lo[a], p[a]);
        box.hi[a] = std::max(box.hi[a], p[a]);
      }
  }
  SamplingPlan plan = plan_sampling(tape, box, order, tolerance);
  plan.approximation.far_faces = false;  // their check samples grid points: points run faces exactly
  plan.evaluation =
      plan.approximation.tolerance > 0 ? SamplingPlan::Evaluation::FarField : SamplingPlan::Evaluation::Exact;
  plan.description = describe(plan, "the points' bounding box");
  return plan;
}

}  // namespace sage
