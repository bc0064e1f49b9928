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

#include <sage/classifier.hpp>
#include <sage/interval.hpp>
#include <sage/rfunction.hpp>
#include <sage/tape.hpp>
#include <sage/tuple.hpp>

#include <array>
#include <vector>

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

/// One operation of the table, generic over the scalar type.
template <class T>
T apply(const Instruction& ins, const T& a, const T& b) {
  switch (ins.op) {
    case Op::Neg: return -a;
    case Op::Square: return square(a);
    case Op::Sqrt: return sqrt(a);
    case Op::Exp: return exp(a);
    case Op::Log: return log(a);
    case Op::Sin: return sin(a);
    case Op::Cos: return cos(a);
    case Op::Abs: return abs(a);
    case Op::Step: return step(a);
    case Op::PowInt: return pow_int(a, static_cast<int>(ins.p0));
    case Op::PowReal: return pow_real(a, ins.p0);
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    case Op::DivSafe: return div_safe(a, b);
    case Op::Min: return min(a, b);
    case Op::Max: return max(a, b);
    case Op::Axpby: return a * ins.p0 + b * ins.p1;
    case Op::RAnd:
    case Op::ROr: {
      const RSystem s{static_cast<RKind>(static_cast<int>(ins.p0)), ins.p1};
      return r_combine(a, b, s, ins.op == Op::RAnd ? -1.0 : 1.0);
    }
    case Op::Const: return T(ins.p0);
    case Op::Classify:
    case Op::Patch: break;  // need the point: evaluate_instruction handles them
    case Op::VarX:
    case Op::VarY:
    case Op::VarZ: break;  // never in code: variables live in fixed registers
  }
  return a;
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
