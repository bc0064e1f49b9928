// Claims (paper 001; FORMULAS.md, "Bounded composition operators"): the
// arc-of-ellipse union G(X, Y) equals X where Y = 0 and Y where X = 0,
// G(0, 0) = 0; G is G1 across the zone borders theta1 and theta2 (the
// one-sided gradients agree); the level-C curve runs along X = C, the
// quarter ellipse and Y = C; with a profile it passes through every
// control point. Bounded potentials lie in [0, 1] and vanish outside the
// support. Intervals enclose the operators' values.

#include "test_support.hpp"

#include <sage/expression/bounded.hpp>

#include <gtest/gtest.h>

#include <iostream>

namespace sage {
namespace {

using test::Point;

const BoundedOp kOps[] = {BoundedOp::Union, BoundedOp::Intersection, BoundedOp::Difference};

BoundedTransition transition(double theta1_degrees, double theta2_degrees) {
  BoundedTransition t;
  t.theta1 = theta1_degrees * M_PI / 180;
  t.theta2 = theta2_degrees * M_PI / 180;
  return t;
}

/// G as a function of (X, Y) = (x, y).
Expr plane_operator(BoundedOp op, const BoundedTransition& t) {
  return bounded_compose(op, Expr::x(), Expr::y(), t, 2);
}

TEST(Bounded, UnionReproducesEachPotentialWhereTheOtherIsZero) {
  const Tape tape(plane_operator(BoundedOp::Union, transition(20, 65)), 2);
  Evaluator<double> g(tape);
  EXPECT_EQ(g.at({0, 0, 0}), 0.0);
  for (double v = 0.01; v <= 1.0; v += 0.01) {
    EXPECT_NEAR(g.at({v, 0, 0}), v, 1e-15);
    EXPECT_NEAR(g.at({0, v, 0}), v, 1e-15);
  }
  const Tape inter(plane_operator(BoundedOp::Intersection, transition(20, 65)), 2);
  Evaluator<double> gi(inter);
  EXPECT_EQ(gi.at({0, 0, 0}), 0.0);
  for (double v = 0.01; v <= 1.0; v += 0.01) {
    EXPECT_EQ(gi.at({v, 0, 0}), 0.0);
    EXPECT_EQ(gi.at({0, v, 0}), 0.0);
  }
}

TEST(Bounded, LevelCurveIsLinesJoinedByAQuarterEllipse) {
  const double C = 0.5, t1 = 20 * M_PI / 180, t2 = 65 * M_PI / 180;
  const Tape uni(plane_operator(BoundedOp::Union, transition(20, 65)), 2);
  const Tape inter(plane_operator(BoundedOp::Intersection, transition(20, 65)), 2);
  Evaluator<double> gu(uni), gi(inter);
  const double k1 = std::tan(t1), k2 = 1 / std::tan(t2);
  for (double s = 0; s <= M_PI / 2; s += M_PI / 64) {
    // Union: centre (C k2, C k1), semi-axes C (1 - k2), C (1 - k1).
    const Point on_union{C * k2 + C * (1 - k2) * std::cos(s), C * k1 + C * (1 - k1) * std::sin(s), 0};
    EXPECT_NEAR(gu.at(on_union), C, 1e-14);
    // Intersection: centre (C / k1, C / k2), the quarter towards the origin.
    const Point on_inter{C / k1 - C * (1 / k1 - 1) * std::cos(s), C / k2 - C * (1 / k2 - 1) * std::sin(s), 0};
    EXPECT_NEAR(gi.at(on_inter), C, 1e-14);
  }
  EXPECT_NEAR(gu.at({C, 0.1, 0}), C, 1e-15);  // the vertical line below theta1
  EXPECT_NEAR(gi.at({1.6, C, 0}), C, 1e-15);  // the horizontal line below theta1 (X >= C cot theta1)
}

/// Largest difference of the gradients on both sides of the zone borders.
double border_gradient_jump(const Expr& g, const BoundedTransition& t) {
  const Tape tape(g, 2);
  Evaluator<Tuple<2, 1>> eval(tape);
  double worst = 0;
  for (double theta : {t.theta1, t.theta2}) {
    for (double r = 0.05; r < 1.0; r += 0.05) {
      const Point p{r * std::cos(theta), r * std::sin(theta), 0};
      const double h = 1e-11;  // across the border, normal to the ray
      const auto a = eval.at({p[0] + h * std::sin(theta), p[1] - h * std::cos(theta), 0}).gradient();
      const auto b = eval.at({p[0] - h * std::sin(theta), p[1] + h * std::cos(theta), 0}).gradient();
      worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1]));
    }
  }
  return worst;
}

TEST(Bounded, GradientIsContinuousAcrossZoneBorders) {
  const BoundedTransition t = transition(15, 70);
  for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
    const double jump = border_gradient_jump(plane_operator(op, t), t);
    std::cout << "[ bounded " << (op == BoundedOp::Union ? "union" : "intersection")
              << " ] gradient jump across the zone borders: " << jump << "\n";
    EXPECT_LT(jump, 1e-8);
  }
  BoundedTransition profiled = t;
  profiled.profile_points = {{0.5, 0.4, 0}, {0.45, 0.6, 0}};
  const double jump = border_gradient_jump(plane_operator(BoundedOp::Union, profiled), t);
  std::cout << "[ bounded union with profile ] gradient jump across the zone borders: " << jump << "\n";
  EXPECT_LT(jump, 1e-8);
  // Test sanity: the same measure sees the kink of plain max.
  EXPECT_GT(border_gradient_jump(max(Expr::x(), Expr::y()), transition(45, 45)), 0.5);
}

TEST(Bounded, ProfileCurvePassesThroughTheControlPoints) {
  // In the (X, Y) = (f1, f2) plane; difference sees Y = 2C - f2 = 1 - y.
  for (BoundedOp op : kOps) {
    BoundedTransition t = transition(10, 80);
    t.profile_points = op == BoundedOp::Difference ? std::vector<Vec3>{{0.7, 0.5, 0}, {0.6, 0.4, 0}}
                                                   : std::vector<Vec3>{{0.5, 0.4, 0}, {0.45, 0.6, 0}};
    const Tape plain(plane_operator(op, transition(10, 80)), 2);
    const Tape shaped(plane_operator(op, t), 2);
    Evaluator<double> g0(plain), g(shaped);
    for (const Vec3& p : t.profile_points) {
      EXPECT_GT(std::abs(g0.at(p) - t.iso), 0.02) << "test setup: without profile the point is off the surface";
      EXPECT_NEAR(g.at(p), t.iso, 1e-14);
    }
  }
  // Two bounded disks in model space, united, shaped through (0, 0.5).
  const Expr a = bounded_potential(1.0 - sqrt(square(Expr::x() + 0.6) + square(Expr::y())), 0.8);
  const Expr b = bounded_potential(1.0 - sqrt(square(Expr::x() - 0.6) + square(Expr::y())), 0.8);
  BoundedTransition t = transition(10, 80);
  t.profile_points = {{0.0, 0.5, 0}};
  const Tape plain(bounded_compose(BoundedOp::Union, a, b, transition(10, 80), 2), 2);
  const Tape shaped(bounded_compose(BoundedOp::Union, a, b, t, 2), 2);
  Evaluator<double> g0(plain), g(shaped);
  EXPECT_GT(g0.at({0.0, 0.5, 0}), 0.6);
  EXPECT_NEAR(g.at({0.0, 0.5, 0}), 0.5, 1e-14);
}

TEST(Bounded, PotentialsStayInUnitRangeAndVanishOutsideTheSupport) {
  const Expr disk = 1.0 - sqrt(square(Expr::x()) + square(Expr::y()));
  const Expr p = bounded_potential(disk, 0.5);
  const Tape tape(std::vector<Expr>{p, disk}, 2);
  Evaluator<double> eval(tape);
  auto rng = test::make_rng(2);
  for (int i = 0; i < 5000; ++i) {
    const Point q = test::random_point(rng, -3, 3, 2);
    eval.evaluate(q.data());
    const double v = eval.result(0), omega = eval.result(1);
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
    if (omega <= -0.5) {
      EXPECT_EQ(v, 0.0);
    }
    if (std::abs(omega) < 1e-3) {
      EXPECT_NEAR(v, 0.5, 2e-3);
    }
  }
  EXPECT_THROW(bounded_potential(disk, 0), std::invalid_argument);
}

TEST(Bounded, OperatorsStayBetweenTheirArgumentsAndIntervalsEncloseThem) {
  const BoundedTransition t = transition(20, 65);
  auto rng = test::make_rng(4);
  for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
    const Tape tape(plane_operator(op, t), 2);
    Evaluator<double> g(tape);
    Evaluator<Interval> boxes(tape);
    for (int i = 0; i < 2000; ++i) {
      const Point p = test::random_point(rng, 0, 1, 2);
      const double v = g.at(p);
      if (op == BoundedOp::Union)
        EXPECT_GE(v, std::max(p[0], p[1]) - 1e-15);
      else
        EXPECT_LE(v, std::min(p[0], p[1]) + 1e-15);
    }
    for (int i = 0; i < 300; ++i) {
      const Point lo = test::random_point(rng, 0, 1, 2);
      const double w = test::uniform(rng, 1e-4, 0.3);
      Interval box[2] = {{lo[0], lo[0] + w}, {lo[1], lo[1] + w}};
      boxes.evaluate_with(box);
      for (int k = 0; k < 10; ++k) {
        const Point p{lo[0] + test::uniform(rng, 0, w), lo[1] + test::uniform(rng, 0, w), 0};
        ASSERT_TRUE(boxes.result().contains(g.at(p)));
      }
    }
  }
}

TEST(Bounded, IntervalsShrinkWithTheBoxOnZoneBordersAndAtTheOrigin) {
  // The zone steps alone give [0, 1] weights on a border at any width, and
  // the whole line next to X = Y = 0; with the linear bounds and the
  // step-free profile of bounded.cpp the enclosure shrinks like the box:
  // width <= K w, with K about the same for w = 1e-3 and 1e-6 (no floor), and
  // K < 4 without a profile.
  BoundedTransition profiled = transition(15, 70);
  profiled.profile_points = {{0.5, 0.4, 0}, {0.45, 0.6, 0}};
  double worst_plain = 0, worst_profiled = 0;
  for (const BoundedTransition& tr : {transition(15, 70), profiled})
    for (BoundedOp op : kOps) {
      if (op != BoundedOp::Union && !tr.profile_points.empty()) continue;  // the points are set for union
      const Tape tape(plane_operator(op, tr), 2);
      Evaluator<Interval> boxes(tape);
      for (double theta : {tr.theta1, tr.theta2, M_PI / 4})
        for (double r : {0.1, 0.5, 0.9}) {
          const double x = r * std::cos(theta), y = r * std::sin(theta);
          // Difference sees Y = 2C - f2: put the box where that Y lies on the border.
          const double f2 = op == BoundedOp::Difference ? 2 * tr.iso - y : y;
          double ratio[2];
          for (int i = 0; i < 2; ++i) {
            const double w = i == 0 ? 1e-3 : 1e-6;
            Interval box[2] = {{x - w / 2, x + w / 2}, {f2 - w / 2, f2 + w / 2}};
            boxes.evaluate_with(box);
            ratio[i] = boxes.result().width() / w;
          }
          // A floor (width not shrinking) would make ratio[1] about 1000 ratio[0].
          EXPECT_LT(ratio[1], 4 * ratio[0] + 2) << "theta " << theta << ", r " << r;
          (tr.profile_points.empty() ? worst_plain : worst_profiled) =
              std::max(tr.profile_points.empty() ? worst_plain : worst_profiled, std::max(ratio[0], ratio[1]));
        }
      // Next to the origin: outside both supports, up to outward rounding.
      if (op != BoundedOp::Difference) {
        Interval tiny[2] = {{-1e-300, 1e-300}, {-1e-300, 1e-300}};
        boxes.evaluate_with(tiny);
        EXPECT_LT(boxes.result().width(), 1e-290);
      }
    }
  std::cout << "[ bounded operators ] largest enclosure width / box width near zone borders: " << worst_plain
            << " (with a profile: " << worst_profiled << ")\n";
  EXPECT_LT(worst_plain, 4.0);
}

TEST(Bounded, BadParametersAreRejected) {
  EXPECT_THROW(plane_operator(BoundedOp::Union, transition(0, 60)), std::invalid_argument);
  EXPECT_THROW(plane_operator(BoundedOp::Union, transition(30, 45)), std::invalid_argument);
  BoundedTransition t = transition(20, 70);
  t.profile_points = {{0.9, 0.01, 0}};  // below theta1
  EXPECT_THROW(plane_operator(BoundedOp::Union, t), std::invalid_argument);
}

}  // namespace
}  // namespace sage
