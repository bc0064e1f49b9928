#pragma once
// A multilevel additive Schwarz preconditioner for the B-spline systems
// (de Prenter, Verhoosel, van Brummelen et al., CMAME 2019 and Comput.
// Mech. 2020: Schwarz smoothers on cell blocks keep immersed B-spline
// systems solvable at iteration counts independent of h and of the cuts).
//
// Level 0 is the system itself. On each level, blocks of the unknowns
// whose B-splines are supported on one grid cell (per component: a
// displacement's components have blocks of their own), at most (n + 1)^D
// of them, inverted densely (as A_b^-1 = G^T G, G = L^-1 of the block's
// Cholesky factor L, in single precision: positive definite whatever the
// rounding). Cut cells' blocks absorb the tiny B-spline
// shares that ruin the diagonal's scaling: point smoothers (Jacobi) fail
// there, at any number of levels. Blocks that are equal (inside cells with
// constant coefficients) share one inverse, applied to 64 blocks at a time
// as one matrix product, and of those only the blocks on cells with even
// coordinates are kept: blocks two cells apart still overlap, at an eighth
// of the cost. Every distinct block (near the boundary) is kept, its G
// packed (the lower triangle only), unless they would fill a quarter of
// the memory available.
//
// The next level comes from the B-splines' two-scale relation: a B-spline
// of width 2h is a sum of n + 2 B-splines of width h per axis, with
// weights binom(n + 1, l) / 2^n. Its prolongation P keeps the fine
// unknowns only (the WEB extension carries the rest), the coarse matrix is
// P^T A P (as S + S^T - P^T D P, S = P^T L P for the lower triangle L,
// built a few hundred columns of P at a time; all coarse matrices before
// any block, so that their temporaries never meet the blocks),
// and coarse B-splines left with under a tenth of themselves in
// the fine unknowns are dropped (they would make P^T A P nearly singular).
// The coarsest level, at most 2,000 unknowns, is solved by sparse Cholesky.
//
//     M^-1 r = S_0 r + P_1 (S_1 + P_2 (... A_L^-1 ...) P_2^T) P_1^T r,
//
//     S_l = W sum_b R_b^T A_b^-1 R_b W,
//
// R_b the restriction to block b, W = diag(1 / sqrt(blocks of each
// unknown)): near the boundary an unknown lies in up to (n + 1)^D blocks,
// inside in 2^D, and W keeps every region and level of like weight.

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace sage::solver {

/// Where each unknown sits on the background grid.
struct SplinePlacement {
  int dimension = 3;
  int degree = 3;
  /// Per unknown: its B-spline's multi-index (unused axes 0).
  std::vector<std::array<int, 3>> index;
  /// Per unknown: its component (a displacement's axis; 0 for Poisson), or
  /// -1 for an unknown with no B-spline of its own (the Robin structure's
  /// second function), which gets its diagonal only.
  std::vector<int> component;
};

class SchwarzPreconditioner {
 public:
  /// Builds the levels from the lower triangle of an SPD matrix.
  SchwarzPreconditioner(const Eigen::SparseMatrix<double>& lower, const SplinePlacement& placement);

  /// M^-1 r.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;

  /// For the report: the levels, the distinct inverses, the coarsest size.
  std::string description() const;
  std::size_t levels() const { return levels_.size() + 1; }
  /// Bytes held (blocks, coarse matrices, prolongations, the coarsest factor).
  std::size_t bytes() const;

  /// One level's cell blocks.
  struct Blocks {
    std::vector<std::size_t> start;  // block b's unknowns: members[start[b] .. start[b + 1])
    std::vector<int> members;
    /// Per inverse A_b^-1 = G^T G (G = L^-1, lower triangular): its order,
    /// and G as a matrix when several blocks share it (applied as matrix
    /// products), else packed (its lower triangle column by column, at
    /// packed_at[f] in packed: half the bytes).
    std::vector<int> order;
    std::vector<Eigen::MatrixXf> factors;
    std::vector<std::size_t> packed_at;
    std::vector<float> packed;
    std::vector<std::vector<int>> users;  // per inverse: its blocks
    Eigen::VectorXd share;                // per unknown: 1 / sqrt(the blocks it lies in), or 0
    /// The application's work, built once: up to kBlocksPerProduct users of one inverse each.
    struct Batch {
      int inverse;
      std::size_t first, last;  // users[inverse][first .. last)
    };
    std::vector<Batch> batches;
    std::vector<int> lone;         // unknowns in no block
    Eigen::VectorXd lone_inverse;  // their inverse diagonal entries, scaled
  };

 private:
  struct Level {
    Blocks blocks;
    Eigen::SparseMatrix<double> prolongation;  // this level's unknowns x the next level's
  };
  std::vector<Level> levels_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> coarsest_;
  Eigen::Index coarsest_size_ = 0;

  Eigen::VectorXd apply(std::size_t level, const Eigen::VectorXd& r) const;
};

/// The lower triangle of P^T A P for A given by its lower triangle: the
/// coarse levels' matrices (exposed for the tests).
Eigen::SparseMatrix<double> galerkin_lower(const Eigen::SparseMatrix<double>& lower,
                                           const Eigen::SparseMatrix<double>& p);

}  // namespace sage::solver
