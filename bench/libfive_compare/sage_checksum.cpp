// sage's side of the libfive comparison: samples the two ball models of
// far_field_bench (exact path, as far_field_bench's "exact s" column) on an
// N^3 grid at orders 0 and 1, prints the time (fastest of R runs), the count
// of positive points, the value sum and the sum of |grad|, and writes the
// order-0 values (raw float64, x fastest) to /tmp/libfive_compare_sage_
// <union>.f64 for balls.cpp to compare with point by point.
// Run with OMP_NUM_THREADS=1 for one thread.
//
// Usage: sage_checksum [N] [R]

#include <sage/geometry/model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/tape/tape.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const int n = argc > 1 ? std::atoi(argv[1]) : 128;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  std::printf("sage, grid %d^3, exact sampling, best of %d runs, OMP_NUM_THREADS=%s\n\n", n, runs,
              std::getenv("OMP_NUM_THREADS") ? std::getenv("OMP_NUM_THREADS") : "(unset)");
  std::printf(
      "| union | order | tape instructions | s | points > 0 | sum of values | sum |grad| "
      "|\n|---|---|---|---|---|---|---|\n");
  for (const char* u : {"minmax", "r0"}) {
    const std::string path = std::string("/tmp/far_field_bench_balls_") + u + ".json";
    const sage::geometry::Model model = sage::geometry::load_model(path, {});
    sage::Grid grid;
    grid.dimension = 3;
    grid.lo = model.bounds->min;
    grid.hi = model.bounds->max;
    grid.points = {n, n, n};
    const sage::Tape tape(model.field, 3);
    for (int order : {0, 1}) {
      sage::FieldSamples s;
      double best = 1e300;
      for (int r = 0; r < runs; ++r) {
        const auto t = std::chrono::steady_clock::now();
        s = sage::sample_field(tape, grid, order);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
      }
      std::size_t positive = 0;
      double sum = 0, grad = 0;
      for (double v : s.omega) positive += v > 0, sum += v;
      for (double g : s.gradient_norm) grad += g;
      std::printf("| %s | %d | %zu | %.4f | %zu | %.6e | %s |\n", u, order, tape.code().size(), best, positive, sum,
                  order ? std::to_string(grad).c_str() : "-");
      if (order == 0) {
        std::ofstream out(std::string("/tmp/libfive_compare_sage_") + u + ".f64", std::ios::binary);
        out.write(reinterpret_cast<const char*>(s.omega.data()), std::streamsize(s.omega.size() * sizeof(double)));
      }
    }
  }
  return 0;
}
