#pragma once
// The solvers' drivers' stage timing.

#include <sage/solver/solver_options.hpp>

#include <chrono>
#include <ctime>

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

}  // namespace sage::solver
