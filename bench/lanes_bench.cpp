// Kernels over a batch's lanes: R0 and rp:4 of 64 first-order tuples
// stored by component, as BatchEvaluator keeps its registers
// (rfunction_lanes.hpp), beside the baseline of the same numbers computed a
// tuple at a time (r0_combine / rp_combine over an array of tuples); and a
// Chebyshev patch of degree 10 over a leaf batch of 4 rows of 16 points
// (ChebyshevPatch::evaluate_rows) beside the same patch point by point;
// and the arithmetic of primitives and trimmed faces on first-order tuples
// (products, squares, roots, quotients, fourth powers: tuple_op_lanes.hpp)
// beside tuple.hpp's operators a tuple at a time; a disk's fused sum
// of squares (square_sum.hpp) beside its instructions' kernels one by one;
// and a mesh face, fused (trimmed_face.hpp), beside the evaluator a point
// at a time.
//
// Prints Google Benchmark's table, then each kernel's time per lane as a
// ratio to its baseline measured in the same run (by component against a
// tuple at a time, rows against point by point).

#include <sage/expression/trimming.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/scalars/rfunction_lanes.hpp>
#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/batch_evaluator.hpp>
#include <sage/tape/chebyshev_patch.hpp>
#include <sage/tape/square_sum.hpp>

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
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

// The same registers as an array of tuples (the baselines' layout).
std::vector<T> as_tuples(std::vector<double> flat) {
  std::vector<T> r(kRegisters * kLanes);
  for (int k = 0; k < kRegisters; ++k)
    for (std::size_t l = 0; l < kLanes; ++l) r[k * kLanes + l] = lanes(flat, k).load(l);
  return r;
}

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
  std::vector<T> r = as_tuples(random_registers());
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

// Tuple arithmetic: one kernel per op, over positive values (roots and
// quotients then take their vector branch, as inside a trimmed face).
enum Arith { kMul, kSquare, kSqrt, kDiv, kPow4 };

std::vector<double> positive_registers() {
  std::vector<double> r = random_registers();
  for (int k = 0; k < kRegisters; ++k)
    for (std::size_t l = 0; l < kLanes; ++l) r[k * T::size * kLanes + l] = 0.1 + std::abs(r[k * T::size * kLanes + l]);
  return r;
}

template <Arith A>
void BM_arith_by_component(benchmark::State& state) {
  std::vector<double> r = positive_registers();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto x = lanes(r, first(i)), y = lanes(r, second(i)), out = lanes(r, kRegisters - 1);
    if constexpr (A == kMul) sage::mul_lanes(x, y, out, kLanes);
    if constexpr (A == kSquare) sage::square_lanes(x, out, kLanes);
    if constexpr (A == kSqrt) sage::sqrt_lanes(x, out, kLanes);
    if constexpr (A == kDiv) sage::div_lanes(x, y, out, kLanes, false);
    if constexpr (A == kPow4) sage::pow_int_lanes(x, 4, out, kLanes);
    benchmark::DoNotOptimize(r.data());
    ++i;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

template <Arith A>
void BM_arith_tuple_at_a_time(benchmark::State& state) {
  std::vector<T> r = as_tuples(positive_registers());
  std::size_t i = 0;
  for (auto _ : state) {
    const T* x = &r[first(i) * kLanes];
    const T* y = &r[second(i) * kLanes];
    T* out = &r[(kRegisters - 1) * kLanes];
    for (std::size_t l = 0; l < kLanes; ++l) {
      if constexpr (A == kMul) out[l] = x[l] * y[l];
      if constexpr (A == kSquare) out[l] = sage::square(x[l]);
      if constexpr (A == kSqrt) out[l] = sage::sqrt(x[l]);
      if constexpr (A == kDiv) out[l] = x[l] / y[l];
      if constexpr (A == kPow4) out[l] = sage::pow_int(x[l], 4);
    }
    benchmark::DoNotOptimize(r.data());
    ++i;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

BENCHMARK(BM_arith_tuple_at_a_time<kMul>);
BENCHMARK(BM_arith_by_component<kMul>);
BENCHMARK(BM_arith_tuple_at_a_time<kSquare>);
BENCHMARK(BM_arith_by_component<kSquare>);
BENCHMARK(BM_arith_tuple_at_a_time<kSqrt>);
BENCHMARK(BM_arith_by_component<kSqrt>);
BENCHMARK(BM_arith_tuple_at_a_time<kDiv>);
BENCHMARK(BM_arith_by_component<kDiv>);
BENCHMARK(BM_arith_tuple_at_a_time<kPow4>);
BENCHMARK(BM_arith_by_component<kPow4>);

// A patch of degree 10 (the most far-field approximation's sampling degree
// 12 allows) of a field with a pole near the box, and a leaf batch: 4 rows
// of 16 points, as 64-point batches of 16 x 16 blocks are.
constexpr std::size_t kRowPoints = 16, kRows = kLanes / kRowPoints;
const sage::Interval kPatchBox[3] = {sage::Interval(-1, 1), sage::Interval(-1, 1), sage::Interval(0.0)};

std::shared_ptr<const sage::ChebyshevPatch> degree_10_patch() {
  const int n = 12;
  std::vector<double> f(static_cast<std::size_t>((n + 1) * (n + 1)));
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto p = sage::ChebyshevPatch::sample_point(kPatchBox, 2, n, k);
    f[k] = 1.0 / (3.0 - p[0] - 0.5 * p[1]);
  }
  for (double tolerance = 1e-12; tolerance < 1; tolerance *= 2)
    if (auto patch = sage::ChebyshevPatch::fit(kPatchBox, 2, n, f, tolerance)) {
      if (patch->degree() != 10) break;
      return patch;
    }
  throw std::logic_error("the benchmark's patch should have degree 10");
}

// The batch's variables x and y, by component, and the points' coordinates.
struct PatchBatch {
  std::vector<double> xs = std::vector<double>(kRowPoints);
  std::vector<std::array<double, 2>> rows = std::vector<std::array<double, 2>>(kRows);
  std::vector<double> vars[2], out = std::vector<double>(T::size * kLanes);
  PatchBatch() {
    for (std::size_t i = 0; i < kRowPoints; ++i) xs[i] = -0.9 + 0.1 * static_cast<double>(i);
    for (std::size_t r = 0; r < kRows; ++r) rows[r] = {-0.7 + 0.4 * static_cast<double>(r), 0.0};
    for (int a = 0; a < 2; ++a) {
      vars[a].resize(T::size * kLanes);
      const sage::TupleLanes<T> lanes{vars[a].data(), kLanes};
      for (std::size_t p = 0; p < kLanes; ++p)
        lanes.store(p, T::variable(a, a == 0 ? xs[p % kRowPoints] : rows[p / kRowPoints][0]));
    }
  }
  T variable(int a, std::size_t p) const { return sage::ConstTupleLanes<T>{vars[a].data(), kLanes}.load(p); }
};

void BM_patch_point_by_point(benchmark::State& state) {
  const auto patch = degree_10_patch();
  PatchBatch batch;
  std::vector<T> out(kLanes);
  for (auto _ : state) {
    for (std::size_t p = 0; p < kLanes; ++p) {
      const T at[2] = {batch.variable(0, p), batch.variable(1, p)};
      out[p] = patch->evaluate(at);
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

void BM_patch_rows(benchmark::State& state) {
  const auto patch = degree_10_patch();
  PatchBatch batch;
  const sage::ConstTupleLanes<T> vars[2] = {{batch.vars[0].data(), kLanes}, {batch.vars[1].data(), kLanes}};
  for (auto _ : state) {
    patch->evaluate_rows(batch.xs.data(), kRowPoints, batch.rows.data(), kRows, vars,
                         sage::TupleLanes<T>{batch.out.data(), kLanes});
    benchmark::DoNotOptimize(batch.out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

BENCHMARK(BM_patch_point_by_point);
BENCHMARK(BM_patch_rows);

// A disk, (r^2 - (x - a)^2 - (y - b)^2) / (2 r), over the point's
// coordinates: the fused kernel (square_sum.hpp) beside its seven tape
// instructions run one by one with the batch evaluator's kernels (what it
// did before the fusion; the same bits, checked once).
struct DiskBatch {
  static constexpr double kA = 0.25, kB = -0.5, kR = 0.75;
  std::vector<double> coordinates[2], out = std::vector<double>(T::size * kLanes),
                                      scratch = std::vector<double>(T::size * kLanes);
  DiskBatch() {
    for (int a = 0; a < 2; ++a) {
      coordinates[a].resize(T::size * kLanes);
      const sage::TupleLanes<T> lanes{coordinates[a].data(), kLanes};
      for (std::size_t p = 0; p < kLanes; ++p)
        lanes.store(p, T::variable(a, -1.0 + 2.0 * static_cast<double>((p * (a + 3)) % kLanes) / kLanes));
    }
  }
  sage::ConstTupleLanes<T> coordinate(int a) const { return {coordinates[a].data(), kLanes}; }
  static sage::SquareSum disk() {
    sage::SquareSum sum;
    sum.terms = 2;
    sum.offsets = {-kA, -kB, 0.0};
    sum.has_minuend = sum.has_divisor = sum.coordinates = true;
    sum.minuend = kR * kR;
    sum.divisor = 2 * kR;
    return sum;
  }
  void fused() {
    const sage::ConstTupleLanes<T> arguments[2] = {coordinate(0), coordinate(1)};
    sage::square_sum_lanes(disk(), arguments, sage::TupleLanes<T>{out.data(), kLanes}, kLanes);
  }
  // Offset (the value + c, the partials + 0.0) and Square into `to`.
  void offset_square(int a, double c, std::vector<double>& to) {
    sage::array_op(sage::ArrayOp::Offset, coordinates[a].data(), nullptr, c, 0, 0, to.data(), kLanes);
    sage::array_op(sage::ArrayOp::Offset, coordinates[a].data() + kLanes, nullptr, 0.0, 0, 0, to.data() + kLanes,
                   2 * kLanes);
    sage::square_lanes(sage::ConstTupleLanes<T>{to.data(), kLanes}, sage::TupleLanes<T>{to.data(), kLanes}, kLanes);
  }
  void one_by_one() {
    offset_square(0, -kA, out);
    offset_square(1, -kB, scratch);
    sage::array_op(sage::ArrayOp::Add, out.data(), scratch.data(), 0, 0, 0, out.data(), T::size * kLanes);
    sage::array_op(sage::ArrayOp::ConstantMinus, out.data(), nullptr, kR * kR, 0, 0, out.data(), kLanes);
    sage::array_op(sage::ArrayOp::ConstantMinus, out.data() + kLanes, nullptr, 0.0, 0, 0, out.data() + kLanes,
                   2 * kLanes);
    sage::div_constant_lanes(sage::ConstTupleLanes<T>{out.data(), kLanes}, 2 * kR,
                             sage::TupleLanes<T>{out.data(), kLanes}, kLanes, false);
  }
};

void BM_disk_one_by_one(benchmark::State& state) {
  DiskBatch batch;
  for (auto _ : state) {
    batch.one_by_one();
    benchmark::DoNotOptimize(batch.out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

void BM_disk_fused(benchmark::State& state) {
  DiskBatch batch;
  batch.one_by_one();
  const std::vector<double> expected = batch.out;
  batch.fused();
  if (batch.out != expected) throw std::logic_error("the fused disk should give the instructions' numbers");
  for (auto _ : state) {
    batch.fused();
    benchmark::DoNotOptimize(batch.out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

BENCHMARK(BM_disk_one_by_one);
BENCHMARK(BM_disk_fused);

// A mesh face (trimming.hpp's triangle_field, 27 instructions), value and
// gradient at 64 points around it: the batch evaluator, where it is one
// fused kernel (trimmed_face.hpp), beside the evaluator a point at a time
// (the same bits, checked once).
struct FaceBatch {
  sage::Tape tape{sage::triangle_field({0.125, -0.25, 0.5}, {1.0, 0.0, 0.25}, {0.25, 1.0, -0.5}), 3};
  std::vector<std::array<double, 3>> points;
  std::vector<double> out = std::vector<double>(kLanes);
  FaceBatch() {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (std::size_t p = 0; p < kLanes; ++p) points.push_back({u(rng), u(rng), u(rng)});
  }
};

void BM_face_point_by_point(benchmark::State& state) {
  FaceBatch face;
  sage::Evaluator<sage::Tuple<3, 1>> single(face.tape);
  for (auto _ : state) {
    for (std::size_t p = 0; p < kLanes; ++p) {
      single.evaluate(face.points[p].data());
      face.out[p] = single.result().c[1];
    }
    benchmark::DoNotOptimize(face.out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

void BM_face_fused(benchmark::State& state) {
  FaceBatch face;
  sage::BatchEvaluator<sage::Tuple<3, 1>> batch(face.tape, kLanes);
  sage::Evaluator<sage::Tuple<3, 1>> single(face.tape);
  batch.evaluate(face.points.data(), kLanes);
  for (std::size_t p = 0; p < kLanes; ++p) {
    single.evaluate(face.points[p].data());
    if (batch.result(p).c != single.result().c) throw std::logic_error("the fused face should give the same numbers");
  }
  for (auto _ : state) {
    batch.evaluate(face.points.data(), kLanes);
    face.out[0] = batch.result(0).c[1];
    benchmark::DoNotOptimize(face.out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kLanes));
}

BENCHMARK(BM_face_point_by_point);
BENCHMARK(BM_face_fused);

// Keeps each run's time per lane for the ratios printed at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) ns_per_lane_[run.benchmark_name()] = run.GetAdjustedCPUTime() / kLanes;
  }
  void print_ratios() const {
    auto ratio = [&](const char* what, const std::string& fast, const std::string& base) {
      if (!ns_per_lane_.count(fast) || !ns_per_lane_.count(base)) return;  // filtered out
      const double f = ns_per_lane_.at(fast), b = ns_per_lane_.at(base);
      std::printf("  %-7s %6.2f ns against %6.2f ns: %.2fx\n", what, f, b, b / f);
    };
    std::printf("\nns per lane against the baseline of the same numbers (same run):\n");
    ratio("r0", "BM_by_component<0>", "BM_tuple_at_a_time<0>");
    ratio("rp:4", "BM_by_component<4>", "BM_tuple_at_a_time<4>");
    ratio("patch", "BM_patch_rows", "BM_patch_point_by_point");
    ratio("disk", "BM_disk_fused", "BM_disk_one_by_one");
    ratio("face", "BM_face_fused", "BM_face_point_by_point");
    const char* arith[] = {"kMul", "kSquare", "kSqrt", "kDiv", "kPow4"};
    const char* names[] = {"mul", "square", "sqrt", "div", "pow 4"};
    for (int a = 0; a < 5; ++a)
      ratio(names[a], std::string("BM_arith_by_component<") + arith[a] + ">",
            std::string("BM_arith_tuple_at_a_time<") + arith[a] + ">");
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
