#include <sage/sampling/grid.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage {

namespace {
std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

double parse_number(const std::string& s, const std::string& what) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    throw std::invalid_argument(what + ": '" + s + "' is not a number");
  }
  if (used != s.size()) throw std::invalid_argument(what + ": '" + s + "' is not a number");
  if (!std::isfinite(v)) throw std::invalid_argument(what + ": '" + s + "' is not finite");
  return v;
}
}  // namespace

std::array<int, 3> Grid::default_points(int dimension) {
  return dimension == 2 ? std::array<int, 3>{200, 200, 1} : std::array<int, 3>{64, 64, 64};
}

std::array<int, 3> Grid::checked_points(const std::vector<double>& counts, int dimension, const std::string& what) {
  if (static_cast<int>(counts.size()) != dimension)
    throw std::invalid_argument(what + ": expected " + std::to_string(dimension) + " point counts");
  std::array<int, 3> n{1, 1, 1};
  for (int i = 0; i < dimension; ++i) {
    const double v = counts[static_cast<std::size_t>(i)];
    if (v != std::floor(v) || v < 2 || v > 100000)
      throw std::invalid_argument(what + ": each count must be an integer from 2 to 100000");
    n[i] = static_cast<int>(v);
  }
  const double total = static_cast<double>(n[0]) * n[1] * n[2];
  if (total > kMaxGridPoints)
    throw std::invalid_argument(what + ": " + std::to_string(static_cast<long long>(total)) +
                                " points is more than the limit of " + std::to_string(kMaxGridPoints));
  return n;
}

std::array<int, 3> Grid::parse_resolution(const std::string& text, int dimension) {
  const auto parts = split(text, 'x');
  if (static_cast<int>(parts.size()) != dimension)
    throw std::invalid_argument("grid '" + text + "': expected " +
                                (dimension == 2 ? "NXxNY (e.g. 200x200)" : "NXxNYxNZ (e.g. 64x64x64)") + " for a " +
                                std::to_string(dimension) + "D model");
  std::vector<double> counts;
  for (const std::string& part : parts) counts.push_back(parse_number(part, "grid"));
  return checked_points(counts, dimension, "grid '" + text + "'");
}

void Grid::space_points(double spacing) {
  std::ostringstream given;
  given << spacing;
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw std::invalid_argument(given.str() + ": must be a positive distance between grid points (the model's units)");
  double total = 1;
  for (int a = 0; a < dimension; ++a) {
    // A hair under the quotient: bounds a whole number of steps apart get
    // no extra point from rounding.
    const double steps = std::ceil((hi[a] - lo[a]) / spacing * (1 - 1e-12));
    if (!(steps < 100000))
      throw std::invalid_argument(given.str() + ": over 100000 points along an axis; give a larger one");
    points[a] = std::max(2, static_cast<int>(steps) + 1);
    hi[a] = lo[a] + (points[a] - 1) * spacing;
    total *= points[a];
  }
  if (total > kMaxGridPoints)
    throw std::invalid_argument(given.str() + ": " + std::to_string(static_cast<long long>(total)) +
                                " points is more than the limit of " + std::to_string(kMaxGridPoints));
}

void Grid::parse_bounds(const std::string& text, int dimension, std::array<double, 3>& lo, std::array<double, 3>& hi) {
  const auto parts = split(text, ',');
  if (static_cast<int>(parts.size()) != 2 * dimension)
    throw std::invalid_argument("bounds '" + text + "': expected " + std::to_string(2 * dimension) +
                                " numbers xmin,xmax,ymin,ymax" + (dimension == 3 ? ",zmin,zmax" : ""));
  for (int i = 0; i < dimension; ++i) {
    lo[i] = parse_number(parts[2 * i], "bounds");
    hi[i] = parse_number(parts[2 * i + 1], "bounds");
    if (!(hi[i] > lo[i])) throw std::invalid_argument("bounds '" + text + "': each max must exceed its min");
  }
}

}  // namespace sage
