// libFuzzer harness: simreel's own STL reader (app/scene/mesh_readers.cpp) on arbitrary bytes, and the
// solid mass properties of what it reads (tests/fuzz/targets.hpp).
#include "tests/fuzz/targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  simreel::fuzz::reader("stl", data, size);
  return 0;
}
