// Tape specialization over boxes and pruned grid sampling: a specialized
// tape gives the same value and derivatives, bit for bit, at every point
// of its box; it is much shorter than the whole tape over small boxes of a
// large min/max tree; constant steps and point classifiers fold; R0 trees
// are left whole; and pruned grid sampling equals point-by-point sampling.

#include "test_support.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/sampling/pruned_grid.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

// A union of `n` random disks minus a union of smaller ones, combined by
// `system`: a large CSG tree whose pieces each matter in a small region.
Expr disks(int n, const RSystem& system, std::uint64_t seed) {
  auto rng = test::make_rng(seed);
  std::vector<Expr> solid, holes;
  for (int i = 0; i < n; ++i) {
    const Vec3 c{test::uniform(rng, -10, 10), test::uniform(rng, -10, 10), 0};
    solid.push_back(ball(c, test::uniform(rng, 0.3, 1.0), 2));
    if (i % 3 == 0) holes.push_back(ball(c, 0.2, 2));
  }
  return r_and(r_disjunction_n(solid, system), -r_disjunction_n(holes, system), system);
}

template <int K>
void expect_same_at(const Tape& whole, const Tape& part, const test::Point& p) {
  Evaluator<Tuple<2, K>> a(whole), b(part);
  const Tuple<2, K> ta = a.at(p), tb = b.at(p);
  for (int i = 0; i < Tuple<2, K>::size; ++i) ASSERT_EQ(ta.c[i], tb.c[i]) << "coefficient " << i;
}

TEST(TapeSpecialization, SameNumbersInsideTheBoxAndShorterTapes) {
  const Tape tape(disks(300, RSystem::min_max(), 1), 2);
  auto rng = test::make_rng(2);
  TapeSpecializer specializer(tape);
  ASSERT_TRUE(TapeSpecializer::worthwhile(tape));
  std::size_t longest = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const double x = test::uniform(rng, -11, 11), y = test::uniform(rng, -11, 11), w = test::uniform(rng, 0.05, 0.5);
    const std::array<Interval, 3> box{Interval(x, x + w), Interval(y, y + w), Interval(0.0)};
    const std::optional<Tape> part = specializer.specialize(box.data());
    ASSERT_TRUE(part.has_value());
    longest = std::max(longest, part->code().size());
    for (int k = 0; k < 20; ++k) {
      const test::Point p{x + test::uniform(rng, 0, w), y + test::uniform(rng, 0, w), 0};
      Evaluator<double> a(tape), b(*part);
      ASSERT_EQ(a.at(p), b.at(p));
      expect_same_at<2>(tape, *part, p);
      EXPECT_TRUE(specializer.result().contains(a.at(p)));
    }
  }
  // Boxes of width <= 0.5 in a 22 x 22 square meet a few of the 300 disks.
  EXPECT_LT(longest * 10, tape.code().size()) << "longest specialized tape " << longest;
}

// min(min(a, b), c) over a box where a overlaps b and b overlaps c, so
// neither min is pruned by its own arguments, but a lies above c: the
// bound from above drops a.
TEST(TapeSpecialization, BoundsFromAboveDropDeepArguments) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr a = square(x) + square(y) + 2.0;  // in [2, 2.02] over the box
  const Expr b = 1.25 + 12.0 * x;              // in [0.05, 2.45]
  const Expr c = 1.2 + x;                      // in [1.1, 1.3]
  const Tape tape(min(min(a, b), c), 2);
  TapeSpecializer specializer(tape);
  const std::array<Interval, 3> box{Interval(-0.1, 0.1), Interval(-0.1, 0.1), Interval(0.0)};
  const std::optional<Tape> part = specializer.specialize(box.data());
  ASSERT_TRUE(part.has_value());
  for (const Instruction& ins : part->code()) EXPECT_NE(ins.op, Op::Square) << "a is still computed";
  auto rng = test::make_rng(5);
  for (int k = 0; k < 100; ++k) {
    const test::Point p{test::uniform(rng, -0.1, 0.1), test::uniform(rng, -0.1, 0.1), 0};
    expect_same_at<2>(tape, *part, p);
  }
}

// Random DAGs of min, max, negation, sums and min/max R-function nodes over
// disks and lines, with shared subterms: every specialized tape gives the
// whole tape's value and derivatives, bit for bit, inside its box.
TEST(TapeSpecialization, MinMaxDagsKeepTheirBits) {
  auto rng = test::make_rng(11);
  std::size_t shortened = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Expr> terms;
    for (int i = 0; i < 12; ++i) {
      const Vec3 c{test::uniform(rng, -4, 4), test::uniform(rng, -4, 4), 0};
      terms.push_back(i % 3 ? ball(c, test::uniform(rng, 0.2, 2.0), 2)
                            : Expr::x() * test::uniform(rng, -1, 1) + Expr::y() * test::uniform(rng, -1, 1));
    }
    for (int i = 0; i < 60; ++i) {
      const Expr& u = terms[std::uniform_int_distribution<std::size_t>(0, terms.size() - 1)(rng)];
      const Expr& v = terms[std::uniform_int_distribution<std::size_t>(0, terms.size() - 1)(rng)];
      switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
        case 0: terms.push_back(min(u, v)); break;
        case 1: terms.push_back(max(u, v)); break;
        case 2: terms.push_back(-u); break;
        case 3: terms.push_back(r_and(u, v, RSystem::min_max())); break;
        case 4: terms.push_back(r_or(u, v, RSystem::min_max())); break;
        default: terms.push_back(u + 0.5 * v); break;
      }
    }
    const Tape tape(terms.back(), 2);
    TapeSpecializer specializer(tape);
    for (int b = 0; b < 10; ++b) {
      const double x = test::uniform(rng, -5, 5), y = test::uniform(rng, -5, 5), w = test::uniform(rng, 0.01, 2);
      const std::array<Interval, 3> box{Interval(x, x + w), Interval(y, y + w), Interval(0.0)};
      const std::optional<Tape> part = specializer.specialize(box.data());
      if (!part) continue;
      shortened += part->code().size() < tape.code().size();
      for (int k = 0; k < 10; ++k) {
        const test::Point p{x + test::uniform(rng, 0, w), y + test::uniform(rng, 0, w), 0};
        expect_same_at<2>(tape, *part, p);
      }
    }
  }
  EXPECT_GT(shortened, 100u);
}

TEST(TapeSpecialization, SeveralBoxesAtOnceGiveEachBoxsTape) {
  // specialize_each over a block's four children (and over one box, and
  // eight) gives the tapes specialize gives box by box: same length, same
  // numbers at points of each box.
  const Tape tape(r_and(disks(200, RSystem::min_max(), 5), 1.0 - square(Expr::x()) * 0.01, RSystem::min_max()), 2);
  TapeSpecializer together(tape), alone(tape);
  auto rng = test::make_rng(6);
  for (std::size_t count : {1, 4, 8}) {
    for (int trial = 0; trial < 10; ++trial) {
      std::array<std::array<Interval, 3>, 8> boxes;
      const double x = test::uniform(rng, -11, 10), y = test::uniform(rng, -11, 10);
      for (std::size_t k = 0; k < count; ++k) {
        const double w = test::uniform(rng, 0.1, 2.0), dx = 0.5 * (k % 2), dy = 0.5 * (k / 2 % 2);
        boxes[k] = {Interval(x + dx, x + dx + w), Interval(y + dy, y + dy + w), Interval(0.0)};
      }
      std::array<std::optional<Tape>, 8> tapes;
      together.specialize_each(boxes.data(), count, tapes.data());
      for (std::size_t k = 0; k < count; ++k) {
        const std::optional<Tape> expected = alone.specialize(boxes[k].data());
        ASSERT_EQ(tapes[k].has_value(), expected.has_value());
        if (!expected) continue;
        EXPECT_EQ(tapes[k]->code().size(), expected->code().size());
        for (int j = 0; j < 5; ++j) {
          const test::Point p{test::uniform(rng, boxes[k][0].lo, boxes[k][0].hi),
                              test::uniform(rng, boxes[k][1].lo, boxes[k][1].hi), 0};
          expect_same_at<1>(tape, *tapes[k], p);
        }
      }
    }
  }
}

TEST(TapeSpecialization, StepsAndClassifiersFoldToConstants) {
  const auto ball = std::make_shared<const test::BallClassifier>();  // |p| < 1.2
  const Expr e = Expr::classify(ball) * (step(Expr::x() - 2.0) + Expr::y());
  const Tape tape(e, 3);
  TapeSpecializer specializer(tape);
  const std::array<Interval, 3> box{Interval(-0.2, 0.2), Interval(-0.3, 0.3), Interval(-0.1, 0.1)};
  const std::optional<Tape> part = specializer.specialize(box.data());
  ASSERT_TRUE(part.has_value());
  for (const Instruction& ins : part->code()) {
    EXPECT_NE(ins.op, Op::Classify);
    EXPECT_NE(ins.op, Op::Step);
  }
  Evaluator<double> a(tape), b(*part);
  EXPECT_EQ(a.at({0.1, 0.2, 0}), b.at({0.1, 0.2, 0}));
  EXPECT_EQ(b.at({0.1, 0.2, 0}), 0.2);
}

TEST(TapeSpecialization, R0TreesAreLeftWhole) {
  const Tape tape(disks(20, RSystem::r0(), 3), 2);
  TapeSpecializer specializer(tape);
  EXPECT_FALSE(TapeSpecializer::worthwhile(tape));
  const std::array<Interval, 3> box{Interval(0, 0.1), Interval(0, 0.1), Interval(0.0)};
  EXPECT_FALSE(specializer.specialize(box.data()).has_value());
  EXPECT_TRUE(specializer.result().lo <= specializer.result().hi);
}

TEST(PrunedGrid, SamplingEqualsPointByPoint) {
  for (const RSystem& system : {RSystem::min_max(), RSystem::r0()}) {
    const Tape tape(disks(100, system, 4), 2);
    Grid grid;
    grid.dimension = 2;
    grid.lo = {-11, -11, 0};
    grid.hi = {11, 11, 0};
    grid.points = {157, 93, 1};  // odd sizes: uneven blocks
    const FieldSamples pruned = sample_field(tape, grid, 2);
    std::vector<double> value(grid.size()), dxy(grid.size());
    for_each_grid_point<Tuple<2, 2>>(tape, grid, [&](std::size_t i, const Evaluator<Tuple<2, 2>>& e) {
      value[i] = e.result().value();
      dxy[i] = e.result().derivative_at(4);  // xy in the graded layout (1, x, y, xx, xy, yy)
    });
    for (std::size_t i = 0; i < grid.size(); ++i) {
      ASSERT_EQ(pruned.omega[i], value[i]) << system.name() << " point " << i;
      ASSERT_EQ(pruned.higher[0].values[3 * i + 1], dxy[i]) << system.name() << " point " << i;
    }
  }
}

TEST(PrunedGrid, EveryPointOnceIn3D) {
  const Expr e = r_or(ball({0, 0, 0}, 1, 3), ball({1, 0, 0}, 0.5, 3), RSystem::min_max());
  const Tape tape(e, 3);
  Grid grid;
  grid.dimension = 3;
  grid.lo = {-2, -2, -2};
  grid.hi = {2, 2, 2};
  grid.points = {17, 9, 13};
  std::vector<int> visits(grid.size(), 0);
  std::vector<double> value(grid.size());
  for_each_grid_point_pruned<double>(tape, grid, [&](std::size_t i, const auto& ev) {
    ++visits[i];
    value[i] = ev.result();
  });
  Evaluator<double> whole(tape);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    ASSERT_EQ(visits[i], 1) << i;
    ASSERT_EQ(value[i], whole.at(grid.point(i))) << i;
  }
}

}  // namespace
}  // namespace sage
