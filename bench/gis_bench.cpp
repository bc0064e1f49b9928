// GIS polygon fields at scale: Greenland (19,989 edges, repaired), the
// size of the classic paper's 20,748-edge Wisconsin. Prints the time to
// read, validate and build each expression; the time of brute-force
// evaluation in doubles (every point runs the whole tape) on an N x N
// grid, per point and extrapolated to 1000 x 1000; and the time of
// `sage field`'s sampling (value and gradient, interval-pruned tapes,
// pruned_grid.hpp) on an M x M grid, on one thread and on all cores, for
// the fields with min/max nodes to prune. Then the same sampling with far-field
// approximation (`sage field --tolerance`), with its deviation from exact
// evaluation measured at random grid points and the brute-force time of
// value and gradient beside it. Baseline in the same run: a single disk.
//
// Usage: gis_bench [GEOJSON] [N] [M] [TOLERANCE] [ENLARGEMENT] [SAMPLING_DEGREE] [ONLY] [CHECKS]
//        (defaults 64, 1000, 1e-10, and sage's defaults of Approximation;
//        TOLERANCE 0 skips the far-field part, ENLARGEMENT and
//        SAMPLING_DEGREE 0 keep the defaults; ONLY, e.g. "CSG r0", keeps
//        the M x M parts to the fields whose names contain it; CHECKS
//        random grid points for the deviation, default 2000)

#include "bench_support.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/geometry/gis_reader.hpp>
#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/polygon_csg.hpp>
#include <sage/geometry/polygon_validation.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape_specialization.hpp>

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <string>

namespace {

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Seconds to evaluate `field` in doubles at every point of `grid`, on all cores.
double evaluate_grid(const sage::Expr& field, const sage::Grid& grid, double* checksum) {
  const sage::Tape tape(field, 2);
  std::vector<double> values(grid.size());
  const auto start = std::chrono::steady_clock::now();
  sage::for_each_grid_point<double>(tape, grid,
                                    [&](std::size_t i, const sage::Evaluator<double>& e) { values[i] = e.result(); });
  const double t = seconds(start);
  *checksum = 0;
  for (double v : values) *checksum += v > 0;
  return t;
}

/// Seconds to sample value and gradient of `field` on `grid` with `threads`.
double sample_grid(const sage::Expr& field, const sage::Grid& grid, int threads,
                   const sage::Approximation* approximation = nullptr, sage::FieldSamples* out = nullptr) {
  const sage::Tape tape(field, 2);
  const int all = omp_get_max_threads();
  omp_set_num_threads(threads);
  const auto start = std::chrono::steady_clock::now();
  sage::FieldSamples samples = sage::sample_field(tape, grid, 1, {}, approximation);
  const double t = seconds(start);
  omp_set_num_threads(all);
  if (out) *out = std::move(samples);
  return t;
}

struct Deviation {
  double value = 0;                    // largest |approximate - exact| over the points
  double gradient = 0;                 // largest |grad approximate - grad exact|
  double exact_seconds_per_point = 0;  // value and gradient, whole tape, one thread
  std::size_t wrong_signs = 0;
};

/// Compares samples with exact evaluation of the whole tape (value and
/// gradient) at `count` random grid points.
Deviation measure_deviation(const sage::Expr& field, const sage::FieldSamples& samples, std::size_t count) {
  const sage::Tape tape(field, 2);
  sage::Evaluator<sage::Tuple<2, 1>> exact(tape);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, samples.grid.size() - 1);
  Deviation d;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = pick(rng);
    const auto t = exact.at(samples.grid.point(i));
    d.value = std::max(d.value, std::abs(t.value() - samples.omega[i]));
    d.gradient =
        std::max(d.gradient, std::hypot(t.c[1] - samples.gradient[3 * i], t.c[2] - samples.gradient[3 * i + 1]));
    d.wrong_signs += (t.value() > 0) != (samples.omega[i] > 0);
  }
  d.exact_seconds_per_point = seconds(start) / static_cast<double>(count);
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const std::string path = argc > 1 ? argv[1] : sage::bench::shared_data("gis/greenland_ne10m_EPSG3413.geojson");
  const int n = argc > 2 ? std::stoi(argv[2]) : 64;
  const int m = argc > 3 ? std::stoi(argv[3]) : 1000;
  const double relative_tolerance = argc > 4 ? std::stod(argv[4]) : 1e-10;
  const std::string only = argc > 7 ? argv[7] : "";
  auto chosen = [&](const char* name) { return std::string(name).find(only) != std::string::npos; };

  auto start = std::chrono::steady_clock::now();
  sage::geometry::LoadOptions options;
  options.repair = true;
  sage::geometry::GisPolygons gis = sage::geometry::read_gis_polygons(path, options);
  const double t_read = seconds(start);
  start = std::chrono::steady_clock::now();
  sage::geometry::validate_polygons(gis.polygons, path);
  const double t_validate = seconds(start);
  const auto& set = gis.polygons;
  std::printf("%s: %zu polygons, %zu edges\n", path.c_str(), set.polygons.size(), set.edge_count());
  std::printf("read + repair %.3f s, validate %.3f s\n", t_read, t_validate);

  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  set.for_each_ring([&](const sage::geometry::Ring& r) {
    for (const auto& p : r.points) {
      x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
    }
  });
  sage::Grid grid;
  grid.dimension = 2;
  grid.lo = {x0, y0, 0};
  grid.hi = {x1, y1, 0};
  grid.points = {n, n, 1};
  sage::Grid big = grid;
  big.points = {m, m, 1};

  struct Case {
    const char* name;
    std::function<sage::Expr()> build;
  };
  const Case cases[] = {
      {"disk (baseline)",
       [&] {
         return sage::ball({0.5 * (x0 + x1), 0.5 * (y0 + y1), 0}, 0.3 * (x1 - x0), 2);
       }},
      {"CSG minmax", [&] { return sage::geometry::polygon_csg(set, sage::RSystem::min_max()); }},
      {"CSG r0", [&] { return sage::geometry::polygon_csg(set, sage::RSystem::r0()); }},
      {"CSG rp:4", [&] { return sage::geometry::polygon_csg(set, sage::RSystem::r_p(4)); }},
      {"CSG rp:8", [&] { return sage::geometry::polygon_csg(set, sage::RSystem::r_p(8)); }},
      {"CSG ralpha:0.5", [&] { return sage::geometry::polygon_csg(set, sage::RSystem::r_alpha(0.5)); }},
      {"B-rep minmax", [&] { return sage::geometry::polygon_brep(set, sage::RSystem::min_max()); }},
      {"B-rep r0", [&] { return sage::geometry::polygon_brep(set, sage::RSystem::r0()); }},
  };
  std::printf("\n%-16s %10s %12s %14s %16s %14s\n", "field", "build s", "tape instr", "grid s", "ns/point/instr",
              "1000^2 est. s");
  struct Measured {
    const Case* c;
    sage::Expr field;
    double brute_per_point;  // seconds, from the table above
  };
  std::vector<Measured> fields;
  double baseline = 0;
  for (const Case& c : cases) {
    start = std::chrono::steady_clock::now();
    const sage::Expr field = c.build();
    const double t_build = seconds(start);
    const std::size_t instructions = sage::Tape(field, 2).code().size();
    double positive = 0;
    const double t_grid = evaluate_grid(field, grid, &positive);
    const double per_point = t_grid / static_cast<double>(grid.size());
    if (baseline == 0) baseline = per_point;
    std::printf("%-16s %10.3f %12zu %14.3f %16.2f %14.1f   (%.0f%% inside, %.0fx baseline)\n", c.name, t_build,
                instructions, t_grid, 1e9 * per_point / static_cast<double>(instructions), per_point * 1e6,
                100.0 * positive / static_cast<double>(grid.size()), per_point / baseline);
    fields.push_back({&c, field, per_point});
  }
  std::printf("\nbrute force: grid %dx%d in doubles on all cores, every point runs the whole tape.\n", n, n);

  std::printf("\nsage field sampling (value + gradient, pruned tapes) on %dx%d:\n", m, m);
  std::printf("%-16s %14s %14s %14s\n", "field", "1 thread s", "all cores s", "brute est. s");
  for (const auto& [c, field, brute_per_point] : fields) {
    if (!chosen(c->name)) continue;
    const double brute = brute_per_point * static_cast<double>(big.size());
    // Pruning needs min/max nodes; R-function trees would run whole (the
    // far-field part below times that as its brute force).
    if (!sage::TapeSpecializer::worthwhile(sage::Tape(field, 2))) {
      std::printf("%-16s %14s %14s %14.1f   (skipped: no pruning of R-function nodes)\n", c->name, "-", "-", brute);
      continue;
    }
    const double one = sample_grid(field, big, 1), all = sample_grid(field, big, omp_get_max_threads());
    std::printf("%-16s %14.3f %14.3f %14.1f   (%.0fx faster than brute force doubles on all cores)\n", c->name, one,
                all, brute, brute / all);
  }

  if (relative_tolerance <= 0) return 0;  // TOLERANCE 0: exact sampling only
  const double diagonal = std::hypot(x1 - x0, y1 - y0);
  sage::Approximation approximation;
  approximation.tolerance = relative_tolerance * diagonal;
  if (argc > 5 && std::stod(argv[5]) > 0) approximation.enlargement = std::stod(argv[5]);
  if (argc > 6 && std::stoi(argv[6]) > 0) approximation.sampling_degree = std::stoi(argv[6]);
  const std::size_t checks = argc > 8 ? std::stoul(argv[8]) : 2000;
  std::printf(
      "\nwith far-field approximation, tolerance %.0e of the diagonal (%.3g), enlargement %.1f, sampling degree"
      " %d, on %dx%d;\n",
      relative_tolerance, approximation.tolerance, approximation.enlargement, approximation.sampling_degree, m, m);
  std::printf(
      "deviation from exact value + gradient at %zu random grid points, brute force = exact value + gradient"
      " of the whole tape at every point, one thread:\n",
      checks);
  std::printf("%-16s %12s %12s %14s %14s %12s %12s %8s\n", "field", "1 thread s", "all cores s", "brute 1 thr s",
              "speed-up", "max |dw|/D", "max |dgrad|", "signs");
  for (const auto& [c, field, brute_per_point] : fields) {
    if (!chosen(c->name)) continue;
    sage::FieldSamples samples;
    const double one = sample_grid(field, big, 1, &approximation);
    const double all = sample_grid(field, big, omp_get_max_threads(), &approximation, &samples);
    const Deviation d = measure_deviation(field, samples, checks);
    const double brute = d.exact_seconds_per_point * static_cast<double>(big.size());
    std::printf("%-16s %12.3f %12.3f %14.1f %13.0fx %12.2e %12.2e %8zu\n", c->name, one, all, brute, brute / one,
                d.value / diagonal, d.gradient, d.wrong_signs);
  }
  return 0;
}
