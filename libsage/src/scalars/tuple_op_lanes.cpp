// Compiled without errno (libsage/CMakeLists.txt), as rfunction_lanes.cpp:
// the roots and divisions of several lanes run in one vector instruction.
// Each entry point is also compiled for AVX2 and AVX-512
// (vector_clones.hpp; no fused multiply-adds, so the same bits).
//
// tuple.hpp's arithmetic for K = 1, term for term: a product's partial k is
// (0.0 + a0 bk) + ak b0 (the product table accumulates into zeros; with
// two terms their order cannot change the sum), a quotient is a times the
// series of 1 / b (1 / b0, then -(1 / b0) / b0 times the partials), an
// integer power is the series pow_int(a0, n) + n pow_int(a0, n - 1) (a - a0).
// Lanes where the operators take another branch (a root of a non-positive
// number, a quotient by zero, a power of zero) are handed to them.

#include <sage/scalars/tuple_op_lanes.hpp>

#include "vector_clones.hpp"

#include <algorithm>
#include <cmath>

namespace sage {
namespace {

constexpr std::size_t kChunk = 64;

// A chunk's results by component before they are stored, and whether
// some lane must be computed by the operators instead. Only whether: a
// flag per lane, stored from the vector loop, made these kernels up to
// twice as slow.
template <int N>
struct Chunk {
  double c[N + 1][kChunk];
  std::size_t any_singular;
};

// Stores chunk lanes [0, n) at out's lanes [start, start + n): the lanes
// where singular(lane) from fallback(lane). Both read that lane's
// arguments before anything overwrites them.
template <int N, class Singular, class Fallback>
[[gnu::always_inline]] inline void store_chunk(const Chunk<N>& chunk, FirstOrderLanes<N> out, std::size_t start,
                                               std::size_t n, Singular singular, Fallback fallback) {
  if (chunk.any_singular == 0) {
    for (int k = 0; k <= N; ++k) {
      double* o = out.component(k) + start;
      for (std::size_t l = 0; l < n; ++l) o[l] = chunk.c[k][l];
    }
    return;
  }
  for (std::size_t l = 0; l < n; ++l) {
    if (singular(start + l)) {
      out.store(start + l, fallback(start + l));
      continue;
    }
    for (int k = 0; k <= N; ++k) out.component(k)[start + l] = chunk.c[k][l];
  }
}

template <int N>
[[gnu::always_inline]] inline void mul(ConstFirstOrderLanes<N> a, ConstFirstOrderLanes<N> b, FirstOrderLanes<N> out,
                                       std::size_t count) {
  const double* a0 = a.component(0);
  const double* b0 = b.component(0);
  for (int k = 1; k <= N; ++k) {
    const double* ak = a.component(k);
    const double* bk = b.component(k);
    double* ok = out.component(k);
#pragma GCC ivdep
    for (std::size_t l = 0; l < count; ++l) ok[l] = (0.0 + a0[l] * bk[l]) + ak[l] * b0[l];
  }
  double* o0 = out.component(0);  // last: the partials read the values
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) o0[l] = 0.0 + a0[l] * b0[l];
}

// The product's terms with b = T(c): partial k is (0.0 + a0 0.0) + ak c
// (a NaN where a0 is infinite, as the table's product gives).
template <int N>
[[gnu::always_inline]] inline void mul_constant(ConstFirstOrderLanes<N> a, double c, FirstOrderLanes<N> out,
                                                std::size_t count) {
  const double* a0 = a.component(0);
  for (int k = 1; k <= N; ++k) {
    const double* ak = a.component(k);
    double* ok = out.component(k);
#pragma GCC ivdep
    for (std::size_t l = 0; l < count; ++l) ok[l] = (0.0 + a0[l] * 0.0) + ak[l] * c;
  }
  double* o0 = out.component(0);
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) o0[l] = 0.0 + a0[l] * c;
}

// div()'s arithmetic with b0 = c and bk = 0: no division per lane.
template <int N>
[[gnu::always_inline]] inline void div_constant(ConstFirstOrderLanes<N> a, double c, FirstOrderLanes<N> out,
                                                std::size_t count, bool safe) {
  if (c == 0.0) {  // tuple.hpp's pole (or div_safe's zero) in every lane
    for (std::size_t l = 0; l < count; ++l)
      out.store(l, safe ? Tuple<N, 1>(0.0) : Tuple<N, 1>(a.load(l).value() / 0.0));
    return;
  }
  const double inverse = 1.0 / c, slope = inverse * -1.0 / c, partial = 0.0 + slope * 0.0;
  const double* a0 = a.component(0);
  for (int k = 1; k <= N; ++k) {
    const double* ak = a.component(k);
    double* ok = out.component(k);
#pragma GCC ivdep
    for (std::size_t l = 0; l < count; ++l) ok[l] = (0.0 + a0[l] * partial) + ak[l] * inverse;
  }
  double* o0 = out.component(0);
#pragma GCC ivdep
  for (std::size_t l = 0; l < count; ++l) o0[l] = 0.0 + a0[l] * inverse;
}

template <int N>
[[gnu::always_inline]] inline void sqrt_of(ConstFirstOrderLanes<N> a, FirstOrderLanes<N> out, std::size_t count) {
  Chunk<N> chunk;
  double slope[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* a0 = a.component(0) + start;
    chunk.any_singular = 0;
    for (std::size_t l = 0; l < n; ++l) {
      const bool regular = a0[l] > 0.0;
      const double x = regular ? a0[l] : 1.0;  // other lanes are redone by the operator
      const double root = std::sqrt(x);
      chunk.c[0][l] = root;
      slope[l] = root * 0.5 / x;
      chunk.any_singular |= static_cast<std::size_t>(!regular);
    }
    for (int k = 1; k <= N; ++k) {
      const double* ak = a.component(k) + start;
      for (std::size_t l = 0; l < n; ++l) chunk.c[k][l] = slope[l] * ak[l];
    }
    store_chunk(
        chunk, out, start, n, [&](std::size_t lane) { return !(a.component(0)[lane] > 0.0); },
        [&](std::size_t lane) { return sqrt(a.load(lane)); });
  }
}

template <int N>
[[gnu::always_inline]] inline void div(ConstFirstOrderLanes<N> a, ConstFirstOrderLanes<N> b, FirstOrderLanes<N> out,
                                       std::size_t count, bool safe) {
  Chunk<N> chunk;
  double inverse[kChunk], slope[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* a0 = a.component(0) + start;
    const double* b0 = b.component(0) + start;
    chunk.any_singular = 0;
    for (std::size_t l = 0; l < n; ++l) {
      const bool regular = b0[l] != 0.0;
      const double y = regular ? b0[l] : 1.0;
      inverse[l] = 1.0 / y;              // power_series(b0, -1): g0 = pow_real(b0, -1) = 1 / b0,
      slope[l] = inverse[l] * -1.0 / y;  // g1 = g0 (-1 - 1 + 1) / (1 b0)
      chunk.c[0][l] = 0.0 + a0[l] * inverse[l];
      chunk.any_singular |= static_cast<std::size_t>(!regular);
    }
    for (int k = 1; k <= N; ++k) {
      const double* ak = a.component(k) + start;
      const double* bk = b.component(k) + start;
      for (std::size_t l = 0; l < n; ++l) chunk.c[k][l] = (0.0 + a0[l] * (0.0 + slope[l] * bk[l])) + ak[l] * inverse[l];
    }
    store_chunk(
        chunk, out, start, n, [&](std::size_t lane) { return !(b.component(0)[lane] != 0.0); },
        [&](std::size_t lane) { return safe ? div_safe(a.load(lane), b.load(lane)) : a.load(lane) / b.load(lane); });
  }
}

// out[l] = sage::pow_int(x[l], n) for n >= 0, its squarings and products
// in the same order, a vector of lanes at a time.
[[gnu::always_inline]] inline void powers(const double* x, int n, double* out, std::size_t count) {
  double base[kChunk];
  for (std::size_t l = 0; l < count; ++l) {
    out[l] = 1.0;
    base[l] = x[l];
  }
  for (unsigned e = static_cast<unsigned>(n); e; e >>= 1) {
    if (e & 1u)
      for (std::size_t l = 0; l < count; ++l) out[l] *= base[l];
    for (std::size_t l = 0; l < count; ++l) base[l] *= base[l];
  }
}

template <int N>
[[gnu::always_inline]] inline void pow_int_of(ConstFirstOrderLanes<N> a, int n_power, FirstOrderLanes<N> out,
                                              std::size_t count) {
  if (n_power < 0) {  // the series of a real power: lane by lane
    for (std::size_t l = 0; l < count; ++l) out.store(l, pow_int(a.load(l), n_power));
    return;
  }
  Chunk<N> chunk;
  double slope[kChunk];
  const double binomial = 1.0 * n_power / 1;  // integer_power_series' C(n, 1)
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* a0 = a.component(0) + start;
    chunk.any_singular = 0;
    powers(a0, n_power, chunk.c[0], n);
    if (n_power >= 1) powers(a0, n_power - 1, slope, n);
    for (std::size_t l = 0; l < n; ++l) {
      const bool regular = a0[l] != 0.0;
      chunk.c[0][l] = 1.0 * chunk.c[0][l];
      slope[l] = n_power >= 1 ? binomial * slope[l] : 0.0;
      chunk.any_singular |= static_cast<std::size_t>(!regular);
    }
    for (int k = 1; k <= N; ++k) {
      const double* ak = a.component(k) + start;
      for (std::size_t l = 0; l < n; ++l) chunk.c[k][l] = 0.0 + slope[l] * ak[l];
    }
    store_chunk(
        chunk, out, start, n, [&](std::size_t lane) { return !(a.component(0)[lane] != 0.0); },
        [&](std::size_t lane) { return pow_int(a.load(lane), n_power); });
  }
}

}  // namespace

SAGE_VECTOR_CLONES void mul_lanes(ConstFirstOrderLanes<2> a, ConstFirstOrderLanes<2> b, FirstOrderLanes<2> out,
                                  std::size_t count) {
  mul(a, b, out, count);
}
SAGE_VECTOR_CLONES void mul_lanes(ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b, FirstOrderLanes<3> out,
                                  std::size_t count) {
  mul(a, b, out, count);
}
SAGE_VECTOR_CLONES void mul_constant_lanes(ConstFirstOrderLanes<2> a, double c, FirstOrderLanes<2> out,
                                           std::size_t count) {
  mul_constant(a, c, out, count);
}
SAGE_VECTOR_CLONES void mul_constant_lanes(ConstFirstOrderLanes<3> a, double c, FirstOrderLanes<3> out,
                                           std::size_t count) {
  mul_constant(a, c, out, count);
}
SAGE_VECTOR_CLONES void div_constant_lanes(ConstFirstOrderLanes<2> a, double c, FirstOrderLanes<2> out,
                                           std::size_t count, bool safe) {
  div_constant(a, c, out, count, safe);
}
SAGE_VECTOR_CLONES void div_constant_lanes(ConstFirstOrderLanes<3> a, double c, FirstOrderLanes<3> out,
                                           std::size_t count, bool safe) {
  div_constant(a, c, out, count, safe);
}
SAGE_VECTOR_CLONES void square_lanes(ConstFirstOrderLanes<2> a, FirstOrderLanes<2> out, std::size_t count) {
  mul(a, a, out, count);
}
SAGE_VECTOR_CLONES void square_lanes(ConstFirstOrderLanes<3> a, FirstOrderLanes<3> out, std::size_t count) {
  mul(a, a, out, count);
}
SAGE_VECTOR_CLONES void sqrt_lanes(ConstFirstOrderLanes<2> a, FirstOrderLanes<2> out, std::size_t count) {
  sqrt_of(a, out, count);
}
SAGE_VECTOR_CLONES void sqrt_lanes(ConstFirstOrderLanes<3> a, FirstOrderLanes<3> out, std::size_t count) {
  sqrt_of(a, out, count);
}
SAGE_VECTOR_CLONES void div_lanes(ConstFirstOrderLanes<2> a, ConstFirstOrderLanes<2> b, FirstOrderLanes<2> out,
                                  std::size_t count, bool safe) {
  div(a, b, out, count, safe);
}
SAGE_VECTOR_CLONES void div_lanes(ConstFirstOrderLanes<3> a, ConstFirstOrderLanes<3> b, FirstOrderLanes<3> out,
                                  std::size_t count, bool safe) {
  div(a, b, out, count, safe);
}
SAGE_VECTOR_CLONES void pow_int_lanes(ConstFirstOrderLanes<2> a, int n, FirstOrderLanes<2> out, std::size_t count) {
  pow_int_of(a, n, out, count);
}
SAGE_VECTOR_CLONES void pow_int_lanes(ConstFirstOrderLanes<3> a, int n, FirstOrderLanes<3> out, std::size_t count) {
  pow_int_of(a, n, out, count);
}

SAGE_VECTOR_CLONES void array_op(ArrayOp op, const double* a, const double* b, double p0, double p1, double p2,
                                 double* out, std::size_t n) {
  // Each element reads its arguments before it writes (out may be a or b).
  auto unary = [&](auto f) {
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) out[i] = f(a[i]);
  };
  auto binary = [&](auto f) {
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) out[i] = f(a[i], b[i]);
  };
  switch (op) {
    case ArrayOp::Add: return binary([](double x, double y) { return x + y; });
    case ArrayOp::Sub: return binary([](double x, double y) { return x - y; });
    case ArrayOp::Scale: return unary([=](double x) { return x * p0; });
    case ArrayOp::Axpby: return binary([=](double x, double y) { return x * p0 + y * p1; });
    case ArrayOp::Offset: return unary([=](double x) { return x + p0; });
    case ArrayOp::ConstantMinus: return unary([=](double x) { return p0 - x; });
    case ArrayOp::Halfplane: return binary([=](double x, double y) { return (x * p0 + y * p1) + p2; });
    case ArrayOp::Mul: return binary([](double x, double y) { return x * y; });
    case ArrayOp::Square: return unary([](double x) { return sage::square(x); });
    case ArrayOp::Sqrt: return unary([](double x) { return std::sqrt(x); });
    case ArrayOp::Div: return binary([](double x, double y) { return x / y; });
    case ArrayOp::DivSafe: return binary([](double x, double y) { return sage::div_safe(x, y); });
    case ArrayOp::DivideBy: return unary([=](double x) { return x / p0; });
    case ArrayOp::Min: return binary([](double x, double y) { return sage::min(x, y); });
    case ArrayOp::Max: return binary([](double x, double y) { return sage::max(x, y); });
  }
}

}  // namespace sage
