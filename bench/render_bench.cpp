// Rays per second of `sage render`'s two hit methods on the same frames:
// interval bisection along the ray (the baseline) and sphere tracing with
// Lipschitz bounds from interval gradients, on 2 threads, for the gallery
// models (paper 003's primitives and CSG combinations) and for a CSG tree
// of about 100 nodes (a union of 25 balls and 25 boxes). Prints primary
// rays per second (no shadows), the ratio sphere / interval, and interval
// bisection without tape pruning (the whole tape on every segment) with
// the speed-up of pruning.
//
// Usage: render_bench [WIDTHxHEIGHT] [MODEL.json ...]
//   (defaults: 320x240, every model in examples/gallery/)

#include <sage/expression/primitives.hpp>
#include <sage/geometry/model.hpp>
#include <sage/render/solid.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

struct Scene {
  std::string name;
  sage::Expr field;
  sage::render::Vec3 lo, hi;
};

/// 25 balls and 25 boxes on a 7 x 7 x 1 lattice, joined by max: 50
/// primitives and 49 unions (each box is itself 6 halfspaces and min nodes).
Scene csg_tree() {
  sage::Expr u;
  bool first = true;
  for (int i = 0; i < 50; ++i) {
    const double x = -1.5 + 0.5 * (i % 7), y = -1.5 + 0.5 * (i / 7 % 7), z = 0.15 * std::sin(1.7 * i);
    const sage::Expr leaf =
        i % 2 ? sage::ball({x, y, z}, 0.22, 3)
              : sage::box({x - 0.18, y - 0.18, z - 0.18}, {x + 0.18, y + 0.18, z + 0.18}, 3, sage::RSystem::min_max());
    u = first ? leaf : max(u, leaf);
    first = false;
  }
  return {"csg_tree_50_balls_boxes", u, {-1.8, -1.8, -0.6}, {1.8, 1.8, 0.6}};
}

struct Run {
  double rays_per_second;
  long long hits;
};

Run run(const Scene& s, sage::render::HitMethod method, int width, int height, bool prune = true) {
  sage::render::SolidOptions o;
  o.prune_tapes = prune;
  o.width = width, o.height = height;
  o.camera = sage::render::camera_for_box(s.lo, s.hi);
  o.method = method;
  const sage::render::SolidPicture pic = sage::render::render_solid(s.field, s.lo, s.hi, o);
  return {pic.stats.rays / pic.stats.seconds, pic.stats.hits};
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int width = 320, height = 240;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.find('x') != std::string::npos && a.find(".json") == std::string::npos)
      std::sscanf(a.c_str(), "%dx%d", &width, &height);
    else
      paths.push_back(a);
  }
  if (paths.empty()) {
    for (const auto& e : std::filesystem::directory_iterator(std::string(SAGE_SOURCE_DIR) + "/examples/gallery"))
      if (e.path().extension() == ".json") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
  }
  std::vector<Scene> scenes;
  for (const std::string& p : paths) {
    const sage::geometry::Model m = sage::geometry::load_model(p);
    if (m.dimension != 3 || !m.bounds) continue;
    scenes.push_back({std::filesystem::path(p).stem().string(), m.field, m.bounds->min, m.bounds->max});
  }
  scenes.push_back(csg_tree());

  omp_set_num_threads(2);
  std::printf("%dx%d primary rays, 2 threads, default camera of each box\n", width, height);
  std::printf("%-34s %8s %14s %14s %8s %14s %8s\n", "model", "hits", "interval ray/s", "sphere ray/s", "ratio",
              "unpruned ray/s", "pruning");
  for (const Scene& s : scenes) {
    const Run a = run(s, sage::render::HitMethod::IntervalBisection, width, height);
    const Run b = run(s, sage::render::HitMethod::SphereTracing, width, height);
    const Run c = run(s, sage::render::HitMethod::IntervalBisection, width, height, false);
    std::printf("%-34s %8lld %14.0f %14.0f %8.2f %14.0f %8.2f%s\n", s.name.c_str(), a.hits, a.rays_per_second,
                b.rays_per_second, b.rays_per_second / a.rays_per_second, c.rays_per_second,
                a.rays_per_second / c.rays_per_second,
                a.hits == b.hits && a.hits == c.hits ? "" : "  (hit counts differ)");
  }
  return 0;
}
