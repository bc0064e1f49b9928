#pragma once
// A linear form of three arguments, a tape run fused into one kernel.
//
// n . p + d in 3D (a mesh face's plane and its three side planes, a box's
// faces) compiles to four instructions: Axpby(a, b) = a p + b q, c k (a
// Scale, or a product with a constant register), their sum, then + d. Run one by one they made a pass
// over memory per instruction and component. Here the run is found once
// per tape (find_linear_form) and computed lane by lane in registers, with
// the instructions' own arithmetic in their own order: the same bits
// (tuple_op_lanes.hpp's product by a constant for first-order tuples,
// scalar.hpp's arithmetic for doubles). Every intermediate result must be
// read only by the next instruction of the run.

#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/tape.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace sage {

/// a p + b q + c k (+ d if has_offset).
struct LinearForm {
  double p = 0, q = 0, k = 0;
  bool has_offset = false;
  double d = 0;
};

/// A run found in a tape: its arithmetic, the registers a, b and c, the
/// register it writes, and how many instructions it stands for.
struct LinearFormRun {
  LinearForm form;
  std::uint32_t a = 0, b = 0, c = 0;
  std::uint32_t out = 0;
  std::size_t length = 0;
};

/// The run starting at instruction `first` (its Axpby), if any.
/// `is_constant` and `constant_value` by register, as BatchEvaluator keeps
/// them.
std::optional<LinearFormRun> find_linear_form(const Tape& tape, std::size_t first, const std::vector<char>& is_constant,
                                              const std::vector<double>& constant_value);

/// out[l] = the run's result at lane l, l < count. out may be any of the
/// arguments (each lane reads before it writes).
void linear_form_lanes(const LinearForm& form, ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b,
                       ConstFirstOrderLanes<3> c, FirstOrderLanes<3> out, std::size_t count);
void linear_form_values(const LinearForm& form, const double* a, const double* b, const double* c, double* out,
                        std::size_t count);

}  // namespace sage
