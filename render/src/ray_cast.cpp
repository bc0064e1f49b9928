#include <sage/expression/derivative.hpp>
#include <sage/render/ray_cast.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace sage::render {

FieldTapes::FieldTapes(const Expr& omega) : field(omega, 3), gradient(sage::gradient(omega, 3), 3) {}

RayCaster::RayCaster(const FieldTapes& tapes, double leaf_width, bool prune)
    : field_(&tapes.field),
      specialize_(prune && TapeSpecializer::worthwhile(tapes.field)),
      point_(tapes.field),
      box_(tapes.field),
      gradient_box_(tapes.gradient),
      leaf_width_(leaf_width) {}

double RayCaster::value(const Vec3& p) {
  ++stats_.point_evaluations;
  point_.evaluate(p.data());
  return point_.result();
}

double RayCaster::at(const Ray& ray, double t) { return value(ray.origin + t * ray.direction); }

namespace {
/// The points o + t d, t in [a, b], as a box (one interval per coordinate).
void segment_box(const Ray& ray, double a, double b, Interval box[3]) {
  for (int i = 0; i < 3; ++i) box[i] = Interval(ray.origin[i]) + Interval(a, b) * Interval(ray.direction[i]);
}
}  // namespace

Interval RayCaster::range(const Ray& ray, double a, double b, Evaluator<Interval>* pruned) {
  ++stats_.interval_evaluations;
  Interval box[3];
  segment_box(ray, a, b, box);
  Evaluator<Interval>& e = pruned ? *pruned : box_;
  e.evaluate_with(box);
  return e.result();
}

double RayCaster::lipschitz_along(const Ray& ray, double a, double b) {
  ++stats_.interval_evaluations;
  Interval box[3];
  segment_box(ray, a, b, box);
  gradient_box_.evaluate_with(box);
  Interval slope(0.0);
  for (int i = 0; i < 3; ++i) slope = slope + gradient_box_.result(i) * Interval(ray.direction[i]);
  if (slope.is_nan()) return std::numeric_limits<double>::infinity();
  return std::max(std::abs(slope.lo), std::abs(slope.hi));
}

double RayCaster::refine(const Ray& ray, double a, double b) {
  // Bisection keeps the bracket omega(a) < 0 <= omega(b) until the two ends
  // are neighbours in floating point (or nearly: 60 halvings).
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (a + b);
    if (m <= a || m >= b) break;
    (at(ray, m) >= 0 ? b : a) = m;
  }
  return b;
}

std::optional<double> RayCaster::first_hit(const Ray& ray, double t0, double t1, HitMethod method) {
  if (!(t1 >= t0)) return std::nullopt;
  if (at(ray, t0) >= 0) return t0;
  return method == HitMethod::SphereTracing ? sphere_trace(ray, t0, t1) : bisect_intervals(ray, t0, t1);
}

std::optional<double> RayCaster::bisect_intervals(const Ray& ray, double t0, double t1) {
  // Large min/max trees: every few levels the segment's tape is
  // specialized to the segment's box (tape_specialization.hpp), so deeper
  // levels evaluate only the primitives near the segment. The numbers are
  // the same bit for bit.
  constexpr int kSpecializeEvery = 3;
  struct Segment {
    double a, b;
    int tape;  // index into tapes: 0 the whole field
    int depth;
  };
  struct Pruned {
    const Tape* tape;
    std::unique_ptr<Tape> owned;
    std::unique_ptr<TapeSpecializer> specializer;
    std::unique_ptr<Evaluator<Interval>> eval;
  };
  std::vector<Pruned> tapes;
  if (specialize_) tapes.push_back({field_, nullptr, nullptr, nullptr});
  std::vector<Segment> stack{{t0, t1, 0, 0}};
  // A leaf that may hold the surface without a sign change at its ends. It
  // is often only the overestimation next to a crossing in the following
  // leaf, so it is returned only if no crossing follows right after it.
  std::optional<double> candidate;
  double candidate_end = 0;
  while (!stack.empty()) {
    const Segment s = stack.back();
    stack.pop_back();
    if (candidate && s.a > candidate_end) return candidate;
    int child_tape = s.tape;
    Interval f;
    if (specialize_ && s.depth % kSpecializeEvery == 0 && tapes[s.tape].tape->code().size() > 16) {
      ++stats_.interval_evaluations;
      Interval box[3];
      segment_box(ray, s.a, s.b, box);
      Pruned& p = tapes[s.tape];
      if (!p.specializer) p.specializer = std::make_unique<TapeSpecializer>(*p.tape);
      std::optional<Tape> smaller = p.specializer->specialize(box);
      f = p.specializer->result();
      if (smaller && !(!f.is_nan() && f.hi < 0)) {
        auto owned = std::make_unique<Tape>(std::move(*smaller));
        const Tape* raw = owned.get();
        tapes.push_back({raw, std::move(owned), nullptr, nullptr});
        child_tape = static_cast<int>(tapes.size()) - 1;
      }
    } else {
      Evaluator<Interval>* eval = nullptr;
      if (specialize_ && s.tape > 0) {
        Pruned& p = tapes[s.tape];
        if (!p.eval) p.eval = std::make_unique<Evaluator<Interval>>(*p.tape);
        eval = p.eval.get();
      }
      f = range(ray, s.a, s.b, eval);
    }
    if (!f.is_nan() && f.hi < 0) continue;  // proved empty: omega < 0 on the whole segment
    if (s.b - s.a > leaf_width_) {
      const double m = 0.5 * (s.a + s.b);
      stack.push_back({m, s.b, child_tape, s.depth + 1});
      stack.push_back({s.a, m, child_tape, s.depth + 1});  // nearer half first
      continue;
    }
    const double fa = at(ray, s.a), fb = at(ray, s.b);
    if (fa >= 0) return s.a;
    if (fb >= 0) return refine(ray, s.a, s.b);
    // No sign change: a feature thinner than the leaf, a ray grazing the
    // surface, or overestimation; NaN everywhere we look is no hit.
    if (f.is_nan() && !std::isfinite(at(ray, 0.5 * (s.a + s.b)))) continue;
    if (!candidate) candidate = 0.5 * (s.a + s.b);
    candidate_end = s.b;
  }
  return candidate;
}

std::optional<double> RayCaster::sphere_trace(const Ray& ray, double t0, double t1) {
  constexpr int kMaxSteps = 64;
  // Segments of about 1/16 of the ray: short enough for useful bounds.
  const double piece = std::max((t1 - t0) / 16, 4 * leaf_width_);
  for (double a = t0; a < t1; a += piece) {
    const double b = std::min(a + piece, t1);
    double t = a, v = at(ray, a);
    if (v >= 0) return t;
    const double lambda = lipschitz_along(ray, a, b);
    // Steps of |v| / lambda would cross the piece in about lambda (b - a) /
    // |v| of them, more where v shrinks: past kMaxSteps, bisection is
    // cheaper (and it is the only choice without a finite bound).
    if (!std::isfinite(lambda) || lambda * (b - a) > kMaxSteps * -v) {
      if (auto hit = bisect_intervals(ray, a, b)) return hit;
      continue;
    }
    for (int steps = 0; t < b; ++steps) {
      if (steps > kMaxSteps) {  // creeping along a grazing ray: let intervals decide
        if (auto hit = bisect_intervals(ray, t, b)) return hit;
        break;
      }
      const double step = lambda > 0 ? -v / lambda : b - t;
      const double next = std::min(t + std::max(step, leaf_width_), b);
      const double v_next = at(ray, next);
      if (v_next >= 0) return refine(ray, t, next);
      if (next >= b) break;
      t = next, v = v_next;
    }
  }
  return std::nullopt;
}

std::optional<std::pair<double, double>> clip_to_box(const Ray& ray, const Vec3& lo, const Vec3& hi) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (ray.direction[i] == 0) {
      if (ray.origin[i] < lo[i] || ray.origin[i] > hi[i]) return std::nullopt;
      continue;
    }
    double a = (lo[i] - ray.origin[i]) / ray.direction[i], b = (hi[i] - ray.origin[i]) / ray.direction[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return std::nullopt;
  return std::make_pair(t0, t1);
}

}  // namespace sage::render
