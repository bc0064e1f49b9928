#pragma once
// The spline space on the domain: weighted B-splines, optionally made
// stable by the WEB extension (Hollig, Reif, Wipper, SIAM J. Numer. Anal.
// 39, 2001).
//
// A B-spline is relevant when its support meets the domain, inner when its
// support holds at least one cell entirely inside, outer otherwise. Outer
// B-splines may have a tiny part of their support in the domain, which
// ruins the conditioning of plain weighted B-splines. The WEB basis keeps
// one unknown per inner B-spline and ties each outer B-spline j to the
// (n + 1)^D array of inner ones l + {0..n}^D closest to it:
//
//     B_i^web = w (B_i + sum_{j outer} e_ij B_j),
//     e_ij = prod_a prod_{mu != i_a - l_a} (j_a - l_a - mu) / (i_a - l_a - mu),
//
// the Lagrange weights that extrapolate polynomial B-spline coefficients, so
// the space still holds w times every polynomial of coordinate degree <= n.
//
// Both bases are written as one extension matrix E (relevant splines by
// unknowns): the coefficients of the relevant B-splines are E c. For plain
// weighted B-splines E is the identity.

#include <sage/solver/background_grid.hpp>
#include <sage/solver/domain_quadrature.hpp>

#include <Eigen/SparseCore>

#include <cstddef>
#include <string>
#include <vector>

namespace sage::solver {

enum class BasisKind { Web, Weighted };

/// Parses "web" or "weighted"; throws std::invalid_argument.
BasisKind parse_basis_kind(const std::string& text);

template <int D>
struct SplineBasis {
  BackgroundGrid<D> grid;
  BasisKind kind = BasisKind::Web;
  std::vector<std::size_t> relevant;   // global spline numbers, increasing
  std::vector<long long> relevant_of;  // global spline number -> position in `relevant`, or -1
  std::size_t inner_count = 0;
  std::size_t outer_count = 0;
  Eigen::SparseMatrix<double> extension;  // relevant x unknowns
  /// Per unknown, the position in `relevant` of its own B-spline: the
  /// coefficient of unknown p of a polynomial of degree <= n is the
  /// polynomial's B-spline coefficient there (the extension keeps them).
  std::vector<std::size_t> unknown_spline;
  std::size_t unknowns() const { return static_cast<std::size_t>(extension.cols()); }
};

/// Builds the basis from the cells that carry quadrature points
/// (`active`) and those entirely inside (`inside`), both per grid cell.
/// Throws std::runtime_error when the grid is too coarse for the WEB
/// extension (no inner cell, or no full array of inner B-splines).
template <int D>
SplineBasis<D> build_basis(const BackgroundGrid<D>& grid, const std::vector<char>& active,
                           const std::vector<char>& inside, BasisKind kind);

}  // namespace sage::solver
