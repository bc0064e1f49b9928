#pragma once
// The system matrix E^T A E of the unknowns (web_basis.hpp), from the
// Galerkin matrix A of the relevant B-splines held as a band: row r of A
// (relevant spline i = grid index of basis.relevant[r]) has (2n + 1)^D
// slots, slot o = sum_a (o_a) (2n + 1)^a (axis 0 fastest) for the column
// spline i + o - n, o_a in 0..2n; slots of splines that are not relevant
// hold 0.
//
// Computed column by column with dense accumulators, E^T (A E(:, p)),
// and only the lower triangle: the sums of a general sparse product,
// without the sparse matrix of the relevant splines, the storage-order
// conversions and the upper half that took most of Eigen's E^T A E on
// the 3D grids. The solvers read the lower triangle only (conjugate
// gradients with Eigen::Lower: half the memory per product).

#include <sage/solver/web_basis.hpp>

#include <Eigen/SparseCore>

#include <vector>

namespace sage::solver {

/// The lower triangle (diagonal included) of E^T A E: unknowns x
/// unknowns, column-major, rows sorted in each column. `band` holds
/// relevant x (2n + 1)^D values as described above, of a symmetric A.
template <int D>
Eigen::SparseMatrix<double> extended_system(const SplineBasis<D>& basis, const std::vector<double>& band);

/// The whole E^T A E for a band of A that need not be symmetric (a
/// coupling of two displacement components, the Robin structure's
/// coupling of its two functions), computed as extended_system is.
template <int D>
Eigen::SparseMatrix<double> extended_product(const SplineBasis<D>& basis, const std::vector<double>& band);

}  // namespace sage::solver
