#pragma once
// R0 and Rp over many points at once, for BatchEvaluator's doubles (fit
// samples) and first-order tuples stored by component (grid values and
// gradients): R-function trees spend most of their time in the roots and
// divisions of these nodes.

#include <sage/scalars/tuple.hpp>
#include <sage/scalars/tuple_lanes.hpp>

#include <cstddef>

namespace sage {

/// out[l] = r0_combine(x[l], y[l], sign) for l < count, the same numbers
/// bit for bit. out may be x or y (each lane reads its arguments before
/// it writes).
void r0_combine_lanes(const double* x, const double* y, double* out, std::size_t count, double sign);
void r0_combine_lanes(ConstTupleLanes<Tuple<2, 1>> x, ConstTupleLanes<Tuple<2, 1>> y, TupleLanes<Tuple<2, 1>> out,
                      std::size_t count, double sign);
void r0_combine_lanes(ConstTupleLanes<Tuple<3, 1>> x, ConstTupleLanes<Tuple<3, 1>> y, TupleLanes<Tuple<3, 1>> out,
                      std::size_t count, double sign);

/// out[l] = rp_combine(x[l], y[l], p, sign) for l < count, the same numbers
/// bit for bit; out may be x or y. p = 2, 4, 8 (roots by square roots, see
/// scalar.hpp's pow_real) run a vector at a time, other p lane by lane.
void rp_combine_lanes(const double* x, const double* y, double* out, std::size_t count, int p, double sign);
void rp_combine_lanes(ConstTupleLanes<Tuple<2, 1>> x, ConstTupleLanes<Tuple<2, 1>> y, TupleLanes<Tuple<2, 1>> out,
                      std::size_t count, int p, double sign);
void rp_combine_lanes(ConstTupleLanes<Tuple<3, 1>> x, ConstTupleLanes<Tuple<3, 1>> y, TupleLanes<Tuple<3, 1>> out,
                      std::size_t count, int p, double sign);

}  // namespace sage
