#include "progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <memory>

namespace sage::cli {

Progress terminal_progress(const std::string& label) {
  if (!isatty(fileno(stderr))) return {};
  auto last = std::make_shared<int>(-1);
  return [label, last](double fraction) {
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == *last) return;
    *last = percent;
    std::fprintf(stderr, "\r%s %3d%%%s", label.c_str(), percent, percent >= 100 ? "\n" : "");
    std::fflush(stderr);
  };
}

}  // namespace sage::cli
