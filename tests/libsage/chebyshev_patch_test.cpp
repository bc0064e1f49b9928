// Chebyshev patches and far-field approximation: polynomials are fitted
// exactly; analytic fields within the stated tail; kinks are refused;
// interval evaluation encloses the patch; tuples give the patch's exact
// derivatives, also a grid row or a batch of scattered points at a time; fits right at their tail pass;
// and approximated grid sampling of a large R0 tree stays
// within its tolerance of exact evaluation, with far boxes reduced to a
// single patch.

#include "test_support.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/expression/trimming.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/pruned_grid.hpp>
#include <sage/tape/chebyshev_patch.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <gtest/gtest.h>

#include <numbers>

namespace sage {
namespace {

using Box = std::array<Interval, 3>;

std::shared_ptr<const ChebyshevPatch> fit_function(const Box& box, int n, double tolerance,
                                                   const std::function<double(double, double)>& f) {
  std::vector<double> values((n + 1) * (n + 1));
  for (std::size_t k = 0; k < values.size(); ++k) {
    const auto p = ChebyshevPatch::sample_point(box.data(), 2, n, k);
    values[k] = f(p[0], p[1]);
  }
  return ChebyshevPatch::fit(box.data(), 2, n, values, tolerance);
}

TEST(ChebyshevPatch, OneDimensionalWorkedExample) {
  // x^2 on [-1, 1] = (T0 + T2) / 2, from the header's example (sampled
  // with n = 4 here: fits go up to degree n - 2).
  const Box box{Interval(-1, 1), Interval(0.0), Interval(0.0)};
  std::vector<double> values(5);
  for (std::size_t k = 0; k < 5; ++k) values[k] = std::pow(ChebyshevPatch::sample_point(box.data(), 1, 4, k)[0], 2);
  const auto patch = ChebyshevPatch::fit(box.data(), 1, 4, values, 1e-14);
  ASSERT_TRUE(patch);
  EXPECT_EQ(patch->degree(), 2);
  const double x = 0.3;
  EXPECT_NEAR(patch->evaluate(&x), 0.09, 1e-15);
}

TEST(ChebyshevPatch, ReproducesPolynomialsWithTheirDerivatives) {
  auto f = [](double x, double y) { return x * x + 3 * x * y - y * y * y + 1; };
  const Box box{Interval(1, 3), Interval(-2, 0), Interval(0.0)};
  const auto patch = fit_function(box, 8, 1e-11, f);
  ASSERT_TRUE(patch);
  EXPECT_EQ(patch->degree(), 3);
  auto rng = test::make_rng(3);
  for (int k = 0; k < 200; ++k) {
    const double x = test::uniform(rng, 1, 3), y = test::uniform(rng, -2, 0);
    const Tuple<2, 2> vars[2] = {Tuple<2, 2>::variable(0, x), Tuple<2, 2>::variable(1, y)};
    const Tuple<2, 2> t = patch->evaluate(vars);
    EXPECT_NEAR(t.value(), f(x, y), 1e-12);
    EXPECT_NEAR(t.derivative({1, 0}), 2 * x + 3 * y, 1e-11);
    EXPECT_NEAR(t.derivative({0, 1}), 3 * x - 3 * y * y, 1e-11);
    EXPECT_NEAR(t.derivative({1, 1}), 3.0, 1e-10);
    EXPECT_NEAR(t.derivative({0, 2}), -6 * y, 1e-10);
  }
}

TEST(ChebyshevPatch, AnalyticFieldsWithinTheirTail) {
  // A distance-like field whose nearest singularity (the corner of an R0
  // wedge at the origin) is 8 half-widths from the box centre.
  auto f = [](double x, double y) { return x + y - std::hypot(x, y); };
  const Box box{Interval(3.5, 4.5), Interval(-0.5, 0.5), Interval(0.0)};
  for (double tolerance : {1e-6, 1e-8, 1e-10}) {
    const auto patch = fit_function(box, 12, tolerance, f);
    ASSERT_TRUE(patch) << tolerance;
    auto rng = test::make_rng(4);
    double worst = 0;
    for (int k = 0; k < 2000; ++k) {
      const double p[2] = {test::uniform(rng, 3.5, 4.5), test::uniform(rng, -0.5, 0.5)};
      worst = std::max(worst, std::abs(patch->evaluate(p) - f(p[0], p[1])));
    }
    EXPECT_LE(worst, tolerance) << "degree " << patch->degree();
    EXPECT_LE(worst, 10 * patch->tail() + 1e-14) << "the tail is an honest error estimate";
  }
}

// A box of `dimension` axes of different widths.
Box test_box(int dimension) {
  Box box{Interval(0.0), Interval(0.0), Interval(0.0)};
  for (int a = 0; a < dimension; ++a) box[a] = Interval(-1.0 + 0.5 * a, 1.5 + a);
  return box;
}

// A patch of `field` over the box (sampling degree 10).
std::shared_ptr<const ChebyshevPatch> fit_field(const Box& box, int dimension, double tolerance,
                                                const std::function<double(const std::array<double, 3>&)>& field) {
  const int n = 10;
  std::size_t samples = 1;
  for (int a = 0; a < dimension; ++a) samples *= n + 1;
  std::vector<double> values(samples);
  for (std::size_t k = 0; k < samples; ++k)
    values[k] = field(ChebyshevPatch::sample_point(box.data(), dimension, n, k));
  return ChebyshevPatch::fit(box.data(), dimension, n, values, tolerance);
}

// A smooth field's patch with tail 1e-3.
std::shared_ptr<const ChebyshevPatch> fit_smooth(const Box& box, int dimension) {
  return fit_field(box, dimension, 1e-3, [](const std::array<double, 3>& p) {
    return std::exp(0.3 * p[0]) * std::cos(p[1] + 0.5 * p[2]) + p[0] * p[1];
  });
}

// Grid sampling asks patches for value and gradient (first-order tuples),
// which take a path of their own: the series and its partials in doubles.
// It must agree with the general tuple path, and through the chain rule
// also for inputs that are not the coordinates themselves.
TEST(ChebyshevPatch, FirstOrderTuplesMatchTheGeneralPath) {
  auto rng = test::make_rng(11);
  for (int dimension = 1; dimension <= 3; ++dimension) {
    const Box box = test_box(dimension);
    const auto patch = fit_smooth(box, dimension);
    ASSERT_TRUE(patch);
    ASSERT_GE(patch->degree(), 3);
    for (int trial = 0; trial < 100; ++trial) {
      // Inputs u_a(s, t) = p_a + s + a t + s t: tuples in two other variables.
      const double s = test::uniform(rng, -0.1, 0.1), t = test::uniform(rng, -0.1, 0.1);
      Tuple<2, 1> fast[3];
      Tuple<2, 2> general[3];
      double point[3];
      for (int a = 0; a < dimension; ++a) {
        const double centre = test::uniform(rng, box[a].lo + 0.3, box[a].hi - 0.3);
        auto input = [&](auto sv, auto tv) { return centre + sv + static_cast<double>(a) * tv + sv * tv; };
        fast[a] = input(Tuple<2, 1>::variable(0, s), Tuple<2, 1>::variable(1, t));
        general[a] = input(Tuple<2, 2>::variable(0, s), Tuple<2, 2>::variable(1, t));
        point[a] = fast[a].value();
      }
      const Tuple<2, 1> a = patch->evaluate(fast);
      const Tuple<2, 2> b = patch->evaluate(general);
      EXPECT_EQ(a.value(), patch->evaluate(point)) << "the value is evaluate<double>'s, bit for bit";
      EXPECT_NEAR(a.value(), b.value(), 1e-12);
      EXPECT_NEAR(a.derivative({1, 0}), b.derivative({1, 0}), 1e-11);
      EXPECT_NEAR(a.derivative({0, 1}), b.derivative({0, 1}), 1e-11);
    }
  }
}

// evaluate_rows() is evaluate() at each point of the tensor grid, bit for
// bit, in doubles and in first-order tuples (whose variables here carry a
// gradient other than the unit seeds), with rows longer than its chunks.
template <int N>
void expect_rows_match_points(const ChebyshevPatch& patch, const Box& box, std::uint64_t seed, std::size_t row_count) {
  auto rng = test::make_rng(seed);
  std::vector<double> xs(70);  // more than one pass of 64
  for (double& x : xs) x = test::uniform(rng, box[0].lo, box[0].hi);
  std::vector<std::array<double, 2>> rows(row_count);
  for (auto& row : rows) row = {test::uniform(rng, box[1].lo, box[1].hi), test::uniform(rng, box[2].lo, box[2].hi)};
  const std::size_t count = xs.size() * rows.size();
  // Tuples stored by component, as BatchEvaluator keeps them.
  std::vector<double> var_storage[3], out_storage((N + 1) * count);
  std::vector<double> values(count);
  std::array<ConstTupleLanes<Tuple<N, 1>>, 3> vars{};
  for (int a = 0; a < N; ++a) {
    var_storage[a].resize((N + 1) * count);
    const TupleLanes<Tuple<N, 1>> lanes{var_storage[a].data(), count};
    for (std::size_t p = 0; p < count; ++p) {
      const double coordinates[3] = {xs[p % xs.size()], rows[p / xs.size()][0], rows[p / xs.size()][1]};
      auto var = Tuple<N, 1>::variable(a, coordinates[a]);
      var.c[1] += 0.25 * (a + 1);  // a gradient that is not a unit seed
      lanes.store(p, var);
    }
    vars[a] = lanes;
  }
  const TupleLanes<Tuple<N, 1>> out{out_storage.data(), count};
  patch.evaluate_rows(xs.data(), xs.size(), rows.data(), rows.size(), vars.data(), out);
  patch.evaluate_rows(xs.data(), xs.size(), rows.data(), rows.size(), values.data());
  for (std::size_t p = 0; p < count; ++p) {
    Tuple<N, 1> point[N];
    double coordinates[N];
    for (int a = 0; a < N; ++a) point[a] = vars[a].load(p), coordinates[a] = point[a].value();
    const Tuple<N, 1> expected = patch.evaluate(point);
    const Tuple<N, 1> got = out.load(p);
    for (int c = 0; c <= N; ++c) ASSERT_EQ(got.c[c], expected.c[c]) << "point " << p << " coefficient " << c;
    ASSERT_EQ(values[p], patch.evaluate(coordinates)) << "point " << p;
  }
}

TEST(ChebyshevPatch, RowsMatchPointByPoint) {
  for (int dimension = 1; dimension <= 3; ++dimension) {
    const Box box = test_box(dimension);
    const auto patch = fit_smooth(box, dimension);
    ASSERT_TRUE(patch);
    ASSERT_GE(patch->degree(), 3);
    // Rows are summed in blocks of 4 and passes of 64: 7 and 70 rows end
    // inside both.
    for (std::size_t rows : {std::size_t{1}, std::size_t{7}, std::size_t{70}}) {
      SCOPED_TRACE(rows);
      if (dimension == 1) expect_rows_match_points<1>(*patch, box, 21, rows);
      if (dimension == 2) expect_rows_match_points<2>(*patch, box, 22, rows);
      if (dimension == 3) expect_rows_match_points<3>(*patch, box, 23, rows);
    }
  }
}

// evaluate_points() is evaluate() at each scattered point, bit for bit, in
// doubles and first-order tuples, over more than one pass of 64 lanes, also
// when it writes over its first variable (as a batch's register may).
template <int N>
void expect_scattered_match_points(const ChebyshevPatch& patch, const Box& box, std::uint64_t seed, std::size_t count) {
  auto rng = test::make_rng(seed);
  std::vector<double> var_storage[3], out_storage((N + 1) * count), values(count);
  std::array<ConstTupleLanes<Tuple<N, 1>>, 3> vars{};
  const double* coordinates[3] = {};
  for (int a = 0; a < N; ++a) {
    var_storage[a].resize((N + 1) * count);
    const TupleLanes<Tuple<N, 1>> lanes{var_storage[a].data(), count};
    for (std::size_t p = 0; p < count; ++p) {
      auto var = Tuple<N, 1>::variable(a, test::uniform(rng, box[a].lo, box[a].hi));
      var.c[1] += 0.25 * (a + 1);  // a gradient that is not a unit seed
      lanes.store(p, var);
    }
    vars[a] = lanes;
    coordinates[a] = var_storage[a].data();  // component 0: the values
  }
  std::vector<Tuple<N, 1>> expected(count);
  std::vector<double> expected_values(count);
  for (std::size_t p = 0; p < count; ++p) {
    Tuple<N, 1> point[N];
    double at[N];
    for (int a = 0; a < N; ++a) point[a] = vars[a].load(p), at[a] = point[a].value();
    expected[p] = patch.evaluate(point);
    expected_values[p] = patch.evaluate(at);
  }
  const TupleLanes<Tuple<N, 1>> out{out_storage.data(), count};
  patch.evaluate_points(count, vars.data(), out);
  patch.evaluate_points(coordinates, count, values.data());
  for (std::size_t p = 0; p < count; ++p) {
    const Tuple<N, 1> got = out.load(p);
    for (int c = 0; c <= N; ++c) ASSERT_EQ(got.c[c], expected[p].c[c]) << "point " << p << " coefficient " << c;
    ASSERT_EQ(values[p], expected_values[p]) << "point " << p;
  }
  // Over the first variable, in doubles and in tuples.
  std::vector<double> x(coordinates[0], coordinates[0] + count);
  const double* over_x[3] = {x.data(), coordinates[1], coordinates[2]};
  patch.evaluate_points(over_x, count, x.data());
  EXPECT_EQ(x, expected_values);
  patch.evaluate_points(count, vars.data(), TupleLanes<Tuple<N, 1>>{var_storage[0].data(), count});
  for (std::size_t p = 0; p < count; ++p)
    for (int c = 0; c <= N; ++c) ASSERT_EQ(vars[0].load(p).c[c], expected[p].c[c]) << "point " << p;
}

TEST(ChebyshevPatch, ScatteredPointsMatchPointByPoint) {
  for (int dimension = 1; dimension <= 3; ++dimension) {
    const Box box = test_box(dimension);
    const auto patch = fit_smooth(box, dimension);
    ASSERT_TRUE(patch);
    for (std::size_t count : {std::size_t{1}, std::size_t{7}, std::size_t{130}}) {
      SCOPED_TRACE(count);
      if (dimension == 1) expect_scattered_match_points<1>(*patch, box, 31, count);
      if (dimension == 2) expect_scattered_match_points<2>(*patch, box, 32, count);
      if (dimension == 3) expect_scattered_match_points<3>(*patch, box, 33, count);
    }
  }
}

TEST(ChebyshevPatch, FitsRightAtTheirTailAreAccepted) {
  // fit() first refuses samples whose interpolant along some line of nodes
  // has a tail over the tolerance, a lower bound of the fit's own tail. It
  // must never refuse a fit that passes: here at the edge, where the
  // tolerance is the tail of the highest degree allowed, n - 2 = 8, of a
  // field with a pole near the box (a tail far above rounding).
  auto near_pole = [](const std::array<double, 3>& p) { return 1.0 / (4.0 - p[0] - 0.5 * p[1] - 0.25 * p[2]); };
  for (int dimension = 1; dimension <= 3; ++dimension) {
    SCOPED_TRACE(dimension);
    const Box box = test_box(dimension);
    std::shared_ptr<const ChebyshevPatch> tight;
    for (double tolerance = 1e-1; tolerance > 1e-16; tolerance /= 2) {
      tight = fit_field(box, dimension, tolerance, near_pole);
      if (!tight || tight->degree() == 8) break;
    }
    ASSERT_TRUE(tight && tight->degree() == 8) << "a tolerance that needs degree 8";
    const double tail = tight->tail();
    ASSERT_GT(tail, 1e-8);
    const auto at_edge = fit_field(box, dimension, tail, near_pole);
    ASSERT_TRUE(at_edge);
    EXPECT_EQ(at_edge->degree(), 8);
    EXPECT_EQ(at_edge->tail(), tail);
    EXPECT_FALSE(fit_field(box, dimension, tail * (1 - 1e-12), near_pole)) << "just below the tail, none passes";
  }
}

TEST(ChebyshevPatch, RefusesKinksAndNonFiniteSamples) {
  const Box box{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  EXPECT_FALSE(fit_function(box, 12, 1e-6, [](double x, double) { return std::abs(x); }));
  EXPECT_FALSE(fit_function(box, 12, 1e-6, [](double x, double y) { return std::min(x, y); }));
  EXPECT_FALSE(fit_function(box, 12, 1e-6, [](double x, double) { return x > 0.9 ? NAN : x; }));
  const Box flat{Interval(-1, 1), Interval(2.0), Interval(0.0)};
  EXPECT_FALSE(fit_function(flat, 12, 1e-6, [](double x, double) { return x; }));
}

TEST(ChebyshevPatch, IntervalsEncloseThePatch) {
  auto f = [](double x, double y) { return std::exp(x) * std::sin(3 * y) + x * y; };
  const Box box{Interval(-1, 2), Interval(0, 1), Interval(0.0)};
  const auto patch = fit_function(box, 12, 1e-4, f);
  ASSERT_TRUE(patch);
  auto rng = test::make_rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const double x = test::uniform(rng, -1, 1.5), y = test::uniform(rng, 0, 0.8);
    const double wx = test::uniform(rng, 0, 0.5), wy = test::uniform(rng, 0, 0.2);
    const Interval sub[2] = {Interval(x, x + wx), Interval(y, y + wy)};
    const Interval range = patch->evaluate(sub);
    for (int k = 0; k < 20; ++k) {
      const double p[2] = {x + test::uniform(rng, 0, wx), y + test::uniform(rng, 0, wy)};
      EXPECT_TRUE(range.contains(patch->evaluate(p)));
    }
  }
}

// The R0 intersection of n halfplanes tangent to a circle of radius 10:
// a regular n-gon, a balanced tree of n - 1 R0 nodes that pruning cannot
// touch (every node depends on both arguments everywhere).
Expr polygon_r0(int n) {
  std::vector<Expr> sides;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    sides.push_back(halfspace({10 * std::cos(a), 10 * std::sin(a), 0}, {std::cos(a), std::sin(a), 0}, 2));
  }
  return r_conjunction_n(sides, RSystem::r0());
}

TEST(FarFieldApproximation, FarBoxesBecomeOnePatchAndNearBoxesKeepTheirEdges) {
  const Tape tape(polygon_r0(256), 2);
  TapeSpecializer specializer(tape);
  Approximation settings;
  settings.tolerance = 1e-9;
  // A box near the centre: the whole field is analytic there.
  const Box centre{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  const std::optional<Tape> far = specializer.approximate(centre.data(), settings);
  ASSERT_TRUE(far);
  ASSERT_EQ(far->code().size(), 1u);
  EXPECT_EQ(far->code()[0].op, Op::Patch);
  // A box on the boundary: shorter, with patches, and the same field. (The
  // edges whose lines cross the enlarged box stay: interval arithmetic
  // cannot tell that their R0 nodes' corners lie far away.)
  const Box edge{Interval(9.5, 10.5), Interval(-0.5, 0.5), Interval(0.0)};
  const std::optional<Tape> near = specializer.approximate(edge.data(), settings);
  ASSERT_TRUE(near);
  EXPECT_LT(near->code().size(), tape.code().size() / 3);
  std::size_t patches = 0;
  for (const Instruction& ins : near->code()) patches += ins.op == Op::Patch;
  EXPECT_GT(patches, 0u);
  auto rng = test::make_rng(6);
  for (const Box* box : {&centre, &edge}) {
    const Tape& part = box == &centre ? *far : *near;
    Evaluator<Tuple<2, 1>> exact(tape), approximate(part);
    for (int k = 0; k < 500; ++k) {
      const test::Point p{test::uniform(rng, (*box)[0].lo, (*box)[0].hi),
                          test::uniform(rng, (*box)[1].lo, (*box)[1].hi), 0};
      const auto a = exact.at(p), b = approximate.at(p);
      EXPECT_NEAR(a.value(), b.value(), settings.tolerance);  // measured 1.9e-10
      EXPECT_NEAR(a.c[1], b.c[1], 1e-6);
      EXPECT_NEAR(a.c[2], b.c[2], 1e-6);
    }
  }
}

std::size_t count_op(const Tape& tape, Op op) {
  std::size_t n = 0;
  for (const Instruction& ins : tape.code()) n += ins.op == op;
  return n;
}

// An R0 node is singular only where both arguments vanish. Two lines that
// pass within the enlarged box but cross far outside it leave the node
// analytic there (the first-order corner estimate sees that; the distance
// to the nearer of the two lines would not), and lines crossing in the
// box do not.
TEST(FarFieldApproximation, CornersFarAwayAreAnalyticEvenWhenBothLinesPassClose) {
  const Expr x = Expr::x(), y = Expr::y();
  const Box box{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  Approximation settings;
  settings.enlargement = 3;  // reach: 3 half-diagonals, 4.24
  settings.tolerance = 1e-6;
  settings.min_subtree = 1;
  // y = 3 and y = -3 + x / 1000: 3 from the centre, crossing at x = 6000.
  const Expr apart = r_and(3.0 - y, y + 3.0 - 0.001 * x, RSystem::r0());
  const Tape far(apart, 2);
  const std::optional<Tape> patched = TapeSpecializer(far).approximate(box.data(), settings);
  ASSERT_TRUE(patched);
  EXPECT_EQ(patched->code().size(), 1u);
  EXPECT_EQ(count_op(*patched, Op::Patch), 1u);
  Evaluator<double> exact(far), approximate(*patched);
  for (double px : {-1.0, 0.3, 1.0})
    for (double py : {-1.0, 0.0, 0.7}) EXPECT_NEAR(exact.at({px, py, 0}), approximate.at({px, py, 0}), 1e-6);
  // The same lines turned to cross at (0.5, 0.5), inside the box.
  const Expr crossing = r_and(0.5 - y, y - 0.5 + 0.3 * (x - 0.5), RSystem::r0());
  const Tape near(crossing, 2);
  const std::optional<Tape> kept = TapeSpecializer(near).approximate(box.data(), settings);
  EXPECT_TRUE(!kept || count_op(*kept, Op::RAnd) == 1u) << "the corner's node stays exact";
}

// Values and gradients of `approximated` against `exact` at random points
// of [-1, 1]^2.
void expect_close_over_unit_box(const Tape& exact_tape, const Tape& approximated, double value, double gradient,
                                std::uint64_t seed) {
  Evaluator<Tuple<2, 1>> exact(exact_tape), approximate(approximated);
  auto rng = test::make_rng(seed);
  for (int k = 0; k < 200; ++k) {
    const test::Point p{test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), 0};
    const auto a = exact.at(p), b = approximate.at(p);
    EXPECT_NEAR(a.value(), b.value(), value);
    EXPECT_NEAR(a.c[1], b.c[1], gradient);
    EXPECT_NEAR(a.c[2], b.c[2], gradient);
  }
}

// The first-order estimate cannot see every singularity: sqrt(x^2 + 1e-4)
// looks analytic from the centre (its argument is positive with zero
// gradient there) but has branch points at x = +-0.01 i. When the fit of a
// subtree fails, its subtrees are tried: the smooth term and the sqrt's
// argument become patches, and the sqrt and the sum stay exact.
TEST(FarFieldApproximation, AFailedFitTriesTheSubtreesBelow) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr field = sqrt(square(x) + 1e-4) + exp(0.2 * x) * cos(0.3 * y + 0.1 * x);
  const Tape tape(field, 2);
  const Box box{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  Approximation settings;
  settings.tolerance = 1e-10;
  settings.min_subtree = 2;
  const std::optional<Tape> approximated = TapeSpecializer(tape).approximate(box.data(), settings);
  ASSERT_TRUE(approximated);
  EXPECT_EQ(count_op(*approximated, Op::Patch), 2u);
  EXPECT_EQ(count_op(*approximated, Op::Sqrt), 1u);
  EXPECT_EQ(count_op(*approximated, Op::Add), 1u);
  // Within the tolerance itself (measured 2.1e-11), and the gradient
  // within n^2 times it (Markov, n <= 14; measured 5.2e-10).
  expect_close_over_unit_box(tape, *approximated, settings.tolerance, 196 * settings.tolerance, 12);
}

// The trimmed field of an edge 12 away along its own line: its square
// roots' arguments are sums of squares that vanish only at the segment's
// end points and branch (complex zeros) at |t| / |grad t| = 6.2 from the
// centre. Judged by the zeros of the arguments alone (t^2 / |grad t^2|,
// half that: 3.1), the enlarged box reached them; judged by the branch
// points, the whole field is one patch. An edge through the box keeps its
// roots.
TEST(FarFieldApproximation, RootsOfSumsOfSquaresAreAnalyticUpToTheirBranchPoints) {
  const Box box{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  Approximation settings;
  settings.enlargement = 3;  // reach: 3 half-diagonals, 4.24
  settings.tolerance = 1e-7;
  settings.min_subtree = 1;
  const Tape far(segment_field({12, 0}, {13, 0}, TrimMethod::Smooth), 2);
  const std::optional<Tape> patched = TapeSpecializer(far).approximate(box.data(), settings);
  ASSERT_TRUE(patched);
  EXPECT_EQ(patched->code().size(), 1u);
  EXPECT_EQ(count_op(*patched, Op::Patch), 1u);
  expect_close_over_unit_box(far, *patched, settings.tolerance, 1e-5, 13);  // value: measured 1.6e-8
  const Tape through(segment_field({0.5, 0}, {1.5, 0}, TrimMethod::Smooth), 2);
  const std::optional<Tape> kept = TapeSpecializer(through).approximate(box.data(), settings);
  EXPECT_TRUE(!kept || count_op(*kept, Op::Sqrt) == 2u) << "the roots stay exact";
}

// The largest tail among a tape's patches.
double largest_tail(const Tape& tape) {
  double tail = 0;
  for (const Instruction& ins : tape.code())
    if (ins.op == Op::Patch) tail = std::max(tail, ins.patch->tail());
  return tail;
}

// An error in F reaches F or C1 twice over where C1 vanishes and F > 0
// (d/dF (F + C + sqrt(F^2 + C^2)) = 1 + F / sqrt(F^2 + C^2)), and F or C1,
// or C2 twice that: a patch of F with a tail of T could move the field by
// nearly 4 T. Corners inside the box keep both R0 nodes exact, so F is
// patched under them, and its fit must leave a tail of at most T / 4. Alone
// (nothing above it), F's fit leaves more, so the bound is what tightens it.
TEST(FarFieldApproximation, PatchesUnderAmplifyingNodesAreFittedTighter) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr f = exp(0.3 * x) * cos(0.2 * y) + 2.0;
  const Expr c1 = r_and(y - 0.1 * x, x + 0.05, RSystem::r0());       // corner at (-0.05, -0.005)
  const Expr c2 = r_and(x - 0.2 * y - 0.1, 0.3 - y, RSystem::r0());  // corner at (0.16, 0.3)
  const Expr field = r_or(r_or(f, c1, RSystem::r0()), c2, RSystem::r0());
  const Box box{Interval(-1, 1), Interval(-1, 1), Interval(0.0)};
  Approximation settings;
  settings.tolerance = 1e-9;
  settings.min_subtree = 1;
  const Tape alone(f, 2);
  const std::optional<Tape> f_patched = TapeSpecializer(alone).approximate(box.data(), settings);
  ASSERT_TRUE(f_patched);
  ASSERT_GT(largest_tail(*f_patched), settings.tolerance / 4) << "alone, F's patch would not do under the nodes";
  const Tape tape(field, 2);
  const std::optional<Tape> approximated = TapeSpecializer(tape).approximate(box.data(), settings);
  ASSERT_TRUE(approximated);
  EXPECT_EQ(count_op(*approximated, Op::ROr), 2u);
  ASSERT_GT(count_op(*approximated, Op::Patch), 0u);
  EXPECT_LE(largest_tail(*approximated), settings.tolerance / 4);
  expect_close_over_unit_box(tape, *approximated, settings.tolerance, 1e-7, 14);
}

TEST(FarFieldApproximation, GridSamplingStaysWithinTheTolerance) {
  const Expr field = polygon_r0(512);
  const Tape tape(field, 2);
  Grid grid;
  grid.lo = {-12, -12, 0};
  grid.hi = {12, 12, 0};
  grid.points = {161, 161, 1};
  Approximation settings;
  const double diagonal = 24 * std::sqrt(2.0);
  settings.tolerance = 1e-10 * diagonal;
  const FieldSamples approximate = sample_field(tape, grid, 1, {}, &settings);
  const FieldSamples exact = sample_field(tape, grid, 1);
  double value = 0, gradient = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    value = std::max(value, std::abs(approximate.omega[i] - exact.omega[i]));
    for (int a = 0; a < 2; ++a)
      gradient = std::max(gradient, std::abs(approximate.gradient[3 * i + a] - exact.gradient[3 * i + a]));
    if (std::abs(exact.omega[i]) > 1e-9 * diagonal) {
      ASSERT_EQ(approximate.omega[i] > 0, exact.omega[i] > 0) << "point " << i;
    }
  }
  std::printf("far field: max deviation %.2e of the diagonal, gradient %.2e\n", value / diagonal, gradient);
  // Each patch moves the field by at most the tolerance to first order
  // (measured 0.95 of it).
  EXPECT_LE(value, settings.tolerance);
  EXPECT_LE(gradient, 1e-6);
  EXPECT_GT(value, 0.0) << "patches were used (else this test proves nothing)";
}

// sage field's default: patches for 2D trees with R-functions that pruning
// cannot shrink, not for min/max trees, formulas or 3D fields.
TEST(FarFieldApproximation, PaysFor2DRFunctionTreesOnly) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  EXPECT_TRUE(far_field_pays(Tape(r_and(x, y, RSystem::r0()), 2)));
  EXPECT_TRUE(far_field_pays(Tape(r_or(x, y, RSystem::parse("rp:4")), 2)));
  EXPECT_FALSE(far_field_pays(Tape(r_and(x, y, RSystem::min_max()), 2)));
  EXPECT_FALSE(far_field_pays(Tape(x * y + 1.0, 2)));
  EXPECT_FALSE(far_field_pays(Tape(r_and(x, z, RSystem::r0()), 3)));
}

}  // namespace
}  // namespace sage
