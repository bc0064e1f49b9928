#pragma once
// The smooth trimming of a B-rep piece, a tape run fused into one kernel.
//
// trim_smooth(h, t) (trimming.hpp) compiles to nine instructions:
//   St = t^2, P = (h c)^4 (h c a Scale; c = 1: none), A = St + P, R = sqrt(A),
//   M = R p + t q (p = 1/2, q = -1/2), SM = M^2, B = S + SM, W = sqrt(B)
// with S = h^2 computed earlier. Every face of a mesh and every edge of a
// polygon B-rep has one, and run one by one they made a pass over memory
// per instruction and component: the larger part of a mesh field's time.
// Here the run is found once per tape (find_smooth_trim) and computed lane
// by lane in registers, with the instructions' own arithmetic in their own
// order (tuple_op_lanes.hpp's for first-order tuples, scalar.hpp's for
// doubles); lanes where an operator takes another branch (a power of zero,
// a root of a non-positive number or NaN) run the operators themselves.
// The same bits as the instructions, as square_sum.hpp.
//
// Every intermediate result must be read only by the next instructions of
// the run, so nothing else misses it, and the registers the run reads must
// hold their values when it starts.

#include <sage/scalars/tuple_op_lanes.hpp>
#include <sage/tape/tape.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>

namespace sage {

/// The arithmetic of a fused trimming: the constants of the run.
struct SmoothTrim {
  bool has_scale = false;
  double scale = 1;        // c: h's factor before the fourth power
  double root_weight = 0;  // p, on R in M = R p + t q
  double t_weight = 0;     // q
};

/// A run found in a tape: its arithmetic, the registers it reads (t, h and
/// the addend S), the register it writes, and how many instructions it
/// stands for.
struct SmoothTrimRun {
  SmoothTrim trim;
  std::uint32_t t = 0, h = 0, addend = 0;
  std::uint32_t out = 0;
  std::size_t length = 0;
};

/// The run starting at instruction `first` (its Square of t), if any.
std::optional<SmoothTrimRun> find_smooth_trim(const Tape& tape, std::size_t first);

/// out[l] = the run's result at lane l, l < count. out may be any of the
/// arguments (each lane reads before it writes).
void smooth_trim_lanes(const SmoothTrim& trim, ConstFirstOrderLanes<2> t, ConstFirstOrderLanes<2> h,
                       ConstFirstOrderLanes<2> addend, FirstOrderLanes<2> out, std::size_t count);
void smooth_trim_lanes(const SmoothTrim& trim, ConstFirstOrderLanes<3> t, ConstFirstOrderLanes<3> h,
                       ConstFirstOrderLanes<3> addend, FirstOrderLanes<3> out, std::size_t count);
void smooth_trim_values(const SmoothTrim& trim, const double* t, const double* h, const double* addend, double* out,
                        std::size_t count);

}  // namespace sage
