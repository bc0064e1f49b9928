#pragma once
// The Boolean skeleton of a field: the smooth pieces it is built from and
// the Boolean formula that their signs obey.
//
// R-functions keep signs like Boolean functions (rfunction.hpp): R-AND
// is >= 0 exactly where both arguments are, R-OR where either is, -x where
// x is not. So are min and max, and so are products with a positive
// constant. Walking a field from its root through those operations only,
// every other subtree is a piece (a halfspace, a ball, a normalized
// ellipsoid, a blend, a trimmed face glued under a classifier, ...), and
//
//     omega(p) >= 0  <=>  F(p_1(p) >= 0, ..., p_k(p) >= 0)
//
// away from the zero sets of the pieces, F built of AND, OR and NOT. A
// box's field R0-AND of 6 halfspaces has 6 planar pieces; a field that is
// not Boolean at its root (a normalized field, a mesh's trimmed faces
// signed by point membership) is its own single piece.
//
// Why: where two pieces meet (the edges and corners of a solid) omega is
// not smooth and no direction is monotone, but each piece is. Cut-cell
// quadrature works on the few pieces whose zero sets meet a cell, and takes
// the inside of their combination from F (solver/include/sage/solver/domain_quadrature.hpp).
//
// Pieces are told apart by node identity (a shared subtree is one piece);
// two equal pieces built separately stay two (coincident faces of a union
// of boxes: their surfaces cancel in F).
//
//     const BooleanForm form = boolean_form(r_and(a, -b, RSystem::r0()));
//     // form.pieces = {a, b}; form.formula: piece 0 AND NOT piece 1
//     form.formula.holds([](std::size_t i) { return i == 0; });   // true

#include <sage/expression/expression.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace sage {

/// A formula of AND, OR and NOT over pieces numbered 0..k-1, or a constant.
/// Nodes are stored children first; the last node is the root.
class BooleanFormula {
 public:
  enum class Kind : std::uint8_t { Piece, Not, And, Or };
  struct Node {
    Kind kind;
    std::uint32_t a = 0;  // Piece: the piece; Not, And, Or: first child node
    std::uint32_t b = 0;  // And, Or: second child node
  };

  /// The constant formula `value`.
  static BooleanFormula constant(bool value);
  /// The formula `piece >= 0`.
  static BooleanFormula piece(std::uint32_t index);

  bool is_constant() const { return nodes_.empty(); }
  bool constant_value() const { return constant_; }
  const std::vector<Node>& nodes() const { return nodes_; }

  /// The formula's value when piece i is inside exactly where inside(i).
  bool holds(const std::function<bool(std::size_t)>& inside) const;
  /// Same, for pieces inside when inside[i] != 0 (a faster path for the
  /// solver's inner loops).
  bool holds(const std::vector<char>& inside) const;

  /// The formula with the pieces whose sign is known replaced by constants
  /// and folded: sign(i) is +1 (inside), -1 (outside) or 0 (unknown).
  BooleanFormula restricted(const std::function<int(std::size_t)>& sign) const;

  /// The pieces the formula still reads, increasing.
  std::vector<std::uint32_t> pieces() const;

  /// Builders used by boolean_form().
  static BooleanFormula negation(const BooleanFormula& f);
  static BooleanFormula conjunction(const BooleanFormula& f, const BooleanFormula& g);
  static BooleanFormula disjunction(const BooleanFormula& f, const BooleanFormula& g);

 private:
  // f AND g or f OR g, constants folded.
  static BooleanFormula join(Kind kind, const BooleanFormula& f, const BooleanFormula& g);

  std::vector<Node> nodes_;
  bool constant_ = false;
};

struct BooleanForm {
  std::vector<Expr> pieces;  // the smooth subtrees, in order of first visit from the root
  BooleanFormula formula;
};

/// The pieces of `field` and the formula their signs obey (see above).
BooleanForm boolean_form(const Expr& field);

}  // namespace sage
