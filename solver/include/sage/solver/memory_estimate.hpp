#pragma once
// What a solve will hold in memory, estimated from the classified grid
// before any quadrature point exists, so that a job too large for the
// machine is refused up front with the figures, not killed by the system.
//
// The largest items, in bytes (8 per double), with q = n + 1 Gauss nodes
// per direction inside and n + 2 in cut cells, S = (2n + 1)^D the band's
// stencil and c the unknowns per B-spline (1; D for elasticity):
//
//     volume points   inside q^D + cut 3 (q + 1)^D, (D + 1) doubles each
//     surface points  cut 4 (q + 1)^(D - 1), (2 D + 1) doubles each
//     bands           relevant B-splines x S doubles per pair of components, c (c + 1) / 2 of them
//     system          its lower triangle, relevant x S x c^2 / 2 entries of 12 bytes, and a quarter
//                     more for the couplings the WEB extension adds
//     assembly        the bands, the system and half of it again (a block's columns being built)
//     direct solve    the system's fill-in: 12.8 times it in 2D, 64 times in 3D
//     Schwarz (3D)    the products that build the coarse levels (a quarter of the system), and
//                     (2n + 1) x cut cells distinct blocks of q^2D / 2 floats (packed triangles)
//                     per component: blocks differ near the boundary only (measured 1.2 to 27
//                     per cut cell)
//
// The estimate is the points and the larger of the assembly and the solve
// (the system and what its solver adds): the bands are gone by the solve.
// Measured against it: 994 MB of an estimated 1,050 (the bracket of
// examples/, elasticity, degree 3, 40 cells).
//
// The cut cells' factor 3 is above what the rule gives for planar faces
// (1 to 3 pieces of (n + 2)^D points per cell) and round boundaries.

#include <cstddef>
#include <string>

namespace sage::solver {

struct MemoryEstimate {
  std::size_t cells_inside = 0, cells_cut = 0, relevant_splines = 0;
  std::size_t volume_points = 0, surface_points = 0;
  double megabytes = 0.0;
  std::string summary() const;  // "about 812 MB (...)"
};

/// The estimate for a grid of the given dimension and degree.
MemoryEstimate estimate_memory(int dimension, int degree, std::size_t cells_inside, std::size_t cells_cut,
                               std::size_t relevant_splines, bool direct_solve, int components = 1);

/// Memory the system can still give this process, in MB (MemAvailable of
/// /proc/meminfo; 0 when unknown).
double available_megabytes();

}  // namespace sage::solver
