#pragma once
// Quadrature over an implicit domain {omega >= 0} cut into grid cells.
//
// Cells are classified with interval arithmetic: Inside when omega > 0 on
// the whole box, Outside when omega < 0 on it, Cut otherwise. Inside cells
// get the tensor Gauss rule. Cut cells get a high-order rule after Saye
// (SIAM J. Sci. Comput. 37, 2015), for one level set:
//
//  1. Enclose omega and its gradient on the box. If some partial d omega /
//     dx_e keeps its sign, omega is monotone along x_e (the "height"
//     direction): every line parallel to x_e meets the boundary at most
//     once. Otherwise split the box in 2^D and retry, down to max_depth;
//     at the bottom use Gauss points masked by the sign of omega.
//  2. Integrate over the base (the box face orthogonal to e) with Gauss
//     rules broken at the zeros of omega on the bottom and top faces, so the
//     inner integral is smooth on every piece. In 3D the base itself is a
//     2D box cut by two level sets: the same steps one dimension down.
//  3. Along each base line, find the root of omega (bracketed secant),
//     and use a Gauss rule on the inside segment.
//
// Interval bounds of the derivatives of deep expressions (normalized
// fields) are often too loose to prove monotonicity; below the top level a
// direction is then accepted when the derivative keeps its sign at the
// corners and the centre, and the line rule finds every root it brackets
// with a few samples, so a line that meets the boundary twice still works.
//
// The surface rule on omega = 0 comes with it: the root on each base line
// is a surface point with weight base_weight |grad omega| / |d omega/dx_e|
// and outward unit normal -grad omega / |grad omega| (omega >= 0 inside).
//
// Ownership: DomainTapes compiles omega once and is shared (read-only) by
// the CellQuadrature objects, one per thread.

#include <sage/evaluator.hpp>
#include <sage/expression.hpp>
#include <sage/interval.hpp>
#include <sage/tape.hpp>

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
};

/// omega and its gradient compiled for the three evaluations the rule needs.
struct DomainTapes {
  DomainTapes(const Expr& omega, int dimension);
  Tape value;      // omega
  Tape enclosure;  // omega, d omega/dx_0 .. d omega/dx_{D-1}
};

template <int D>
class CellQuadrature {
 public:
  CellQuadrature(const DomainTapes& tapes, QuadratureOptions options);

  CellKind classify(const Box<D>& box);
  /// Appends the rule of the part of `box` inside the domain to `volume`,
  /// and of omega = 0 in the box to `surface` when it is not null.
  void append_rule(const Box<D>& box, CellKind kind, std::vector<VolumePoint<D>>& volume,
                   std::vector<SurfacePoint<D>>* surface);

 private:
  struct Target {
    std::vector<VolumePoint<D>>* volume;
    std::vector<SurfacePoint<D>>* surface;
  };
  double omega_at(const std::array<double, D>& p);
  std::array<Interval, D + 1> enclose(const Box<D>& box);
  void tensor_rule(const Box<D>& box, bool masked, int points, Target target);
  void cut_rule(const Box<D>& box, int depth, Target target);
  void height_rule(const Box<D>& box, int e, Target target);
  void base_rule_2d(const Box<D>& box, int e, const Box<D>& base, int depth, Target target);
  int sampled_height(const Box<D>& box, int fixed_axis, const std::vector<double>& faces = {});
  void line_rule(std::array<double, D> p, int e, const Box<D>& box, double base_weight, Target target);

  QuadratureOptions options_;
  Evaluator<double> value_;
  Evaluator<Interval> enclosure_;
  Evaluator<Tuple<D, 1>> gradient_;
};

}  // namespace sage::solver
