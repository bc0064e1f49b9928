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
// Far-field approximation (approximate()) is for them: over a box, a
// subtree whose every singular set (the corner of an R-function, where both
// arguments vanish; the root of a sqrt; the kink of an unsettled min) lies
// farther from the box centre than `enlargement` half-diagonals, by the
// first-order estimate |f| / |grad f| from values and gradients at the
// centre, is smooth across the box. (An R-function's corner also counts as
// far when the linearized zero sets of its arguments cross at twice that
// distance: a coast's edge lines pass close by everywhere but cross far
// away.) A Chebyshev patch (chebyshev_patch.hpp) fitted to its values at
// Chebyshev points then replaces it, if the patch's coefficients show it
// within the tolerance; if not, its subtrees are tried. Far from a polygon's
// coast the whole field becomes one patch; near it, the edges close by stay
// exact and the rest of the coast is a few patches. Interval enclosures of
// deep R-function trees are too wide to decide this, and the estimate is
// not a proof: the result is no longer bit-identical, and tests and
// bench/gis_bench measure its deviation against exact evaluation.
//
// Each patch's tolerance is divided by a bound, over the box, of how much
// the roots move per unit change of its subtree (the chain rule backward
// from the roots, each operation's partial derivatives bounded from its
// arguments' enclosures: partial_bounds.hpp). R-function partials reach 2
// where an argument may have the sign that matters (x < 0 in x AND y, with
// y near 0), so a patch under a few such nodes could otherwise move the
// field several times its tail; where the roots barely depend on a subtree
// (a far edge beside a near one) its patch may be coarser. Either way each
// patch moves the roots by at most the tolerance, to first order.
//
//     TapeSpecializer specializer(tape);   // if TapeSpecializer::worthwhile(tape)
//     std::array<Interval, 3> box{Interval(0, 1), Interval(0, 1), Interval(0)};
//     if (auto smaller = specializer.specialize(box.data())) use(*smaller);
//     else use(tape);   // nothing to prune over this box

#include <sage/interval.hpp>
#include <sage/tape.hpp>
#include <sage/tuple.hpp>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace sage {

/// Settings of far-field approximation.
/// Whether far-field patches pay for `tape`, as `sage field`'s default:
/// 2D tapes with R-function nodes that interval pruning cannot shrink (R0,
/// R_alpha, Rp, R0^m). Min/max trees are pruned exactly instead, and in 3D
/// fitting (n + 1)^3 samples per patch costs more than the patches save
/// (far_field_bench: 1,000 balls at 128^3 four times slower, meshes no
/// faster).
bool far_field_pays(const Tape& tape);

struct Approximation {
  double tolerance = 0;          // how far each patch may move the roots (field units, first order)
  double enlargement = 1;        // singular sets must be this many half-diagonals from the box centre
  int sampling_degree = 16;      // (n + 1)^dim Chebyshev samples, patches of total degree <= n - 2
  std::size_t min_subtree = 16;  // smaller subtrees are cheaper to run than a patch (a row at a time)
};

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
