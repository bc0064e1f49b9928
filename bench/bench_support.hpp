#pragma once
// Small helpers shared by the benchmark programs.

#include <fstream>
#include <string>

namespace sage::bench {

/// Starts the peak below over (Linux: writing 5 to clear_refs resets VmHWM).
inline void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

/// Peak resident set size of this process since the last reset_peak(), in MB (Linux).
inline double peak_megabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

}  // namespace sage::bench
