#pragma once
// Small helpers of the solvers' drivers: stage timing and message text.

#include <sage/solver/solver_options.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>

namespace sage::solver {

/// Wall-clock and process CPU seconds per stage (CPU time is what a
/// one-thread benchmark on a shared machine can compare).
class StageTimer {
 public:
  explicit StageTimer(SolveReport& report) : report_(report) {}
  void lap(double StageSeconds::*stage) {
    const auto now = std::chrono::steady_clock::now();
    const std::clock_t cpu_now = std::clock();
    report_.seconds.*stage = std::chrono::duration<double>(now - start_).count();
    report_.cpu_seconds.*stage = static_cast<double>(cpu_now - cpu_start_) / CLOCKS_PER_SEC;
    start_ = now;
    cpu_start_ = cpu_now;
  }

 private:
  SolveReport& report_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::clock_t cpu_start_ = std::clock();
};

/// x in %g style with `digits` significant digits, for messages.
inline std::string number_text(double x, int digits = 3) {
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
