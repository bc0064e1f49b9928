#include <sage/solver/memory_estimate.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace sage::solver {

std::string MemoryEstimate::summary() const {
  char text[256];
  std::snprintf(text, sizeof text,
                "about %.0f MB (%zu cells inside and %zu cut, %zu B-splines, %zu volume and %zu surface quadrature "
                "points)",
                megabytes, cells_inside, cells_cut, relevant_splines, volume_points, surface_points);
  return text;
}

MemoryEstimate estimate_memory(int dimension, int degree, std::size_t cells_inside, std::size_t cells_cut,
                               std::size_t relevant_splines, int threads, bool direct_solve, int components) {
  MemoryEstimate e;
  e.cells_inside = cells_inside;
  e.cells_cut = cells_cut;
  e.relevant_splines = relevant_splines;
  const double q = degree + 1, d = dimension;
  const double stencil = std::pow(2.0 * degree + 1.0, d) * components * components;
  const double volume =
      static_cast<double>(cells_inside) * std::pow(q, d) + 3.0 * static_cast<double>(cells_cut) * std::pow(q + 1.0, d);
  const double surface = 4.0 * static_cast<double>(cells_cut) * std::pow(q + 1.0, d - 1.0);
  e.volume_points = static_cast<std::size_t>(volume);
  e.surface_points = static_cast<std::size_t>(surface);
  const double splines = static_cast<double>(relevant_splines);
  double bytes = volume * (d + 1.0) * 8.0 + surface * (2.0 * d + 1.0) * 8.0;
  bytes += splines * stencil * 8.0 * std::max(threads, 1);
  const double system = 2.0 * splines * stencil * 12.0;
  bytes += system;
  if (direct_solve) {
    bytes += system * (dimension == 2 ? 4.0 : 20.0);
  } else if (dimension == 3) {
    // The multilevel Schwarz preconditioner: the products that build the
    // coarse levels, and the distinct blocks' factors (single precision).
    const double block = std::pow(q, 2.0 * d) * 4.0 * components;
    bytes += system / 4.0 + (2.0 * degree + 1.0) * static_cast<double>(cells_cut) * block;
  }
  e.megabytes = bytes / (1024.0 * 1024.0);
  return e;
}

double available_megabytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kilobytes = 0.0;
  std::string unit;
  while (meminfo >> key >> kilobytes >> unit)
    if (key == "MemAvailable:") return kilobytes / 1024.0;
  return 0.0;
}

}  // namespace sage::solver
