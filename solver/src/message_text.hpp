#pragma once
// Numbers and points as the solvers' messages print them.

#include <array>
#include <cstdio>
#include <string>

namespace sage::solver {

/// x in %g style with `digits` significant digits, for messages.
inline std::string number_text(double x, int digits = 3) {
  if (x != x) return "NaN";  // not "nan" or "-nan", by the sign bit
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, x);
  return text;
}

inline std::string scientific(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", x);
  return text;
}

template <int D>
std::string point_text(const std::array<double, D>& x) {
  std::string text = "(";
  for (int a = 0; a < D; ++a) text += (a ? ", " : "") + std::to_string(x[a]);
  return text + ")";
}

}  // namespace sage::solver
