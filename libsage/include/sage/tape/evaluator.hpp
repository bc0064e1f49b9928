#pragma once
// Evaluator<T>: runs a Tape with one scalar type T (double, Interval or
// Tuple<N, K>). Every operation is written once below, generic over T;
// types specialise only through the overloads of their own headers (the
// exact interval rule of monotone R-functions, for instance).
//
// Ownership: an Evaluator borrows its Tape (which must outlive it) and owns
// its registers. It is not thread-safe: make one per thread; they may share
// the tape.
//
//     Tape tape(field, 2);
//     Evaluator<double> eval(tape);
//     double w = eval.at({0.5, 0.25});
//     Evaluator<Tuple<2, 4>> tuples(tape);
//     Tuple<2, 4> t = tuples.at({0.5, 0.25});   // value and partials to order 4

#include <sage/expression/classifier.hpp>
#include <sage/scalars/interval.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/scalars/tuple.hpp>
#include <sage/tape/chebyshev_patch.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <type_traits>
#include <vector>

#if defined(__GNUC__)
#define SAGE_ALWAYS_INLINE [[gnu::always_inline]] inline
#else
#define SAGE_ALWAYS_INLINE inline
#endif

namespace sage {

/// How to seed independent variable `var` at `value` in scalar type T.
template <class T>
struct Seed {
  static T variable(int /*var*/, double value) { return T(value); }
};
template <int N, int K>
struct Seed<Tuple<N, K>> {
  static Tuple<N, K> variable(int var, double value) { return Tuple<N, K>::variable(var, value); }
};

/// Point membership at the evaluation point: a constant for doubles and
/// tuples (classified at the value), the classifier's enclosure for boxes.
inline double classify_at(const PointClassifier& c, const double* vars) { return c.classify(vars); }
inline Interval classify_at(const PointClassifier& c, const Interval* vars) { return c.classify_box(vars); }
template <int N, int K>
Tuple<N, K> classify_at(const PointClassifier& c, const Tuple<N, K>* vars) {
  double p[3] = {0, 0, 0};
  for (int i = 0; i < N; ++i) p[i] = vars[i].value();
  return Tuple<N, K>(c.classify(p));
}

/// Operation `op` of the table, generic over the scalar type.
template <Op op, class T>
SAGE_ALWAYS_INLINE T apply_op(const Instruction& ins, const T& a, const T& b) {
  if constexpr (op == Op::Neg)
    return -a;
  else if constexpr (op == Op::Square)
    return square(a);
  else if constexpr (op == Op::Sqrt)
    return sqrt(a);
  else if constexpr (op == Op::Exp)
    return exp(a);
  else if constexpr (op == Op::Log)
    return log(a);
  else if constexpr (op == Op::Sin)
    return sin(a);
  else if constexpr (op == Op::Cos)
    return cos(a);
  else if constexpr (op == Op::Abs)
    return abs(a);
  else if constexpr (op == Op::Step)
    return step(a);
  else if constexpr (op == Op::PowInt)
    return pow_int(a, static_cast<int>(ins.p0));
  else if constexpr (op == Op::PowReal)
    return pow_real(a, ins.p0);
  else if constexpr (op == Op::Add)
    return a + b;
  else if constexpr (op == Op::Sub)
    return a - b;
  else if constexpr (op == Op::Mul)
    return a * b;
  else if constexpr (op == Op::Div)
    return a / b;
  else if constexpr (op == Op::DivSafe)
    return div_safe(a, b);
  else if constexpr (op == Op::Min)
    return min(a, b);
  else if constexpr (op == Op::Max)
    return max(a, b);
  else if constexpr (op == Op::Axpby)
    return a * ins.p0 + b * ins.p1;
  else if constexpr (op == Op::Offset)
    return a + T(ins.p0);  // as Add with the constant's register: the same numbers
  else if constexpr (op == Op::Scale)
    return a * T(ins.p0);  // as Mul with the constant's register: the same numbers
  else if constexpr (op == Op::RAnd || op == Op::ROr) {
    const RSystem s{static_cast<RKind>(static_cast<int>(ins.p0)), ins.p1};
    // min/max, R0 and Rp nodes fill large CSG trees: spare points the general
    // call. (Intervals keep it: its end-point rule maps NaN ends to
    // infinities.)
    if constexpr (!std::is_same_v<T, Interval>) {
      if (s.kind == RKind::MinMax) return op == Op::RAnd ? min(a, b) : max(a, b);
      if (s.kind == RKind::R0) return r0_combine(a, b, op == Op::RAnd ? -1.0 : 1.0);
      if (s.kind == RKind::Rp) return rp_combine(a, b, static_cast<int>(s.parameter), op == Op::RAnd ? -1.0 : 1.0);
    }
    return r_combine(a, b, s, op == Op::RAnd ? -1.0 : 1.0);
  } else if constexpr (op == Op::Const)
    return T(ins.p0);
  // Classify and Patch need the point: evaluate_instruction handles them.
  // Variables are never in code: they live in fixed registers.
  else
    return a;
}

/// One operation of the table, chosen at run time.
template <class T>
T apply(const Instruction& ins, const T& a, const T& b) {
  return visit_op(ins.op, [&](auto op) -> T { return apply_op<decltype(op)::value>(ins, a, b); });
}

/// One instruction over registers `regs` (variables in 0..dimension-1).
template <class T>
T evaluate_instruction(const Instruction& ins, const T* regs) {
  if (ins.op == Op::Classify) return classify_at(*ins.classifier, regs);
  if (ins.op == Op::Patch) return ins.patch->evaluate(regs);
  return apply<T>(ins, regs[ins.a], regs[ins.b]);
}

template <class T>
class Evaluator {
 public:
  explicit Evaluator(const Tape& tape) : tape_(&tape), regs_(tape.register_count()) {
    for (const auto& [r, c] : tape.constants()) regs_[r] = T(c);
  }

  /// Evaluates every root at the point whose coordinates are p[0..dim-1].
  void evaluate(const double* p) {
    for (int i = 0; i < tape_->dimension(); ++i) regs_[i] = Seed<T>::variable(i, p[i]);
    run();
  }
  /// Evaluates every root with the variables given as scalars (an interval
  /// box, or tuples seeded some other way).
  void evaluate_with(const T* variables) {
    for (int i = 0; i < tape_->dimension(); ++i) regs_[i] = variables[i];
    run();
  }

  /// Result of root i of the last evaluation.
  const T& result(std::size_t i = 0) const { return regs_[tape_->results()[i]]; }

  /// Convenience: evaluate and return root 0.
  T at(std::array<double, 3> p) {
    evaluate(p.data());
    return result();
  }

 private:
  void run() {
    for (const Instruction& ins : tape_->code()) regs_[ins.out] = evaluate_instruction<T>(ins, regs_.data());
  }

  const Tape* tape_;
  std::vector<T> regs_;
};

}  // namespace sage
