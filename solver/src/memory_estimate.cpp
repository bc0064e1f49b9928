#include <sage/solver/memory_estimate.hpp>

#include <algorithm>
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
                               std::size_t relevant_splines, bool direct_solve, int components) {
  MemoryEstimate e;
  e.cells_inside = cells_inside;
  e.cells_cut = cells_cut;
  e.relevant_splines = relevant_splines;
  const double q = degree + 1, d = dimension, c = components;
  const double stencil = std::pow(2.0 * degree + 1.0, d);
  const double volume =
      static_cast<double>(cells_inside) * std::pow(q, d) + 3.0 * static_cast<double>(cells_cut) * std::pow(q + 1.0, d);
  const double surface = 4.0 * static_cast<double>(cells_cut) * std::pow(q + 1.0, d - 1.0);
  e.volume_points = static_cast<std::size_t>(volume);
  e.surface_points = static_cast<std::size_t>(surface);
  const double splines = static_cast<double>(relevant_splines);
  const double points = volume * (d + 1.0) * 8.0 + surface * (2.0 * d + 1.0) * 8.0;
  const double bands = splines * stencil * c * (c + 1.0) / 2.0 * 8.0;
  const double system = 1.25 * splines * stencil * c * c / 2.0 * 12.0;
  const double assembly = bands + 1.5 * system;
  double solve = system;
  if (direct_solve) {
    solve += system * (dimension == 2 ? 12.8 : 64.0);
  } else if (dimension == 3) {
    const double packed_block = std::pow(q, 2.0 * d) * 2.0 * c;
    solve += system / 4.0 + (2.0 * degree + 1.0) * static_cast<double>(cells_cut) * packed_block;
  }
  e.megabytes = (points + std::max(assembly, solve)) / (1024.0 * 1024.0);
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
