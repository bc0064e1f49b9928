#pragma once
// BatchEvaluator<T>: runs a Tape at many points at once, for grid blocks.
//
// Evaluator<T> decodes every instruction at every point; here each
// instruction is decoded once per batch and then applied across the
// batch's lanes in a tight loop, so a short specialized tape (a few dozen
// instructions over a small grid block) spends its time computing, not
// dispatching. The arithmetic is apply_op, the same as Evaluator's, so the
// numbers are the same, bit for bit.
//
// Registers are stored register-major and, for tuples, by component
// (tuple_lanes.hpp): coefficient k of lane l of register r is
// data_[(r * components + k) * width + l]. So an instruction reads and
// writes whole arrays of one component, and the kernels for R-functions
// and patches vectorize without shuffling tuples apart (64 lanes of
// Tuple<2, 1> through R0: 2.0 ns a lane, against 3.75 ns as tuples).
//
//     BatchEvaluator<Tuple<2, 1>> batch(tape, 64);
//     batch.evaluate(points.data(), points.size());   // at most 64 points
//     double w = batch.result(3).value();             // root 0 at point 3

#include <sage/scalars/rfunction_lanes.hpp>
#include <sage/scalars/tuple_lanes.hpp>
#include <sage/tape/evaluator.hpp>

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace sage {

template <class T>
class BatchEvaluator {
 public:
  /// Borrows `tape` (which must outlive it); at most `width` points per batch.
  BatchEvaluator(const Tape& tape, std::size_t width) { rebind(tape, width); }

  /// Runs `tape` from now on, keeping the register storage (grid sampling
  /// runs thousands of small tapes per thread; clearing megabytes of
  /// registers for each cost more than running them).
  void rebind(const Tape& tape, std::size_t width) {
    tape_ = &tape;
    width_ = width;
    const std::size_t doubles = tape.register_count() * kComponents * width;
    if (data_.size() < doubles) data_.resize(doubles);
    for (const auto& [r, c] : tape.constants())
      for (std::size_t l = 0; l < width; ++l) store(r, l, T(c));
  }

  std::size_t width() const { return width_; }

  /// Evaluates every root at points[0..count-1], count <= width().
  void evaluate(const std::array<double, 3>* points, std::size_t count) {
    count_ = count;
    for (int v = 0; v < tape_->dimension(); ++v)
      for (std::size_t l = 0; l < count; ++l)
        store(static_cast<std::uint32_t>(v), l, Seed<T>::variable(v, points[l][v]));
    run(nullptr);
  }

  /// Evaluates every root at the grid points xs[0..nx) x rows[0..row_count)
  /// (nx * row_count <= width()): point p = r * nx + i lies at (xs[i],
  /// rows[r][0], rows[r][1]). The same numbers as evaluate() at those
  /// points; far-field patches run a row at a time (ChebyshevPatch::
  /// evaluate_rows), about five times cheaper than point by point.
  void evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows, std::size_t row_count) {
    count_ = nx * row_count;
    for (int v = 0; v < tape_->dimension(); ++v)
      for (std::size_t r = 0; r < row_count; ++r)
        for (std::size_t i = 0; i < nx; ++i)
          store(static_cast<std::uint32_t>(v), r * nx + i,
                Seed<T>::variable(v, v == 0 ? xs[i] : rows[r][static_cast<std::size_t>(v - 1)]));
    const Rows layout{xs, nx, rows, row_count};
    run(&layout);
  }

  /// Root `root` at point `lane` of the last batch.
  T result(std::size_t lane, std::size_t root = 0) const { return load(tape_->results()[root], lane); }

  /// One point's results, shaped like an Evaluator's (result(root)).
  class Point {
   public:
    Point(const BatchEvaluator& batch, std::size_t lane) : batch_(&batch), lane_(lane) {}
    T result(std::size_t root = 0) const { return batch_->result(lane_, root); }

   private:
    const BatchEvaluator* batch_;
    std::size_t lane_;
  };
  Point point(std::size_t lane) const { return Point(*this, lane); }

 private:
  static constexpr int components() {
    if constexpr (std::is_same_v<T, double>)
      return 1;
    else
      return T::size;
  }
  static constexpr int kComponents = components();

  // Register r's lanes of component k.
  double* component(std::uint32_t r, int k = 0) {
    return data_.data() + (static_cast<std::size_t>(r) * kComponents + static_cast<std::size_t>(k)) * width_;
  }
  const double* component(std::uint32_t r, int k = 0) const {
    return data_.data() + (static_cast<std::size_t>(r) * kComponents + static_cast<std::size_t>(k)) * width_;
  }
  TupleLanes<T> lanes_of(std::uint32_t r) { return {component(r), width_}; }
  T load(std::uint32_t r, std::size_t l) const {
    if constexpr (std::is_same_v<T, double>)
      return component(r)[l];
    else
      return ConstTupleLanes<T>{component(r), width_}.load(l);
  }
  void store(std::uint32_t r, std::size_t l, const T& value) {
    if constexpr (std::is_same_v<T, double>)
      component(r)[l] = value;
    else
      lanes_of(r).store(l, value);
  }

  // evaluate_rows()'s points.
  struct Rows {
    const double* xs;
    std::size_t nx;
    const std::array<double, 2>* rows;
    std::size_t row_count;
  };
  // Doubles and first-order tuples (what grid sampling and fits run) have
  // kernels a row or a vector at a time: patches by rows, R0 by lanes.
  static constexpr bool kLaneKernels = std::is_same_v<T, double> || detail::IsFirstOrderTuple<T>::value;

  // Every instruction at the count_ seeded points.
  void run(const Rows* layout) {
    const std::size_t count = count_;
    const std::vector<Instruction>& code = tape_->code();
    for (std::size_t i = 0; i < code.size(); ++i) {
      const Instruction& ins = code[i];
      if constexpr (kLaneKernels) {
        if (ins.op == Op::Patch && layout) {
          if constexpr (std::is_same_v<T, double>) {
            ins.patch->evaluate_rows(layout->xs, layout->nx, layout->rows, layout->row_count, component(ins.out));
          } else {
            std::array<ConstTupleLanes<T>, 3> vars{};
            for (int v = 0; v < tape_->dimension(); ++v) vars[v] = lanes_of(static_cast<std::uint32_t>(v));
            ins.patch->evaluate_rows(layout->xs, layout->nx, layout->rows, layout->row_count, vars.data(),
                                     lanes_of(ins.out));
          }
          continue;
        }
      }
      if (ins.op == Op::Classify || ins.op == Op::Patch) {
        run_pointwise(ins);
        continue;
      }
      // R0 and Rp trees of values, or of value and gradient: their roots
      // and divisions a vector at a time (the same numbers).
      if constexpr (kLaneKernels) {
        if (ins.op == Op::RAnd || ins.op == Op::ROr) {
          const auto kind = static_cast<RKind>(static_cast<int>(ins.p0));
          const double sign = ins.op == Op::RAnd ? -1.0 : 1.0;
          if (kind == RKind::R0 || kind == RKind::Rp) {
            const auto a = lanes_or_doubles(ins.a), b = lanes_or_doubles(ins.b);
            const auto out = lanes_or_doubles(ins.out);
            if (kind == RKind::R0)
              r0_combine_lanes(a, b, out, count, sign);
            else
              rp_combine_lanes(a, b, out, count, static_cast<int>(ins.p1), sign);
            continue;
          }
        }
      }
      if constexpr (kLaneKernels) {
        if (i + 1 < code.size() && halfplane(ins, code[i + 1])) {
          run_halfplane(ins, code[i + 1].p0, count);
          ++i;
          continue;
        }
      }
      if constexpr (kComponents > 1) {
        if (run_by_component(ins, count)) continue;
      }
      // Elementwise, so an output register shared with an argument is safe.
      visit_op(ins.op, [&](auto op) {
        for (std::size_t l = 0; l < count; ++l)
          store(ins.out, l, apply_op<decltype(op)::value>(ins, load(ins.a, l), load(ins.b, l)));
      });
    }
  }

  // Tuple ops that treat every coefficient alike (sums, negation, the
  // halfplanes' Axpby and Offset), a component at a time: the arithmetic of
  // tuple.hpp's operators, so the same numbers as apply_op. Each lane reads
  // its arguments before it writes, hence ivdep. False for other ops.
  bool run_by_component(const Instruction& ins, std::size_t count) {
    const Op op = ins.op;
    if (op != Op::Add && op != Op::Sub && op != Op::Neg && op != Op::Axpby && op != Op::Offset) return false;
    for (int k = 0; k < kComponents; ++k) {
      const double* a = component(ins.a, k);
      const double* b = component(ins.b, k);
      double* out = component(ins.out, k);
      const double p0 = ins.p0, p1 = ins.p1;
      const double offset = k == 0 ? p0 : 0.0;  // a + T(p0)
      switch (op) {
        case Op::Add:
#pragma GCC ivdep
          for (std::size_t l = 0; l < count; ++l) out[l] = a[l] + b[l];
          break;
        case Op::Sub:
#pragma GCC ivdep
          for (std::size_t l = 0; l < count; ++l) out[l] = a[l] - b[l];
          break;
        case Op::Neg:  // a *= -1.0
#pragma GCC ivdep
          for (std::size_t l = 0; l < count; ++l) out[l] = a[l] * -1.0;
          break;
        case Op::Axpby:
#pragma GCC ivdep
          for (std::size_t l = 0; l < count; ++l) out[l] = a[l] * p0 + b[l] * p1;
          break;
        default:  // Offset
#pragma GCC ivdep
          for (std::size_t l = 0; l < count; ++l) out[l] = a[l] + offset;
      }
    }
    return true;
  }

  // Whether `next` adds a constant to the Axpby `ins` in its own register
  // (a halfplane, n . p + c): nothing else can read the Axpby's value, so
  // one pass may compute both.
  static bool halfplane(const Instruction& ins, const Instruction& next) {
    return ins.op == Op::Axpby && next.op == Op::Offset && next.a == ins.out && next.out == ins.out;
  }

  // Axpby, then Offset, a lane at a time: the same numbers as the two
  // instructions (the Offset adds p0 to the value and 0.0 to the partials).
  void run_halfplane(const Instruction& ins, double offset, std::size_t count) {
    for (int k = 0; k < kComponents; ++k) {
      const double* a = component(ins.a, k);
      const double* b = component(ins.b, k);
      double* out = component(ins.out, k);
      const double p0 = ins.p0, p1 = ins.p1, c = k == 0 ? offset : 0.0;
#pragma GCC ivdep
      for (std::size_t l = 0; l < count; ++l) out[l] = (a[l] * p0 + b[l] * p1) + c;
    }
  }

  // The kernels' view of a register: its doubles, or its tuple lanes.
  auto lanes_or_doubles(std::uint32_t r) {
    if constexpr (std::is_same_v<T, double>)
      return component(r);
    else
      return lanes_of(r);
  }

  // Classifiers and patches read the point's variables: gather them per lane.
  void run_pointwise(const Instruction& ins) {
    for (std::size_t l = 0; l < count_; ++l) {
      std::array<T, 3> vars{};
      for (int v = 0; v < tape_->dimension(); ++v) vars[v] = load(static_cast<std::uint32_t>(v), l);
      store(ins.out, l, evaluate_instruction<T>(ins, vars.data()));
    }
  }

  const Tape* tape_;
  std::size_t width_;
  std::size_t count_ = 0;
  std::vector<double> data_;
};

}  // namespace sage
