// libFuzzer harness: mass properties of arbitrary triangle meshes, every mode (tests/fuzz/targets.hpp
// has the input format).
#include "tests/fuzz/targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  simreel::fuzz::mass(data, size);
  return 0;
}
