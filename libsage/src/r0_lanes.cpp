// Compiled without errno (libsage/CMakeLists.txt): sqrt then needs no
// library call for negative arguments, so the compiler runs the roots and
// the divisions of several lanes in one vector instruction. The arithmetic
// is tuple.hpp's r0_combine, operation for operation (detail::r0_from_root
// finishes both). Each entry point is also compiled for AVX2, chosen at run
// time (four lanes per root or division instead of two: Greenland's R0
// field 10% faster on one thread); AVX2 has no fused multiply-add, so the
// bits stay the same.

#include <sage/r0_lanes.hpp>

#include <algorithm>
#include <cmath>

// x86-64 only: elsewhere the one default build.
#if defined(__x86_64__) && defined(__GNUC__)
#define SAGE_ALSO_AVX2 [[gnu::target_clones("avx2", "default")]]
#else
#define SAGE_ALSO_AVX2
#endif

namespace sage {
namespace {

template <int N>
[[gnu::always_inline]] inline void combine_lanes(const Tuple<N, 1>* x, const Tuple<N, 1>* y, Tuple<N, 1>* out,
                                                 std::size_t count, double sign) {
  constexpr std::size_t kChunk = 64;
  double r2[kChunk], root[kChunk], slope[kChunk];
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t n = std::min(kChunk, count - start);
    const Tuple<N, 1>* xs = x + start;
    const Tuple<N, 1>* ys = y + start;
    Tuple<N, 1>* outs = out + start;
    for (std::size_t l = 0; l < n; ++l) r2[l] = xs[l].c[0] * xs[l].c[0] + ys[l].c[0] * ys[l].c[0];
    for (std::size_t l = 0; l < n; ++l) {
      const double r = r2[l] > 0.0 ? r2[l] : 1.0;  // corner and NaN lanes are redone below
      root[l] = std::sqrt(r);
      slope[l] = sign * root[l] * 0.5 / r;
    }
    for (std::size_t l = 0; l < n; ++l)
      outs[l] =
          r2[l] > 0.0 ? detail::r0_from_root(xs[l], ys[l], sign, root[l], slope[l]) : r0_combine(xs[l], ys[l], sign);
  }
}

}  // namespace

SAGE_ALSO_AVX2 void r0_combine_lanes(const double* x, const double* y, double* out, std::size_t count, double sign) {
  // rfunction.hpp's r0_combine<double>, operation for operation.
  for (std::size_t l = 0; l < count; ++l) {
    const double r2 = x[l] * x[l] + y[l] * y[l];
    out[l] = x[l] + y[l] + sign * std::sqrt(r2 > 0 ? r2 : 0.0);
  }
}
SAGE_ALSO_AVX2 void r0_combine_lanes(const Tuple<2, 1>* x, const Tuple<2, 1>* y, Tuple<2, 1>* out, std::size_t count,
                                     double sign) {
  combine_lanes(x, y, out, count, sign);
}
SAGE_ALSO_AVX2 void r0_combine_lanes(const Tuple<3, 1>* x, const Tuple<3, 1>* y, Tuple<3, 1>* out, std::size_t count,
                                     double sign) {
  combine_lanes(x, y, out, count, sign);
}

}  // namespace sage
