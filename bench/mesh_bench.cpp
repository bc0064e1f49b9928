// Trimmed-face B-rep fields of closed meshes at scale: the 75k-triangle
// Stanford bunny (bunny00.off) on a 128^3 grid. Prints the time to read,
// validate and build the field; the time of `sage field`'s sampling (value
// and gradient, interval-pruned tapes, pruned_grid.hpp) on all cores, in
// points per second; and beside it, in the same run, brute force (every
// point runs the whole tape, value and gradient, all cores) measured on a
// few points and extrapolated to the grid. For min/max gluing it first
// prints how far specialization shrinks the tape over nested boxes.
//
// Usage: mesh_bench [MESH] [N] [RFUNCTION ...]   (defaults: bunny00.off, 128, minmax r0)

#include "bench_support.hpp"
#include "mesh_grid.hpp"

#include <sage/geometry/mesh_model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Seconds per point of whole-tape evaluation (value and gradient) over
/// `samples` points spread through the grid, on all cores.
double brute_force_per_point(const sage::Tape& tape, const sage::Grid& grid, std::size_t samples) {
  const std::size_t stride = grid.size() / samples;
  std::vector<double> sink(samples);
  const auto start = std::chrono::steady_clock::now();
#pragma omp parallel
  {
    sage::Evaluator<sage::Tuple<3, 1>> eval(tape);
#pragma omp for schedule(dynamic, 1)
    for (std::size_t i = 0; i < samples; ++i) {
      const auto p = grid.point(i * stride + stride / 2);
      sink[i] = eval.at(p).value();
    }
  }
  return seconds(start) / static_cast<double>(samples);
}

/// Instructions left after specializing over nested boxes, 1/2 to 1/256
/// of the grid's extent, centred at `fraction` of the way along its
/// diagonal: how fast interval pruning shrinks the tape.
void print_shrinking(const sage::Tape& tape, const sage::Grid& grid, double fraction) {
  std::printf("  boxes around %.1f of the diagonal:", fraction);
  const sage::Tape* current = &tape;
  std::vector<std::unique_ptr<sage::Tape>> kept;
  for (int depth = 1; depth <= 8; ++depth) {
    std::array<sage::Interval, 3> box{};
    for (int a = 0; a < 3; ++a) {
      const double centre = grid.lo[a] + fraction * (grid.hi[a] - grid.lo[a]);
      const double half = 0.5 * (grid.hi[a] - grid.lo[a]) / (1 << depth);
      box[a] = sage::Interval(centre - half, centre + half);
    }
    sage::TapeSpecializer specializer(*current);
    if (std::optional<sage::Tape> smaller = specializer.specialize(box.data())) {
      kept.push_back(std::make_unique<sage::Tape>(std::move(*smaller)));
      current = kept.back().get();
    }
    std::printf(" 1/%d: %zu", 1 << depth, current->code().size());
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const std::string path = argc > 1 ? argv[1] : sage::bench::shared_data("meshes/bunny00.off");
  const int n = argc > 2 ? std::stoi(argv[2]) : 128;
  std::vector<std::string> systems;
  for (int i = 3; i < argc; ++i) systems.emplace_back(argv[i]);
  if (systems.empty()) systems = {"minmax", "r0"};

  std::printf("%s, %dx%dx%d grid, value and gradient\n", path.c_str(), n, n, n);
  std::printf("%-8s %9s %12s %12s %14s %14s %14s\n", "gluing", "build s", "tape instr", "sampling s", "points/s",
              "brute est. s", "brute points/s");
  for (const std::string& name : systems) {
    sage::geometry::LoadOptions options;
    options.method = "brep";
    options.rfunction = sage::RSystem::parse(name);
    auto start = std::chrono::steady_clock::now();
    const sage::geometry::Model model = sage::geometry::load_mesh(path, options);
    const double t_build = seconds(start);
    const sage::Tape tape(model.field, 3);

    const sage::Grid grid = sage::bench::mesh_grid(model, n);
    if (model.rfunction.kind == sage::RKind::MinMax) {
      std::printf("%-8s tape left after specializing (of %zu instructions):\n", name.c_str(), tape.code().size());
      for (double fraction : {0.5, 0.3, 0.1}) print_shrinking(tape, grid, fraction);
    }
    const double brute = brute_force_per_point(tape, grid, 256) * static_cast<double>(grid.size());

    // Pruning pays off for min/max gluing only (R-function nodes depend on
    // both arguments everywhere): run the grid when it takes minutes at most.
    double t_sample = -1;
    if (brute < 300 || model.rfunction.kind == sage::RKind::MinMax) {
      start = std::chrono::steady_clock::now();
      const sage::FieldSamples samples = sage::sample_field(tape, grid, 1);
      t_sample = seconds(start);
    }
    const double points = static_cast<double>(grid.size());
    if (t_sample >= 0)
      std::printf("%-8s %9.2f %12zu %12.2f %14.3g %14.0f %14.3g   (%.0fx)\n", name.c_str(), t_build, tape.code().size(),
                  t_sample, points / t_sample, brute, points / brute, brute / t_sample);
    else
      std::printf("%-8s %9.2f %12zu %12s %14s %14.0f %14.3g   (not run: no pruning)\n", name.c_str(), t_build,
                  tape.code().size(), "-", "-", brute, points / brute);
  }
  return 0;
}
