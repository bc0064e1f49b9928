#pragma once
// Running the `sage` program from tests: exit code and all output, and
// scratch files in the test process's own temporary folder.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <test_files.hpp>

namespace sage_cli_test {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

inline Result run(const std::string& args) {
  const std::string command = std::string(SAGE_EXECUTABLE) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

inline fs::path scratch(const std::string& name) { return sage::test::scratch_dir() / name; }

inline std::string write_file(const std::string& name, const std::string& text) {
  const fs::path p = scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

/// The cube [lo, hi]^3 as 12 outward-oriented triangles (OFF), written to
/// the scratch folder as `name`.
inline std::string write_cube_off(const std::string& name, double lo, double hi) {
  std::string text = "OFF\n8 12 0\n";
  for (int v = 0; v < 8; ++v) {  // corners 0-3 at z = lo, 4-7 at z = hi, anticlockwise from (lo, lo)
    const int xy = v % 4;
    const double x = (xy == 1 || xy == 2) ? hi : lo, y = xy >= 2 ? hi : lo, z = v >= 4 ? hi : lo;
    text += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  }
  text +=
      "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n3 3 0 4\n3 3 4 "
      "7\n";
  return write_file(name, text);
}

}  // namespace sage_cli_test
