// Claims of batch_evaluator.hpp: a BatchEvaluator gives the same numbers,
// bit for bit, as an Evaluator at every point of a batch,
//  - for every op of the table (the sweep of tape_test), in doubles and in
//    second-order tuples, with partial batches (count < width);
//  - for tapes whose registers are reused (outputs written over arguments)
//    and that have several roots;
//  - for tapes with far-field patches (Op::Patch reads the point itself),
//    also over grid rows (evaluate_rows, where patches run a row at a time);
//  - for R0 and Rp nodes in doubles and first-order tuples
//    (rfunction_lanes.hpp), also at the corner, at NaN, at a zero argument
//    and over batches wider than their chunks;
//  - for products, squares, roots, quotients and integer powers of
//    first-order tuples (tuple_op_lanes.hpp), at signed zeros, NaN,
//    infinities and the operators' singular branches;
//  - for sums of squares fused into one kernel (square_sum.hpp: balls,
//    disks), smooth trimmings (smooth_trim.hpp: every edge of a polygon
//    B-rep), 3D linear forms (linear_form.hpp) and whole mesh faces
//    (trimmed_face.hpp), which are found where they are and nowhere else.

#include "test_support.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/expression/trimming.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/tape/batch_evaluator.hpp>
#include <sage/tape/far_faces.hpp>
#include <sage/tape/linear_form.hpp>
#include <sage/tape/smooth_trim.hpp>
#include <sage/tape/square_sum.hpp>
#include <sage/tape/tape_specialization.hpp>
#include <sage/tape/trimmed_face.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>

namespace sage {
namespace {

using Points = std::vector<std::array<double, 3>>;

Points random_points(std::size_t count, std::uint64_t seed, double lo, double hi) {
  auto rng = test::make_rng(seed);
  Points points;
  for (std::size_t k = 0; k < count; ++k) points.push_back(test::random_point(rng, lo, hi));
  return points;
}

// Same bits, the sign of a zero included (NaN equals NaN: both evaluators
// must agree on it too).
void expect_same(double batch, double single, const std::string& where) {
  if (std::isnan(single)) {
    EXPECT_TRUE(std::isnan(batch)) << where;
    return;
  }
  EXPECT_EQ(batch, single) << where;
  EXPECT_EQ(std::signbit(batch), std::signbit(single)) << where << ": the sign of " << single;
}

template <class T>
void expect_batch_equals_evaluator(const Tape& tape, const Points& points, std::size_t width) {
  BatchEvaluator<T> batch(tape, width);
  Evaluator<T> single(tape);
  for (std::size_t first = 0; first < points.size(); first += width) {
    const std::size_t count = std::min(width, points.size() - first);
    batch.evaluate(points.data() + first, count);
    for (std::size_t l = 0; l < count; ++l) {
      single.evaluate(points[first + l].data());
      for (std::size_t root = 0; root < tape.results().size(); ++root) {
        const std::string where = "point " + std::to_string(first + l) + " root " + std::to_string(root);
        if constexpr (std::is_same_v<T, double>) {
          expect_same(batch.result(l, root), single.result(root), where);
          expect_same(batch.point(l).result(root), single.result(root), where);
        } else {
          for (int c = 0; c < T::size; ++c)
            expect_same(batch.result(l, root).c[c], single.result(root).c[c],
                        where + " coefficient " + std::to_string(c));
        }
      }
    }
  }
}

TEST(BatchEvaluator, EveryOpGivesTheEvaluatorsBits) {
  const Points points = random_points(45, 31, -2, 2);  // a full batch of 16, then partial ones
  for (const test::OpCase& c : test::op_cases(true)) {
    SCOPED_TRACE(c.name);
    const Tape tape(c.build(Expr::x(), Expr::y(), Expr::z()), 3);
    expect_batch_equals_evaluator<double>(tape, points, 16);
    expect_batch_equals_evaluator<Tuple<3, 2>>(tape, points, 16);
    expect_batch_equals_evaluator<Tuple<3, 1>>(tape, points, 16);
  }
}

TEST(BatchEvaluator, R0AndRpLanesAtTheCornerAndAtNaN) {
  const Expr x = Expr::x(), y = Expr::y();
  Points points = random_points(150, 33, -1, 1);  // wider than the 64-lane chunks
  points[3] = {0, 0, 0};                          // both corners
  points[70] = {1, 0, 0};                         // the outer corner: inner = 0, x - 1 = 0
  points[71] = {std::nan(""), 0.5, 0};
  points[100] = {0, 0.5, 0};  // a zero argument
  points[140] = {0, 0, 0};
  // rp:6 runs lane by lane, the others a vector at a time.
  for (const RSystem& system : {RSystem::r0(), RSystem::r_p(2), RSystem::r_p(4), RSystem::r_p(6), RSystem::r_p(8)}) {
    SCOPED_TRACE(system.name());
    // The inner node's output register is reused by the outer one (aliasing).
    const Expr inner = r_and(x, y, system);
    const Tape tape(std::vector<Expr>{r_or(inner, x - 1.0, system), r_or(x, y, system)}, 2);
    expect_batch_equals_evaluator<Tuple<2, 1>>(tape, points, 150);
    expect_batch_equals_evaluator<Tuple<2, 1>>(tape, points, 64);
    expect_batch_equals_evaluator<double>(tape, points, 150);
    expect_batch_equals_evaluator<double>(tape, points, 64);
  }
}

TEST(BatchEvaluator, ComponentwiseOpsAtSignedZerosNaNAndInfinity) {
  // Sums, negation, Axpby and Offset run a component at a time over tuples
  // stored by component, and a halfplane read once (Axpby, then Offset in
  // its register) in one pass; their bits must be tuple.hpp's even where a
  // zero's sign or a NaN's would tell (-0 + 0 = +0; x * -1 keeps a NaN's sign).
  const Expr x = Expr::x(), y = Expr::y();
  const Expr halfplane = 2.0 * x - 3.0 * y;  // Axpby, read twice
  const Expr read_once = 0.5 * x + 4.0 * y - 2.0;
  const Tape tape(std::vector<Expr>{halfplane + 1.0, -x + 0.5, -(x - y), -halfplane - y, x + y, read_once}, 2);
  std::set<Op> ops;
  for (const Instruction& ins : tape.code()) ops.insert(ins.op);
  for (const Op op : {Op::Axpby, Op::Offset, Op::Neg, Op::Sub, Op::Add}) ASSERT_TRUE(ops.count(op)) << op_name(op);
  std::size_t fused = 0;  // Axpby, then Offset in its register
  for (std::size_t i = 0; i + 1 < tape.code().size(); ++i) {
    const Instruction &ins = tape.code()[i], &next = tape.code()[i + 1];
    fused += ins.op == Op::Axpby && next.op == Op::Offset && next.a == ins.out && next.out == ins.out;
  }
  ASSERT_EQ(fused, 1u) << "the halfplane read once";
  Points points = random_points(70, 34, -1, 1);
  const double inf = std::numeric_limits<double>::infinity();
  points[0] = {-0.0, 0.0, 0};
  points[1] = {0.0, -0.0, 0};
  points[2] = {-0.0, -0.0, 0};
  points[3] = {std::nan(""), -0.0, 0};
  points[4] = {-std::nan(""), 1.0, 0};
  points[5] = {inf, -inf, 0};
  points[6] = {inf, inf, 0};
  expect_batch_equals_evaluator<Tuple<2, 1>>(tape, points, 64);
  expect_batch_equals_evaluator<Tuple<2, 2>>(tape, points, 16);
  expect_batch_equals_evaluator<double>(tape, points, 64);
}

TEST(BatchEvaluator, TupleArithmeticLanesAtZerosNaNAndInfinity) {
  // Products, squares, roots, quotients and integer powers of first-order
  // tuples run a component at a time (tuple_op_lanes.hpp), constant
  // arguments read as one number; lanes where tuple.hpp takes another
  // branch (sqrt of 0 or less, a quotient by 0, a power of 0) are handed
  // back to it. Values run over whole arrays. Same bits everywhere, also
  // where an output overwrites its argument and over batches wider than a
  // chunk.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr product = x * y;
  std::vector<Expr> roots{product * (y - 1.0), square(x - y), sqrt(x), sqrt(square(x) + square(y)), x / y,
                          div_safe(y, x), pow_int(x, 4), pow_int(y, 3), pow_int(x - z, 0), pow_int(y, -2),
                          sqrt(product) / (x + z),
                          // constant arguments, read as one number:
                          (0.25 - square(x) - square(y)) / 0.5, product / 0.0, div_safe(y, Expr(0.0)), product * 3.0,
                          3.0 * sqrt(y), 2.0 - product, product - 2.0, 1.5 + product};
  const Tape tape(roots, 3);
  std::set<Op> ops, with_constant;
  std::set<std::uint32_t> constants;
  for (const auto& [r, c] : tape.constants()) constants.insert(r);
  for (const Instruction& ins : tape.code()) {
    ops.insert(ins.op);
    if (constants.count(ins.a) || (arity(ins.op) == 2 && constants.count(ins.b))) with_constant.insert(ins.op);
  }
  for (const Op op : {Op::Mul, Op::Scale, Op::Square, Op::Sqrt, Op::Div, Op::DivSafe, Op::PowInt})
    ASSERT_TRUE(ops.count(op)) << op_name(op);
  // a + c is an Offset, a c a Scale; c a stays a product.
  for (const Op op : {Op::Mul, Op::Div, Op::DivSafe, Op::Sub})
    EXPECT_TRUE(with_constant.count(op)) << op_name(op) << " with a constant argument";
  Points points = random_points(150, 35, -1, 1);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const std::vector<std::array<double, 3>> special{
      {0.0, 0.0, 0.0},       {-0.0, 0.0, 0.0},     {0.0, -0.0, 1.0},    {-0.0, -0.0, -0.0}, {nan, 1.0, 0.0},
      {1.0, nan, 0.5},       {-nan, -nan, 0.0},    {inf, 2.0, 0.0},     {2.0, -inf, inf},   {-inf, -inf, 1.0},
      {1e-170, 1e-170, 0.0}, {1e170, -1e170, 0.0}, {-0.25, 0.0, -0.25}, {0.5, 0.5, 0.5}};
  for (std::size_t k = 0; k < special.size(); ++k) {
    points[5 * k] = special[k];
    points[149 - k] = special[k];  // in the second chunk too
  }
  expect_batch_equals_evaluator<Tuple<3, 1>>(tape, points, 150);
  expect_batch_equals_evaluator<Tuple<3, 1>>(tape, points, 64);
  // Values run these ops over whole arrays too, min and max with them.
  for (const Expr& e : {min(x, y), max(product, z), min(x, Expr(0.5))}) roots.push_back(e);
  const Tape values(roots, 3);
  expect_batch_equals_evaluator<double>(values, points, 150);
  expect_batch_equals_evaluator<double>(values, points, 64);
  const Tape planar(std::vector<Expr>{x * y, square(x), sqrt(x - y), x / y, div_safe(x, y), pow_int(y, 5)}, 2);
  expect_batch_equals_evaluator<Tuple<2, 1>>(planar, points, 150);
}

// The runs that `find` (find_square_sum, find_smooth_trim) finds in
// `tape`, as BatchEvaluator looks for them.
template <class Find>
auto fused_runs(const Tape& tape, Find find) {
  std::vector<char> is_constant(tape.register_count(), 0);
  std::vector<double> constant_value(tape.register_count(), 0.0);
  for (const auto& [r, c] : tape.constants()) {
    is_constant[r] = 1;
    constant_value[r] = c;
  }
  std::vector<typename decltype(find(tape, 0, is_constant, constant_value))::value_type> runs;
  for (std::size_t i = 0; i < tape.code().size(); ++i)
    if (auto run = find(tape, i, is_constant, constant_value)) {
      runs.push_back(*run);
      i += run->length - 1;
    }
  return runs;
}

std::vector<SquareSumRun> square_sum_runs(const Tape& tape) { return fused_runs(tape, find_square_sum); }
std::vector<SmoothTrimRun> smooth_trim_runs(const Tape& tape) {
  return fused_runs(
      tape, [](const Tape& t, std::size_t first, const auto&, const auto&) { return find_smooth_trim(t, first); });
}
std::vector<LinearFormRun> linear_form_runs(const Tape& tape) { return fused_runs(tape, find_linear_form); }
std::vector<TrimmedFaceRun> trimmed_face_runs(const Tape& tape) { return fused_runs(tape, find_trimmed_face); }

// 150 points with `special` among the first chunk and the last lanes.
void place_special_points(Points& points, const std::vector<std::array<double, 3>>& special) {
  for (std::size_t k = 0; k < special.size(); ++k) {
    points[7 * k] = special[k];
    points[149 - k] = special[k];
  }
}

// `special`, then signed zeros, NaN, infinities, overflow and underflow.
std::vector<std::array<double, 3>> with_extremes(std::vector<std::array<double, 3>> special) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  for (const auto& p : std::vector<std::array<double, 3>>{{-0.0, -0.0, -0.0},
                                                          {nan, 1.0, 0.0},
                                                          {1.0, -nan, 0.5},
                                                          {inf, 2.0, 0.0},
                                                          {2.0, -inf, inf},
                                                          {1e-170, 1e170, -1e300}})
    special.push_back(p);
  return special;
}

// A 3D tape with fused runs, in doubles and tuples, full and partial batches.
void expect_fused_bits(const Tape& tape, const Points& points) {
  expect_batch_equals_evaluator<double>(tape, points, 64);
  expect_batch_equals_evaluator<double>(tape, points, 150);
  expect_batch_equals_evaluator<Tuple<3, 1>>(tape, points, 64);
  expect_batch_equals_evaluator<Tuple<3, 1>>(tape, points, 150);
}

TEST(BatchEvaluator, FusedSumsOfSquaresAreTheirInstructionsFound) {
  // A ball is ten instructions: three Offset-Square terms summed, r^2
  // minus the sum, divided by 2 r. All of it is one run, over the point's
  // coordinates in order.
  const Tape tape(ball({0.5, -0.25, 2.0}, 0.75, 3), 3);
  ASSERT_EQ(tape.code().size(), 10u);
  const auto runs = square_sum_runs(tape);
  ASSERT_EQ(runs.size(), 1u);
  const SquareSumRun& run = runs[0];
  EXPECT_EQ(run.length, 10u);
  EXPECT_EQ(run.sum.terms, 3);
  EXPECT_TRUE(run.sum.coordinates);
  EXPECT_EQ(run.sum.offsets, (std::array<double, 3>{-0.5, 0.25, -2.0}));
  EXPECT_TRUE(run.sum.has_minuend);
  EXPECT_EQ(run.sum.minuend, 0.75 * 0.75);
  EXPECT_TRUE(run.sum.has_divisor);
  EXPECT_EQ(run.sum.divisor, 1.5);
  EXPECT_EQ(run.out, tape.results()[0]);

  // A sum read twice ends the run where it is read: r^2 - s stays its own
  // instruction, the sum itself is still fused.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr s = square(x - 1.0) + square(y + 2.0);
  const Tape shared(std::vector<Expr>{s, 4.0 - s}, 2);
  const auto shared_runs = square_sum_runs(shared);
  ASSERT_EQ(shared_runs.size(), 1u);
  EXPECT_EQ(shared_runs[0].sum.terms, 2);
  EXPECT_FALSE(shared_runs[0].sum.has_minuend);
  EXPECT_EQ(shared_runs[0].length, 5u);
  // Terms over other registers, or the coordinates out of order, fuse too,
  // but not as coordinates.
  const Tape swapped(square(y - 1.0) + square(x - 2.0), 2);
  const auto swapped_runs = square_sum_runs(swapped);
  ASSERT_EQ(swapped_runs.size(), 1u);
  EXPECT_FALSE(swapped_runs[0].sum.coordinates);
  // A centre coordinate 0 leaves a Square alone: still a term.
  const auto axis_runs = square_sum_runs(Tape(ball({0.5, 0.0, 0.0}, 0.75, 3), 3));
  ASSERT_EQ(axis_runs.size(), 1u);
  EXPECT_EQ(axis_runs[0].length, 8u);
  EXPECT_TRUE(axis_runs[0].sum.coordinates);
  // A single square with nothing after it is left to the square kernel.
  EXPECT_TRUE(square_sum_runs(Tape(square(x - 1.0) * y, 2)).empty());
}

TEST(BatchEvaluator, FusedSumsOfSquaresGiveTheInstructionsBits) {
  // Balls, disks and other sums of squares run as one kernel give what
  // their instructions give one by one, in doubles and first-order tuples,
  // at signed zeros, NaN and infinities too, and next to instructions they
  // must not swallow.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr s = square(x - 1.0) + square(y + 2.0);
  const std::vector<Expr> roots{ball({0.5, -0.25, 2.0}, 0.75, 3),
                                r_or(ball({0.1, 0.2, 0.3}, 0.5, 3), ball({-0.4, 0.0, 0.1}, 0.25, 3), RSystem::r0()),
                                square(x * y - 1.0) + square(z + 2.0),  // terms over computed registers
                                square(x * z) + square(y),
                                square(z - 1.0) + square(x + 0.5) + square(y),
                                (2.0 - square(x - 0.125)) / 3.0,  // one term with both tails
                                square(y + 0.25) / 0.0,           // a zero divisor is the quotient's own business
                                s,
                                4.0 - s,
                                s * x};
  const Tape tape(roots, 3);
  ASSERT_EQ(square_sum_runs(tape).size(), 8u);  // s once; not the zero divisor
  Points points = random_points(150, 36, -1.5, 1.5);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const std::vector<std::array<double, 3>> special{{0.0, 0.0, 0.0},   {-0.0, -0.0, -0.0}, {1.0, -2.0, -1.0},
                                                   {0.5, 0.25, -2.0}, {nan, 1.0, 0.0},    {1.0, nan, -nan},
                                                   {inf, 2.0, 0.0},   {2.0, -inf, inf},   {1e-170, 1e170, 0.0}};
  place_special_points(points, special);
  expect_fused_bits(tape, points);
  const Tape planar(std::vector<Expr>{ball({0.5, -0.25, 0.0}, 0.75, 2), s, 4.0 - s, square(y - 1.0) + square(x)}, 2);
  ASSERT_EQ(square_sum_runs(planar).size(), 3u);
  expect_batch_equals_evaluator<double>(planar, points, 64);
  expect_batch_equals_evaluator<Tuple<2, 1>>(planar, points, 64);
}

TEST(BatchEvaluator, FusedSmoothTrimsAreTheirInstructionsFound) {
  // trim_smooth(h, t) is h^2 (computed first) and then eight instructions:
  // t^2, h^4, their sum, its root, (root - t) / 2 as one Axpby, its
  // square, the sum with h^2 and the root of that. With a scale, h is
  // multiplied by 1 / sqrt(scale) before its fourth power: nine.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr h = x * 0.6 - y * 0.8 + 0.25, t = r_and(z + 1.0, 0.5 - y, RSystem::r0());
  const Tape plain(trim_smooth(h, t), 3);
  const auto runs = smooth_trim_runs(plain);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].length, 8u);
  EXPECT_FALSE(runs[0].trim.has_scale);
  EXPECT_EQ(runs[0].trim.root_weight, 0.5);
  EXPECT_EQ(runs[0].trim.t_weight, -0.5);
  EXPECT_EQ(runs[0].out, plain.results()[0]);
  EXPECT_EQ(plain.code().back().op, Op::Sqrt);

  const auto scaled = smooth_trim_runs(Tape(trim_smooth(h, t, 4.0), 3));
  ASSERT_EQ(scaled.size(), 1u);
  EXPECT_EQ(scaled[0].length, 9u);
  EXPECT_TRUE(scaled[0].trim.has_scale);
  EXPECT_EQ(scaled[0].trim.scale, 0.5);

  // A polygon's edges, glued: one run per edge.
  const Expr edges = r_and(segment_field({0, 0}, {2, 0.5}, TrimMethod::Smooth, RSystem::r0()),
                           segment_field({2, 0.5}, {-1, 1}, TrimMethod::Smooth, RSystem::r0()), RSystem::r0());
  EXPECT_EQ(smooth_trim_runs(Tape(edges, 2)).size(), 2u);

  // Where an intermediate is read elsewhere too, the run stops short and
  // nothing is fused: the root of t^2 + h^4 as a second root.
  const Expr root = sqrt(square(t) + pow_int(h, 4));
  const Expr written_out = sqrt(square(h) + square(root * 0.5 - t * 0.5));
  EXPECT_EQ(smooth_trim_runs(Tape(written_out, 3)).size(), 1u);
  EXPECT_TRUE(smooth_trim_runs(Tape(std::vector<Expr>{written_out, root}, 3)).empty());
  // Other powers, or a different mix of root and t, are not the trimming.
  EXPECT_TRUE(smooth_trim_runs(Tape(sqrt(square(h) + square(sqrt(square(t) + pow_int(h, 6)) - t)), 3)).empty());
}

TEST(BatchEvaluator, FusedSmoothTrimsGiveTheInstructionsBits) {
  // Trimmings run as one kernel give what their instructions give one by
  // one, in doubles and first-order tuples, on the carrier (h = 0: the
  // fourth power's and both roots' singular branches), at signed zeros,
  // NaN, infinities and underflow, and next to the R0 nodes that glue them.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr h = x - 0.5, t = r_and(y + 1.0, 1.0 - y, RSystem::r0());
  const Expr face = trim_smooth(z * 0.8 - x * 0.6, r_and(x + 0.5, 0.5 - z, RSystem::r0()));
  const std::vector<Expr> roots{trim_smooth(h, t),
                                trim_smooth(h, t, 0.3),
                                trim_smooth(y, x),
                                face,
                                r_and(face, trim_smooth(h, t), RSystem::r0()),
                                trim_smooth(h, y * y - 1.0, 2.0)};
  const Tape tape(roots, 3);
  ASSERT_EQ(smooth_trim_runs(tape).size(), 6u);
  Points points = random_points(150, 37, -1.5, 1.5);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const std::vector<std::array<double, 3>> special{{0.5, 0.0, 0.0},       {0.5, 2.0, -1.0},     {0.5, -0.0, 0.0},
                                                   {0.0, 0.0, 0.0},       {-0.0, -0.0, -0.0},   {0.5, nan, 0.0},
                                                   {nan, 1.0, 0.0},       {inf, 2.0, 0.0},      {0.5, -inf, inf},
                                                   {1e-170, 1e-170, 0.0}, {0.5, 1e170, 1e-300}, {0.6, 0.0, 0.8}};
  place_special_points(points, special);
  expect_fused_bits(tape, points);
  const Tape planar(
      std::vector<Expr>{trim_smooth(h, y), segment_field({0, 0}, {2, 0.5}, TrimMethod::Smooth, RSystem::r0())}, 2);
  ASSERT_EQ(smooth_trim_runs(planar).size(), 2u);
  expect_batch_equals_evaluator<double>(planar, points, 64);
  expect_batch_equals_evaluator<Tuple<2, 1>>(planar, points, 64);
}

TEST(BatchEvaluator, FusedLinearFormsAreFoundAndGiveTheInstructionsBits) {
  // x p + y q + z k + d is Axpby, Scale, Add and Offset: one run. Without
  // the constant term it is three; a sum read twice stops the run before
  // its Offset; the factor may also come from a constant register (c z).
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr plane = x * 0.6 + y * -0.8 + z * 0.25 - 1.5;
  const Tape single(plane, 3);
  ASSERT_EQ(single.code().size(), 4u);
  const auto runs = linear_form_runs(single);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].length, 4u);
  EXPECT_EQ(runs[0].form.p, 0.6);
  EXPECT_EQ(runs[0].form.q, -0.8);
  EXPECT_EQ(runs[0].form.k, 0.25);
  EXPECT_TRUE(runs[0].form.has_offset);
  EXPECT_EQ(runs[0].form.d, -1.5);
  const Expr sum = x * 0.6 + y * -0.8 + z * 0.25;
  EXPECT_EQ(linear_form_runs(Tape(sum, 3))[0].length, 3u);
  const auto shared = linear_form_runs(Tape(std::vector<Expr>{sum + 2.0, sum * sum}, 3));
  ASSERT_EQ(shared.size(), 1u);
  EXPECT_EQ(shared[0].length, 3u);
  const Expr constant_first = x * 0.6 + y * -0.8 + 0.25 * z + 1.0;
  ASSERT_EQ(linear_form_runs(Tape(constant_first, 3)).size(), 1u);

  // Over computed registers (x y, the last root, is compiled first, so
  // its Scale follows the Axpby).
  const Expr product = x * y;
  const Expr computed = sin(x) * 2.0 + square(y) * 0.5 + product * -3.0 + 0.125;
  const std::vector<Expr> roots{plane,
                                sum + 2.0,
                                sum * sum,
                                constant_first,
                                computed,
                                r_and(plane, z * 1.5 + x * 0.5 + y * -0.25, RSystem::r0()),
                                x * 1e300 + y * 1e300 + z * 1e300,
                                product};
  const Tape tape(roots, 3);
  ASSERT_EQ(linear_form_runs(tape).size(), 6u);
  Points points = random_points(150, 38, -1.5, 1.5);
  place_special_points(points, with_extremes({{0.0, 0.0, 0.0}, {0.0, -0.0, 6.0}}));
  expect_fused_bits(tape, points);
}

// Mesh faces as mesh_field.cpp builds them (trimming.hpp's triangle_field).
Expr mesh_face(const std::array<std::array<double, 3>, 3>& v) { return triangle_field(v[0], v[1], v[2]); }

const std::array<std::array<double, 3>, 3> kTriangle{{{0.125, -0.25, 0.5}, {1.0, 0.0, 0.25}, {0.25, 1.0, -0.5}}};
// In the plane z = 0.5, with a vertex at x = y = 0: planes of one and two
// terms, some without a constant.
const std::array<std::array<double, 3>, 3> kFlatTriangle{{{0.0, 0.0, 0.5}, {1.0, -0.5, 0.5}, {-0.5, 1.0, 0.5}}};

TEST(BatchEvaluator, FusedTrimmedFacesAreTheirInstructionsFound) {
  // A face in general position is 27 instructions: four planes of three
  // terms (4 each), h^2, two R0 and the trimming (8). Glued by R0, each
  // face is one run and the glue is not.
  const Expr face = mesh_face(kTriangle);
  const Tape single(face, 3);
  ASSERT_EQ(single.code().size(), 27u);
  const auto runs = trimmed_face_runs(single);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].length, 27u);
  EXPECT_EQ(runs[0].out, single.results()[0]);
  EXPECT_TRUE(runs[0].face.trimming_first);
  EXPECT_EQ(runs[0].face.first_sign, -1.0);
  // The planes' partials at a finite point are their coefficients.
  for (const FacePlane& plane : runs[0].face.planes) {
    ASSERT_EQ(plane.kind, FacePlane::Kind::ThreeTerms);
    std::array<double, 3> gradient{};
    const std::array<double, 3> coefficient{plane.form.p, plane.form.q, plane.form.k};
    for (std::size_t a = 0; a < 3; ++a) gradient[static_cast<std::size_t>(plane.variables[a])] = coefficient[a];
    EXPECT_EQ(plane.partials, gradient);
  }
  // A face in z = 0.5: h is z - 0.5 (an Offset of z, or its negation and
  // an Offset), the side planes have no z term, one has no constant.
  const Tape flat(mesh_face(kFlatTriangle), 3);
  EXPECT_LT(flat.code().size(), 27u);
  const auto flat_runs = trimmed_face_runs(flat);
  ASSERT_EQ(flat_runs.size(), 1u);
  EXPECT_EQ(flat_runs[0].length, flat.code().size());
  const FacePlane& own = flat_runs[0].face.planes[0];
  EXPECT_TRUE(own.kind == FacePlane::Kind::Variable || own.kind == FacePlane::Kind::Negated);
  EXPECT_EQ(own.variables[0], 2);
  EXPECT_EQ(std::abs(own.partials[2]), 1.0);
  int without_constant = 0;
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_EQ(flat_runs[0].face.planes[k].kind, FacePlane::Kind::TwoTerms);
    without_constant += !flat_runs[0].face.planes[k].form.has_offset;
  }
  EXPECT_EQ(without_constant, 2);  // the two sides through the vertex at x = y = 0
  const Tape glued(r_and(face, mesh_face(kFlatTriangle), RSystem::r0()), 3);
  EXPECT_EQ(trimmed_face_runs(glued).size(), 2u);
  EXPECT_EQ(glued.code().size(), 27u + flat.code().size() + 1u);

  // Not a face: a side plane read again elsewhere, a side over a computed
  // register, a trimming by something else than two R0 of planes.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr side = x * 0.6 + y * 0.8 + z * 0.0 + 0.25;
  const Expr h = x * 0.8 - y * 0.6 + z * 0.5 - 0.125;
  const Expr other = x * -0.6 + y * 0.25 + z * 0.75 + 1.0;
  const Expr fourth = x * 0.5 + y * 0.5 + z * 0.5 - 1.0;
  const RSystem r0 = RSystem::r0();
  const Expr shaped = trim_smooth(h, r_and(r_and(side, other, r0), fourth, r0));
  ASSERT_EQ(trimmed_face_runs(Tape(shaped, 3)).size(), 1u);
  // The trimming written s'' AND (s AND s') is found too.
  const auto reversed = trimmed_face_runs(Tape(trim_smooth(h, r_and(fourth, r_and(side, other, r0), r0)), 3));
  ASSERT_EQ(reversed.size(), 1u);
  EXPECT_FALSE(reversed[0].face.trimming_first);
  EXPECT_TRUE(trimmed_face_runs(Tape(std::vector<Expr>{shaped, side}, 3)).empty());
  const Expr computed = sin(x) * 0.6 + y * 0.8 + z * 0.1 + 0.25;
  EXPECT_TRUE(trimmed_face_runs(Tape(trim_smooth(h, r_and(r_and(computed, other, r0), fourth, r0)), 3)).empty());
  EXPECT_TRUE(trimmed_face_runs(Tape(trim_smooth(h, r_and(side, other, r0)), 3)).empty());
  EXPECT_TRUE(
      trimmed_face_runs(Tape(trim_smooth(h, r_and(r_and(side, other, RSystem::r_p(2)), fourth, r0)), 3)).empty());
}

TEST(BatchEvaluator, FusedTrimmedFacesGiveTheInstructionsBits) {
  // Faces run as one kernel give what their instructions give one by one,
  // in doubles and first-order tuples: on the face's plane (h = 0: the
  // fourth power's zero), on the normal lines through its vertices (two
  // side planes vanish: R0's corner), at a vertex, at signed zeros, NaN,
  // infinities, overflow and underflow, glued, with the trimming in either
  // order, and with a scale.
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const RSystem r0 = RSystem::r0();
  const Expr face = mesh_face(kTriangle);
  // A face in z = 0.5, its trimming s'' AND (s AND s'), whose sides s and
  // s' have no constant: they vanish together on the line x = y = 0.
  const Expr flat = trim_smooth(z * -1.0 + 0.5, r_and(y + 0.75, r_and(x * 0.6 + y * 0.8, x * -0.8 + y * 0.6, r0), r0));
  const Expr side = x * 0.6 + y * 0.8 + z * 0.0 + 0.25;
  const Expr other = x * -0.6 + y * 0.25 + z * 0.75 + 1.0;
  const Expr fourth = x * 0.5 + y * 0.5 + z * 0.5 - 1.0;
  const Expr scaled = trim_smooth(x * 0.8 - y * 0.6 + 0.5 * z - 0.125, r_and(r_and(side, other, r0), fourth, r0), 4.0);
  const std::vector<Expr> roots{face, flat, r_and(face, flat, r0), r_or(flat, face, r0), scaled};
  const Tape tape(roots, 3);
  ASSERT_EQ(trimmed_face_runs(tape).size(), 3u);  // each face compiled once
  Points points = random_points(150, 39, -1.5, 1.5);
  place_special_points(points, with_extremes({{0.125, -0.25, 0.5},  // a vertex of the general face
                                              {0.25, 0.125, 0.5},   // on the flat face's plane: h = 0
                                              {0.0, 0.0, 0.5},      // and where two of its sides vanish
                                              {0.0, 0.0, -2.0},     // two sides vanish: R0's corner
                                              {1.0, -0.5, 3.0},     // near a vertex's normal line
                                              {1e-300, -1e-300, 0.5}}));
  expect_fused_bits(tape, points);
}

// ---- far faces in single precision (far_faces.hpp) ----

// A small triangle in the plane z = height, near (cx, cy).
std::array<std::array<double, 3>, 3> small_triangle(double cx, double cy, double height) {
  return {{{cx, cy, height}, {cx + 0.2, cy + 0.05, height}, {cx + 0.05, cy + 0.2, height}}};
}

TEST(BatchEvaluator, FarFacesAreClustersReadOnlyThroughTheirRoots) {
  std::vector<TrimmedFace> faces;
  for (int k = 0; k < 4; ++k)
    faces.push_back(trimmed_face_runs(Tape(mesh_face(small_triangle(k, 0, 0)), 3)).at(0).face);
  using Kind = FarFaces::Step::Kind;
  auto face = [&](int k, std::uint32_t out) {
    return FarFaces::Step{Kind::Face, &faces[static_cast<std::size_t>(k)], -1, out, {}, 0};
  };
  auto glue = [](std::uint32_t a, std::uint32_t b, std::uint32_t out) {
    return FarFaces::Step{Kind::Glue, nullptr, -1, out, {a, b, 0}, 2};
  };
  auto other = [](std::uint32_t read, std::uint32_t out) {
    return FarFaces::Step{Kind::Other, nullptr, -1, out, {read, read, 0}, 2};
  };
  // ((f0 f1) (f2 f3)): four faces, three glues, every one a cluster.
  const std::vector<FarFaces::Step> tree{face(0, 10), face(1, 11),      glue(10, 11, 12), face(2, 13),
                                         face(3, 14), glue(13, 14, 15), glue(12, 15, 16)};
  FarFaces clusters;
  clusters.build(tree, {16});
  EXPECT_EQ(clusters.cluster_count(), 7u);
  Box3 far_away{{100, 100, 100}, {101, 101, 101}};
  ASSERT_EQ(clusters.last_step(clusters.far_cluster_at(0, far_away)), 6u);  // the whole tree
  EXPECT_EQ(clusters.output(clusters.far_cluster_at(0, far_away)), 16u);
  // Beside f0: f0 itself is near, (f0 f1) too; f1 alone is far enough.
  const Box3 beside_f0{{0.0, 0.0, 0.05}, {0.1, 0.1, 0.15}};
  EXPECT_EQ(clusters.far_cluster_at(0, beside_f0), -1);
  EXPECT_GE(clusters.far_cluster_at(3, beside_f0), 0);  // (f2 f3)

  // f0's result read after the tree: (f0 f1) and the whole tree would skip
  // computing it, so they are no clusters.
  std::vector<FarFaces::Step> read_inside = tree;
  read_inside.push_back(other(10, 17));
  clusters.build(read_inside, {16, 17});
  EXPECT_EQ(clusters.cluster_count(), 5u);
  EXPECT_EQ(clusters.last_step(clusters.far_cluster_at(0, far_away)), 0u);  // f0 alone
  // A register written again before it is read holds a new value: no harm.
  std::vector<FarFaces::Step> reused = tree;
  reused.push_back(other(1, 10));
  reused.push_back(other(10, 18));
  clusters.build(reused, {16, 18});
  EXPECT_EQ(clusters.cluster_count(), 7u);
  // A glue whose faces are not just before it glues no cluster.
  const std::vector<FarFaces::Step> apart{face(0, 10), face(1, 11), other(1, 20), glue(10, 11, 12)};
  clusters.build(apart, {12, 20});
  EXPECT_EQ(clusters.cluster_count(), 2u);
}

TEST(BatchEvaluator, FarFacesRunInSinglePrecisionNearTheDoubles) {
  // 16 small triangles on a ring, glued by a balanced R0 tree; the second
  // root reads a face's result too.
  std::vector<Expr> level;
  for (int k = 0; k < 16; ++k) {
    const double angle = 2 * std::numbers::pi * k / 16;
    level.push_back(mesh_face(small_triangle(std::cos(angle), std::sin(angle), 0.05 * k)));
  }
  const Expr first = level[0];
  while (level.size() > 1) {
    std::vector<Expr> next;
    for (std::size_t k = 0; k + 1 < level.size(); k += 2) next.push_back(r_and(level[k], level[k + 1], RSystem::r0()));
    level = next;
  }
  const Tape tape(std::vector<Expr>{level[0], first * 2.0}, 3);
  BatchEvaluator<Tuple<3, 1>> exact(tape, 128), far(tape, 128);
  far.set_far_faces(true);
  BatchEvaluator<double> exact_values(tape, 128), far_values(tape, 128);
  far_values.set_far_faces(true);
  const double epsilon = std::numeric_limits<float>::epsilon();
  auto check = [&](const Points& points, bool bits, std::size_t roots) {
    exact.evaluate(points.data(), points.size());
    far.evaluate(points.data(), points.size());
    exact_values.evaluate(points.data(), points.size());
    far_values.evaluate(points.data(), points.size());
    for (std::size_t l = 0; l < points.size(); ++l)
      for (std::size_t root = 0; root < roots; ++root) {
        const Tuple<3, 1> want = exact.result(l, root), got = far.result(l, root);
        EXPECT_NEAR(far_values.result(l, root), want.value(), 8 * epsilon * want.value()) << l;
        if (bits) {
          EXPECT_EQ(got.value(), want.value());
          EXPECT_EQ(got.gradient(), want.gradient());
          continue;
        }
        EXPECT_NEAR(got.value(), want.value(), 8 * epsilon * want.value()) << l;
        const auto gw = want.gradient(), gg = got.gradient();
        const double length = std::hypot(gw[0], gw[1], gw[2]);
        EXPECT_LT(std::hypot(gg[0] - gw[0], gg[1] - gw[1], gg[2] - gw[2]), 1e-4 * length) << l;
      }
  };
  // Far above the ring: every cluster at once, in five runs, for the second
  // root reads f0 and no cluster holding f0 with other faces may skip it:
  // f0, f1, (f2 f3), (f4 .. f7) and (f8 .. f15).
  Points above = random_points(128, 7, -0.1, 0.1);
  for (auto& p : above) p[2] += 6.0;
  std::size_t runs = far.far_cluster_runs();
  check(above, false, 2);
  EXPECT_EQ(far.far_cluster_runs(), runs + 5);
  // Beside one triangle: it stays in doubles, far clusters do not.
  Points beside = random_points(128, 8, -0.05, 0.05);
  for (auto& p : beside) p = {p[0] + 1.1, p[1] + 0.1, p[2] + 0.1};
  runs = far.far_cluster_runs();
  check(beside, false, 2);
  EXPECT_GT(far.far_cluster_runs(), runs);
  // On the normal line through a far face's vertex, where its first R0's
  // sides vanish (x = y = 0, as in FusedTrimmedFacesGiveTheInstructionsBits)
  // in single precision too: R0's corner, where its partials are not
  // defined, so the batch's tuples run in doubles, bit for bit (values
  // alone are regular there).
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const RSystem r0 = RSystem::r0();
  const Tape corner(trim_smooth(z * -1.0 + 0.5, r_and(y + 0.75, r_and(x * 0.6 + y * 0.8, x * -0.8 + y * 0.6, r0), r0)),
                    3);
  exact.rebind(corner, 128);
  far.rebind(corner, 128);
  exact_values.rebind(corner, 128);
  far_values.rebind(corner, 128);
  Points line(128);
  for (std::size_t l = 0; l < line.size(); ++l)
    line[l] = {l % 2 ? 0.01 : -0.01, l % 4 < 2 ? 0.01 : -0.01, 20.0 + 0.01 * static_cast<double>(l / 4)};
  line[0] = {0, 0, 20.0};
  runs = far.far_cluster_runs();
  check(line, true, 1);
  EXPECT_EQ(far.far_cluster_runs(), runs);
}

// Faces whose trimming has disjunctions too (a mesh's triangles have
// conjunctions only): each pair of R0 signs runs a kernel of its own.
TEST(BatchEvaluator, FarFacesOfEverySignPairRunNearTheDoubles) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const RSystem r0 = RSystem::r0();
  auto glue = [&](bool disjunction, const Expr& a, const Expr& b) {
    return disjunction ? r_or(a, b, r0) : r_and(a, b, r0);
  };
  const double epsilon = std::numeric_limits<float>::epsilon();
  for (const bool first_or : {false, true})
    for (const bool second_or : {false, true}) {
      const Tape tape(
          trim_smooth(z * -1.0 + 0.5, glue(second_or, y + 0.75, glue(first_or, x * 0.6 + y * 0.8, x * -0.8 + y * 0.6))),
          3);
      BatchEvaluator<Tuple<3, 1>> exact(tape, 128), far(tape, 128);
      far.set_far_faces(true);
      Points points = random_points(128, 11, -0.2, 0.2);
      for (auto& p : points) p = {p[0] + 3.0, p[1] - 2.0, p[2] + 10.0};
      exact.evaluate(points.data(), points.size());
      far.evaluate(points.data(), points.size());
      ASSERT_EQ(far.far_cluster_runs(), 1u) << "signs " << first_or << second_or;
      for (std::size_t l = 0; l < points.size(); ++l) {
        const Tuple<3, 1> want = exact.result(l), got = far.result(l);
        EXPECT_NEAR(got.value(), want.value(), 8 * epsilon * want.value()) << first_or << second_or << l;
        const auto gw = want.gradient(), gg = got.gradient();
        EXPECT_LT(std::hypot(gg[0] - gw[0], gg[1] - gw[1], gg[2] - gw[2]), 1e-4 * std::hypot(gw[0], gw[1], gw[2]))
            << first_or << second_or << l;
      }
    }
}

// A glue of two values far apart in size: 256 faces close together (their
// R0 conjunction far smaller than any of them) and one more face. In
// single precision x + y - sqrt(x^2 + y^2) would lose x / y roundings;
// the far clusters' conjunction keeps within a few.
TEST(BatchEvaluator, FarFacesGlueValuesFarApartInSize) {
  std::vector<Expr> level;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j) level.push_back(mesh_face(small_triangle(0.25 * i, 0.25 * j, 0.0)));
  while (level.size() > 1) {
    std::vector<Expr> next;
    for (std::size_t k = 0; k + 1 < level.size(); k += 2) next.push_back(r_and(level[k], level[k + 1], RSystem::r0()));
    level = next;
  }
  const Tape tape(r_and(level[0], mesh_face(small_triangle(2.0, 2.0, 5.0)), RSystem::r0()), 3);
  BatchEvaluator<Tuple<3, 1>> exact(tape, 128), far(tape, 128);
  far.set_far_faces(true);
  BatchEvaluator<double> far_values(tape, 128);
  far_values.set_far_faces(true);
  Points points = random_points(128, 9, -0.2, 0.2);
  for (auto& p : points) p = {p[0] + 2.0, p[1] + 2.0, p[2] + 40.0};
  exact.evaluate(points.data(), points.size());
  far.evaluate(points.data(), points.size());
  far_values.evaluate(points.data(), points.size());
  ASSERT_EQ(far.far_cluster_runs(), 1u);  // the whole tree
  const double epsilon = std::numeric_limits<float>::epsilon();
  double worst = 0;
  for (std::size_t l = 0; l < points.size(); ++l) {
    const double want = exact.result(l).value();
    worst = std::max({worst, std::fabs(far.result(l).value() - want) / (epsilon * want),
                      std::fabs(far_values.result(l) - want) / (epsilon * want)});
  }
  EXPECT_LT(worst, 8) << "single-precision roundings of the value";
}

// Grid blocks at a grid's edges hold fewer points: rebinding the same tape
// to a narrower batch keeps the registers' layout and what was found in
// the tape (redoing it per edge block cost elephant.off 30% more time at
// 66^3 than at 64^3), and gives the numbers of an evaluator made for that
// width.
TEST(BatchEvaluator, NarrowerBatchesOfTheSameTapeKeepTheirLayout) {
  std::vector<Expr> level;
  for (int i = 0; i < 8; ++i) level.push_back(mesh_face(small_triangle(0.3 * i, 0.1 * i, 0.0)));
  while (level.size() > 1) {
    std::vector<Expr> next;
    for (std::size_t k = 0; k + 1 < level.size(); k += 2) next.push_back(r_or(level[k], level[k + 1], RSystem::r0()));
    level = next;
  }
  const Tape tape(level[0], 3);
  BatchEvaluator<Tuple<3, 1>> reused(tape, 128), narrow(tape, 50);
  reused.set_far_faces(true);
  narrow.set_far_faces(true);
  Points points = random_points(128, 10, -0.2, 0.2);
  for (auto& p : points) p[2] += 30.0;
  reused.evaluate(points.data(), points.size());
  reused.rebind(tape, 50);
  EXPECT_EQ(reused.width(), 128u);  // the registers' layout kept
  points.resize(50);
  reused.evaluate(points.data(), points.size());
  narrow.evaluate(points.data(), points.size());
  EXPECT_EQ(reused.far_cluster_runs(), 2u);  // the whole tree, in both batches
  EXPECT_EQ(narrow.far_cluster_runs(), 1u);
  for (std::size_t l = 0; l < points.size(); ++l) {
    EXPECT_EQ(reused.result(l).value(), narrow.result(l).value()) << l;
    EXPECT_EQ(reused.result(l).gradient(), narrow.result(l).gradient()) << l;
  }
}

TEST(BatchEvaluator, ReusedRegistersAndSeveralRoots) {
  const Expr x = Expr::x(), y = Expr::y();
  Expr f = x;
  for (int i = 0; i < 200; ++i) f = sin(f) * 0.9 + y * 0.1 - square(f) * 0.01;
  const Expr g = r_and(ball({0, 0, 0}, 1, 2), f, RSystem::r0());
  const Tape tape(std::vector<Expr>{f, g, x * y}, 2);
  // Constants keep their registers; the chain's values reuse a handful.
  ASSERT_LT(tape.register_count(), tape.constants().size() + 20)
      << "registers must be reused for this test to mean anything";
  const Points points = random_points(100, 32, -1, 1);
  expect_batch_equals_evaluator<double>(tape, points, 64);
  expect_batch_equals_evaluator<Tuple<2, 3>>(tape, points, 7);
  expect_batch_equals_evaluator<Tuple<2, 1>>(tape, points, 64);
}

TEST(BatchEvaluator, TapesWithFarFieldPatches) {
  std::vector<Expr> sides;
  for (int i = 0; i < 128; ++i) {
    const double a = 2 * std::numbers::pi * i / 128;
    sides.push_back(halfspace({10 * std::cos(a), 10 * std::sin(a), 0}, {std::cos(a), std::sin(a), 0}, 2));
  }
  const Tape tape(r_conjunction_n(sides, RSystem::r0()), 2);
  TapeSpecializer specializer(tape);
  Approximation settings;
  settings.tolerance = 1e-9;
  const std::array<Interval, 3> box{Interval(9.5, 10.5), Interval(-0.5, 0.5), Interval(0.0)};
  const std::optional<Tape> near = specializer.approximate(box.data(), settings);
  ASSERT_TRUE(near);
  std::size_t patches = 0;
  for (const Instruction& ins : near->code()) patches += ins.op == Op::Patch;
  ASSERT_GT(patches, 0u);
  Points points = random_points(50, 33, -0.5, 0.5);
  for (auto& p : points) p = {10 + p[0], p[1], 0};
  expect_batch_equals_evaluator<Tuple<2, 1>>(*near, points, 32);

  // Over grid rows: 5 rows of 7 points, the points of a grid block.
  std::vector<double> xs;
  std::vector<std::array<double, 2>> rows;
  for (int i = 0; i < 7; ++i) xs.push_back(9.6 + 0.13 * i);
  for (int r = 0; r < 5; ++r) rows.push_back({-0.4 + 0.17 * r, 0.0});
  Points grid;
  for (const auto& row : rows)
    for (double x : xs) grid.push_back({x, row[0], 0});
  auto expect_rows = [&]<class T>(T) {
    BatchEvaluator<T> batch(*near, grid.size());
    batch.evaluate_rows(xs.data(), xs.size(), rows.data(), rows.size());
    Evaluator<T> single(*near);
    for (std::size_t p = 0; p < grid.size(); ++p) {
      single.evaluate(grid[p].data());
      const std::string where = "grid point " + std::to_string(p);
      if constexpr (std::is_same_v<T, double>) {
        expect_same(batch.result(p), single.result(), where);
      } else {
        for (int c = 0; c < T::size; ++c) expect_same(batch.result(p).c[c], single.result().c[c], where);
      }
    }
  };
  expect_rows(0.0);
  expect_rows(Tuple<2, 1>());
  expect_rows(Tuple<2, 2>());  // no row path for patches: point by point
}

}  // namespace
}  // namespace sage
