#pragma once
// Tape specialization over a box: the interval pruning that makes large
// min/max trees cheap (as in libfive's interval pruning).
//
// Over a box, interval arithmetic often proves that one argument of a min
// or max (or of a min/max R-function node) is below the other everywhere;
// the node is then that argument, for the value and for every derivative
// at every point of the box. In a tree of mins an argument is also dropped
// when it lies above an upper bound passed down from higher up (in
// min(min(a, b), c), a when a.lo > min(b.hi, c.hi)): mins above could never
// choose it. Likewise for max with lower bounds, and through negation.
// Likewise a point classifier that is constant
// over the box, and a step whose argument keeps its sign, are constants.
// The specialized tape drops those nodes and everything only they used, so
// it computes exactly the same numbers at the box's points, bit for bit,
// with fewer instructions. Specializing recursively over subdivided boxes
// shrinks a 20,000-edge polygon's tape to the few edges near each small box.
//
// R0, R_alpha and Rp nodes depend on both arguments everywhere, so they are
// never pruned: their fields are exact only when evaluated whole.
//
// Far-field approximation (approximate(), far_field.hpp) is for them.
//
//     TapeSpecializer specializer(tape);   // if TapeSpecializer::worthwhile(tape)
//     std::array<Interval, 3> box{Interval(0, 1), Interval(0, 1), Interval(0)};
//     if (auto smaller = specializer.specialize(box.data())) use(*smaller);
//     else use(tape);   // nothing to prune over this box

#include <sage/scalars/interval.hpp>
#include <sage/scalars/tuple.hpp>
#include <sage/tape/far_field.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace sage {

class TapeSpecializer {
 public:
  /// Borrows `tape`, which must outlive the specializer. Not thread-safe:
  /// one per thread.
  explicit TapeSpecializer(const Tape& tape);
  ~TapeSpecializer();
  TapeSpecializer(TapeSpecializer&&) noexcept;
  TapeSpecializer& operator=(TapeSpecializer&&) noexcept;

  /// Specializes `tape` from now on, keeping the buffers of the previous
  /// one: grid sampling specializes thousands of tapes per thread.
  void rebind(const Tape& tape);

  /// Evaluates the tape over `box` (dimension() intervals) and returns the
  /// tape specialized to it, or nothing when no instruction could be
  /// dropped. The roots' enclosures over the box are in result() either way.
  std::optional<Tape> specialize(const Interval* box);

  /// Specializes over `count` boxes at once (a grid block's children):
  /// tapes[k] is what specialize(boxes[k].data()) would give, but one pass
  /// over the code evaluates the enclosures over all boxes, decoding each
  /// instruction once. result() is then root enclosures over boxes[0].
  void specialize_each(const std::array<Interval, 3>* boxes, std::size_t count, std::optional<Tape>* tapes);

  /// Specializes over `box` as specialize() does, with the min/max and
  /// constant decisions taken over the enlarged box, and also replaces the
  /// largest analytic subtrees by Chebyshev patches fitted over `box` (see
  /// above). Returns nothing when nothing changed.
  std::optional<Tape> approximate(const Interval* box, const Approximation& settings);

  /// Whether enough of `tape`'s instructions could ever be dropped (min,
  /// max, min/max R-function nodes, steps, point classifiers: at least one
  /// in 64; a trimmed face takes about 37) to pay for interval evaluations. An R0 tree glued to one point
  /// classifier is not worth it. O(tape size): ask once per tape.
  static bool worthwhile(const Tape& tape);

  /// Enclosure of root i over the last box.
  const Interval& result(std::size_t i = 0) const { return registers_[tape_->results()[i] * lanes_]; }

 private:
  // What an instruction becomes over the box.
  enum class Fate : unsigned char { Keep, FirstArgument, SecondArgument, Constant, Patch };

  // The interval pass over one box and its decisions; true if anything
  // was pruned.
  bool decide(const Interval* box);
  // The interval pass over `lanes` boxes: every instruction's enclosures.
  void trace(const std::array<Interval, 3>* boxes, std::size_t lanes);
  // Fates over box `lane` of the last trace; true if anything was pruned.
  bool decide_lane(std::size_t lane);
  // An argument's enclosure over the current lane's box.
  const Interval& enclosure(std::uint32_t producer, std::uint32_t reg) const;
  // Prunes min/max arguments that bounds from above rule out; true if any.
  bool prune_by_bounds();
  // Which instructions are analytic across the box enlarged (from values
  // and gradients at its centre).
  void mark_analytic(const Interval* box, double enlargement);
  // Per instruction, a bound over the box (from the last trace) of how much
  // the roots can move per unit change of its value.
  const std::vector<double>& sensitivities();
  // Fits patches to the largest analytic subtrees; true if any was made.
  bool fit_patches(const Interval* box, const Approximation& settings);
  // The program of the kept instructions, with registers reallocated; its
  // roots are the tape's, or the values of instructions `outputs`.
  Tape rebuild(const std::vector<std::size_t>* outputs = nullptr);

  struct Scratch;  // rebuild()'s work arrays, kept between calls
  struct Bounds;   // trace()'s records for the decisions and prune_by_bounds()

  const Tape* tape_;
  std::vector<Interval> registers_;  // per box: registers_[r * lanes_ + lane]
  std::size_t lanes_ = 1;            // boxes of the last trace
  std::size_t lane_ = 0;             // the box being decided
  std::vector<Fate> fate_;
  std::vector<double> constant_;  // the value, for Fate::Constant
  std::vector<char> analytic_;    // per instruction, over the last enlarged box
  std::vector<char> register_analytic_;
  std::vector<Tuple<3, 1>> jets_;
  std::vector<double> squares_gradient2_;  // per instruction: sum of |grad c|^2 if a sum of squares c^2, else -1
  std::vector<std::shared_ptr<const ChebyshevPatch>> patch_;  // for Fate::Patch
  std::unique_ptr<Scratch> scratch_;
  std::unique_ptr<Bounds> bounds_;
};

}  // namespace sage
