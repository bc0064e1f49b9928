#pragma once
// The subcommands of the `sage` program. Each parses its own options
// (Boost.Program_options) and returns the process exit code. Errors in the
// user's input are thrown as exceptions and reported by main().

#include <string>
#include <vector>

namespace sage::cli {

/// Bad command line: reported with a hint to --help, exit code 2.
struct UsageError {
  std::string message;
};

int run_field(const std::vector<std::string>& args);
int run_info(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_demo(const std::vector<std::string>& args);
int run_solve(const std::vector<std::string>& args);
int run_sample(const std::vector<std::string>& args);

}  // namespace sage::cli
