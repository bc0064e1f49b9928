// Tape evaluation speed: the paper 004 fig. 9 solid (an R0 intersection of
// two cylinders, a cone and two planes) evaluated point by point with each
// scalar type, beside the same field written by hand in C++ (the baseline:
// what a compiler makes of the formula with no tape at all).
//
// Prints Google Benchmark's table, then each case's time per point as a
// ratio to the hand-written baseline measured in the same run.

#include <sage/geometry/csg_model.hpp>
#include <sage/tape/evaluator.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

const sage::geometry::Model& fig9() {
  static const sage::geometry::Model m =
      sage::geometry::read_model(std::string(SAGE_SOURCE_DIR) + "/examples/models/paper004_fig9_solid.json");
  return m;
}

std::vector<std::array<double, 3>> sample_points() {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.2, 1.2), w(-0.2, 1.4);
  std::vector<std::array<double, 3>> p(4096);
  for (auto& q : p) q = {u(rng), u(rng), w(rng)};
  return p;
}

// The same field as examples/models/paper004_fig9_solid.json, by hand.
double r0_and(double a, double b) { return a + b - std::sqrt(a * a + b * b); }
double fig9_by_hand(const std::array<double, 3>& p) {
  const double x = p[0], y = p[1], z = p[2];
  const double rho2 = x * x + y * y;
  const double outer = (1 - rho2) / 2;
  const double bore = -(0.0625 - rho2) / 0.5;
  const double bottom = z;
  const double top = -(x + 2 * y + 8 * (z - 1)) / std::sqrt(69.0);
  const double h = 2 - z, a = 35 * M_PI / 180;
  const double cone = h * std::sin(a) - std::sqrt(rho2) * std::cos(a);
  return r0_and(r0_and(r0_and(outer, bore), r0_and(bottom, top)), cone);
}

void BM_hand_written_double(benchmark::State& state) {
  const auto points = sample_points();
  for (auto _ : state)
    for (const auto& p : points) benchmark::DoNotOptimize(fig9_by_hand(p));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(points.size()));
}

template <class T>
void BM_tape(benchmark::State& state) {
  const sage::Tape tape(fig9().field, 3);
  sage::Evaluator<T> eval(tape);
  const auto points = sample_points();
  for (auto _ : state)
    for (const auto& p : points) {
      eval.evaluate(p.data());
      benchmark::DoNotOptimize(eval.result());
    }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(points.size()));
}

void BM_tape_interval(benchmark::State& state) {
  const sage::Tape tape(fig9().field, 3);
  sage::Evaluator<sage::Interval> eval(tape);
  const auto points = sample_points();
  for (auto _ : state)
    for (const auto& p : points) {
      const sage::Interval box[3] = {{p[0], p[0] + 0.01}, {p[1], p[1] + 0.01}, {p[2], p[2] + 0.01}};
      eval.evaluate_with(box);
      benchmark::DoNotOptimize(eval.result());
    }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(points.size()));
}

BENCHMARK(BM_hand_written_double);
BENCHMARK(BM_tape<double>);
BENCHMARK(BM_tape_interval);
BENCHMARK(BM_tape<sage::Tuple<3, 1>>);
BENCHMARK(BM_tape<sage::Tuple<3, 2>>);
BENCHMARK(BM_tape<sage::Tuple<3, 4>>);
BENCHMARK(BM_tape<sage::Tuple<3, 6>>);

/// Records each run's time per iteration, to print ratios at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) times_[r.benchmark_name()] = r.GetAdjustedRealTime();
    ConsoleReporter::ReportRuns(runs);
  }
  void print_ratios() const {
    const auto base = times_.find("BM_hand_written_double");
    if (base == times_.end()) return;
    std::printf("\nTime per point relative to the hand-written double baseline (same run):\n");
    for (const auto& [name, t] : times_) std::printf("  %-34s %8.2fx\n", name.c_str(), t / base->second);
  }

 private:
  std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::printf("fig. 9 solid: %zu tape instructions\n", sage::Tape(fig9().field, 3).code().size());
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  benchmark::Shutdown();
  return 0;
}
