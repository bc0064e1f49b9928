#pragma once
// Files the tests read and write.
//  - test_data("gis/x.geojson"): a file of tests/data (origins and licences
//    in tests/data/README.md). A missing file throws, so the test fails and
//    names the path: no test skips itself.
//  - scratch_dir(): a folder of this test process's own, made on first use
//    under the system's temporary folder and removed when the process ends.
//    CTest runs every test in a process of its own, so two suites running at
//    once (a release and a sanitizer build, two checkouts) never share a file.

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace sage::test {

inline std::string test_data(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(SAGE_TEST_DATA_DIR) / relative;
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("test data file missing: " + path.string());
  return path.string();
}

class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "sage_test_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot make a folder from " + pattern);
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_dir() {
  static const ScratchDir dir;
  return dir.path();
}

/// Writes `text` to the file `name` in the scratch folder; its path.
inline std::string write_scratch(const std::string& name, const std::string& text) {
  const std::string p = (scratch_dir() / name).string();
  std::ofstream(p) << text;
  return p;
}

}  // namespace sage::test
