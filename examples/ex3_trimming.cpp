//                         sage example 3: trimming
//
// Sample runs:  ex3_trimming
//
// Description:  The half-line y = 0, x >= 0 (paper 004, fig. 12) as a
//               distance field, by simple, normalized and smooth trimming,
//               compared with the exact Euclidean distance along a circle
//               of radius 0.5 around the end point. Normalized (C1)
//               trimming is exact; the smooth variant trades exactness far
//               from the entity for smoothness; simple trimming is only
//               right close to the half-line. Adds to example 2: trimming
//               operators built from two fields.

#include <sage/expression/trimming.hpp>
#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

int main() {
  using namespace sage;
  const Expr h = Expr::y();  // the carrier line, normalized
  const Expr t = Expr::x();  // the trimming region x >= 0, normalized

  // 1. Three trimmed fields of the same entity.
  const Tape simple(trim_simple(h, t, RSystem::r0()), 2);
  const Tape normalized(trim_normalized(h, t), 2);
  const Tape smooth(trim_smooth(h, t), 2);
  Evaluator<double> es(simple), en(normalized), em(smooth);

  // 2. The exact distance to the half-line, and the largest deviation of
  //    each field from it around the end point.
  auto exact = [](double px, double py) { return px >= 0 ? std::abs(py) : std::hypot(px, py); };
  double worst[3] = {0, 0, 0};
  std::printf("%8s %10s %10s %10s %10s\n", "angle", "exact", "simple", "normalized", "smooth");
  for (int k = 0; k <= 12; ++k) {
    const double a = M_PI * k / 12.0 + 0.01, px = 0.5 * std::cos(a), py = 0.5 * std::sin(a);
    const double d = exact(px, py), v[3] = {es.at({px, py}), en.at({px, py}), em.at({px, py})};
    for (int i = 0; i < 3; ++i) worst[i] = std::max(worst[i], std::abs(v[i] - d));
    std::printf("%8.3f %10.6f %10.6f %10.6f %10.6f\n", a, d, v[0], v[1], v[2]);
  }
  std::printf("largest |field - distance|: simple %.3g, normalized %.3g, smooth %.3g\n", worst[0], worst[1], worst[2]);
  // 3. Check: normalized trimming is the exact distance here.
  return worst[1] < 1e-12 ? 0 : 1;
}
