// Compiled without errno (libsage/CMakeLists.txt): sqrt then needs no
// library call for negative arguments, so the compiler runs the roots and
// the divisions of several lanes in one vector instruction. The arithmetic
// is tuple.hpp's and rfunction.hpp's r0_combine and rp_combine, operation
// for operation (detail::r0_from_root and detail::rp_from_factors finish
// the tuples of both; here over tuples stored by component, R0 a lane at
// a time, Rp a component at a time). Each entry point is also compiled
// for AVX2 and AVX-512, chosen at run time (vector_clones.hpp: four or
// eight lanes per root or division instead of two), with the same bits.
//
// Every lane reads its own arguments before it writes its result, and no
// other lane's: so `out` may be `x` or `y`, and `#pragma GCC ivdep` tells
// the compiler that no iteration depends on another even then.

#include <sage/scalars/rfunction_lanes.hpp>

#include <sage/scalars/rfunction.hpp>

#include "lane_steps.hpp"
#include "vector_clones.hpp"

#include <algorithm>
#include <cmath>

namespace sage {
namespace {

constexpr std::size_t kChunk = 64;

template <int N>
using Lanes = TupleLanes<Tuple<N, 1>>;
template <int N>
using ConstLanes = ConstTupleLanes<Tuple<N, 1>>;

// A chunk [start, start + n) without singular lanes: component k >= 1 of
// lane start + l is xk + yk + partial(l, x0, y0, xk, yk), a component at a
// time, then the value x0 + y0 + sign * root[l] (last, as the partials read
// the values).
template <int N, class Partial>
[[gnu::always_inline]] inline void finish_by_component(ConstLanes<N> x, ConstLanes<N> y, Lanes<N> out,
                                                       std::size_t start, std::size_t n, const double* root,
                                                       double sign, Partial partial) {
  const double* x0 = x.component(0) + start;
  const double* y0 = y.component(0) + start;
  for (int k = 1; k <= N; ++k) {
    const double* xk = x.component(k) + start;
    const double* yk = y.component(k) + start;
    double* ok = out.component(k) + start;
#pragma GCC ivdep
    for (std::size_t l = 0; l < n; ++l) ok[l] = xk[l] + yk[l] + partial(l, x0[l], y0[l], xk[l], yk[l]);
  }
  double* o0 = out.component(0) + start;
#pragma GCC ivdep
  for (std::size_t l = 0; l < n; ++l) o0[l] = x0[l] + y0[l] + sign * root[l];
}

// detail::r0_from_root a lane at a time, every component in one loop: the
// root and the division of each lane then overlap the sums and products
// of the others (split by component, the loop with the divisions waited
// on them alone: 1,000 balls' R0 union 1.4 times slower). The same
// operations on each number as r0_from_root.
template <int N>
[[gnu::always_inline]] inline void r0_regular(ConstLanes<N> x, ConstLanes<N> y, Lanes<N> out, std::size_t start,
                                              std::size_t n, double sign) {
  const double *xs[N + 1], *ys[N + 1];
  double* os[N + 1];
  for (int k = 0; k <= N; ++k) {
    xs[k] = x.component(k) + start;
    ys[k] = y.component(k) + start;
    os[k] = out.component(k) + start;
  }
#pragma GCC ivdep
  for (std::size_t l = 0; l < n; ++l) {
    double a[N + 1], b[N + 1], o[N + 1];
    for (int k = 0; k <= N; ++k) {
      a[k] = xs[k][l];
      b[k] = ys[k][l];
    }
    lane::r0<N>(a, b, sign, o);
    for (int k = 0; k <= N; ++k) os[k][l] = o[k];
  }
}

template <int N>
[[gnu::always_inline]] inline void r0_lanes(ConstLanes<N> x, ConstLanes<N> y, Lanes<N> out, std::size_t count,
                                            double sign) {
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* x0 = x.component(0) + start;
    const double* y0 = y.component(0) + start;
    std::size_t singular = 0;
    for (std::size_t l = 0; l < n; ++l) singular += !(x0[l] * x0[l] + y0[l] * y0[l] > 0.0);
    if (singular == 0) {
      r0_regular(x, y, out, start, n, sign);
      continue;
    }
    // A chunk with the corner (both values 0) or NaN: r0_combine itself.
    for (std::size_t l = 0; l < n; ++l) out.store(start + l, r0_combine(x.load(start + l), y.load(start + l), sign));
  }
}

// pow_real(s, 1 / P) for s > 0 and P = 2^roots: that many square roots.
template <int P>
[[gnu::always_inline]] inline double root_of_order(double s) {
  static_assert(P == 1 || P == 2 || P == 4 || P == 8);
  if constexpr (P == 1)
    return s;
  else
    return root_of_order<P / 2>(std::sqrt(s));
}

// sage::pow_int(b, E) unrolled at compile time (r = 1 to start): the same
// products in the same order, but a loop over lanes around it vectorizes.
template <unsigned E>
[[gnu::always_inline]] inline double pow_unrolled(double b, double r = 1.0) {
  if constexpr (E == 0)
    return r;
  else
    return pow_unrolled<(E >> 1)>(b * b, (E & 1u) ? r * b : r);
}

template <int P>
[[gnu::always_inline]] inline void rp_lanes(const double* x, const double* y, double* out, std::size_t count,
                                            double sign) {
  double s[kChunk], root[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* xs = x + start;
    const double* ys = y + start;
    std::size_t singular = 0;
    for (std::size_t l = 0; l < n; ++l) {
      s[l] = pow_unrolled<P>(xs[l]) + pow_unrolled<P>(ys[l]);
      singular += !(s[l] > 0.0);
      root[l] = root_of_order<P>(s[l] > 0.0 ? s[l] : 1.0);
    }
    // rfunction.hpp's rp_combine<double>; pow_real keeps 0, NaN and inf.
    if (singular == 0) {
      for (std::size_t l = 0; l < n; ++l) out[start + l] = xs[l] + ys[l] + sign * root[l];
      continue;
    }
    for (std::size_t l = 0; l < n; ++l)
      out[start + l] = xs[l] + ys[l] + sign * (s[l] > 0.0 ? root[l] : pow_real(s[l], 1.0 / P));
  }
}

template <int P, int N>
[[gnu::always_inline]] inline void rp_lanes(ConstLanes<N> x, ConstLanes<N> y, Lanes<N> out, std::size_t count,
                                            double sign) {
  double s[kChunk], root[kChunk], slope[kChunk], px[kChunk], py[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const double* x0 = x.component(0) + start;
    const double* y0 = y.component(0) + start;
    // tuple.hpp's rp_combine: its factors (integer_power_series and
    // power_series of order 1) and its fallback for zero arguments, the
    // corner and NaN.
    std::size_t singular = 0;
    for (std::size_t l = 0; l < n; ++l) {
      s[l] = pow_unrolled<P>(x0[l]) + pow_unrolled<P>(y0[l]);
      px[l] = static_cast<double>(P) * pow_unrolled<P - 1>(x0[l]);
      py[l] = static_cast<double>(P) * pow_unrolled<P - 1>(y0[l]);
      singular += !(x0[l] != 0.0 && y0[l] != 0.0 && s[l] > 0.0);
    }
    for (std::size_t l = 0; l < n; ++l) {
      const double safe = s[l] > 0.0 ? s[l] : 1.0;  // singular lanes are redone below
      root[l] = root_of_order<P>(safe);
      slope[l] = power_series_from<1>(root[l], safe, 1.0 / P)[1];
    }
    if (singular == 0) {  // detail::rp_from_factors
      finish_by_component(x, y, out, start, n, root, sign, [&](std::size_t l, double, double, double a, double b) {
        return sign * (slope[l] * (px[l] * a + py[l] * b));
      });
      continue;
    }
    for (std::size_t l = 0; l < n; ++l) {
      const Tuple<N, 1> a = x.load(start + l), b = y.load(start + l);
      const bool regular = x0[l] != 0.0 && y0[l] != 0.0 && s[l] > 0.0;
      out.store(start + l, regular ? detail::rp_from_factors(a, b, sign, root[l], slope[l], px[l], py[l])
                                   : rp_combine(a, b, P, sign));
    }
  }
}

// One lane of doubles or of tuples stored by component.
inline double load_lane(const double* x, std::size_t l) { return x[l]; }
inline void store_lane(double* out, std::size_t l, double value) { out[l] = value; }
template <int N>
Tuple<N, 1> load_lane(ConstLanes<N> x, std::size_t l) {
  return x.load(l);
}
template <int N>
void store_lane(Lanes<N> out, std::size_t l, const Tuple<N, 1>& value) {
  out.store(l, value);
}

// p = 2, 4, 8 a vector at a time, any other p lane by lane.
template <class In, class Out>
[[gnu::always_inline]] inline void rp_lanes_of_order(In x, In y, Out out, std::size_t count, int p, double sign) {
  switch (p) {
    case 2: return rp_lanes<2>(x, y, out, count, sign);
    case 4: return rp_lanes<4>(x, y, out, count, sign);
    case 8: return rp_lanes<8>(x, y, out, count, sign);
    default:
      for (std::size_t l = 0; l < count; ++l) store_lane(out, l, rp_combine(load_lane(x, l), load_lane(y, l), p, sign));
  }
}

}  // namespace

SAGE_VECTOR_CLONES void r0_combine_lanes(const double* x, const double* y, double* out, std::size_t count,
                                         double sign) {
  // rfunction.hpp's r0_combine<double>, operation for operation.
  for (std::size_t l = 0; l < count; ++l) {
    out[l] = lane::r0(x[l], y[l], sign);
  }
}
SAGE_VECTOR_CLONES void r0_combine_lanes(ConstTupleLanes<Tuple<2, 1>> x, ConstTupleLanes<Tuple<2, 1>> y,
                                         TupleLanes<Tuple<2, 1>> out, std::size_t count, double sign) {
  r0_lanes(x, y, out, count, sign);
}
SAGE_VECTOR_CLONES void r0_combine_lanes(ConstTupleLanes<Tuple<3, 1>> x, ConstTupleLanes<Tuple<3, 1>> y,
                                         TupleLanes<Tuple<3, 1>> out, std::size_t count, double sign) {
  r0_lanes(x, y, out, count, sign);
}

SAGE_VECTOR_CLONES void rp_combine_lanes(const double* x, const double* y, double* out, std::size_t count, int p,
                                         double sign) {
  rp_lanes_of_order(x, y, out, count, p, sign);
}
SAGE_VECTOR_CLONES void rp_combine_lanes(ConstTupleLanes<Tuple<2, 1>> x, ConstTupleLanes<Tuple<2, 1>> y,
                                         TupleLanes<Tuple<2, 1>> out, std::size_t count, int p, double sign) {
  rp_lanes_of_order(x, y, out, count, p, sign);
}
SAGE_VECTOR_CLONES void rp_combine_lanes(ConstTupleLanes<Tuple<3, 1>> x, ConstTupleLanes<Tuple<3, 1>> y,
                                         TupleLanes<Tuple<3, 1>> out, std::size_t count, int p, double sign) {
  rp_lanes_of_order(x, y, out, count, p, sign);
}

}  // namespace sage
