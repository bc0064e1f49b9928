// Fused sums of squares (square_sum.hpp). Compiled without errno and
// trapping math, as tuple_op_lanes.cpp, and for AVX2 and AVX-512 too
// (vector_clones.hpp: no fused multiply-adds, so the same bits).
//
// The arithmetic, step for step, is what BatchEvaluator's kernels do for
// the instructions of the run (tests/libsage/batch_evaluator_test.cpp
// compares both with Evaluator bit for bit):
//   Offset        value a0 + c, partials ak + 0.0 (T(c) has zero partials;
//                 a Square without an Offset is run as one with c = 0)
//   Square        tuple_op_lanes' product: value 0.0 + o0 o0,
//                 partials (0.0 + o0 ok) + ok o0
//   Add           by component
//   c - sum       value c - s0, partials 0.0 - sk
//   sum / c       div_constant: value 0.0 + s0 / c's inverse, partials
//                 (0.0 + s0 slope 0.0) + sk inverse
// Doubles: a + c, (a + c) (a + c), sums, c - s, s / c.

#include <sage/tape/square_sum.hpp>

#include "../scalars/vector_clones.hpp"

#include <type_traits>

namespace sage {

std::optional<SquareSumRun> find_square_sum(const Tape& tape, std::size_t first, const std::vector<char>& is_constant,
                                            const std::vector<double>& constant_value) {
  const std::vector<Instruction>& code = tape.code();
  const std::vector<std::uint32_t>& readers = tape.readers();
  const std::size_t n = code.size();
  // Instruction k's result is read once, by the next step of the run.
  auto only_reader_next = [&](std::size_t k) { return readers[k] == 1; };
  // A term at j: Offset(a) then its Square, or a Square alone (offset 0:
  // squaring a + 0.0 gives the bits of squaring a, as only the sign of a
  // zero can differ).
  struct Term {
    std::uint32_t argument;
    double offset;
    std::size_t square;
  };
  auto term_at = [&](std::size_t j) -> std::optional<Term> {
    if (j >= n) return std::nullopt;
    if (code[j].op == Op::Square) return Term{code[j].a, 0.0, j};
    if (j + 1 < n && code[j].op == Op::Offset && code[j + 1].op == Op::Square && code[j + 1].a == code[j].out &&
        only_reader_next(j))
      return Term{code[j].a, code[j].p0, j + 1};
    return std::nullopt;
  };

  SquareSumRun run;
  const auto head = term_at(first);
  if (!head) return std::nullopt;
  run.arguments[0] = head->argument;
  run.sum.offsets[0] = head->offset;
  run.sum.terms = 1;
  std::size_t last = head->square;  // the instruction holding the sum so far
  std::size_t j = last + 1;
  while (run.sum.terms < 3) {
    const auto term = term_at(j);
    if (!term || term->square + 1 >= n) break;
    const Instruction& add = code[term->square + 1];
    const std::uint32_t sum = code[last].out, square = code[term->square].out;
    const bool adds = add.op == Op::Add && ((add.a == sum && add.b == square) || (add.a == square && add.b == sum));
    // The term's argument must still hold its value: no step so far wrote it.
    bool argument_intact = true;
    for (std::size_t k = first; k < j; ++k) argument_intact &= code[k].out != term->argument;
    if (!adds || sum == square || !argument_intact || !only_reader_next(last) || !only_reader_next(term->square)) break;
    run.arguments[static_cast<std::size_t>(run.sum.terms)] = term->argument;
    run.sum.offsets[static_cast<std::size_t>(run.sum.terms)] = term->offset;
    ++run.sum.terms;
    last = term->square + 1;
    j = last + 1;
  }
  auto constant = [&](std::uint32_t r) { return r < is_constant.size() && is_constant[r]; };
  if (j < n && code[j].op == Op::Sub && code[j].b == code[last].out && code[j].a != code[j].b && constant(code[j].a) &&
      only_reader_next(last)) {
    run.sum.has_minuend = true;
    run.sum.minuend = constant_value[code[j].a];
    last = j++;
  }
  if (j < n && code[j].op == Op::Div && code[j].a == code[last].out && code[j].a != code[j].b && constant(code[j].b) &&
      constant_value[code[j].b] != 0.0 && only_reader_next(last)) {
    run.sum.has_divisor = true;
    run.sum.divisor = constant_value[code[j].b];
    last = j++;
  }
  if (run.sum.terms < 2 && !run.sum.has_minuend && !run.sum.has_divisor) return std::nullopt;
  run.sum.coordinates = run.sum.terms == tape.dimension();
  for (int t = 0; t < run.sum.terms; ++t)
    run.sum.coordinates &= run.arguments[static_cast<std::size_t>(t)] == Tape::variable_register(t);
  run.out = code[last].out;
  run.length = j - first;
  return run;
}

namespace {

// The run with its shape known at compile time, so that the loop over
// lanes has no branches and vectorizes.
template <int N, int Terms, bool Minuend, bool Divisor, bool Coordinates>
[[gnu::always_inline]] inline void square_sum(const SquareSum& sum, const ConstFirstOrderLanes<N>* arguments,
                                              FirstOrderLanes<N> out, std::size_t count) {
  const double inverse = 1.0 / sum.divisor, slope = inverse * -1.0 / sum.divisor, partial = 0.0 + slope * 0.0;
  const double minuend = sum.minuend;
  const double* a[Terms][N + 1];
  double offset[Terms];
  for (int j = 0; j < Terms; ++j) {
    offset[j] = sum.offsets[static_cast<std::size_t>(j)];
    for (int k = 0; k <= N; ++k) a[j][k] = arguments[j].component(k);
  }
  double* o[N + 1];
  for (int k = 0; k <= N; ++k) o[k] = out.component(k);
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) {
    double s[N + 1];
    for (int j = 0; j < Terms; ++j) {
      const double o0 = a[j][0][l] + offset[j];
      if constexpr (Coordinates) {
        // The same terms with partials known exactly: 1.0 on the term's
        // own axis, +0.0 on the others (o0 1.0 is o0; 0.0 o0 is o0 0.0).
        const double t = o0 * 0.0, zero = (0.0 + t) + t, unit = (0.0 + o0) + o0;
        for (int k = 1; k <= N; ++k) s[k] = j == 0 ? (k == 1 ? unit : zero) : s[k] + (k == j + 1 ? unit : zero);
      } else {
        for (int k = 1; k <= N; ++k) {
          const double ok = a[j][k][l] + 0.0;
          const double q = (0.0 + o0 * ok) + ok * o0;
          s[k] = j == 0 ? q : s[k] + q;
        }
      }
      const double q0 = 0.0 + o0 * o0;
      s[0] = j == 0 ? q0 : s[0] + q0;
    }
    if constexpr (Minuend) {
      for (int k = 1; k <= N; ++k) s[k] = 0.0 - s[k];
      s[0] = minuend - s[0];
    }
    if constexpr (Divisor) {
      for (int k = 1; k <= N; ++k) s[k] = (0.0 + s[0] * partial) + s[k] * inverse;
      s[0] = 0.0 + s[0] * inverse;
    }
    for (int k = 0; k <= N; ++k) o[k][l] = s[k];
  }
}

template <int Terms, bool Minuend, bool Divisor>
[[gnu::always_inline]] inline void square_sum(const SquareSum& sum, const double* const* arguments, double* out,
                                              std::size_t count) {
  const double minuend = sum.minuend, divisor = sum.divisor;
  const double* a[Terms];
  double offset[Terms];
  for (int j = 0; j < Terms; ++j) {
    a[j] = arguments[j];
    offset[j] = sum.offsets[static_cast<std::size_t>(j)];
  }
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) {
    double s = 0;
    for (int j = 0; j < Terms; ++j) {
      const double v = a[j][l] + offset[j];
      s = j == 0 ? v * v : s + v * v;
    }
    if constexpr (Minuend) s = minuend - s;
    if constexpr (Divisor) s = s / divisor;
    out[l] = s;
  }
}

// Calls run(terms, minuend, divisor) with the run's shape as compile-time
// constants. Everything down to the loop is inlined into the entry points,
// so their clones compile it for AVX2 and AVX-512.
template <class Run>
[[gnu::always_inline]] inline void dispatch(const SquareSum& sum, Run run) {
  auto tails = [&](auto terms) __attribute__((always_inline)) {
    if (sum.has_minuend && sum.has_divisor) return run(terms, std::true_type{}, std::true_type{});
    if (sum.has_minuend) return run(terms, std::true_type{}, std::false_type{});
    if (sum.has_divisor) return run(terms, std::false_type{}, std::true_type{});
    return run(terms, std::false_type{}, std::false_type{});
  };
  switch (sum.terms) {
    case 1: return tails(std::integral_constant<int, 1>{});
    case 2: return tails(std::integral_constant<int, 2>{});
    default: return tails(std::integral_constant<int, 3>{});
  }
}

// First-order tuples of N variables: the coordinates' kernel where the
// terms are the point's coordinates, in order, one per axis.
template <int N>
[[gnu::always_inline]] inline void square_sum_tuples(const SquareSum& sum, const ConstFirstOrderLanes<N>* arguments,
                                                     FirstOrderLanes<N> out, std::size_t count) {
  dispatch(
      sum, [&](auto terms, auto minuend, auto divisor) __attribute__((always_inline)) {
        if (sum.coordinates && terms() == N)
          square_sum<N, terms(), minuend(), divisor(), true>(sum, arguments, out, count);
        else
          square_sum<N, terms(), minuend(), divisor(), false>(sum, arguments, out, count);
      });
}

}  // namespace

SAGE_VECTOR_CLONES void square_sum_lanes(const SquareSum& sum, const ConstFirstOrderLanes<2>* arguments,
                                         FirstOrderLanes<2> out, std::size_t count) {
  square_sum_tuples(sum, arguments, out, count);
}
SAGE_VECTOR_CLONES void square_sum_lanes(const SquareSum& sum, const ConstFirstOrderLanes<3>* arguments,
                                         FirstOrderLanes<3> out, std::size_t count) {
  square_sum_tuples(sum, arguments, out, count);
}
SAGE_VECTOR_CLONES void square_sum_values(const SquareSum& sum, const double* const* arguments, double* out,
                                          std::size_t count) {
  dispatch(
      sum, [&](auto terms, auto minuend, auto divisor) __attribute__((always_inline)) {
        square_sum<terms(), minuend(), divisor()>(sum, arguments, out, count);
      });
}

}  // namespace sage
