// R-function kernels over a batch's lanes (rfunction_lanes.hpp): R0 and
// rp:4 of 64 first-order tuples stored by component, as BatchEvaluator
// keeps its registers, beside the baseline of the same numbers computed a
// tuple at a time (r0_combine / rp_combine over an array of tuples).
//
// Prints Google Benchmark's table, then each kernel's time per lane as a
// ratio to its baseline measured in the same run.

#include <sage/rfunction.hpp>
#include <sage/rfunction_lanes.hpp>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using T = sage::Tuple<2, 1>;
constexpr std::size_t kLanes = 64;
constexpr int kRegisters = 8;  // the last is the output, the others inputs

// kRegisters registers of kLanes random tuples (values and partials in
// [-1, 1]), stored by component.
std::vector<double> random_registers() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> r(kRegisters * T::size * kLanes);
  for (double& v : r) v = u(rng);
  return r;
}

sage::TupleLanes<T> lanes(std::vector<double>& r, int k) { return {r.data() + k * T::size * kLanes, kLanes}; }

// Which registers iteration i combines (never the output, so values stay bounded).
int first(std::size_t i) { return static_cast<int>(i % (kRegisters - 1)); }
int second(std::size_t i) { return static_cast<int>((i + 1) % (kRegisters - 1)); }

template <int P>  // 0: R0
void BM_by_component(benchmark::State& state) {
  std::vector<double> r = random_registers();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto x = lanes(r, first(i)), y = lanes(r, second(i)), out = lanes(r, kRegisters - 1);
    if constexpr (P == 0)
      sage::r0_combine_lanes(x, y, out, kLanes, -1.0);
    else
      sage::rp_combine_lanes(x, y, out, kLanes, P, -1.0);
    benchmark::DoNotOptimize(r.data());
    ++i;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

template <int P>
void BM_tuple_at_a_time(benchmark::State& state) {
  std::vector<double> flat = random_registers();
  std::vector<T> r(kRegisters * kLanes);
  for (int k = 0; k < kRegisters; ++k)
    for (std::size_t l = 0; l < kLanes; ++l) r[k * kLanes + l] = lanes(flat, k).load(l);
  std::size_t i = 0;
  for (auto _ : state) {
    const T* x = &r[first(i) * kLanes];
    const T* y = &r[second(i) * kLanes];
    T* out = &r[(kRegisters - 1) * kLanes];
    for (std::size_t l = 0; l < kLanes; ++l)
      out[l] = P == 0 ? sage::r0_combine(x[l], y[l], -1.0) : sage::rp_combine(x[l], y[l], P, -1.0);
    benchmark::DoNotOptimize(r.data());
    ++i;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

BENCHMARK(BM_tuple_at_a_time<0>);
BENCHMARK(BM_by_component<0>);
BENCHMARK(BM_tuple_at_a_time<4>);
BENCHMARK(BM_by_component<4>);

// Keeps each run's time per lane for the ratios printed at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) ns_per_lane_[run.benchmark_name()] = run.GetAdjustedCPUTime() / kLanes;
  }
  void print_ratios() const {
    std::printf("\nns per lane, by component against a tuple at a time (same run):\n");
    for (const char* p : {"0", "4"}) {
      const double base = ns_per_lane_.at(std::string("BM_tuple_at_a_time<") + p + ">");
      const double fast = ns_per_lane_.at(std::string("BM_by_component<") + p + ">");
      std::printf("  %-5s %6.2f ns against %6.2f ns: %.2fx\n", *p == '0' ? "r0" : "rp:4", fast, base, base / fast);
    }
  }

 private:
  std::map<std::string, double> ns_per_lane_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  benchmark::Shutdown();
}
