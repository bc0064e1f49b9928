// Claims of grid.hpp / field_samples.hpp: resolutions and bounds parse or
// fail with std::invalid_argument; points are numbered x fastest; and
// sample_field gives, at every grid point, the value, gradient, |grad| and
// every higher partial (named by the variables it differentiates, values
// as derivatives not Taylor coefficients) of direct evaluation and of the
// closed form.

#include "test_support.hpp"

#include <sage/expression/formula.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

TEST(Grid, ParseResolution) {
  EXPECT_EQ(Grid::parse_resolution("200x100", 2), (std::array<int, 3>{200, 100, 1}));
  EXPECT_EQ(Grid::parse_resolution("64x32x16", 3), (std::array<int, 3>{64, 32, 16}));
  for (const char* bad :
       {"200", "200x", "x200", "200x200x2", "1x5", "abcx4", "2.5x4", "-4x4", "4x100001", "", "4 x4", "4x4x"})
    EXPECT_THROW(Grid::parse_resolution(bad, 2), std::invalid_argument) << bad;
  for (const char* bad : {"64x64", "64x64x1", "64x64x64x64", "100000x100000x100000"})
    EXPECT_THROW(Grid::parse_resolution(bad, 3), std::invalid_argument) << bad;
  EXPECT_THROW(Grid::parse_resolution("100000x100000", 2), std::invalid_argument);  // 1e10 points
}

TEST(Grid, ParseBounds) {
  std::array<double, 3> lo{}, hi{};
  Grid::parse_bounds("-1,2,-3.5,4e1", 2, lo, hi);
  EXPECT_EQ(lo[0], -1.0);
  EXPECT_EQ(hi[0], 2.0);
  EXPECT_EQ(lo[1], -3.5);
  EXPECT_EQ(hi[1], 40.0);
  Grid::parse_bounds("0,1,0,1,-1,0", 3, lo, hi);
  EXPECT_EQ(lo[2], -1.0);
  EXPECT_EQ(hi[2], 0.0);
  for (const char* bad : {"0,1,0", "0,1,0,1,0,1", "1,0,0,1", "0,0,0,1", "0,a,0,1", "0,1,0,1,", "0,1,,1", "0,inf,0,1",
                          "0,nan,0,1", "0,1x,0,1", ""})
    EXPECT_THROW(Grid::parse_bounds(bad, 2, lo, hi), std::invalid_argument) << bad;
  EXPECT_THROW(Grid::parse_bounds("0,1,0,1", 3, lo, hi), std::invalid_argument);
}

TEST(Grid, PointNumberingIsXFastest) {
  Grid g;
  g.dimension = 3;
  g.lo = {-1, 0, 2};
  g.hi = {1, 3, 4};
  g.points = {3, 4, 5};
  ASSERT_EQ(g.size(), 60u);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        const auto p = g.point(static_cast<std::size_t>(i + 3 * (j + 4 * k)));
        EXPECT_DOUBLE_EQ(p[0], -1 + i * 1.0);
        EXPECT_DOUBLE_EQ(p[1], 0 + j * 1.0);
        EXPECT_DOUBLE_EQ(p[2], 2 + k * 0.5);
      }
  // The last point is the upper corner.
  const auto last = g.point(g.size() - 1);
  EXPECT_DOUBLE_EQ(last[0], 1.0);
  EXPECT_DOUBLE_EQ(last[1], 3.0);
  EXPECT_DOUBLE_EQ(last[2], 4.0);
}

TEST(FieldSamples, MatchesDirectEvaluationAndClosedForm2D) {
  // f = x^3 y^2 + sin(x): partials in closed form.
  const Expr f = parse_formula("x^3 * y^2 + sin(x)", 2);
  const Tape tape(f, 2);
  Grid g;
  g.dimension = 2;
  g.lo = {-1, -2, 0};
  g.hi = {2, 1, 0};
  g.points = {13, 11, 1};
  const FieldSamples s = sample_field(tape, g, 4);
  ASSERT_EQ(s.omega.size(), g.size());
  ASSERT_EQ(s.gradient.size(), 3 * g.size());
  ASSERT_EQ(s.higher.size(), 3u);  // orders 2, 3, 4
  EXPECT_EQ(s.higher[0].components, (std::vector<std::string>{"xx", "xy", "yy"}));
  EXPECT_EQ(s.higher[1].components, (std::vector<std::string>{"xxx", "xxy", "xyy", "yyy"}));
  EXPECT_EQ(s.higher[2].components, (std::vector<std::string>{"xxxx", "xxxy", "xxyy", "xyyy", "yyyy"}));
  Evaluator<double> ev(tape);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto p = g.point(i);
    const double x = p[0], y = p[1];
    EXPECT_EQ(s.omega[i], ev.at(p));
    const double fx = 3 * x * x * y * y + std::cos(x), fy = 2 * x * x * x * y;
    EXPECT_NEAR(s.gradient[3 * i], fx, 1e-13);
    EXPECT_NEAR(s.gradient[3 * i + 1], fy, 1e-13);
    EXPECT_EQ(s.gradient[3 * i + 2], 0.0);
    EXPECT_NEAR(s.gradient_norm[i], std::hypot(fx, fy), 1e-13);
    const std::vector<double> d2 = {6 * x * y * y - std::sin(x), 6 * x * x * y, 2 * x * x * x};
    const std::vector<double> d3 = {6 * y * y - std::cos(x), 12 * x * y, 6 * x * x, 0};
    const std::vector<double> d4 = {std::sin(x), 12 * y, 12 * x, 0, 0};
    const std::vector<const std::vector<double>*> want = {&d2, &d3, &d4};
    for (int k = 0; k < 3; ++k) {
      const auto& arr = s.higher[static_cast<std::size_t>(k)];
      EXPECT_EQ(arr.order, k + 2);
      const std::size_t m = arr.components.size();
      ASSERT_EQ(arr.values.size(), m * g.size());
      for (std::size_t c = 0; c < m; ++c) EXPECT_NEAR(arr.values[i * m + c], (*want[k])[c], 1e-12) << arr.components[c];
    }
  }
}

TEST(FieldSamples, MatchesDirectEvaluation3DAndComponentNames) {
  const Expr f = parse_formula("exp(x - 2*y) * cos(z) + x*y*z", 3);
  const Tape tape(f, 3);
  Grid g;
  g.dimension = 3;
  g.lo = {-1, -1, -1};
  g.hi = {1, 1, 1};
  g.points = {7, 6, 5};
  const FieldSamples s = sample_field(tape, g, 3);
  ASSERT_EQ(s.higher.size(), 2u);
  EXPECT_EQ(s.higher[0].components, (std::vector<std::string>{"xx", "xy", "xz", "yy", "yz", "zz"}));
  EXPECT_EQ(s.higher[1].components,
            (std::vector<std::string>{"xxx", "xxy", "xxz", "xyy", "xyz", "xzz", "yyy", "yyz", "yzz", "zzz"}));
  Evaluator<Tuple<3, 3>> ev(tape);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto p = g.point(i);
    const auto t = ev.at(p);
    EXPECT_EQ(s.omega[i], t.value());
    for (int v = 0; v < 3; ++v) EXPECT_EQ(s.gradient[3 * i + static_cast<std::size_t>(v)], t.gradient()[v]);
    // xyz component: d3/dxdydz of e^(x-2y) cos z + xyz = 2 e^(x-2y) sin z + 1.
    const auto& a3 = s.higher[1];
    EXPECT_NEAR(a3.values[i * 10 + 4], 2 * std::exp(p[0] - 2 * p[1]) * std::sin(p[2]) + 1, 1e-12);
    // zz: -e^(x-2y) cos z; yy: 4 e^(x-2y) cos z.
    const double e = std::exp(p[0] - 2 * p[1]);
    EXPECT_NEAR(s.higher[0].values[i * 6 + 5], -e * std::cos(p[2]), 1e-12);
    EXPECT_NEAR(s.higher[0].values[i * 6 + 3], 4 * e * std::cos(p[2]), 1e-12);
  }
}

TEST(FieldSamples, OrdersZeroAndOneHaveNoHigherArraysAndErrorsThrow) {
  const Tape tape(parse_formula("x + y", 2), 2);
  Grid g;
  g.dimension = 2;
  g.points = {4, 4, 1};
  const FieldSamples s = sample_field(tape, g, 1);
  EXPECT_TRUE(s.higher.empty());
  for (double n : s.gradient_norm) EXPECT_NEAR(n, std::sqrt(2.0), 1e-15);
  EXPECT_THROW(sample_field(tape, g, -1), std::invalid_argument);
  EXPECT_THROW(sample_field(tape, g, kMaxSampleOrder + 1), std::invalid_argument);
  // Order 0: values only, the same values.
  const FieldSamples values = sample_field(tape, g, 0);
  EXPECT_TRUE(values.gradient.empty() && values.gradient_norm.empty() && values.higher.empty());
  ASSERT_EQ(values.omega.size(), s.omega.size());
  for (std::size_t i = 0; i < s.omega.size(); ++i) EXPECT_EQ(values.omega[i], s.omega[i]);
  Grid g3 = g;
  g3.dimension = 3;
  g3.points = {2, 2, 2};
  EXPECT_THROW(sample_field(tape, g3, 1), std::invalid_argument);
  // Order 6 (the maximum) works and has orders 2..6.
  EXPECT_EQ(sample_field(tape, g, kMaxSampleOrder).higher.size(), static_cast<std::size_t>(kMaxSampleOrder - 1));
  // Progress reaches 1.
  double last = 0;
  sample_field(tape, g, 2, [&](double f) { last = f; });
  EXPECT_EQ(last, 1.0);
}

}  // namespace
}  // namespace sage

// Interval evaluation over grid cells encloses the field at points inside
// each cell, and cells whose interval excludes 0 hold no boundary.
TEST(GridCells, IntervalsEncloseSampledValuesInEveryCell) {
  sage::Grid grid;
  grid.dimension = 2;
  grid.lo = {-1.3, -1.1, 0};
  grid.hi = {1.2, 1.4, 0};
  grid.points = {12, 9, 1};
  const sage::Expr f =
      sage::r_and(sage::parse_formula("1 - x^2 - y^2", 2), sage::parse_formula("x + 0.3", 2), sage::RSystem::r_p(4));
  const sage::Tape tape(f, 2);
  std::vector<sage::Interval> ranges(grid.cell_count());
  ASSERT_EQ(ranges.size(), 11u * 8u);
  sage::for_each_grid_cell(tape, grid,
                           [&](std::size_t c, const sage::Evaluator<sage::Interval>& e) { ranges[c] = e.result(); });
  sage::Evaluator<double> eval(tape);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int proven_empty = 0;
  for (std::size_t c = 0; c < ranges.size(); ++c) {
    const auto box = grid.cell(c);
    proven_empty += !ranges[c].contains_zero();
    for (int k = 0; k < 50; ++k) {
      const double x = box[0].lo + u(rng) * box[0].width(), y = box[1].lo + u(rng) * box[1].width();
      const double v = eval.at({x, y, 0});
      EXPECT_TRUE(ranges[c].contains(v)) << "cell " << c << " at (" << x << ", " << y << ")";
    }
  }
  EXPECT_GT(proven_empty, 0);
}
