#pragma once
// Tape specialization over a box: the interval pruning that makes large
// min/max trees cheap (as in libfive's interval pruning).
//
// Over a box, interval arithmetic often proves that one argument of a min
// or max (or of a min/max R-function node) is below the other everywhere;
// the node is then that argument, for the value and for every derivative
// at every point of the box. Likewise a point classifier that is constant
// over the box, and a step whose argument keeps its sign, are constants.
// The specialized tape drops those nodes and everything only they used, so
// it computes exactly the same numbers at the box's points, bit for bit,
// with fewer instructions. Specializing recursively over subdivided boxes
// shrinks a 20,000-edge polygon's tape to the few edges near each small box.
//
// R0, R_alpha and Rp nodes depend on both arguments everywhere, so they are
// never pruned: their fields are exact only when evaluated whole.
//
//     TapeSpecializer specializer(tape);   // if TapeSpecializer::worthwhile(tape)
//     std::array<Interval, 3> box{Interval(0, 1), Interval(0, 1), Interval(0)};
//     if (auto smaller = specializer.specialize(box.data())) use(*smaller);
//     else use(tape);   // nothing to prune over this box

#include <sage/interval.hpp>
#include <sage/tape.hpp>

#include <optional>
#include <vector>

namespace sage {

class TapeSpecializer {
 public:
  /// Borrows `tape`, which must outlive the specializer. Not thread-safe:
  /// one per thread.
  explicit TapeSpecializer(const Tape& tape);

  /// Evaluates the tape over `box` (dimension() intervals) and returns the
  /// tape specialized to it, or nothing when no instruction could be
  /// dropped. The roots' enclosures over the box are in result() either way.
  std::optional<Tape> specialize(const Interval* box);

  /// Whether enough of `tape`'s instructions could ever be dropped (min,
  /// max, min/max R-function nodes, steps, point classifiers: at least one
  /// in 64; a trimmed face takes about 37) to pay for interval evaluations. An R0 tree glued to one point
  /// classifier is not worth it. O(tape size): ask once per tape.
  static bool worthwhile(const Tape& tape);

  /// Enclosure of root i over the last box.
  const Interval& result(std::size_t i = 0) const { return registers_[tape_->results()[i]]; }

 private:
  // What an instruction becomes over the box.
  enum class Fate : unsigned char { Keep, FirstArgument, SecondArgument, Constant };

  Tape rebuild() const;

  const Tape* tape_;
  std::vector<Interval> registers_;
  std::vector<Fate> fate_;
  std::vector<double> constant_;  // the value, for Fate::Constant
};

}  // namespace sage
