// Fused linear forms (linear_form.hpp). Compiled without errno and trapping
// math, as tuple_op_lanes.cpp, and for AVX2 and AVX-512 too
// (vector_clones.hpp: no fused multiply-adds, so the same bits).
//
// The instructions' arithmetic, step for step (lane_steps.hpp):
//   Axpby   by component, a p + b q
//   c k     mul_constant: value 0.0 + c0 k, partials (0.0 + c0 0.0) + cj k
//   Add     by component
//   + d     value + d, partials + 0.0
// Doubles: a p + b q, c k, their sum, + d.

#include <sage/tape/linear_form.hpp>

#include "../scalars/lane_steps.hpp"
#include "../scalars/vector_clones.hpp"

namespace sage {

std::optional<LinearFormRun> find_linear_form(const Tape& tape, std::size_t first, const std::vector<char>& is_constant,
                                              const std::vector<double>& constant_value) {
  const std::vector<Instruction>& code = tape.code();
  const auto& producers = tape.producers();
  const auto& readers = tape.readers();
  if (tape.dimension() != 3 || first + 2 >= code.size()) return std::nullopt;
  auto constant = [&](std::uint32_t r) { return r < is_constant.size() && is_constant[r]; };
  const Instruction &axpby = code[first], &product = code[first + 1], &sum = code[first + 2];
  if (axpby.op != Op::Axpby || sum.op != Op::Add || readers[first] != 1 || readers[first + 1] != 1) return std::nullopt;
  const bool scale = product.op == Op::Scale;
  if (!scale && (product.op != Op::Mul || constant(product.a) == constant(product.b))) return std::nullopt;
  const auto& read = producers[first + 2];
  if (!((read[0] == first && read[1] == first + 1) || (read[0] == first + 1 && read[1] == first))) return std::nullopt;
  LinearFormRun run;
  run.a = axpby.a;
  run.b = axpby.b;
  const bool k_first = !scale && constant(product.a);
  run.c = k_first ? product.b : product.a;
  if (run.c == axpby.out) return std::nullopt;  // c must still hold its value after the Axpby
  const double k = scale ? product.p0 : constant_value[k_first ? product.a : product.b];
  run.form = {axpby.p0, axpby.p1, k, false, 0.0};
  std::size_t last = first + 2;
  if (last + 1 < code.size() && code[last + 1].op == Op::Offset && producers[last + 1][0] == last &&
      readers[last] == 1) {
    ++last;
    run.form.has_offset = true;
    run.form.d = code[last].p0;
  }
  run.out = code[last].out;
  run.length = last + 1 - first;
  return run;
}

namespace {

// The form is copied: stores to `out` cannot then change it, and the
// compiler keeps its numbers in registers.
[[gnu::always_inline]] inline void linear_form(const LinearForm form, ConstFirstOrderLanes<3> a,
                                               ConstFirstOrderLanes<3> b, ConstFirstOrderLanes<3> c,
                                               FirstOrderLanes<3> out, std::size_t count) {
  const LinearForm& f = form;
  const double *a0 = a.component(0), *b0 = b.component(0), *c0 = c.component(0);
  const double* aj[3] = {a.component(1), a.component(2), a.component(3)};
  const double* bj[3] = {b.component(1), b.component(2), b.component(3)};
  const double* cj[3] = {c.component(1), c.component(2), c.component(3)};
  double* o[4] = {out.component(0), out.component(1), out.component(2), out.component(3)};
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) {
    double partial[3];
    for (int j = 0; j < 3; ++j) partial[j] = lane::linear_form_partial(f, c0[l], aj[j][l], bj[j][l], cj[j][l]);
    o[0][l] = lane::linear_form_value<true>(f, a0[l], b0[l], c0[l]);
    for (int j = 0; j < 3; ++j) o[j + 1][l] = partial[j];
  }
}

}  // namespace

SAGE_VECTOR_CLONES void linear_form_lanes(const LinearForm& form, ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b,
                                          ConstFirstOrderLanes<3> c, FirstOrderLanes<3> out, std::size_t count) {
  linear_form(form, a, b, c, out, count);
}
SAGE_VECTOR_CLONES void linear_form_values(const LinearForm& form, const double* a, const double* b, const double* c,
                                           double* out, std::size_t count) {
  const LinearForm f = form;
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) out[l] = lane::linear_form_value<false>(f, a[l], b[l], c[l]);
}

}  // namespace sage
