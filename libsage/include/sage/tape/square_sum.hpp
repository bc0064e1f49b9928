#pragma once
// Sums of squares of shifted arguments, a tape run fused into one kernel.
//
// A ball compiles to ten instructions: (x - cx)^2 + (y - cy)^2 + (z - cz)^2
// as three Offsets, three Squares and two Adds, then r^2 minus the sum and
// a quotient by 2 r. BatchEvaluator runs each over all its lanes, a pass
// over memory per instruction and per component; a union of a thousand
// balls spent most of its time there (bench/far_field_bench balls). Here
// the whole run is found once per tape (find_square_sum) and computed lane
// by lane in registers, with the instructions' own arithmetic in their own
// order: the same bits as running them one by one (tuple_op_lanes.hpp's
// products for first-order tuples, scalar.hpp's for doubles), NaN,
// infinities and signed zeros included.
//
// A run is 1 to 3 terms Offset(a_j) -> Square (or a Square alone: a
// centre coordinate 0), summed left to right by Adds, then optionally
// c - sum (a constant register minus it) and sum / c (a nonzero constant
// register). Every intermediate result must be read only by the next
// instruction of the run, so nothing else misses it.

#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/tape.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace sage {

/// The arithmetic of a fused run: sum_j (a_j + offset_j)^2, then
/// minuend - sum if has_minuend, then / divisor if has_divisor.
struct SquareSum {
  int terms = 0;  // 1 to 3
  std::array<double, 3> offsets{};
  bool has_minuend = false;
  double minuend = 0;
  bool has_divisor = false;
  double divisor = 1;  // nonzero
  // The terms read the point's coordinates x, y (, z) in order, seeded as
  // the evaluators seed them (partial i of coordinate i is 1, the others
  // +0.0): first-order tuples then skip multiplying by those partials.
  bool coordinates = false;
};

/// A run found in a tape: its arithmetic, the registers its terms read,
/// the register it writes last, and how many instructions it stands for.
struct SquareSumRun {
  SquareSum sum;
  std::array<std::uint32_t, 3> arguments{};
  std::uint32_t out = 0;
  std::size_t length = 0;
};

/// The run starting at instruction `first`, if any (at least two terms, or
/// one term with a minuend or divisor). `is_constant` and `constant_value`
/// by register, as BatchEvaluator keeps them.
std::optional<SquareSumRun> find_square_sum(const Tape& tape, std::size_t first, const std::vector<char>& is_constant,
                                            const std::vector<double>& constant_value);

/// out[l] = the run's result at lane l, l < count. `arguments` holds
/// sum.terms views; out may be one of them (each lane reads before it writes).
void square_sum_lanes(const SquareSum& sum, const ConstFirstOrderLanes<2>* arguments, FirstOrderLanes<2> out,
                      std::size_t count);
void square_sum_lanes(const SquareSum& sum, const ConstFirstOrderLanes<3>* arguments, FirstOrderLanes<3> out,
                      std::size_t count);
void square_sum_values(const SquareSum& sum, const double* const* arguments, double* out, std::size_t count);

}  // namespace sage
