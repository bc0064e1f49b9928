// Claims of sampling_plan.hpp: sage field's decision how to sample a
// field. Small CSG models are evaluated exactly; a large 2D R0 tree (a
// GIS polygon's field) gets far-field patches within 1e-10 of the grid
// box's diagonal; a mesh's trimmed-face field of 1,024 faces gets far faces
// in single precision at order 0 and 1, not at order 2 nor with 1,023
// faces; a tolerance given is used as it is (0: exact) and turns far faces
// off; the description says which.

#include "test_support.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/expression/trimming.hpp>
#include <sage/sampling/sampling_plan.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage {
namespace {

using Evaluation = SamplingPlan::Evaluation;

Grid grid_over(int dimension, double lo, double hi) {
  Grid grid;
  grid.dimension = dimension;
  grid.lo = {lo, lo, dimension == 3 ? lo : 0.0};
  grid.hi = {hi, hi, dimension == 3 ? hi : 0.0};
  grid.points = {17, 17, dimension == 3 ? 17 : 1};
  return grid;
}

// A GIS polygon's field as polygon_csg builds it: the R0 conjunction of
// many edges' halfplanes (here n tangent to a circle of radius 10).
Tape polygon_tape(int edges) {
  std::vector<Expr> sides;
  for (int i = 0; i < edges; ++i) {
    const double a = 2 * std::numbers::pi * i / edges;
    sides.push_back(halfspace({10 * std::cos(a), 10 * std::sin(a), 0}, {std::cos(a), std::sin(a), 0}, 2));
  }
  return Tape(r_conjunction_n(sides, RSystem::r0()), 2);
}

// A mesh's trimmed-face field as mesh_field.cpp builds it: `faces` small
// triangles (trimming.hpp's triangle_field) glued by R0, each at its own
// height (no plane shared: each face is a fused run of its own).
Tape mesh_tape(int faces) {
  std::vector<Expr> level;
  for (int k = 0; k < faces; ++k) {
    const double x = 0.25 * (k % 32), y = 0.25 * (k / 32), z = 0.001 * k;
    level.push_back(triangle_field({x, y, z}, {x + 0.2, y + 0.05, z}, {x + 0.05, y + 0.2, z}));
  }
  return Tape(r_conjunction_n(level, RSystem::r0()), 3);
}

void expect_exact(const SamplingPlan& plan, bool by_default) {
  EXPECT_EQ(plan.evaluation, Evaluation::Exact);
  EXPECT_EQ(plan.by_default, by_default);
  EXPECT_EQ(plan.relative_tolerance, 0.0);
  EXPECT_EQ(plan.approximation.tolerance, 0.0);
  EXPECT_FALSE(plan.approximation.far_faces);
  EXPECT_EQ(plan.description,
            by_default ? "exact evaluation (far-field patches pay only for 2D R-function fields)" : "exact evaluation");
}

TEST(SamplingPlan, SmallCsgModelsAreSampledExactly) {
  // 3D R0 and 2D min/max: patches do not pay, and there are no mesh faces.
  const Expr solid = r_and(ball({0, 0, 0}, 1, 3), halfspace({0, 0, 0.5}, {0, 0, 1}, 3), RSystem::r0());
  const Expr plate = r_and(ball({0, 0, 0}, 1, 2), halfspace({0, 0.5, 0}, {0, 1, 0}, 2), RSystem::min_max());
  for (int order : {0, 1, 2}) {
    expect_exact(plan_sampling(Tape(solid, 3), grid_over(3, -1.5, 1.5), order), true);
    expect_exact(plan_sampling(Tape(plate, 2), grid_over(2, -1.5, 1.5), order), true);
  }
}

TEST(SamplingPlan, LargeGisFieldsGetFarFieldPatchesWithTheDefaultTolerance) {
  const Tape tape = polygon_tape(512);
  const Grid grid = grid_over(2, -12, 12);
  for (int order = 0; order <= kMaxSampleOrder; ++order) {
    const SamplingPlan plan = plan_sampling(tape, grid, order);
    EXPECT_EQ(plan.evaluation, Evaluation::FarField) << order;
    EXPECT_TRUE(plan.by_default);
    EXPECT_EQ(plan.relative_tolerance, kDefaultFarFieldTolerance);
    EXPECT_DOUBLE_EQ(plan.approximation.tolerance, 1e-10 * 24 * std::sqrt(2.0));
    EXPECT_FALSE(plan.approximation.far_faces);
  }
  EXPECT_EQ(plan_sampling(tape, grid, 1).description,
            "far-field approximation: patches within 1e-10 of the grid box's diagonal (3.39411e-09) each (the default "
            "for 2D R-function fields)");

  // A tolerance given: used as it is, said without "default".
  const SamplingPlan coarser = plan_sampling(tape, grid, 1, 1e-8);
  EXPECT_EQ(coarser.evaluation, Evaluation::FarField);
  EXPECT_FALSE(coarser.by_default);
  EXPECT_EQ(coarser.relative_tolerance, 1e-8);
  EXPECT_DOUBLE_EQ(coarser.approximation.tolerance, 1e-8 * grid.diagonal());
  EXPECT_EQ(coarser.description,
            "far-field approximation: patches within 1e-08 of the grid box's diagonal "
            "(3.39411e-07) each");
}

TEST(SamplingPlan, MeshesOf1024FacesGetFarFacesAtOrderZeroAndOne) {
  const Tape tape = mesh_tape(1024);
  const Grid grid = grid_over(3, -1, 9);
  for (int order : {0, 1}) {
    const SamplingPlan plan = plan_sampling(tape, grid, order);
    EXPECT_EQ(plan.evaluation, Evaluation::FarFaces) << order;
    EXPECT_TRUE(plan.by_default);
    EXPECT_TRUE(plan.approximation.far_faces) << order;
    EXPECT_EQ(plan.approximation.tolerance, 0.0);  // no patches in 3D
    EXPECT_EQ(plan.approximation.far_faces_check_points, 2000u);
    EXPECT_EQ(plan.approximation.far_faces_limit, 1e-9);
    EXPECT_EQ(plan.description,
              "far mesh faces in single precision (clusters farther from a batch of points than their size), checked "
              "against exact evaluation at 2000 grid points: beyond 1e-09 of the grid box's diagonal, sampled again "
              "exactly");
  }
  // Far faces run for values and gradients only; and pay from 1,024 faces.
  for (int order : {2, 3}) expect_exact(plan_sampling(tape, grid, order), true);
  expect_exact(plan_sampling(mesh_tape(1023), grid, 1), true);
}

TEST(SamplingPlan, ToleranceZeroIsExact) {
  expect_exact(plan_sampling(polygon_tape(512), grid_over(2, -12, 12), 1, 0.0), false);
  expect_exact(plan_sampling(mesh_tape(1024), grid_over(3, -1, 9), 1, 0.0), false);
  expect_exact(plan_sampling(mesh_tape(1024), grid_over(3, -1, 9), 0, 0.0), false);
  for (double bad : {-1e-10, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(plan_sampling(polygon_tape(8), grid_over(2, -12, 12), 1, bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace sage
