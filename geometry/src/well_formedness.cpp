#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/well_formedness.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <sstream>
#include <vector>

namespace sage::geometry {

namespace {

using Box = std::array<Interval, 2>;

// Depth-first interval subdivision; each box's tape is specialized to it
// (tape_specialization.hpp), so small boxes of a min/max field run only the
// edges near them. Boxes are OpenMP tasks.
class Prover {
 public:
  Prover(const PolygonSet& polygons, double band, std::size_t budget)
      : edges_(polygons), band_(band), budget_(budget) {}

  // Verdicts of a box that could not be proven free of zeros.
  enum class Finding { PossibleZero = 2, Zero = 3 };
  struct Failure {
    Box box;
    Finding finding;
  };

  void prove(const Tape& tape, const Box& b, int depth) {
    if (gave_up_ || failed_) return;
    if (boxes_.fetch_add(1) >= budget_) {
      gave_up_ = true;
      return;
    }
    TapeSpecializer specializer(tape);
    const std::optional<Tape> smaller = specializer.specialize(b.data());
    const Tape& here = smaller ? *smaller : tape;
    const Interval range = specializer.result();
    if (!range.is_nan() && !range.contains_zero()) return;  // proven: no zero here
    const double width = std::max(b[0].width(), b[1].width());
    const Box grown{Interval(b[0].lo - band_, b[0].hi + band_), Interval(b[1].lo - band_, b[1].hi + band_)};
    const bool near_edge = edges_.edge_meets(grown.data());
    if (width <= band_ && near_edge) return;  // within 3 sqrt(2) band of an edge
    // Away from the edges: a sign change between sample points proves a
    // zero there (omega is continuous and the box meets no edge).
    if (!near_edge && changes_sign(here, b)) return fail(b, Finding::Zero);
    // Interval bounds overestimate in proportion to the box size, and
    // without bound where three or more leaf lines pass close together
    // (their sign combinations are not independent there), so a box away
    // from the edges is split much further before it counts as a possible
    // zero; only such places go this deep.
    if (width <= band_ * 0x1p-24) return fail(b, Finding::PossibleZero);
    const double mx = b[0].mid(), my = b[1].mid();
    const Box children[4] = {{Interval(b[0].lo, mx), Interval(b[1].lo, my)},
                             {Interval(mx, b[0].hi), Interval(b[1].lo, my)},
                             {Interval(b[0].lo, mx), Interval(my, b[1].hi)},
                             {Interval(mx, b[0].hi), Interval(my, b[1].hi)}};
    for (const Box& child : children) {
#pragma omp task default(shared) firstprivate(child) if (depth < 10)
      prove(here, child, depth + 1);
    }
#pragma omp taskwait
  }

  std::size_t boxes() const { return boxes_; }
  bool gave_up() const { return gave_up_; }
  /// The failure with the lowest corner, so reports are repeatable.
  std::optional<Failure> failure() const {
    if (failures_.empty()) return std::nullopt;
    return *std::min_element(failures_.begin(), failures_.end(), [](const Failure& a, const Failure& b) {
      return std::make_pair(a.box[0].lo, a.box[1].lo) < std::make_pair(b.box[0].lo, b.box[1].lo);
    });
  }

 private:
  // Does omega take both signs (or 0) at the corners and centre of b?
  static bool changes_sign(const Tape& tape, const Box& b) {
    Evaluator<double> values(tape);
    int positive = 0, negative = 0;
    for (double fx : {0.0, 0.5, 1.0})
      for (double fy : {0.0, 0.5, 1.0}) {
        const double v = values.at({b[0].lo + fx * b[0].width(), b[1].lo + fy * b[1].width(), 0.0});
        positive += v >= 0;
        negative += v <= 0;
      }
    return positive > 0 && negative > 0;
  }

  void fail(const Box& b, Finding f) {
    const std::lock_guard<std::mutex> lock(mutex_);
    failures_.push_back({b, f});
    failed_ = true;
  }

  const PolygonClassifier edges_;  // its box test finds edges near a box
  const double band_;
  const std::size_t budget_;
  std::atomic<std::size_t> boxes_{0};
  std::atomic<bool> gave_up_{false};
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::vector<Failure> failures_;  // read without the lock only after the run
};

}  // namespace

Certificate certify_no_spurious_zeros(const Expr& field, const PolygonSet& polygons, const Bounds& bounds, double band,
                                      std::size_t budget) {
  const Tape tape(field, 2);
  Prover prover(polygons, band, budget);
  const Box all{Interval(bounds.min[0], bounds.max[0]), Interval(bounds.min[1], bounds.max[1])};
#pragma omp parallel
#pragma omp single
  prover.prove(tape, all, 0);

  Certificate c;
  // A box at most `band` wide that meets an edge once grown by `band` lies
  // within the grown box's diagonal, 3 sqrt(2) band, of that edge.
  c.band = 3 * std::sqrt(2.0) * band;
  c.boxes = prover.boxes();
  const std::optional<Prover::Failure> failure = prover.failure();
  std::ostringstream text;
  text.precision(9);
  if (failure) {
    text << "NOT well-formed: omega " << (failure->finding == Prover::Finding::Zero ? "vanishes" : "may vanish")
         << " away from the boundary near (" << failure->box[0].mid() << ", " << failure->box[1].mid() << ")";
  } else if (prover.gave_up()) {
    text << "not certified: gave up after " << c.boxes << " interval boxes";
  } else {
    c.certified = true;
    text << "certified well-formed: no zeros of omega farther than " << c.band
         << " from the boundary within the bounds (interval arithmetic, " << c.boxes << " boxes)";
  }
  c.text = text.str();
  return c;
}

}  // namespace sage::geometry
