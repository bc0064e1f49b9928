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
// Registers are stored register-major: lane l of register r is
// regs_[r * width + l].
//
//     BatchEvaluator<Tuple<2, 1>> batch(tape, 64);
//     batch.evaluate(points.data(), points.size());   // at most 64 points
//     double w = batch.result(3).value();             // root 0 at point 3

#include <sage/evaluator.hpp>
#include <sage/rfunction_lanes.hpp>

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
    if (regs_.size() < tape.register_count() * width) regs_.resize(tape.register_count() * width);
    for (const auto& [r, c] : tape.constants())
      for (std::size_t l = 0; l < width; ++l) regs_[r * width + l] = T(c);
  }

  std::size_t width() const { return width_; }

  /// Evaluates every root at points[0..count-1], count <= width().
  void evaluate(const std::array<double, 3>* points, std::size_t count) {
    count_ = count;
    for (int v = 0; v < tape_->dimension(); ++v) {
      T* lanes = lanes_of(static_cast<std::uint32_t>(v));
      for (std::size_t l = 0; l < count; ++l) lanes[l] = Seed<T>::variable(v, points[l][v]);
    }
    run(nullptr);
  }

  /// Evaluates every root at the grid points xs[0..nx) x rows[0..row_count)
  /// (nx * row_count <= width()): point p = r * nx + i lies at (xs[i],
  /// rows[r][0], rows[r][1]). The same numbers as evaluate() at those
  /// points; far-field patches run a row at a time (ChebyshevPatch::
  /// evaluate_rows), about five times cheaper than point by point.
  void evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows, std::size_t row_count) {
    count_ = nx * row_count;
    for (int v = 0; v < tape_->dimension(); ++v) {
      T* lanes = lanes_of(static_cast<std::uint32_t>(v));
      for (std::size_t r = 0; r < row_count; ++r)
        for (std::size_t i = 0; i < nx; ++i)
          lanes[r * nx + i] = Seed<T>::variable(v, v == 0 ? xs[i] : rows[r][static_cast<std::size_t>(v - 1)]);
    }
    const Rows layout{xs, nx, rows, row_count};
    run(&layout);
  }

  /// Root `root` at point `lane` of the last batch.
  const T& result(std::size_t lane, std::size_t root = 0) const {
    return regs_[tape_->results()[root] * width_ + lane];
  }

  /// One point's results, shaped like an Evaluator's (result(root)).
  class Point {
   public:
    Point(const BatchEvaluator& batch, std::size_t lane) : batch_(&batch), lane_(lane) {}
    const T& result(std::size_t root = 0) const { return batch_->result(lane_, root); }

   private:
    const BatchEvaluator* batch_;
    std::size_t lane_;
  };
  Point point(std::size_t lane) const { return Point(*this, lane); }

 private:
  T* lanes_of(std::uint32_t r) { return regs_.data() + static_cast<std::size_t>(r) * width_; }

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
    for (const Instruction& ins : tape_->code()) {
      if constexpr (kLaneKernels) {
        if (ins.op == Op::Patch && layout) {
          const T* vars[3] = {nullptr, nullptr, nullptr};
          for (int v = 0; v < tape_->dimension(); ++v) vars[v] = lanes_of(static_cast<std::uint32_t>(v));
          ins.patch->evaluate_rows(layout->xs, layout->nx, layout->rows, layout->row_count, vars, lanes_of(ins.out));
          continue;
        }
      }
      if (ins.op == Op::Classify || ins.op == Op::Patch) {
        run_pointwise(ins);
        continue;
      }
      T* out = lanes_of(ins.out);
      const T* a = lanes_of(ins.a);
      const T* b = lanes_of(ins.b);
      // R0 and Rp trees of values, or of value and gradient: their roots
      // and divisions a vector at a time (the same numbers).
      if constexpr (kLaneKernels) {
        if (ins.op == Op::RAnd || ins.op == Op::ROr) {
          const auto kind = static_cast<RKind>(static_cast<int>(ins.p0));
          const double sign = ins.op == Op::RAnd ? -1.0 : 1.0;
          if (kind == RKind::R0) {
            r0_combine_lanes(a, b, out, count, sign);
            continue;
          }
          if (kind == RKind::Rp) {
            rp_combine_lanes(a, b, out, count, static_cast<int>(ins.p1), sign);
            continue;
          }
        }
      }
      // Elementwise, so an output register shared with an argument is safe.
      visit_op(ins.op, [&](auto op) {
        for (std::size_t l = 0; l < count; ++l) out[l] = apply_op<decltype(op)::value>(ins, a[l], b[l]);
      });
    }
  }

  // Classifiers and patches read the point's variables: gather them per lane.
  void run_pointwise(const Instruction& ins) {
    T* out = lanes_of(ins.out);
    for (std::size_t l = 0; l < count_; ++l) {
      std::array<T, 3> vars{};
      for (int v = 0; v < tape_->dimension(); ++v) vars[v] = lanes_of(static_cast<std::uint32_t>(v))[l];
      out[l] = evaluate_instruction<T>(ins, vars.data());
    }
  }

  const Tape* tape_;
  std::size_t width_;
  std::size_t count_ = 0;
  std::vector<T> regs_;
};

}  // namespace sage
