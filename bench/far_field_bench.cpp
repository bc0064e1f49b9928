// What the default far-field approximation of `sage field` costs and
// gains: for bundled models, GIS data and a mesh, the field is sampled
// exactly and with the default tolerance (1e-10 of the grid box's
// diagonal), on all cores, side by side in the same run (the fastest of
// three alternating runs each). Prints both times, their ratio and the
// largest deviations over the whole grid: values relative to the
// diagonal, wrong signs, gradients, and higher derivatives relative to
// their largest magnitude on the grid.
//
// Usage: far_field_bench [ORDER] [N2D,N3D] [MODEL... | balls]
//        ORDER default 3; grids N2D^2 and N3D^3, default 200 and 32;
//        models default: examples/models/*.json, four GIS files of
//        ../shared, joint.off; "balls": 1,000 random balls united by R0
//        and by min/max, written as JSON models to the temporary folder.

#include "bench_support.hpp"

#include <sage/geometry/model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/tape/tape.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
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

void compare(const std::string& path, int order, int points_2d, int points_3d) {
  sage::geometry::LoadOptions options;
  options.repair = true;
  const sage::geometry::Model model = sage::geometry::load_model(path, options);
  sage::Grid grid;
  grid.dimension = model.dimension;
  grid.lo = model.bounds->min;
  grid.hi = model.bounds->max;
  grid.points = model.dimension == 2 ? std::array<int, 3>{points_2d, points_2d, 1}
                                     : std::array<int, 3>{points_3d, points_3d, points_3d};
  if (model.dimension == 2) grid.lo[2] = grid.hi[2] = 0.0;
  const sage::Tape tape(model.field, model.dimension);
  sage::Approximation approximation;
  approximation.tolerance = sage::kDefaultFarFieldTolerance * grid.diagonal();

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
  const double value = deviation(approximate.omega, exact.omega).first / grid.diagonal();
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

/// JSON models of `count` random balls (centres in [-1, 1]^3, radii 0.02
/// to 0.1) united by R0 and by min/max; returns their paths.
std::vector<std::string> write_random_balls(int count) {
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> centre(-1.0, 1.0), radius(0.02, 0.1);
  std::string balls;
  for (int i = 0; i < count; ++i) {
    const double x = centre(random), y = centre(random), z = centre(random);
    balls += (i ? ",\n" : "") + std::string(R"({"primitive": "ball", "center": [)") + std::to_string(x) + ", " +
             std::to_string(y) + ", " + std::to_string(z) + "], \"radius\": " + std::to_string(radius(random)) + "}";
  }
  std::vector<std::string> paths;
  for (const char* system : {"r0", "minmax"}) {
    const auto path =
        std::filesystem::temp_directory_path() / ("far_field_bench_balls_" + std::string(system) + ".json");
    std::ofstream(path) << R"({"dimension": 3, "rfunction": ")" << system
                        << R"(", "bounds": {"min": [-1.1, -1.1, -1.1], "max": [1.1, 1.1, 1.1]},
  "field": {"op": "union", "args": [)"
                        << balls << "]}}";
    paths.push_back(path.string());
  }
  return paths;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const int order = argc > 1 ? std::stoi(argv[1]) : 3;
  int first_model = 2, points_2d = 200, points_3d = 32;
  if (argc > 2 && std::isdigit(static_cast<unsigned char>(argv[2][0]))) {  // "N2D,N3D"
    points_2d = std::stoi(argv[2]);
    const char* comma = std::strchr(argv[2], ',');
    points_3d = comma ? std::stoi(comma + 1) : points_3d;
    first_model = 3;
  }
  std::vector<std::string> models;
  for (int i = first_model; i < argc; ++i) models.emplace_back(argv[i]);
  if (models.size() == 1 && models[0] == "balls") models = write_random_balls(1000);
  if (models.empty()) {
    const std::filesystem::path source(SAGE_SOURCE_DIR);
    for (const auto& entry : std::filesystem::directory_iterator(source / "examples/models"))
      if (entry.path().extension() == ".json") models.push_back(entry.path().string());
    std::sort(models.begin(), models.end());
    for (const char* name :
         {"gis/washington_island_wi_osm_EPSG3070.geojson", "gis/door_county_wi_us-atlas.geojson",
          "gis/lake_vanern_se_osm_EPSG32633.geojson", "gis/wisconsin_us-atlas_EPSG3070.geojson", "meshes/joint.off"})
      models.push_back(sage::bench::shared_data(name));
  }
  std::printf(
      "Grids %d^2 and %d^3, all cores, order %d; deviations over the whole grid: value / diagonal,\n"
      "gradient (absolute), higher orders relative to their largest magnitude\n\n",
      points_2d, points_3d, order);
  std::printf("| model | instructions | grid | exact s | approximate s | ratio | value | wrong signs | gradient |");
  for (int k = 2; k <= order; ++k) std::printf(" order %d |", k);
  std::printf("\n|---|---|---|---|---|---|---|---|---|");
  for (int k = 2; k <= order; ++k) std::printf("---|");
  std::printf("\n");
  for (const std::string& path : models) compare(path, order, points_2d, points_3d);
  return 0;
}
