#pragma once
// Quadrature over an implicit domain {omega >= 0} cut into grid cells.
//
// The domain is read as its Boolean skeleton (boolean_form.hpp): smooth
// pieces p_1..p_k (halfspaces, balls, normalized primitives, or the whole
// field when it is not Boolean at its root) and the formula F that their
// signs obey. A box is Inside when interval arithmetic shows F true over it
// (every piece's sign that F reads is known there), Outside when it shows F
// false, Cut otherwise; the pieces left in the box's restricted formula are
// the few whose zero sets may meet it. Inside cells get the tensor Gauss
// rule. Cut cells get a rule after Saye (SIAM J. Sci. Comput. 37, 2015,
// and J. Comput. Phys. 448, 2022, for several level sets):
//
//  1. Volume. Find a height direction e in which every active piece is
//     monotone (interval bounds of its gradient; a piece that does not
//     depend on x_e at all, a face parallel to e, also qualifies). Every
//     line parallel to e then meets each piece's zero set at most once.
//     Integrate over the base (the box face orthogonal to e) with Gauss
//     rules broken where the line integral is not smooth: where a piece
//     vanishes on the bottom or top face (its root enters or leaves the
//     box), where an e-independent piece vanishes, and where two pieces'
//     roots cross (the projection of their intersection, the zero set of
//     p_i evaluated on the root of p_j). In 3D the base is a 2D box with
//     these curves as its level sets: the same steps one dimension down.
//     Along each base line the pieces' roots split the line, and the
//     segments where F holds (read at their midpoints) get Gauss rules.
//     No direction: split the box in 2^D and retry, down to max_depth; at
//     the bottom, Gauss points masked by the sign of F (counted in
//     QuadratureCounts::masked_points: a last resort).
//  2. Surface. Each active piece separately, in its own height direction:
//     the base broken where its root leaves the box and where the other
//     pieces vanish on it; on each base line its root is a surface point
//     when F changes across it there, with weight base_weight |grad p| /
//     |dp/dx_e| and the outward normal -+grad p / |grad p| of that piece.
//     So a box's edge gets the two faces' own normals, and each face's
//     point lies exactly on it.
//
// Deep single pieces (normalized fields) have derivative enclosures too
// loose to prove monotonicity; below the top level a direction is then
// accepted when the derivative keeps its sign at the corners and the
// centre, and line roots are found with a few samples, so a line that
// meets the boundary twice still works.
//
// A boundary on a cell's face (a domain edge on the grid's lattice) gives
// p = 0 exactly at the end of a line: the cell on the domain's side takes
// the surface point, so the neighbour does not take it twice.
//
// Ownership: DomainPieces compiles the pieces once and is shared
// (read-only) by the ImplicitCellQuadrature objects, one per thread.

#include <sage/expression/boolean_form.hpp>
#include <sage/expression/expression.hpp>
#include <sage/scalars/interval.hpp>
#include <sage/solver/background_grid.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace sage::solver {

template <int D>
struct VolumePoint {
  std::array<double, D> x;
  double weight;
};

template <int D>
struct SurfacePoint {
  std::array<double, D> x;
  double weight;
  std::array<double, D> normal;  // outward, unit
};

enum class CellKind : std::uint8_t { Outside, Inside, Cut };

template <int D>
struct Box {
  std::array<double, D> lo;
  std::array<double, D> hi;
};

struct QuadratureOptions {
  int points = 5;         // Gauss nodes per direction and per piece in cut cells
  int inside_points = 0;  // per direction in inside cells (0: same as points)
  int max_depth = 4;      // subdivisions of a cut cell searching for a height direction
  int curved_extra = 0;   // more nodes in cut boxes where a curved piece is active
};

/// The domain's pieces and formula, compiled once.
struct DomainPieces {
  DomainPieces(const Expr& omega, int dimension);
  int dimension;
  BooleanFormula formula;
  std::vector<Tape> value;      // per piece: p
  std::vector<Tape> enclosure;  // per piece: p, dp/dx_0 .. dp/dx_{D-1}
  std::vector<char> planar;     // per piece: its gradient is constant (a halfspace)
  std::size_t piece_count() const { return value.size(); }
};

/// What a box holds of the domain: its kind and the formula restricted to
/// it, which reads the pieces whose zero sets may meet the box (for an
/// Inside box, those that only touch its faces; none otherwise).
struct ClassifiedCell {
  CellKind kind = CellKind::Outside;
  BooleanFormula formula = BooleanFormula::constant(false);
};

/// Classifies every cell of `grid`, descending from blocks of cells to
/// cells so that each box evaluates only the pieces its parent could not
/// settle (a polygon of thousands of edges costs a few per cell). Runs on
/// all cores.
template <int D>
std::vector<ClassifiedCell> classify_cells(const DomainPieces& pieces, const BackgroundGrid<D>& grid);

/// What the rules fell back on, summed over the calls of an ImplicitCellQuadrature.
struct QuadratureCounts {
  std::size_t masked_boxes = 0;        // sub-boxes integrated by sign-masked Gauss points
  std::size_t masked_points = 0;       // volume points those produced
  std::size_t unresolved_surface = 0;  // sub-boxes where a piece's surface found no height direction
  std::size_t unbroken_boxes = 0;      // mesh cells whose planes bend slightly: base rules without breaks
};

template <int D>
class ImplicitCellQuadrature {
 public:
  ImplicitCellQuadrature(const DomainPieces& pieces, QuadratureOptions options);
  ~ImplicitCellQuadrature();
  ImplicitCellQuadrature(ImplicitCellQuadrature&&) noexcept;

  /// The kind of `box` and the formula restricted to it.
  ClassifiedCell classify(const Box<D>& box);
  /// Appends the rule of the part of `box` inside the domain to `volume`,
  /// and of the boundary in the box to `surface` when it is not null.
  void append_rule(const Box<D>& box, const ClassifiedCell& cell, std::vector<VolumePoint<D>>& volume,
                   std::vector<SurfacePoint<D>>* surface);

  const QuadratureCounts& counts() const;

 private:
  class Rule;  // the pieces' tapes and the cut-cell rule (domain_quadrature.cpp)
  std::unique_ptr<Rule> rule_;
};

}  // namespace sage::solver
