// Bounds of partial derivatives over a box (libsage/src/tape/partial_bounds.hpp,
// internal: far-field approximation tightens a patch's tolerance by how
// much the operations above it can amplify its error). Every bound holds
// against finite differences at random points of random boxes, and the
// R-function bounds are attained at a corner of the box.

#include "test_support.hpp"

#include "../../libsage/src/tape/partial_bounds.hpp"

#include <sage/scalars/rfunction.hpp>
#include <sage/tape/evaluator.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace sage {
namespace {

Instruction make(Op op, double p0 = 0, double p1 = 0) { return Instruction{op, 2, 0, 1, p0, p1}; }
Instruction r_node(Op op, const RSystem& s) { return make(op, static_cast<double>(s.kind), s.parameter); }

struct Case {
  std::string name;
  Instruction ins;
  double lo, hi;  // where the random boxes' ends lie (both arguments)
};

TEST(PartialBounds, BoundFiniteDifferencesOverRandomBoxes) {
  const Case cases[] = {
      {"r0 and", r_node(Op::RAnd, RSystem::r0()), -3, 3},
      {"r0 or", r_node(Op::ROr, RSystem::r0()), -3, 3},
      {"rp:4 and", r_node(Op::RAnd, RSystem::r_p(4)), -3, 3},
      {"rp:8 or", r_node(Op::ROr, RSystem::r_p(8)), -3, 3},
      {"ralpha:0.5 and", r_node(Op::RAnd, RSystem::r_alpha(0.5)), -3, 3},
      {"ralpha:-0.5 or", r_node(Op::ROr, RSystem::r_alpha(-0.5)), -3, 3},
      {"ralpha:var and", r_node(Op::RAnd, RSystem::r_alpha_variable()), -3, 3},
      {"ralpha:var or", r_node(Op::ROr, RSystem::r_alpha_variable()), -0.5, 0.5},
      {"rm:2 or", r_node(Op::ROr, RSystem::r_m(2)), -2, 2},
      {"minmax and", r_node(Op::RAnd, RSystem::min_max()), -3, 3},
      {"mul", make(Op::Mul), -3, 3},
      {"div", make(Op::Div), 0.5, 3},
      {"square", make(Op::Square), -3, 3},
      {"sqrt", make(Op::Sqrt), 0.1, 3},
      {"pow_int 3", make(Op::PowInt, 3), -2, 2},
      {"pow_int -2", make(Op::PowInt, -2), 0.5, 2},
      {"pow_real 0.5", make(Op::PowReal, 0.5), 0.2, 3},
      {"pow_real 2.5", make(Op::PowReal, 2.5), 0.0, 3},
      {"exp", make(Op::Exp), -2, 2},
      {"log", make(Op::Log), 0.2, 3},
      {"sin", make(Op::Sin), -3, 3},
      {"axpby", make(Op::Axpby, 2, -3), -3, 3},
      {"sub", make(Op::Sub), -3, 3},
      {"offset", make(Op::Offset, 4), -3, 3},
  };
  auto rng = test::make_rng(41);
  for (const Case& c : cases) {
    const int arguments = arity(c.ins.op);
    for (int trial = 0; trial < 300; ++trial) {
      Interval box[2];
      for (Interval& x : box) {
        const double u = test::uniform(rng, c.lo, c.hi), v = test::uniform(rng, c.lo, c.hi);
        x = Interval(std::min(u, v), std::max(u, v));
      }
      for (int k = 0; k < arguments; ++k) {
        const double bound = detail::partial_bound(c.ins, box[0], box[1], k);
        ASSERT_GE(bound, 0.0) << c.name;
        for (int point = 0; point < 20; ++point) {
          const double h = 1e-6 * (1 + std::abs(box[k].hi) + std::abs(box[k].lo));
          if (box[k].width() < 2 * h) continue;
          double p[2] = {test::uniform(rng, box[0].lo, box[0].hi), test::uniform(rng, box[1].lo, box[1].hi)};
          p[k] = test::uniform(rng, box[k].lo + h, box[k].hi - h);
          double up[2] = {p[0], p[1]}, down[2] = {p[0], p[1]};
          up[k] += h;
          down[k] -= h;
          const double slope = (apply<double>(c.ins, up[0], up[1]) - apply<double>(c.ins, down[0], down[1])) / (2 * h);
          ASSERT_LE(std::abs(slope), bound * (1 + 1e-5) + 1e-5)
              << c.name << " argument " << k << " over [" << box[0].lo << ", " << box[0].hi << "] x [" << box[1].lo
              << ", " << box[1].hi << "] at (" << p[0] << ", " << p[1] << ")";
        }
      }
    }
  }
}

// The R-function bounds are the derivative at a corner of the box, not
// the global 2: over x in [1, 2], y in [5, 6] the R0 conjunction moves
// with x by at most 1 - 1 / sqrt(1 + 36); where x may be negative and y
// may vanish, by 2.
TEST(PartialBounds, RFunctionBoundsAreAttainedAtACorner) {
  const Instruction and0 = r_node(Op::RAnd, RSystem::r0());
  EXPECT_NEAR(detail::partial_bound(and0, Interval(1, 2), Interval(5, 6), 0), 1 - 1 / std::sqrt(37.0), 1e-15);
  EXPECT_DOUBLE_EQ(detail::partial_bound(and0, Interval(-1, 2), Interval(-5, 6), 0), 2.0);
  // Rp, p = 4, disjunction, x in [-3, -1]: 1 + (x / rho)^3 is largest at
  // x = -1 with |y| = 2 the largest.
  const Instruction or4 = r_node(Op::ROr, RSystem::r_p(4));
  EXPECT_NEAR(detail::partial_bound(or4, Interval(-3, -1), Interval(1, 2), 0),
              1 - std::pow(1 / std::pow(17.0, 0.25), 3), 1e-15);
  // Unknown where the derivative has no bound: a root at 0, a pole.
  EXPECT_TRUE(std::isinf(detail::partial_bound(make(Op::Sqrt), Interval(0, 1), Interval(0.0), 0)));
  EXPECT_TRUE(std::isinf(detail::partial_bound(make(Op::Div), Interval(1, 2), Interval(-1, 1), 0)));
}

}  // namespace
}  // namespace sage
