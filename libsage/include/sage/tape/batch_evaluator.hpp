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
#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/far_faces.hpp>
#include <sage/tape/linear_form.hpp>
#include <sage/tape/smooth_trim.hpp>
#include <sage/tape/square_sum.hpp>
#include <sage/tape/trimmed_face.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <type_traits>
#include <variant>
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
    // Grid slabs rebind the same tape again and again: its constants' lanes
    // (a mesh field has tens of thousands), fused runs and far faces are in
    // place, also for narrower batches (a grid's edge blocks).
    if (tape_ && tape.serial() == serial_ && width <= width_) {
      tape_ = &tape;
      return;
    }
    tape_ = &tape;
    serial_ = tape.serial();
    width_ = width;
    const std::size_t doubles = tape.register_count() * kComponents * width;
    if (data_.size() < doubles) data_.resize(doubles);
    is_constant_.assign(tape.register_count(), 0);
    constant_value_.resize(tape.register_count());
    for (const auto& [r, c] : tape.constants()) {
      for (std::size_t l = 0; l < width; ++l) store(r, l, T(c));
      is_constant_[r] = 1;
      constant_value_[r] = c;
    }
    find_fused_runs();
    if (far_faces_on_) set_far_faces(true);
  }

  /// The largest batch: the registers' storage (rebinding the same tape to
  /// a narrower batch keeps it).
  std::size_t width() const { return width_; }

  /// Whether clusters of mesh faces far from a batch's points run in single
  /// precision (far_faces.hpp): no longer the instructions' bits, within
  /// about 1e-7 of the field, relative. For 3D tapes of doubles or
  /// first-order tuples; a no-op for others.
  void set_far_faces(bool on) {
    if constexpr (kLinearForms) {
      on = on && tape_->dimension() == 3;
      if (on && (!far_faces_on_ || far_faces_serial_ != serial_)) build_far_faces();
      far_faces_on_ = on;
    }
  }

  /// Far clusters run in single precision since the evaluator was made.
  std::size_t far_cluster_runs() const { return far_cluster_runs_; }

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
    const std::size_t steps = steps_.size();
    if constexpr (kLinearForms)
      if (far_faces_on_) bound_batch(count);
    for (std::size_t i = 0; i < steps; ++i) {
      const Instruction& ins = steps_[i].instruction;
      if constexpr (kLinearForms) {
        if (far_faces_on_) {
          const int cluster = far_faces_.far_cluster_at(i, box_);
          if (cluster >= 0 && run_far(cluster, count)) {
            i = far_faces_.last_step(cluster);
            continue;
          }
        }
      }
      if constexpr (kLaneKernels) {
        if (steps_[i].fused) {
          std::visit([&](const auto& fused) { run_fused(fused, count); }, fused_[steps_[i].fused - 1]);
          continue;
        }
        if (ins.op == Op::Patch) {
          // A grid's rows, or scattered points a lane each (the variables' values).
          const int dimension = tape_->dimension();
          if constexpr (std::is_same_v<T, double>) {
            if (layout) {
              ins.patch->evaluate_rows(layout->xs, layout->nx, layout->rows, layout->row_count, component(ins.out));
            } else {
              const double* coordinates[3] = {component(0),
                                              component(static_cast<std::uint32_t>(std::min(1, dimension - 1))),
                                              component(static_cast<std::uint32_t>(std::min(2, dimension - 1)))};
              ins.patch->evaluate_points(coordinates, count, component(ins.out));
            }
          } else {
            std::array<ConstTupleLanes<T>, 3> vars{};
            for (int v = 0; v < dimension; ++v) vars[v] = lanes_of(static_cast<std::uint32_t>(v));
            if (layout)
              ins.patch->evaluate_rows(layout->xs, layout->nx, layout->rows, layout->row_count, vars.data(),
                                       lanes_of(ins.out));
            else
              ins.patch->evaluate_points(count, vars.data(), lanes_of(ins.out));
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
      if constexpr (detail::IsFirstOrderTuple<T>::value) {
        if (run_tuple_arithmetic(ins, count)) continue;
      }
      if constexpr (kLaneKernels) {
        if (i + 1 < steps && !steps_[i + 1].fused && halfplane(ins, steps_[i + 1].instruction)) {
          run_halfplane(ins, steps_[i + 1].instruction.p0, count);
          ++i;
          continue;
        }
      }
      if constexpr (std::is_same_v<T, double>) {  // after the halfplane: Axpby then Offset in one pass
        if (run_double_arithmetic(ins, count)) continue;
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

  // Products, squares, roots, quotients and integer powers of first-order
  // tuples, a component at a time (tuple_op_lanes.hpp: the same numbers as
  // apply_op), constant factors and divisors read as one number. False for
  // other ops.
  bool run_tuple_arithmetic(const Instruction& ins, std::size_t count) {
    switch (ins.op) {
      case Op::Mul:
        if (is_constant_[ins.b])
          mul_constant_lanes(lanes_of(ins.a), constant_value_[ins.b], lanes_of(ins.out), count);
        else if (is_constant_[ins.a])  // c a: the same two terms per partial, so the same sums
          mul_constant_lanes(lanes_of(ins.b), constant_value_[ins.a], lanes_of(ins.out), count);
        else
          mul_lanes(lanes_of(ins.a), lanes_of(ins.b), lanes_of(ins.out), count);
        return true;
      case Op::Scale: mul_constant_lanes(lanes_of(ins.a), ins.p0, lanes_of(ins.out), count); return true;
      case Op::Square: square_lanes(lanes_of(ins.a), lanes_of(ins.out), count); return true;
      case Op::Sqrt: sqrt_lanes(lanes_of(ins.a), lanes_of(ins.out), count); return true;
      case Op::Div:
      case Op::DivSafe:
        if (is_constant_[ins.b])
          div_constant_lanes(lanes_of(ins.a), constant_value_[ins.b], lanes_of(ins.out), count, ins.op == Op::DivSafe);
        else
          div_lanes(lanes_of(ins.a), lanes_of(ins.b), lanes_of(ins.out), count, ins.op == Op::DivSafe);
        return true;
      case Op::PowInt: pow_int_lanes(lanes_of(ins.a), static_cast<int>(ins.p0), lanes_of(ins.out), count); return true;
      default: return false;
    }
  }

  // The arithmetic of values (scalar.hpp's) over whole arrays, compiled for
  // AVX2 and AVX-512 too; constant factors, divisors and terms read as one number.
  // False for other ops.
  bool run_double_arithmetic(const Instruction& ins, std::size_t count) {
    const double* a = component(ins.a);
    const double* b = component(ins.b);
    double* out = component(ins.out);
    auto run = [&](ArrayOp op, double p0 = 0, double p1 = 0) {
      array_op(op, a, b, p0, p1, 0.0, out, count);
      return true;
    };
    const bool a_constant = is_constant_[ins.a], b_constant = arity(ins.op) == 2 && is_constant_[ins.b];
    switch (ins.op) {
      case Op::Add: return run(ArrayOp::Add);
      case Op::Sub:
        if (b_constant) return run(ArrayOp::Offset, -constant_value_[ins.b]);  // a - c = a + (-c)
        if (a_constant) {
          a = b;
          return run(ArrayOp::ConstantMinus, constant_value_[ins.a]);
        }
        return run(ArrayOp::Sub);
      case Op::Neg: return run(ArrayOp::Scale, -1.0);  // a * -1.0
      case Op::Axpby: return run(ArrayOp::Axpby, ins.p0, ins.p1);
      case Op::Offset: return run(ArrayOp::Offset, ins.p0);
      case Op::Scale: return run(ArrayOp::Scale, ins.p0);
      case Op::Mul:
        if (b_constant) return run(ArrayOp::Scale, constant_value_[ins.b]);
        if (a_constant) {
          a = b;
          return run(ArrayOp::Scale, constant_value_[ins.a]);
        }
        return run(ArrayOp::Mul);
      case Op::Square: return run(ArrayOp::Square);
      case Op::Sqrt: return run(ArrayOp::Sqrt);
      case Op::Div: return b_constant ? run(ArrayOp::DivideBy, constant_value_[ins.b]) : run(ArrayOp::Div);
      case Op::DivSafe: return run(ArrayOp::DivSafe);
      case Op::Min: return run(ArrayOp::Min);
      case Op::Max: return run(ArrayOp::Max);
      default: return false;
    }
  }

  // Tuple ops that treat every coefficient alike (sums, negation, the
  // halfplanes' Axpby and Offset), a component at a time: the arithmetic of
  // tuple.hpp's operators, so the same numbers as apply_op. Each lane reads
  // its arguments before it writes, hence ivdep. False for other ops.
  bool run_by_component(const Instruction& ins, std::size_t count) {
    const Op op = ins.op;
    if (op != Op::Add && op != Op::Sub && op != Op::Neg && op != Op::Axpby && op != Op::Offset) return false;
    if (op == Op::Sub && (is_constant_[ins.a] || is_constant_[ins.b])) {
      run_difference_with_constant(ins, count);
      return true;
    }
    switch (op) {
      case Op::Add: by_component(ArrayOp::Add, ins, count); break;
      case Op::Sub: by_component(ArrayOp::Sub, ins, count); break;
      case Op::Neg: by_component(ArrayOp::Scale, ins, count, -1.0); break;  // a *= -1.0
      case Op::Axpby: by_component(ArrayOp::Axpby, ins, count, ins.p0, ins.p1); break;
      default: by_value_and_partials(ArrayOp::Offset, ins.a, ins.out, count, ins.p0, 0.0);  // a + T(p0)
    }
    return true;
  }

  // An ArrayOp on every component alike: in one run over the register's
  // components when the batch is full (they lie back to back).
  void by_component(ArrayOp op, const Instruction& ins, std::size_t count, double p0 = 0, double p1 = 0) {
    if (count == width_) {
      array_op(op, component(ins.a), component(ins.b), p0, p1, 0.0, component(ins.out), kComponents * count);
      return;
    }
    for (int k = 0; k < kComponents; ++k)
      array_op(op, component(ins.a, k), component(ins.b, k), p0, p1, 0.0, component(ins.out, k), count);
  }

  // An ArrayOp with parameter `value` on the value and `partial` on the
  // partials (a constant added or subtracted: T(c) has zero partials).
  void by_value_and_partials(ArrayOp op, std::uint32_t a, std::uint32_t out, std::size_t count, double value,
                             double partial) {
    array_op(op, component(a), nullptr, value, 0.0, 0.0, component(out), count);
    if (count == width_) {
      array_op(op, component(a, 1), nullptr, partial, 0.0, 0.0, component(out, 1), (kComponents - 1) * count);
      return;
    }
    for (int k = 1; k < kComponents; ++k)
      array_op(op, component(a, k), nullptr, partial, 0.0, 0.0, component(out, k), count);
  }

  // a - c or c - a with c a constant register, read as one number (T(c)
  // is c and zero partials; a - c is a + (-c) exactly). The tape writes
  // a + c as an Offset.
  void run_difference_with_constant(const Instruction& ins, std::size_t count) {
    if (is_constant_[ins.a])
      by_value_and_partials(ArrayOp::ConstantMinus, ins.b, ins.out, count, constant_value_[ins.a], 0.0);
    else
      by_value_and_partials(ArrayOp::Offset, ins.a, ins.out, count, -constant_value_[ins.b], -0.0);
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
    array_op(ArrayOp::Halfplane, component(ins.a), component(ins.b), ins.p0, ins.p1, offset, component(ins.out), count);
    for (int k = 1; k < kComponents; ++k)
      array_op(ArrayOp::Halfplane, component(ins.a, k), component(ins.b, k), ins.p0, ins.p1, 0.0, component(ins.out, k),
               count);
  }

  // The tape's fused runs (trimmed_face.hpp, square_sum.hpp,
  // smooth_trim.hpp, linear_form.hpp), and the steps of the code with
  // them: a fused run or an instruction, copied. A mesh field's tape is 15
  // to 70 MB of instructions, most of them fused; read in place, each
  // instruction left between two runs (an R0 gluing faces) was a cache
  // miss per batch, about a tenth of the sampling time.
  void find_fused_runs() {
    fused_.clear();
    steps_.clear();
    const std::vector<Instruction>& code = tape_->code();
    for (std::size_t i = 0; i < code.size(); ++i) {
      if constexpr (kLaneKernels) {
        auto found = [&](const auto& run) {
          fused_.push_back(run);
          steps_.push_back({static_cast<std::uint32_t>(fused_.size()), code[i]});
          i += run.length - 1;
        };
        if (auto face = kLinearForms ? find_trimmed_face(*tape_, i, is_constant_, constant_value_) : std::nullopt) {
          found(*face);
          continue;
        }
        if (auto trim = find_smooth_trim(*tape_, i)) {
          found(*trim);
          continue;
        }
        if (auto sum = find_square_sum(*tape_, i, is_constant_, constant_value_)) {
          found(*sum);
          continue;
        }
        if (auto form = kLinearForms ? find_linear_form(*tape_, i, is_constant_, constant_value_) : std::nullopt) {
          found(*form);
          continue;
        }
      }
      steps_.push_back({0, code[i]});
    }
  }

  // Linear forms and mesh faces are found in 3D tapes only: doubles, or
  // tuples of x, y, z.
  static constexpr bool kLinearForms = kComponents == 1 || kComponents == 4;

  // The clusters of fused faces glued by R0, from the steps.
  void build_far_faces() {
    std::vector<FarFaces::Step> view(steps_.size());
    for (std::size_t i = 0; i < steps_.size(); ++i) {
      const Instruction& ins = steps_[i].instruction;
      FarFaces::Step& v = view[i];
      v.out = ins.out;
      v.reads = {ins.a, ins.b, 0};
      v.read_count = 2;
      if (steps_[i].fused) {
        std::visit(
            [&](const auto& run) {
              using Run = std::decay_t<decltype(run)>;
              v.out = run.out;
              if constexpr (std::is_same_v<Run, TrimmedFaceRun>) {
                v.kind = FarFaces::Step::Kind::Face;
                v.face = &run.face;
                v.read_count = 0;  // x, y and z
              } else if constexpr (std::is_same_v<Run, LinearFormRun>) {
                v.reads = {run.a, run.b, run.c};
                v.read_count = 3;
              } else if constexpr (std::is_same_v<Run, SmoothTrimRun>) {
                v.reads = {run.t, run.h, run.addend};
                v.read_count = 3;
              } else {
                v.reads = run.arguments;
                v.read_count = run.sum.terms;
              }
            },
            fused_[steps_[i].fused - 1]);
      } else if ((ins.op == Op::RAnd || ins.op == Op::ROr) &&
                 static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::R0) {
        v.kind = FarFaces::Step::Kind::Glue;
        v.sign = ins.op == Op::RAnd ? -1.0 : 1.0;
      }
    }
    far_faces_.build(view, tape_->results());
    far_faces_serial_ = serial_;
  }

  // box_ = the box of the batch's points (their x, y, z registers' values).
  void bound_batch(std::size_t count) {
    for (int a = 0; a < 3; ++a) {
      const double* v = component(static_cast<std::uint32_t>(a));
      box_.lo[a] = box_.hi[a] = count > 0 ? v[0] : 0.0;
      for (std::size_t l = 0; l < count; ++l) {
        box_.lo[a] = std::min(box_.lo[a], v[l]);
        box_.hi[a] = std::max(box_.hi[a], v[l]);
      }
    }
  }

  // The cluster in single precision into its register; false (and nothing
  // written) where some lane is not finite.
  bool run_far(int cluster, std::size_t count) {
    std::array<double, 3> centre{};
    for (int a = 0; a < 3; ++a) centre[a] = 0.5 * (box_.lo[a] + box_.hi[a]);
    const std::uint32_t out = far_faces_.output(cluster);
    bool done = false;
    if constexpr (std::is_same_v<T, double>) {
      done = far_faces_.evaluate(cluster, centre, component(0), component(1), component(2), count, component(out),
                                 nullptr);
    } else {
      const std::array<double*, 3> gradient{component(out, 1), component(out, 2), component(out, 3)};
      done = far_faces_.evaluate(cluster, centre, component(0), component(1), component(2), count, component(out),
                                 &gradient);
    }
    far_cluster_runs_ += done ? 1 : 0;
    return done;
  }

  void run_fused(const LinearFormRun& fused, std::size_t count) {
    if constexpr (std::is_same_v<T, double>)
      linear_form_values(fused.form, component(fused.a), component(fused.b), component(fused.c), component(fused.out),
                         count);
    else if constexpr (kComponents == 4)
      linear_form_lanes(fused.form, lanes_of(fused.a), lanes_of(fused.b), lanes_of(fused.c), lanes_of(fused.out),
                        count);
  }

  void run_fused(const TrimmedFaceRun& fused, std::size_t count) {
    if constexpr (std::is_same_v<T, double>)
      trimmed_face_values(fused.face, component(0), component(1), component(2), component(fused.out), count);
    else if constexpr (kComponents == 4)
      trimmed_face_lanes(fused.face, lanes_of(0), lanes_of(1), lanes_of(2), lanes_of(fused.out), count);
  }

  void run_fused(const SmoothTrimRun& fused, std::size_t count) {
    if constexpr (std::is_same_v<T, double>)
      smooth_trim_values(fused.trim, component(fused.t), component(fused.h), component(fused.addend),
                         component(fused.out), count);
    else
      smooth_trim_lanes(fused.trim, lanes_of(fused.t), lanes_of(fused.h), lanes_of(fused.addend), lanes_of(fused.out),
                        count);
  }

  void run_fused(const SquareSumRun& fused, std::size_t count) {
    const auto terms = static_cast<std::size_t>(fused.sum.terms);
    if constexpr (std::is_same_v<T, double>) {
      std::array<const double*, 3> arguments{};
      for (std::size_t j = 0; j < terms; ++j) arguments[j] = component(fused.arguments[j]);
      square_sum_values(fused.sum, arguments.data(), component(fused.out), count);
    } else {
      std::array<ConstTupleLanes<T>, 3> arguments{};
      for (std::size_t j = 0; j < terms; ++j) arguments[j] = lanes_of(fused.arguments[j]);
      square_sum_lanes(fused.sum, arguments.data(), lanes_of(fused.out), count);
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

  const Tape* tape_ = nullptr;
  std::uint64_t serial_ = 0;
  std::size_t width_ = 0;
  // Which registers hold constants, and their values: kernels read those
  // as one number rather than as lanes.
  std::vector<char> is_constant_;
  std::vector<double> constant_value_;
  // Fused runs of instructions, and the steps that run the code: 1 + the
  // index of a fused run, or 0 and an instruction.
  std::vector<std::variant<SquareSumRun, SmoothTrimRun, LinearFormRun, TrimmedFaceRun>> fused_;
  struct Step {
    std::uint32_t fused;
    Instruction instruction;
  };
  std::vector<Step> steps_;
  std::size_t count_ = 0;
  std::vector<double> data_;
  // Far faces in single precision (set_far_faces), and the batch's box.
  FarFaces far_faces_;
  bool far_faces_on_ = false;
  std::uint64_t far_faces_serial_ = 0;
  std::size_t far_cluster_runs_ = 0;
  Box3 box_;
};

}  // namespace sage
