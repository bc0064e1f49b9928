// The libFuzzer entry of one fuzz target: SAGE_FUZZ_BODY names its body
// (fuzz_targets.hpp), set by fuzz/CMakeLists.txt.
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sage::fuzz::SAGE_FUZZ_BODY(data, size);
  return 0;
}
