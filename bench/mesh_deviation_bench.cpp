// How far `sage field`'s default sampling of a mesh's trimmed-face field
// (far faces in single precision, far_faces.hpp) lies from exact
// evaluation: at 10,000 grid points drawn at random (their own seed, apart
// from the 2,000 that sample_field checks), the largest difference of the
// value relative to the grid box's diagonal and in single-precision
// roundings of the exact value there, of the gradient relative to its
// length, and the number of signs that differ; with the sampling time
// (all cores). The acceptance check for mesh fields.
//
// Usage: mesh_deviation_bench N MESH...   (an N^3 grid over each mesh's box)

#include "mesh_grid.hpp"

#include <sage/geometry/mesh_model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (argc < 3) {
    std::fprintf(stderr, "usage: mesh_deviation_bench N MESH...\n");
    return 2;
  }
  const int n = std::stoi(argv[1]);
  constexpr std::size_t kPoints = 10000;
  std::printf("%-20s %6s %11s %12s %12s %12s %6s\n", "mesh", "grid", "sampling s", "value/diag", "roundings",
              "gradient/len", "signs");
  for (int m = 2; m < argc; ++m) {
    const std::string path = argv[m];
    const sage::geometry::Model model = sage::geometry::load_mesh(path, {});  // sage field's defaults
    const sage::Tape tape(model.field, 3);
    const sage::Grid grid = sage::bench::mesh_grid(model, n);

    const sage::SamplingPlan plan = sage::plan_sampling(tape, grid, 1);  // sage field's default
    const auto start = std::chrono::steady_clock::now();
    const sage::FieldSamples samples = sage::sample_field(tape, grid, 1, {}, &plan.approximation);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::mt19937_64 rng(4242);
    std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
    std::vector<std::size_t> at(kPoints);
    for (auto& i : at) i = pick(rng);
    std::vector<double> value_error(kPoints), roundings(kPoints), gradient_error(kPoints);
    std::vector<int> sign_differs(kPoints);
#pragma omp parallel
    {
      sage::Evaluator<sage::Tuple<3, 1>> exact(tape);
#pragma omp for schedule(dynamic, 16)
      for (std::size_t k = 0; k < kPoints; ++k) {
        const std::size_t i = at[k];
        const sage::Tuple<3, 1> want = exact.at(grid.point(i));
        value_error[k] = std::fabs(samples.omega[i] - want.value());
        roundings[k] = want.value() != 0
                           ? value_error[k] / (std::numeric_limits<float>::epsilon() * std::fabs(want.value()))
                           : 0.0;
        sign_differs[k] = (samples.omega[i] > 0) != (want.value() > 0) || (samples.omega[i] < 0) != (want.value() < 0);
        const auto g = want.gradient();
        double difference = 0, length = 0;
        for (int a = 0; a < 3; ++a) {
          const double d = samples.gradient[3 * i + static_cast<std::size_t>(a)] - g[static_cast<std::size_t>(a)];
          difference += d * d;
          length += g[static_cast<std::size_t>(a)] * g[static_cast<std::size_t>(a)];
        }
        gradient_error[k] = length > 0 ? std::sqrt(difference / length) : std::sqrt(difference);
      }
    }
    std::size_t signs = 0;
    for (int s : sign_differs) signs += static_cast<std::size_t>(s);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    std::printf("%-20s %6d %11.2f %12.2e %12.2f %12.2e %6zu%s\n", name.c_str(), n, seconds,
                *std::max_element(value_error.begin(), value_error.end()) / grid.diagonal(),
                *std::max_element(roundings.begin(), roundings.end()),
                *std::max_element(gradient_error.begin(), gradient_error.end()), signs,
                samples.far_faces ? (samples.far_faces_rejected ? "  (far faces rejected)" : "") : "  (exact)");
  }
  return 0;
}
