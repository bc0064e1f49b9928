#pragma once
// First hit of a ray with the surface omega = 0 of a 3D field (omega >= 0
// inside), by two methods (papers 003 and 000):
//
//  - Interval bisection: the ray segment [a, b] is a box of points; if the
//    interval enclosure of omega over it excludes 0, the segment holds no
//    surface. Otherwise it is halved, nearer half first, down to a width
//    `leaf_width`; a leaf whose ends differ in sign is refined by bisection
//    in doubles to a few ulps, and a leaf that still may hold the surface
//    without a sign change (a feature thinner than the leaf, or a ray
//    grazing the surface within about leaf_width) counts as a hit. No
//    feature is missed that interval arithmetic can see.
//  - Sphere tracing: on each segment the directional derivative d . grad
//    omega is enclosed by interval evaluation of the symbolic gradient,
//    which bounds the Lipschitz constant lambda there; steps of |omega| /
//    lambda cannot cross the surface. Segments whose bound is infinite, or
//    so large that crossing them would take more than 64 steps, fall back
//    to interval bisection (cheaper there), and so do rays still creeping
//    after 64 steps. Steps shorter than leaf_width
//    are taken as leaf_width, so features thinner than that may be missed.
//
// Ownership: a RayCaster borrows nothing; it owns its tapes. One
// RayCaster per thread (it holds evaluators); tracers share nothing.

#include <sage/expression/expression.hpp>
#include <sage/render/camera.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <memory>
#include <optional>

namespace sage::render {

enum class HitMethod { IntervalBisection, SphereTracing };

/// The compiled field and gradient, shared by the casters of all threads.
struct FieldTapes {
  explicit FieldTapes(const Expr& omega);
  Tape field;     // omega
  Tape gradient;  // d omega / dx, dy, dz (symbolic, for Lipschitz bounds)
};

struct CastStats {
  long long interval_evaluations = 0;
  long long point_evaluations = 0;
};

class RayCaster {
 public:
  /// prune: specialize the tape to segments of the ray where that pays
  /// (min/max trees); the hits are the same bit for bit.
  RayCaster(const FieldTapes& tapes, double leaf_width, bool prune = true);

  /// Distance t in [t0, t1] along the ray of the first point where
  /// omega >= 0, or nothing. t0 itself is returned when omega(t0) >= 0.
  std::optional<double> first_hit(const Ray& ray, double t0, double t1, HitMethod method);

  double value(const Vec3& p);
  const CastStats& stats() const { return stats_; }

 private:
  std::optional<double> bisect_intervals(const Ray& ray, double t0, double t1);
  std::optional<double> sphere_trace(const Ray& ray, double t0, double t1);
  /// Root of omega in [a, b], omega(a) < 0 <= omega(b), in doubles.
  double refine(const Ray& ray, double a, double b);
  /// omega over the segment, by `pruned` (the evaluator of a tape
  /// specialized to a box holding the segment) when given.
  Interval range(const Ray& ray, double a, double b, Evaluator<Interval>* pruned = nullptr);
  double lipschitz_along(const Ray& ray, double a, double b);
  double at(const Ray& ray, double t);

  const Tape* field_;
  bool specialize_;  // the field's tape has min/max nodes worth pruning
  Evaluator<double> point_;
  Evaluator<Interval> box_;
  Evaluator<Interval> gradient_box_;
  double leaf_width_;
  CastStats stats_;
};

/// The part [t0, t1] of the ray inside the box [lo, hi]; nothing if the ray
/// misses it.
std::optional<std::pair<double, double>> clip_to_box(const Ray& ray, const Vec3& lo, const Vec3& hi);

}  // namespace sage::render
