#pragma once
// Products, squares, roots, quotients and integer powers of first-order
// tuples over many points at once, stored by component (tuple_lanes.hpp):
// BatchEvaluator's kernels for the arithmetic of primitives and trimmed
// faces (a ball is three squares and a quotient, a trimmed triangle three
// squares, a fourth power and two roots). Lane by lane, through Tuple's
// operators, each of these costs a gather, a scatter and a call; here a
// component at a time, they run in vector instructions.
//
// The numbers are tuple.hpp's, bit for bit, for every input (zeros,
// infinities and NaNs included): its products and series for K = 1 written
// out term for term (tests/libsage/tuple_op_lanes_test.cpp checks them
// against the operators). out may be a or b: each lane reads its
// arguments before it writes.

#include <sage/scalars/tuple.hpp>
#include <sage/scalars/tuple_lanes.hpp>

#include <cstddef>

namespace sage {

template <int N>
using FirstOrderLanes = TupleLanes<Tuple<N, 1>>;
template <int N>
using ConstFirstOrderLanes = ConstTupleLanes<Tuple<N, 1>>;

/// out[l] = a[l] * b[l] for l < count.
void mul_lanes(ConstFirstOrderLanes<2> a, ConstFirstOrderLanes<2> b, FirstOrderLanes<2> out, std::size_t count);
void mul_lanes(ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b, FirstOrderLanes<3> out, std::size_t count);

/// out[l] = a[l] * T(c) and a[l] / T(c) (div_safe when `safe`): a
/// constant factor or divisor read as one number, not as lanes (a ball
/// divides by its diameter; a thousand balls' constants as lanes would
/// stream megabytes per batch).
void mul_constant_lanes(ConstFirstOrderLanes<2> a, double c, FirstOrderLanes<2> out, std::size_t count);
void mul_constant_lanes(ConstFirstOrderLanes<3> a, double c, FirstOrderLanes<3> out, std::size_t count);
void div_constant_lanes(ConstFirstOrderLanes<2> a, double c, FirstOrderLanes<2> out, std::size_t count, bool safe);
void div_constant_lanes(ConstFirstOrderLanes<3> a, double c, FirstOrderLanes<3> out, std::size_t count, bool safe);

/// out[l] = square(a[l]).
void square_lanes(ConstFirstOrderLanes<2> a, FirstOrderLanes<2> out, std::size_t count);
void square_lanes(ConstFirstOrderLanes<3> a, FirstOrderLanes<3> out, std::size_t count);

/// out[l] = sqrt(a[l]).
void sqrt_lanes(ConstFirstOrderLanes<2> a, FirstOrderLanes<2> out, std::size_t count);
void sqrt_lanes(ConstFirstOrderLanes<3> a, FirstOrderLanes<3> out, std::size_t count);

/// out[l] = a[l] / b[l], or div_safe(a[l], b[l]) when `safe`.
void div_lanes(ConstFirstOrderLanes<2> a, ConstFirstOrderLanes<2> b, FirstOrderLanes<2> out, std::size_t count,
               bool safe);
void div_lanes(ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b, FirstOrderLanes<3> out, std::size_t count,
               bool safe);

/// out[l] = pow_int(a[l], n).
void pow_int_lanes(ConstFirstOrderLanes<2> a, int n, FirstOrderLanes<2> out, std::size_t count);
void pow_int_lanes(ConstFirstOrderLanes<3> a, int n, FirstOrderLanes<3> out, std::size_t count);

/// Elementwise arithmetic over arrays of n doubles, for the tuple ops that
/// treat every coefficient alike (one component's lanes, or a register's
/// components back to back, or doubles): out[i] = op(a[i], b[i]), the
/// arithmetic of scalar.hpp, compiled for AVX2
/// and AVX-512 too (BatchEvaluator itself is not: these sums then ran two doubles per
/// instruction). out may be a or b.
enum class ArrayOp {
  Add,            // a + b
  Sub,            // a - b
  Scale,          // a * p0 (negation: p0 = -1)
  Axpby,          // a * p0 + b * p1
  Offset,         // a + p0
  ConstantMinus,  // p0 - a
  Halfplane,      // (a * p0 + b * p1) + p2
  // Doubles only (values without partials):
  Mul,       // a * b
  Square,    // a * a
  Sqrt,      // sqrt(a)
  Div,       // a / b
  DivSafe,   // a / b, 0 where b = 0
  DivideBy,  // a / p0
  Min,       // sage::min(a, b)
  Max,       // sage::max(a, b)
};
void array_op(ArrayOp op, const double* a, const double* b, double p0, double p1, double p2, double* out,
              std::size_t n);

}  // namespace sage
