// Fused smooth trimmings (smooth_trim.hpp). Compiled without errno and
// trapping math, as tuple_op_lanes.cpp, and for AVX2 and AVX-512 too
// (vector_clones.hpp: no fused multiply-adds, so the same bits).
//
// The arithmetic is lane_steps.hpp's, step for step what BatchEvaluator's
// kernels do for the instructions of the run
// (tests/libsage/batch_evaluator_test.cpp compares both with Evaluator bit
// for bit).

#include <sage/tape/smooth_trim.hpp>

#include <sage/scalars/tuple.hpp>

#include "../scalars/lane_steps.hpp"
#include "../scalars/vector_clones.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace sage {

std::optional<SmoothTrimRun> find_smooth_trim(const Tape& tape, std::size_t first) {
  const std::vector<Instruction>& code = tape.code();
  const auto& producers = tape.producers();
  const auto& readers = tape.readers();
  const std::size_t n = code.size();
  if (first >= n || code[first].op != Op::Square) return std::nullopt;
  // Instruction j's arguments are the results of instructions x and y (in
  // either order), and each intermediate is read by the run alone.
  auto reads = [&](std::size_t j, std::size_t x, std::size_t y) {
    const auto& p = producers[j];
    return (p[0] == x && p[1] == y) || (p[0] == y && p[1] == x);
  };
  auto read_once = [&](std::size_t j) { return readers[j] == 1; };

  SmoothTrimRun run;
  const std::size_t square_t = first;
  run.t = code[square_t].a;
  const std::uint32_t t_producer = producers[square_t][0];
  std::size_t j = first + 1;
  // Optional h c, then u^4.
  std::size_t power_argument = Tape::kInput;
  if (j < n && code[j].op == Op::Scale && read_once(j)) {
    run.h = code[j].a;
    run.trim.has_scale = true;
    run.trim.scale = code[j].p0;
    power_argument = j++;
  }
  if (j >= n || code[j].op != Op::PowInt || code[j].p0 != 4.0 || !read_once(j)) return std::nullopt;
  if (run.trim.has_scale) {
    if (producers[j][0] != power_argument) return std::nullopt;
  } else {
    run.h = code[j].a;
  }
  const std::size_t power = j++;
  if (j + 5 >= n || !read_once(square_t)) return std::nullopt;
  const std::size_t sum = j, root = j + 1, mix = j + 2, square_mix = j + 3, total = j + 4, result = j + 5;
  if (code[sum].op != Op::Add || !reads(sum, square_t, power) || !read_once(sum)) return std::nullopt;
  if (code[root].op != Op::Sqrt || producers[root][0] != sum || !read_once(root)) return std::nullopt;
  if (code[mix].op != Op::Axpby || !reads(mix, root, t_producer) || !read_once(mix)) return std::nullopt;
  if (code[mix].a == code[mix].b) return std::nullopt;
  const bool root_first = producers[mix][0] == root;
  if ((root_first ? code[mix].b : code[mix].a) != run.t) return std::nullopt;
  run.trim.root_weight = root_first ? code[mix].p0 : code[mix].p1;
  run.trim.t_weight = root_first ? code[mix].p1 : code[mix].p0;
  if (code[square_mix].op != Op::Square || producers[square_mix][0] != mix || !read_once(square_mix))
    return std::nullopt;
  if (code[total].op != Op::Add || code[total].a == code[total].b || !read_once(total)) return std::nullopt;
  const bool mix_first = producers[total][0] == square_mix;
  if (!mix_first && producers[total][1] != square_mix) return std::nullopt;
  run.addend = mix_first ? code[total].b : code[total].a;
  if (code[result].op != Op::Sqrt || producers[result][0] != total) return std::nullopt;
  // t, h and the addend still hold their values where the run reads them:
  // no instruction of the run before that point wrote their registers.
  auto intact = [&](std::uint32_t r, std::size_t until) {
    for (std::size_t k = first; k < until; ++k)
      if (code[k].out == r) return false;
    return true;
  };
  const std::size_t reads_h = run.trim.has_scale ? power_argument : power;
  if (!intact(run.t, mix) || !intact(run.h, reads_h) || !intact(run.addend, total)) return std::nullopt;
  run.out = code[result].out;
  run.length = result + 1 - first;
  return run;
}

namespace {

constexpr std::size_t kChunk = 64;

template <int N, bool Scale>
[[gnu::always_inline]] inline void smooth_trim(const SmoothTrim& trim, ConstFirstOrderLanes<N> t,
                                               ConstFirstOrderLanes<N> h, ConstFirstOrderLanes<N> addend,
                                               FirstOrderLanes<N> out, std::size_t count) {
  double w[N + 1][kChunk];
  bool singular[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    std::size_t singular_count = 0;
#pragma GCC ivdep
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = start + l;
      double tl[N + 1], hl[N + 1], sl[N + 1], wl[N + 1];
      for (int k = 0; k <= N; ++k) {
        tl[k] = t.component(k)[i];
        hl[k] = h.component(k)[i];
        sl[k] = addend.component(k)[i];
      }
      const bool is_singular = !lane::smooth_trim<N, Scale>(trim, tl, hl, sl, wl);
      for (int k = 0; k <= N; ++k) w[k][l] = wl[k];
      singular[l] = is_singular;
      singular_count += is_singular;
    }
    if (singular_count == 0) {
      for (int k = 0; k <= N; ++k) std::copy(w[k], w[k] + n, out.component(k) + start);
      continue;
    }
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = start + l;
      if (singular[l]) {
        out.store(i, lane::smooth_trim_operators(trim, t.load(i), h.load(i), addend.load(i)));
        continue;
      }
      for (int k = 0; k <= N; ++k) out.component(k)[i] = w[k][l];
    }
  }
}

template <int N>
[[gnu::always_inline]] inline void smooth_trim_tuples(const SmoothTrim& trim, ConstFirstOrderLanes<N> t,
                                                      ConstFirstOrderLanes<N> h, ConstFirstOrderLanes<N> addend,
                                                      FirstOrderLanes<N> out, std::size_t count) {
  if (trim.has_scale)
    smooth_trim<N, true>(trim, t, h, addend, out, count);
  else
    smooth_trim<N, false>(trim, t, h, addend, out, count);
}

template <bool Scale>
[[gnu::always_inline]] inline void smooth_trim(const SmoothTrim& trim, const double* t, const double* h,
                                               const double* addend, double* out, std::size_t count) {
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) out[l] = lane::smooth_trim<Scale>(trim, t[l], h[l], addend[l]);
}

}  // namespace

SAGE_VECTOR_CLONES void smooth_trim_lanes(const SmoothTrim& trim, ConstFirstOrderLanes<2> t, ConstFirstOrderLanes<2> h,
                                          ConstFirstOrderLanes<2> addend, FirstOrderLanes<2> out, std::size_t count) {
  smooth_trim_tuples(trim, t, h, addend, out, count);
}
SAGE_VECTOR_CLONES void smooth_trim_lanes(const SmoothTrim& trim, ConstFirstOrderLanes<3> t, ConstFirstOrderLanes<3> h,
                                          ConstFirstOrderLanes<3> addend, FirstOrderLanes<3> out, std::size_t count) {
  smooth_trim_tuples(trim, t, h, addend, out, count);
}
SAGE_VECTOR_CLONES void smooth_trim_values(const SmoothTrim& trim, const double* t, const double* h,
                                           const double* addend, double* out, std::size_t count) {
  if (trim.has_scale)
    smooth_trim<true>(trim, t, h, addend, out, count);
  else
    smooth_trim<false>(trim, t, h, addend, out, count);
}

}  // namespace sage
