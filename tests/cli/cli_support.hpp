#pragma once
// Running the `sage` program from tests: exit code and all output, and
// scratch files under the system's temporary folder.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

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

inline fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "sage_cli_test";
  fs::create_directories(dir);
  return dir / name;
}

inline std::string write_file(const std::string& name, const std::string& text) {
  const fs::path p = scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace sage_cli_test
