// Claims (paper 000; FORMULAS.md, "Soft blending"): with exact signed
// distances as arguments, the blended union, intersection and difference
// stay Lipschitz-1 for all six blend functions (-1 <= fb' <= 0); they are
// C1 across f1 = f2 (fb'(0) = -1/2); functions 3 to 6 are local (no change
// past their threshold) and 6 has a kink there; n = 0 is plain min/max.

#include "test_support.hpp"

#include <sage/expression/blend.hpp>

#include <gtest/gtest.h>

#include <iostream>

namespace sage {
namespace {

using test::Point;

const BlendFunction kAllBlends[] = {BlendFunction::Sqrt, BlendFunction::Rational,  BlendFunction::CosOver,
                                    BlendFunction::Cos,  BlendFunction::Quadratic, BlendFunction::Linear};

Expr sphere_distance(const Point& c, double r) {
  return r - sqrt(square(Expr::x() - c[0]) + square(Expr::y() - c[1]) + square(Expr::z() - c[2]));
}

/// A nested tree of exact-distance primitives with every blended operator.
Expr nested_tree(BlendFunction fb, double n) {
  const Expr a = sphere_distance({-0.4, 0, 0}, 0.7), b = sphere_distance({0.4, 0.1, 0}, 0.6);
  const Expr c = sphere_distance({0, 0.5, 0.2}, 0.5), plane = 0.2 - Expr::z();  // below z = 0.2
  const Expr body = blend_union(blend_union(a, b, fb, n), c, fb, n);
  return blend_difference(blend_intersection(body, plane, fb, n), sphere_distance({0, 0, -0.6}, 0.3), fb, n);
}

double distance(const Point& p, const Point& q) {
  return std::sqrt(square(p[0] - q[0]) + square(p[1] - q[1]) + square(p[2] - q[2]));
}

TEST(Blend, NestedTreesOfDistancesStayLipschitzOne) {
  for (BlendFunction fb : kAllBlends) {
    const Tape tape(nested_tree(fb, 0.25), 3);
    Evaluator<double> eval(tape);
    auto rng = test::make_rng(static_cast<int>(fb));
    double worst = 0;
    for (int i = 0; i < 100000; ++i) {
      const Point p = test::random_point(rng, -1.5, 1.5);
      // Half the pairs close together, where a kink would show.
      const double spread = i % 2 ? 1e-3 : 1.0;
      Point q = p;
      for (double& v : q) v += test::uniform(rng, -spread, spread);
      const double fp = eval.at(p), fq = eval.at(q);
      worst = std::max(worst, std::abs(fp - fq) / distance(p, q));
    }
    std::cout << "[ blend " << static_cast<int>(fb) << " ] max |f(p) - f(q)| / |p - q| = " << worst << "\n";
    EXPECT_LE(worst, 1.0 + 1e-9) << "blend function " << static_cast<int>(fb);
    EXPECT_GT(worst, 0.9) << "test setup: the pairs should reach the unit slope of the distances";
  }
}

/// One-sided gradients across f1 = f2 (the plane x = 0 for two equal
/// spheres mirrored in it) and across the locality threshold.
struct Sides {
  double across_equal = 0;
  double across_threshold = 0;
};

Sides gradient_jumps(BlendFunction fb, double n) {
  const Expr f1 = sphere_distance({-0.5, 0, 0}, 1.0), f2 = sphere_distance({0.5, 0, 0}, 1.0);
  const Tape tape(blend_union(f1, f2, fb, n), 3);
  Evaluator<Tuple<3, 1>> eval(tape);
  auto jump = [&](const Point& p, const Point& direction, double h) {
    Point lo = p, hi = p;
    for (int i = 0; i < 3; ++i) lo[i] -= h * direction[i], hi[i] += h * direction[i];
    const auto g_lo = eval.at(lo).gradient(), g_hi = eval.at(hi).gradient();
    return std::sqrt(square(g_lo[0] - g_hi[0]) + square(g_lo[1] - g_hi[1]) + square(g_lo[2] - g_hi[2]));
  };
  Sides s;
  auto rng = test::make_rng(7);
  for (int i = 0; i < 200; ++i) {
    const double y = test::uniform(rng, -0.5, 0.5), z = test::uniform(rng, -0.5, 0.5);
    s.across_equal = std::max(s.across_equal, jump({0, y, z}, {1, 0, 0}, 1e-10));
    // On y = z = 0, |f1 - f2| = |2 x| for |x| < 0.5: the threshold is at x = t / 2.
    const double t = blend_threshold(fb, n);
    if (std::isfinite(t) && t < 1)
      s.across_threshold = std::max(s.across_threshold, jump({t / 2, 0, 0}, {1, 0, 0}, 1e-10));
  }
  return s;
}

TEST(Blend, UnionIsC1AcrossEqualArguments) {
  for (BlendFunction fb : kAllBlends) {
    const Sides s = gradient_jumps(fb, 0.2);
    std::cout << "[ blend " << static_cast<int>(fb) << " ] gradient jump across f1 = f2: " << s.across_equal
              << ", across the threshold: " << s.across_threshold << "\n";
    EXPECT_LT(s.across_equal, 1e-8) << "blend function " << static_cast<int>(fb);
    if (fb == BlendFunction::Linear)
      EXPECT_GT(s.across_threshold, 0.4) << "function 6 has a kink at its threshold";
    else
      EXPECT_LT(s.across_threshold, 1e-8) << "blend function " << static_cast<int>(fb);
  }
  // Plain max has the kink that blending removes.
  EXPECT_GT(gradient_jumps(BlendFunction::Sqrt, 0.0).across_equal, 1.0);
}

TEST(Blend, LocalFunctionsChangeNothingPastTheirThreshold) {
  const Expr f1 = sphere_distance({-0.5, 0, 0}, 1.0), f2 = sphere_distance({0.5, 0.2, 0}, 0.8);
  const Tape plain(std::vector<Expr>{max(f1, f2), min(f1, f2), min(f1, -f2), abs(f1 - f2), abs(f1 + f2)}, 3);
  Evaluator<double> ref(plain);
  for (BlendFunction fb : kAllBlends) {
    const double n = 0.1, t = blend_threshold(fb, n);
    const Tape tape(std::vector<Expr>{blend_union(f1, f2, fb, n), blend_intersection(f1, f2, fb, n),
                                      blend_difference(f1, f2, fb, n)},
                    3);
    Evaluator<double> eval(tape);
    auto rng = test::make_rng(11);
    int past = 0, changed_past = 0;
    for (int i = 0; i < 20000; ++i) {
      const Point p = test::random_point(rng, -2, 2);
      ref.evaluate(p.data());
      eval.evaluate(p.data());
      for (int k = 0; k < 3; ++k) {
        const double x = ref.result(k < 2 ? 3 : 4);
        if (x < t * (1 + 1e-12) + 1e-12) continue;
        ++past;
        if (eval.result(k) != ref.result(k)) ++changed_past;
      }
    }
    if (std::isfinite(t)) {
      EXPECT_GT(past, 1000);
      EXPECT_EQ(changed_past, 0) << "blend function " << static_cast<int>(fb);
    } else {
      // 1 and 2 never reach 0: they add material everywhere.
      eval.evaluate(Point{5, 5, 5}.data());
      ref.evaluate(Point{5, 5, 5}.data());
      EXPECT_GT(eval.result(0), ref.result(0)) << "blend function " << static_cast<int>(fb);
    }
  }
}

TEST(Blend, AmountZeroIsPlainMinMaxAndSmallAmountsApproachIt) {
  const Expr f1 = sphere_distance({-0.5, 0, 0}, 1.0), f2 = sphere_distance({0.5, 0.2, 0}, 0.8);
  const Tape plain(std::vector<Expr>{max(f1, f2), min(f1, f2), min(f1, -f2)}, 3);
  Evaluator<double> ref(plain);
  for (BlendFunction fb : kAllBlends) {
    for (double n : {0.0, 1e-10}) {
      const Tape tape(std::vector<Expr>{blend_union(f1, f2, fb, n), blend_intersection(f1, f2, fb, n),
                                        blend_difference(f1, f2, fb, n)},
                      3);
      Evaluator<double> eval(tape);
      auto rng = test::make_rng(3);
      double worst = 0;
      for (int i = 0; i < 2000; ++i) {
        const Point p = test::random_point(rng, -2, 2);
        ref.evaluate(p.data());
        eval.evaluate(p.data());
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(eval.result(k) - ref.result(k)));
      }
      // fb(0, n) is at most n (1 + sqrt(3)/2) (function 3), or sqrt(n) / 2 (function 1).
      EXPECT_LE(worst, n == 0 ? 0.0 : 1e-5) << "blend function " << static_cast<int>(fb) << ", n = " << n;
    }
  }
}

TEST(Blend, BlendFunctionsHaveThePaperSlopeAtZero) {
  const Expr x = Expr::x();
  for (BlendFunction fb : kAllBlends) {
    const Tape tape(blend_amount(x, fb, 0.3), 1);
    Evaluator<Tuple<1, 1>> eval(tape);
    EXPECT_NEAR(eval.at({0, 0, 0}).gradient()[0], -0.5, 1e-12) << "blend function " << static_cast<int>(fb);
    // Non-increasing with slope in [-1, 0] on x >= 0.
    for (double v = 0; v < 3; v += 0.01) {
      const double slope = eval.at({v, 0, 0}).gradient()[0];
      EXPECT_LE(slope, 1e-12);
      EXPECT_GE(slope, -1 - 1e-12);
    }
  }
  EXPECT_THROW(blend_function_from_number(7), std::invalid_argument);
  EXPECT_THROW(blend_amount(x, BlendFunction::Sqrt, -1), std::invalid_argument);
}

TEST(Blend, IntervalsEncloseSampledBlendValues) {
  for (BlendFunction fb : kAllBlends) {
    const Tape tape(nested_tree(fb, 0.25), 3);
    Evaluator<double> eval(tape);
    Evaluator<Interval> boxes(tape);
    auto rng = test::make_rng(5);
    for (int i = 0; i < 200; ++i) {
      const Point lo = test::random_point(rng, -1.5, 1.5);
      const double w = test::uniform(rng, 1e-3, 0.5);
      Interval box[3] = {{lo[0], lo[0] + w}, {lo[1], lo[1] + w}, {lo[2], lo[2] + w}};
      boxes.evaluate_with(box);
      const Interval range = boxes.result();
      for (int k = 0; k < 20; ++k) {
        const Point p{lo[0] + test::uniform(rng, 0, w), lo[1] + test::uniform(rng, 0, w),
                      lo[2] + test::uniform(rng, 0, w)};
        ASSERT_TRUE(range.contains(eval.at(p))) << "blend function " << static_cast<int>(fb);
      }
    }
  }
}

}  // namespace
}  // namespace sage
