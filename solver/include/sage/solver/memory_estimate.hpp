#pragma once
// What a solve will hold in memory, estimated from the classified grid
// before any quadrature point exists, so that a job too large for the
// machine is refused up front with the figures, not killed by the system.
//
// The largest items, in bytes (8 per double), with q = n + 1 Gauss nodes
// per direction inside and n + 2 in cut cells, S = (2n + 1)^D the band's
// stencil and T the threads:
//
//     volume points   inside q^D + cut 3 (q + 1)^D, (D + 1) doubles each
//     surface points  cut 4 (q + 1)^(D - 1), (2 D + 1) doubles each
//     band            relevant B-splines x S doubles, one per thread
//     system          2 x relevant x S entries of 12 bytes (the extended matrix and its build)
//     direct solve    the system's entries again times a fill-in factor (4 in 2D, 20 in 3D)
//     Schwarz (3D)    the products that build the coarse levels (a quarter of the system term),
//                     and (2n + 1) x cut cells distinct blocks of q^2D floats (per component):
//                     blocks differ near the boundary only (measured 1.2 to 27 per cut cell)
//
// A vector problem of c components per B-spline (elasticity.hpp) has c^2
// times the band and the system.
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
                               std::size_t relevant_splines, int threads, bool direct_solve, int components = 1);

/// Memory the system can still give this process, in MB (MemAvailable of
/// /proc/meminfo; 0 when unknown).
double available_megabytes();

}  // namespace sage::solver
