// Claims (issue 5; paper 001 section 6; bounded.hpp, "Sharp transition"):
// the sharp bounded union G(X, Y) equals X where Y = 0 and Y where X = 0,
// G(0, 0) = 0, and outside the zone [theta1, theta2] it is X or Y like the
// smooth operator; its level-C curve is the corner max(X, Y) = C
// (intersection: min(X, Y) = C) while the other levels are rounded arcs;
// the field is G1 across the zone borders and across the tangent points
// where the arcs leave the straight lines; tuple derivatives agree with
// finite differences; intervals enclose the values and shrink with the box
// where the zone steps switch; difference is intersection with 2C - f2;
// a profile is refused.

#include "test_support.hpp"

#include <sage/expression/bounded.hpp>
#include <sage/expression/derivative.hpp>

#include <gtest/gtest.h>

#include <iostream>

namespace sage {
namespace {

using test::Point;

BoundedTransition sharp(double theta1_degrees, double theta2_degrees, double iso = 0.5) {
  BoundedTransition t;
  t.theta1 = theta1_degrees * M_PI / 180;
  t.theta2 = theta2_degrees * M_PI / 180;
  t.iso = iso;
  t.sharp = true;
  return t;
}

Expr plane_operator(BoundedOp op, const BoundedTransition& t) {
  return bounded_compose(op, Expr::x(), Expr::y(), t, 2);
}

/// Where the arc of level c leaves the vertical line X = c (bounded.cpp:
/// X - Y = b (1 - c / C) s(X, Y) for c <= C, Y - C = tan theta1 (c - C)
/// above), with b = 1 - tan theta1 and s the chord gauge.
double tangent_height(double c, const BoundedTransition& t) {
  const double a = 1 - 1 / std::tan(t.theta2), b = 1 - std::tan(t.theta1), C = t.iso;
  if (c >= C) return C + std::tan(t.theta1) * (c - C);
  const double alpha = b / (a + b - a * b), beta = a / (a + b - a * b), tau = 1 - c / C;
  return c * (1 - b * alpha * tau) / (1 + b * beta * tau);
}

TEST(BoundedSharp, ReproducesEachPotentialWhereTheOtherIsZero) {
  for (const BoundedTransition& t : {sharp(20, 65), sharp(10, 80, 0.3), sharp(2, 88, 0.08), sharp(42, 48, 0.92)}) {
    const Tape uni(plane_operator(BoundedOp::Union, t), 2);
    const Tape inter(plane_operator(BoundedOp::Intersection, t), 2);
    Evaluator<double> gu(uni), gi(inter);
    EXPECT_EQ(gu.at({0, 0, 0}), 0.0);
    EXPECT_EQ(gi.at({0, 0, 0}), 0.0);
    for (double v = 0.01; v <= 1.2; v += 0.01) {
      EXPECT_NEAR(gu.at({v, 0, 0}), v, 1e-15);
      EXPECT_NEAR(gu.at({0, v, 0}), v, 1e-15);
      EXPECT_EQ(gi.at({v, 0, 0}), 0.0);
      EXPECT_EQ(gi.at({0, v, 0}), 0.0);
    }
  }
}

TEST(BoundedSharp, OutsideTheZoneTheLevelCurvesAreTheStraightLines) {
  const BoundedTransition t = sharp(20, 65);
  const Tape uni(plane_operator(BoundedOp::Union, t), 2);
  const Tape inter(plane_operator(BoundedOp::Intersection, t), 2);
  Evaluator<double> gu(uni), gi(inter);
  auto rng = test::make_rng(11);
  for (int i = 0; i < 2000; ++i) {
    const double r = test::uniform(rng, 0.01, 1.5);
    const bool below = i % 2 == 0;
    const double theta = below ? test::uniform(rng, 0, t.theta1) : test::uniform(rng, t.theta2, M_PI / 2);
    const Point p{r * std::cos(theta), r * std::sin(theta), 0};
    EXPECT_NEAR(gu.at(p), below ? p[0] : p[1], 1e-15 * r);
    EXPECT_NEAR(gi.at(p), below ? p[1] : p[0], 1e-15 * r);
  }
}

TEST(BoundedSharp, LevelCIsTheCornerAndOtherLevelsAreRounded) {
  for (const BoundedTransition& t :
       {sharp(20, 65), sharp(10, 80, 0.3), sharp(35, 55, 0.7), sharp(2, 88, 0.08), sharp(42, 48, 0.92)}) {
    const double C = t.iso, k1 = std::tan(t.theta1), k2 = std::tan(t.theta2);
    const Tape uni(plane_operator(BoundedOp::Union, t), 2);
    const Tape inter(plane_operator(BoundedOp::Intersection, t), 2);
    Evaluator<double> gu(uni), gi(inter);
    double worst = 0;
    for (int i = 0; i <= 40; ++i) {
      const double u = i / 40.0;
      // Union: X = C from theta1 up to the corner, Y = C from the corner to theta2.
      worst = std::max(worst, std::abs(gu.at({C, C * (k1 + (1 - k1) * u), 0}) - C));
      worst = std::max(worst, std::abs(gu.at({C * (1 / k2 + (1 - 1 / k2) * u), C, 0}) - C));
      // Intersection: Y = C out to theta1 (X = C / tan theta1), X = C up to theta2.
      worst = std::max(worst, std::abs(gi.at({C + (C / k1 - C) * u, C, 0}) - C));
      worst = std::max(worst, std::abs(gi.at({C, C + (C * k2 - C) * u, 0}) - C));
    }
    std::cout << "[ sharp bounded, theta " << t.theta1 * 180 / M_PI << "-" << t.theta2 * 180 / M_PI << ", C " << C
              << " ] largest |G - C| on the corner: " << worst << "\n";
    EXPECT_LT(worst, 1e-12);
    // Other levels are rounded: on the diagonal the union exceeds max(X, Y)
    // and the intersection stays below min(X, Y), by at least a tenth of the
    // smooth operator's rounding at the same point, and by an amount that
    // shrinks to 0 as the level approaches C (the corner).
    BoundedTransition smooth = t;
    smooth.sharp = false;
    const Tape su(plane_operator(BoundedOp::Union, smooth), 2);
    const Tape si(plane_operator(BoundedOp::Intersection, smooth), 2);
    Evaluator<double> gsu(su), gsi(si);
    for (double f : {0.5, 1.5}) {
      const double v = f * C;
      EXPECT_GT(gu.at({v, v, 0}) - v, 0.1 * (gsu.at({v, v, 0}) - v)) << f;
      EXPECT_GT(v - gi.at({v, v, 0}), 0.1 * (v - gsi.at({v, v, 0}))) << f;
    }
    const double near_union = gu.at({0.999 * C, 0.999 * C, 0}) - 0.999 * C;
    EXPECT_GT(near_union, 0);
    EXPECT_LT(near_union, 0.01 * (gsu.at({C, C, 0}) - C));
    // The smooth operator rounds level C too (test sanity).
    EXPECT_GT(gsu.at({C, C, 0}) - C, 0.01 * C);
  }
}

/// Largest difference of the gradients at p + h n and p - h n.
double gradient_jump(Evaluator<Tuple<2, 1>>& eval, const Point& p, double nx, double ny, double h) {
  const auto a = eval.at({p[0] + h * nx, p[1] + h * ny, 0}).gradient();
  const auto b = eval.at({p[0] - h * nx, p[1] - h * ny, 0}).gradient();
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

TEST(BoundedSharp, GradientIsContinuousAcrossZoneBordersAndTangentPoints) {
  const BoundedTransition t = sharp(15, 70);
  const double C = t.iso;
  for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
    const char* name = op == BoundedOp::Union ? "union" : "intersection";
    const Tape tape(plane_operator(op, t), 2);
    Evaluator<Tuple<2, 1>> eval(tape);
    Evaluator<double> g(tape);
    double rays = 0, tangents = 0, at_1e7 = 0, at_1e9 = 0;
    // Across the rays theta1 and theta2 (levels r cos theta1 etc., never C on this grid).
    for (double theta : {t.theta1, t.theta2})
      for (double r = 0.05; r < 1.2; r += 0.05)
        rays = std::max(rays, gradient_jump(eval, {r * std::cos(theta), r * std::sin(theta), 0}, std::sin(theta),
                                            -std::cos(theta), 1e-11));
    // Across the tangent points of levels c != C (the true zone borders),
    // on X = c and by symmetry of the construction on Y = c for theta
    // mirrored; here the vertical lines.
    for (double c = 0.04; c < 1.2; c += 0.04) {
      if (std::abs(c - C) < 0.03) continue;
      const double yt = tangent_height(c, t);
      const Point p{c, yt, 0};
      // Non-vacuous: straight (G = X, or Y for intersection) just below, curved above.
      const double straight = op == BoundedOp::Union ? c : yt - 1e-6;
      EXPECT_NEAR(g.at({c, yt - 1e-6, 0}), straight, 1e-14) << name << " c " << c;
      const double above = g.at({c, yt + 1e-3, 0});
      EXPECT_GT(op == BoundedOp::Union ? above - c : (yt + 1e-3) - above, 1e-9) << name << " c " << c;
      tangents = std::max(tangents, gradient_jump(eval, p, 0, 1, 1e-11));
      at_1e7 = std::max(at_1e7, gradient_jump(eval, p, 0, 1, 1e-7));
      at_1e9 = std::max(at_1e9, gradient_jump(eval, p, 0, 1, 1e-9));
    }
    std::cout << "[ sharp bounded " << name << " ] gradient jump across theta1/theta2: " << rays
              << ", across the tangent points: " << tangents << " (at +-1e-9: " << at_1e9 << ", +-1e-7: " << at_1e7
              << ")\n";
    EXPECT_LT(rays, 1e-8);
    EXPECT_LT(tangents, 1e-8);
    // Linear in the offset: a jump J would give about J at every offset.
    EXPECT_LT(at_1e9, 0.05 * at_1e7);
  }
  // Test sanity: the same measure sees the corner of the level C.
  const Tape tape(plane_operator(BoundedOp::Union, t), 2);
  Evaluator<Tuple<2, 1>> eval(tape);
  EXPECT_GT(gradient_jump(eval, {C, C, 0}, 1, 1, 1e-9), 0.3);
}

TEST(BoundedSharp, TupleDerivativesMatchFiniteDifferencesAndLieInTheUnitRange) {
  for (const BoundedTransition& t : {sharp(20, 65), sharp(10, 80, 0.3), sharp(2, 88, 0.08), sharp(42, 48, 0.92)}) {
    for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
      const Tape tape(plane_operator(op, t), 2);
      Evaluator<double> g(tape);
      Evaluator<Tuple<2, 1>> tuples(tape);
      auto rng = test::make_rng(7);
      double worst = 0;
      int tested = 0;
      while (tested < 1000) {
        const Point p = test::random_point(rng, 0.01, 1.2, 2);
        if (std::hypot(p[0] - t.iso, p[1] - t.iso) < 0.05) continue;  // the corner
        ++tested;
        const auto grad = tuples.at(p).gradient();
        EXPECT_NEAR(tuples.at(p).value(), g.at(p), 1e-13);
        for (int axis = 0; axis < 2; ++axis) {
          const double fd = test::central_difference([&](const Point& q) { return g.at(q); }, p, axis, 1e-6);
          worst = std::max(worst, std::abs(grad[axis] - fd));
          EXPECT_GE(grad[axis], -1e-12);
          EXPECT_LE(grad[axis], 1 + 1e-12);
        }
      }
      std::cout << "[ sharp bounded " << (op == BoundedOp::Union ? "union" : "intersection") << ", C " << t.iso
                << " ] largest |tuple gradient - central difference|: " << worst << "\n";
      EXPECT_LT(worst, 1e-6);
    }
  }
}

/// Mirror of tangent_height: where the arc of level c leaves Y = c.
double tangent_abscissa(double c, const BoundedTransition& t) {
  const double a = 1 - 1 / std::tan(t.theta2), b = 1 - std::tan(t.theta1), C = t.iso;
  if (c >= C) return C + (c - C) / std::tan(t.theta2);
  const double alpha = b / (a + b - a * b), beta = a / (a + b - a * b), tau = 1 - c / C;
  return c * (1 - a * beta * tau) / (1 + a * alpha * tau);
}

TEST(BoundedSharp, SecondOrderTuplesAndSymbolicDerivativesAgree) {
  // Away from the tangent points (where the curvature of the level curves,
  // hence the second derivatives, jump: the field is G1, not C2) and from
  // the corner: Hessians of Tuple<2, 2> against central differences of
  // the tuple gradients, and the symbolic derivatives against the tuples.
  const BoundedTransition t = sharp(20, 65);
  for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
    const Expr g = plane_operator(op, t);
    const Tape tape(g, 2);
    const Tape symbolic(gradient(g, 2), 2);
    Evaluator<Tuple<2, 2>> second(tape);
    Evaluator<Tuple<2, 1>> first(tape);
    Evaluator<double> grad(symbolic);
    auto rng = test::make_rng(13);
    double worst_hessian = 0, worst_symbolic = 0;
    int tested = 0;
    while (tested < 500) {
      const Point p = test::random_point(rng, 0.02, 1.2, 2);
      if (std::hypot(p[0] - t.iso, p[1] - t.iso) < 0.05) continue;
      if (std::abs(p[1] - tangent_height(p[0], t)) < 2e-3 || std::abs(p[0] - tangent_abscissa(p[1], t)) < 2e-3)
        continue;
      ++tested;
      const Tuple<2, 2> h = second.at(p);
      grad.evaluate(p.data());
      for (int i = 0; i < 2; ++i) {
        worst_symbolic = std::max(worst_symbolic, std::abs(grad.result(i) - h.gradient()[i]));
        for (int j = 0; j < 2; ++j) {
          MultiIndex<2> alpha{0, 0};
          ++alpha[i], ++alpha[j];
          const double fd =
              test::central_difference([&](const Point& q) { return first.at(q).gradient()[i]; }, p, j, 1e-6);
          worst_hessian = std::max(worst_hessian, std::abs(h.derivative(alpha) - fd) / std::max(1.0, std::abs(fd)));
        }
      }
    }
    std::cout << "[ sharp bounded " << (op == BoundedOp::Union ? "union" : "intersection")
              << " ] Hessian against differences of gradients (relative): " << worst_hessian
              << ", symbolic against tuple gradient: " << worst_symbolic << "\n";
    EXPECT_LT(worst_hessian, 1e-5);
    EXPECT_LT(worst_symbolic, 1e-12);
  }
}

TEST(BoundedSharp, StaysBetweenItsArgumentsAndIntervalsEncloseIt) {
  auto rng = test::make_rng(5);
  for (const BoundedTransition& t : {sharp(20, 65), sharp(10, 80, 0.3), sharp(2, 88, 0.08), sharp(42, 48, 0.92)})
    for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection, BoundedOp::Difference}) {
      const Tape tape(plane_operator(op, t), 2);
      Evaluator<double> g(tape);
      Evaluator<Interval> boxes(tape);
      Evaluator<Tuple<2, 1>> tuples(tape);
      for (int i = 0; i < 500; ++i) {  // finite everywhere, negative and large inputs included
        const Point p = test::random_point(rng, -1, 3, 2);
        const auto grad = tuples.at(p).gradient();
        ASSERT_TRUE(std::isfinite(g.at(p)) && std::isfinite(grad[0]) && std::isfinite(grad[1])) << p[0] << ", " << p[1];
      }
      for (int i = 0; i < 2000; ++i) {
        const Point p = test::random_point(rng, 0, 1.2, 2);
        if (op == BoundedOp::Union) {
          EXPECT_GE(g.at(p), std::max(p[0], p[1]));
        } else if (op == BoundedOp::Intersection) {
          EXPECT_LE(g.at(p), std::min(p[0], p[1]));
        }
      }
      for (int i = 0; i < 400; ++i) {
        const Point lo = test::random_point(rng, -0.2, 1.2, 2);
        const double w = std::exp(test::uniform(rng, std::log(1e-6), std::log(0.5)));
        Interval box[2] = {{lo[0], lo[0] + w}, {lo[1], lo[1] + w}};
        boxes.evaluate_with(box);
        for (int k = 0; k < 12; ++k) {
          const Point p{lo[0] + (k < 4 ? (k & 1) * w : test::uniform(rng, 0, w)),
                        lo[1] + (k < 4 ? (k >> 1) * w : test::uniform(rng, 0, w)), 0};
          ASSERT_TRUE(boxes.result().contains(g.at(p))) << "box at " << lo[0] << ", " << lo[1] << ", width " << w;
        }
      }
    }
}

TEST(BoundedSharp, IntervalsShrinkWithTheBoxWhereTheStepsSwitch) {
  // Boxes centred on the tangent points, the rays, the line max(X, Y) = C
  // and the corner (where the steps switch), and on the diagonal inside
  // the zone: the enclosure width / box width stays about the same from
  // w = 1e-3 C to 1e-6 C (a floor would multiply it by 1000).
  double worst_switch = 0, worst_inside = 0;
  for (const BoundedTransition& t : {sharp(15, 70), sharp(2, 88, 0.08), sharp(42, 48, 0.92)}) {
    const double C = t.iso;
    std::vector<Point> centres{{0.5 * C, 0.5 * C, 0}, {1.5 * C, 1.5 * C, 0}};  // inside: the first two
    centres.insert(centres.end(), {{C, C, 0}, {C, 0.3 * C, 0}, {0.3 * C, C, 0}});
    for (double f : {0.2, 0.6, 0.9, 1.4, 2.0}) centres.push_back({f * C, tangent_height(f * C, t), 0});
    for (double theta : {t.theta1, t.theta2})
      for (double r : {0.4 * C, 1.8 * C}) centres.push_back({r * std::cos(theta), r * std::sin(theta), 0});
    for (BoundedOp op : {BoundedOp::Union, BoundedOp::Intersection}) {
      const Tape tape(plane_operator(op, t), 2);
      Evaluator<Interval> boxes(tape);
      for (std::size_t c = 0; c < centres.size(); ++c) {
        const Point& p = centres[c];
        double ratio[2];
        for (int i = 0; i < 2; ++i) {
          const double w = i == 0 ? 1e-3 * C : 1e-6 * C;
          Interval box[2] = {{p[0] - w / 2, p[0] + w / 2}, {p[1] - w / 2, p[1] + w / 2}};
          boxes.evaluate_with(box);
          ratio[i] = boxes.result().width() / w;
        }
        EXPECT_LT(ratio[1], 4 * ratio[0] + 2) << "at " << p[0] << ", " << p[1] << ", C " << C;
        double& worst = c < 2 ? worst_inside : worst_switch;
        worst = std::max({worst, ratio[0], ratio[1]});
      }
      Interval tiny[2] = {{-1e-300, 1e-300}, {-1e-300, 1e-300}};
      boxes.evaluate_with(tiny);
      EXPECT_LT(boxes.result().width(), 1e-290);
    }
  }
  std::cout << "[ sharp bounded ] largest enclosure width / box width where the steps switch: " << worst_switch
            << ", inside the zone: " << worst_inside << "\n";
  EXPECT_LT(worst_switch, 8.0);
}

TEST(BoundedSharp, DifferenceIsIntersectionWithTheReflectedSecondPotential) {
  for (const BoundedTransition& t : {sharp(20, 65), sharp(10, 80, 0.3), sharp(2, 88, 0.08), sharp(42, 48, 0.92)}) {
    const Expr diff = plane_operator(BoundedOp::Difference, t);
    const Expr inter = bounded_compose(BoundedOp::Intersection, Expr::x(), 2 * t.iso - Expr::y(), t, 2);
    const Tape tape(std::vector<Expr>{diff, inter}, 2);
    Evaluator<double> eval(tape);
    auto rng = test::make_rng(9);
    for (int i = 0; i < 2000; ++i) {
      const Point p = test::random_point(rng, 0, 1, 2);
      eval.evaluate(p.data());
      EXPECT_EQ(eval.result(0), eval.result(1));
    }
    // f2 = 0 leaves f1 = 0.1 C: (f1, 2C) lies above theta2.
    Evaluator<double> g(tape);
    EXPECT_NEAR(g.at({0.1 * t.iso, 0, 0}), 0.1 * t.iso, 1e-15);
  }
}

TEST(BoundedSharp, BadParametersAreRejected) {
  BoundedTransition t = sharp(20, 70);
  t.profile_points = {{0.5, 0.4, 0}};
  try {
    plane_operator(BoundedOp::Union, t);
    FAIL() << "profile accepted with the sharp transition";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sharp"), std::string::npos) << e.what();
  }
  EXPECT_THROW(plane_operator(BoundedOp::Intersection, sharp(0, 60)), std::invalid_argument);
  EXPECT_THROW(plane_operator(BoundedOp::Union, sharp(30, 90)), std::invalid_argument);
  EXPECT_THROW(plane_operator(BoundedOp::Difference, sharp(20, 70, 1.0)), std::invalid_argument);
  EXPECT_THROW(plane_operator(BoundedOp::Union, sharp(20, 70, 0.0)), std::invalid_argument);
}

}  // namespace
}  // namespace sage
