#pragma once
// Small helpers shared by the benchmark programs.

#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace sage::bench {

/// Starts the peak below over (Linux: writing 5 to clear_refs resets VmHWM
/// to the resident size), after handing the memory freed by earlier runs
/// back to the system: kept by malloc, it would count in every later peak.
inline void reset_peak() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

/// Peak resident set size of this process since the last reset_peak(), in MB (Linux).
inline double peak_megabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

#ifdef SAGE_SOURCE_DIR
/// A file of the project's data collection, ../shared/data beside the
/// checkout: on the development machines and in CI, not in a user's clone.
/// Ends the program with a message naming the path when it is missing.
inline std::string shared_data(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(SAGE_SOURCE_DIR) / "../shared/data" / relative;
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr,
                 "%s is missing: this benchmark reads the project's data collection (../shared/data beside the "
                 "checkout); give the file's path on the command line instead\n",
                 path.lexically_normal().c_str());
    std::exit(2);
  }
  return path.lexically_normal().string();
}
#endif

}  // namespace sage::bench
