#pragma once
// Far-field approximation of R-function trees over a box
// (TapeSpecializer::approximate(), tape_specialization.hpp for the exact
// pruning it builds on):
//
// R0, R_alpha and Rp nodes cannot be pruned. Over a box, a
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

#include <sage/tape/tape.hpp>

#include <cstddef>

namespace sage {

/// Whether far-field patches pay for `tape`, as `sage field`'s default:
/// 2D tapes with R-function nodes that interval pruning cannot shrink (R0,
/// R_alpha, Rp, R0^m). Min/max trees are pruned exactly instead, and in 3D
/// fitting (n + 1)^3 samples per patch costs more than the patches save
/// (far_field_bench: 1,000 balls at 128^3 four times slower, meshes no
/// faster).
bool far_field_pays(const Tape& tape);

/// Settings of far-field approximation.
struct Approximation {
  double tolerance = 0;          // how far each patch may move the roots (field units, first order)
  double enlargement = 1;        // singular sets must be this many half-diagonals from the box centre
  int sampling_degree = 16;      // (n + 1)^dim Chebyshev samples, patches of total degree <= n - 2
  std::size_t min_subtree = 16;  // smaller subtrees are cheaper to run than a patch (a row at a time)
  // Mesh faces far from a batch in single precision (far_faces.hpp; order
  // <= 1), checked against exact evaluation at far_faces_check_points grid
  // points: beyond far_faces_limit of the grid box's diagonal, the grid is
  // sampled again exactly.
  bool far_faces = false;
  double far_faces_limit = 1e-9;
  std::size_t far_faces_check_points = 2000;
};

}  // namespace sage
