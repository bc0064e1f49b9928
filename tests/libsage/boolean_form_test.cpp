// The Boolean skeleton of a field (boolean_form.hpp): the pieces found are
// the smooth leaves, and the formula of their signs agrees with the sign of
// the field itself at random points, for every R-function system, min/max,
// negation and positive or negative scaling; restricting the formula to a
// box by the pieces' enclosures keeps it true to the field there.
#include "test_support.hpp"

#include <sage/expression/boolean_form.hpp>
#include <sage/expression/normalize.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/scalars/interval.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

using test::Point;

/// A CSG part with a hole, a union, a min/max node and scalings.
Expr part(const RSystem& s) {
  const Expr plate = box({-0.9, -0.7, -0.6}, {0.8, 0.75, 0.65}, 3, s);
  const Expr hole = cylinder({0.1, -0.05, 0}, {0, 0.3, 1}, 0.3);
  const Expr boss = ball({0.7, 0.6, 0.5}, 0.35, 3);
  const Expr slot = max(halfspace({0, 0, 0.3}, {0, 0, -1}, 3), -2.0 * ball({-0.5, 0.2, 0.5}, 0.2, 3));
  return r_or(r_and(plate, -hole, s), 0.5 * r_and(boss, slot, RSystem::min_max()), s);
}

/// The pieces' signs at p, and whether the formula holds there; false when
/// some piece is too close to 0 for its sign to be sure.
bool formula_at(const BooleanForm& form, const std::vector<Tape>& tapes, const Point& p, bool& holds) {
  std::vector<char> inside(form.pieces.size());
  for (std::size_t i = 0; i < tapes.size(); ++i) {
    Evaluator<double> e(tapes[i]);
    const double v = e.at(p);
    if (std::abs(v) < 1e-9) return false;
    inside[i] = v > 0 ? 1 : 0;
  }
  holds = form.formula.holds(inside);
  return true;
}

TEST(BooleanForm, PiecesAreTheSmoothLeaves) {
  const RSystem r0 = RSystem::r0();
  // A box: its 6 faces.
  EXPECT_EQ(boolean_form(box({-1, -1, -1}, {1, 1, 1}, 3, r0)).pieces.size(), 6u);
  // A normalized field is not Boolean at its root: one piece.
  const Expr normalized = normalize(box({-1, -1, 0}, {1, 1, 0}, 2, r0), 2);
  EXPECT_EQ(boolean_form(normalized).pieces.size(), 1u);
  // A shared subtree is one piece; a scaled or negated one too.
  const Expr disk = ball({0, 0, 0}, 1, 2);
  const BooleanForm shared = boolean_form(r_and(disk, -3.0 * r_or(disk, Expr::x(), r0), r0));
  EXPECT_EQ(shared.pieces.size(), 2u);
  // The part: 6 faces, the hole, the boss, the slot's plane and ball.
  EXPECT_EQ(boolean_form(part(r0)).pieces.size(), 10u);
  // A constant field is a constant formula.
  EXPECT_TRUE(boolean_form(Expr(-1.0)).formula.is_constant());
  EXPECT_FALSE(boolean_form(Expr(-1.0)).formula.constant_value());
}

TEST(BooleanForm, FormulaAgreesWithTheFieldsSign) {
  auto rng = test::make_rng(7);
  for (const RSystem s : {RSystem::r0(), RSystem::min_max(), RSystem::r_p(4), RSystem::r_alpha(0.5), RSystem::r_m(2),
                          RSystem::r_alpha_variable()}) {
    const Expr field = part(s);
    const BooleanForm form = boolean_form(field);
    std::vector<Tape> tapes;
    for (const Expr& p : form.pieces) tapes.emplace_back(p, 3);
    const Tape whole(field, 3);
    Evaluator<double> eval(whole);
    int checked = 0, inside = 0;
    for (int k = 0; k < 4000; ++k) {
      const Point p = test::random_point(rng, -1.1, 1.1);
      const double w = eval.at(p);
      bool holds = false;
      if (std::abs(w) < 1e-9 || !formula_at(form, tapes, p, holds)) continue;
      ++checked;
      inside += holds ? 1 : 0;
      ASSERT_EQ(holds, w > 0) << s.name() << " at (" << p[0] << ", " << p[1] << ", " << p[2] << "): omega " << w;
    }
    EXPECT_GT(checked, 3900) << s.name();
    EXPECT_GT(inside, 400) << s.name();  // both answers are exercised
    EXPECT_GT(checked - inside, 400) << s.name();
  }
}

TEST(BooleanForm, RestrictionToABoxKeepsTheFormulaTrue) {
  auto rng = test::make_rng(11);
  const BooleanForm form = boolean_form(part(RSystem::r0()));
  std::vector<Tape> tapes;
  for (const Expr& p : form.pieces) tapes.emplace_back(p, 3);
  int folded = 0, constant = 0;
  for (int k = 0; k < 300; ++k) {
    const Point c = test::random_point(rng, -1.0, 1.0);
    const double half = test::uniform(rng, 0.02, 0.4);
    std::array<Interval, 3> box{};
    for (int a = 0; a < 3; ++a) box[a] = Interval(c[a] - half, c[a] + half);
    const BooleanFormula restricted = form.formula.restricted([&](std::size_t i) {
      Evaluator<Interval> e(tapes[i]);
      e.evaluate_with(box.data());
      const Interval v = e.result();
      return v.lo > 0 ? 1 : (v.hi < 0 ? -1 : 0);
    });
    folded += restricted.pieces().size() < form.pieces.size() ? 1 : 0;
    constant += restricted.is_constant() ? 1 : 0;
    for (int j = 0; j < 20; ++j) {
      Point p{};
      for (int a = 0; a < 3; ++a) p[a] = test::uniform(rng, box[a].lo, box[a].hi);
      bool holds = false;
      if (!formula_at(form, tapes, p, holds)) continue;
      std::vector<char> inside(form.pieces.size());
      for (std::size_t i = 0; i < tapes.size(); ++i) {
        Evaluator<double> e(tapes[i]);
        inside[i] = e.at(p) > 0 ? 1 : 0;
      }
      ASSERT_EQ(restricted.holds(inside), holds);
      // The restricted formula reads only pieces whose sign is unknown.
      for (const std::uint32_t i : restricted.pieces()) {
        Evaluator<Interval> e(tapes[i]);
        e.evaluate_with(box.data());
        EXPECT_TRUE(e.result().contains_zero());
      }
    }
  }
  EXPECT_GT(folded, 250);
  EXPECT_GT(constant, 30);
}

}  // namespace
}  // namespace sage
