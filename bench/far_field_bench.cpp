// What the default far-field approximation of `sage field` costs and
// gains: for bundled models, GIS data and a mesh, the field is sampled on
// the default grid exactly and with the default tolerance (1e-10 of the
// grid box's diagonal), on all cores, side by side in the same run (the
// fastest of three alternating runs each). Prints both times, their ratio and the largest deviations over the whole
// grid: values relative to the diagonal, wrong signs, gradients, and second and third derivatives relative to their
// largest magnitude on the grid.
//
// Usage: far_field_bench [ORDER] [MODEL...]   (ORDER default 3; models
//        default: examples/models/*.json, four GIS files of ../shared, joint.off)

#include <sage/field_samples.hpp>
#include <sage/geometry/model.hpp>
#include <sage/tape.hpp>
#include <sage/tape_specialization.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Largest |a - b| over two arrays, and the largest |b| (the exact one).
std::pair<double, double> deviation(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return {worst, scale};
}

void compare(const std::string& path, int order) {
  sage::geometry::LoadOptions options;
  options.repair = true;
  const sage::geometry::Model model = sage::geometry::load_model(path, options);
  sage::Grid grid;
  grid.dimension = model.dimension;
  grid.lo = model.bounds->min;
  grid.hi = model.bounds->max;
  grid.points = model.dimension == 2 ? std::array<int, 3>{200, 200, 1} : std::array<int, 3>{32, 32, 32};
  if (model.dimension == 2) grid.lo[2] = grid.hi[2] = 0.0;
  double diagonal2 = 0.0;
  for (int a = 0; a < grid.dimension; ++a) diagonal2 += std::pow(grid.hi[a] - grid.lo[a], 2);
  const sage::Tape tape(model.field, model.dimension);
  sage::Approximation approximation;
  approximation.tolerance = 1e-10 * std::sqrt(diagonal2);

  // Fastest of three runs each, alternating: small models take milliseconds.
  sage::FieldSamples exact, approximate;
  double t_exact = 1e300, t_approximate = 1e300;
  for (int run = 0; run < 3; ++run) {
    auto start = std::chrono::steady_clock::now();
    exact = sage::sample_field(tape, grid, order);
    t_exact = std::min(t_exact, seconds(start));
    start = std::chrono::steady_clock::now();
    approximate = sage::sample_field(tape, grid, order, {}, &approximation);
    t_approximate = std::min(t_approximate, seconds(start));
  }

  std::size_t wrong_signs = 0;
  for (std::size_t i = 0; i < exact.omega.size(); ++i)
    wrong_signs += (exact.omega[i] > 0) != (approximate.omega[i] > 0);
  const double value = deviation(approximate.omega, exact.omega).first / std::sqrt(diagonal2);
  const double gradient = deviation(approximate.gradient, exact.gradient).first;
  std::printf("| %s | %zu | %dx%d%s | %.4f | %.4f | %.1f | %.1e | %zu | %.1e |",
              std::filesystem::path(path).filename().c_str(), tape.code().size(), grid.points[0], grid.points[1],
              grid.dimension == 3 ? ("x" + std::to_string(grid.points[2])).c_str() : "", t_exact, t_approximate,
              t_exact / t_approximate, value, wrong_signs, gradient);
  for (std::size_t k = 0; k < exact.higher.size(); ++k) {
    const auto [worst, scale] = deviation(approximate.higher[k].values, exact.higher[k].values);
    std::printf(" %.1e |", scale > 0 ? worst / scale : 0.0);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const int order = argc > 1 ? std::stoi(argv[1]) : 3;
  std::vector<std::string> models;
  for (int i = 2; i < argc; ++i) models.emplace_back(argv[i]);
  if (models.empty()) {
    const std::filesystem::path source(SAGE_SOURCE_DIR);
    for (const auto& entry : std::filesystem::directory_iterator(source / "examples/models"))
      if (entry.path().extension() == ".json") models.push_back(entry.path().string());
    std::sort(models.begin(), models.end());
    const std::filesystem::path shared = source / "../shared/data";
    for (const char* name :
         {"gis/washington_island_wi_osm_EPSG3070.geojson", "gis/door_county_wi_us-atlas.geojson",
          "gis/lake_vanern_se_osm_EPSG32633.geojson", "gis/wisconsin_us-atlas_EPSG3070.geojson", "meshes/joint.off"})
      models.push_back((shared / name).string());
  }
  std::printf(
      "Default grids (200^2, 32^3), all cores, order %d; deviations over the whole grid: value / diagonal,\n"
      "gradient (absolute), higher orders relative to their largest magnitude\n\n",
      order);
  std::printf("| model | instructions | grid | exact s | approximate s | ratio | value | wrong signs | gradient |");
  for (int k = 2; k <= order; ++k) std::printf(" order %d |", k);
  std::printf("\n|---|---|---|---|---|---|---|---|---|");
  for (int k = 2; k <= order; ++k) std::printf("---|");
  std::printf("\n");
  for (const std::string& path : models) compare(path, order);
  return 0;
}
