#pragma once
// The cut-cell rule of domain_quadrature.hpp (its header says how it
// works), for any set of smooth pieces: the tapes of an implicit field's
// pieces (domain_quadrature.cpp) or the planes of a mesh's triangles in a
// cell (mesh_domain.cpp). Internal to the solver library.

#include <sage/expression/boolean_form.hpp>
#include <sage/scalars/interval.hpp>
#include <sage/solver/domain_quadrature.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace sage::solver {

/// The pieces a cut-cell rule reads, by index: values, gradients and
/// enclosures over boxes. Not thread-safe: one per thread.
template <int D>
class PieceSource {
 public:
  virtual ~PieceSource() = default;
  virtual std::size_t count() const = 0;
  virtual double value(std::uint32_t i, const std::array<double, D>& p) = 0;
  /// The value, and the gradient in g.
  virtual double gradient(std::uint32_t i, const std::array<double, D>& p, std::array<double, D>& g) = 0;
  /// Enclosures of the value and the D partial derivatives over the box.
  virtual std::array<Interval, D + 1> enclosure(std::uint32_t i, const std::array<Interval, D>& box) = 0;
  /// Whether the piece is affine (a halfspace): no extra Gauss nodes.
  virtual bool planar(std::uint32_t i) const = 0;
};

/// +1 when the piece is positive over the box, -1 when negative, 0 when unknown.
inline int sign_of(const Interval& v) { return v.lo > 0 ? 1 : (v.hi < 0 ? -1 : 0); }

/// The sign of a piece over the box's interior when its zero set meets the
/// box only at its boundary, to 1e-12 of its range (a face of the domain on
/// a cell face: the enclosure is [0 - rounding, x]); 0 otherwise.
int touching_sign(const Interval& v);

/// A cell's kind from the formula restricted to it (the pieces whose sign
/// over the cell is not known) and the pieces' enclosures there. Pieces that
/// only touch the cell count by the sign of its interior for the volume, so
/// a cell with a face of the domain on its boundary is Inside, but stay in
/// the formula: its surface rule still runs for them.
ClassifiedCell classified_cell(const BooleanFormula& restricted,
                               const std::function<Interval(std::uint32_t)>& enclosure);

/// One per thread.
template <int D>
class CutCellRule {
 public:
  explicit CutCellRule(QuadratureOptions options);
  ~CutCellRule();
  CutCellRule(CutCellRule&&) noexcept;

  /// Appends the rule of the part of `box` inside the domain that `cell`
  /// describes (its kind and its formula over `pieces`), and of the
  /// boundary in the box when `surface` is not null. Without
  /// `resolve_base`, only the volume, from lines whose roots are exact but
  /// over a base not broken where their integrals have kinks (for boxes
  /// with too many pieces for the breaks, whose caller has a surface rule).
  void append(PieceSource<D>& pieces, const Box<D>& box, const ClassifiedCell& cell,
              std::vector<VolumePoint<D>>& volume, std::vector<SurfacePoint<D>>* surface, bool resolve_base = true);
  const QuadratureCounts& counts() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sage::solver
