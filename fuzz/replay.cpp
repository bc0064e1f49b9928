// Replays saved inputs through a fuzz target's body in an ordinary build
// (no libFuzzer): sage_fuzz_replay TARGET PATH... where a folder stands for
// the files in it. CTest runs it on fuzz/regressions/TARGET (inputs that
// once crashed) and fuzz/corpus/TARGET (the seeds). A finding crashes the
// process; otherwise it prints one line per input and a count.
#include "fuzz_targets.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <vector>

int main(int argc, char** argv) {
  using Body = void (*)(const std::uint8_t*, std::size_t);
  const std::map<std::string, Body> bodies{{"model", sage::fuzz::model},     {"problem", sage::fuzz::problem},
                                           {"formula", sage::fuzz::formula}, {"mesh", sage::fuzz::mesh},
                                           {"geojson", sage::fuzz::geojson}, {"solve", sage::fuzz::solve}};
  const auto body = argc > 1 ? bodies.find(argv[1]) : bodies.end();
  if (body == bodies.end()) {
    std::fprintf(stderr, "usage: sage_fuzz_replay model|problem|formula|mesh|geojson|solve PATH...\n");
    return 2;
  }
  std::vector<std::filesystem::path> inputs;
  for (int i = 2; i < argc; ++i) {
    if (std::filesystem::is_directory(argv[i])) {
      std::vector<std::filesystem::path> files;
      for (const auto& entry : std::filesystem::directory_iterator(argv[i]))
        if (entry.is_regular_file()) files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      inputs.insert(inputs.end(), files.begin(), files.end());
    } else {
      inputs.emplace_back(argv[i]);
    }
  }
  for (const auto& path : inputs) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", path.c_str());
      return 1;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    body->second(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    std::printf("ok %s\n", path.c_str());
  }
  std::printf("%s: %zu passed, 0 failed\n", argv[1], inputs.size());
  return 0;
}
