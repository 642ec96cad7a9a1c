// libFuzzer harness: simreel's own OBJ reader (app/mesh_readers.cpp) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sim/error.hpp"
#include "tests/fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace simreel;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string kind;
  try {
    const detail::RawMesh m = detail::parse_obj(text, std::string(fuzz::kFakeDir) + "/in.obj");
    fuzz::check_raw(m);
    fuzz::weigh(m);
  } catch (const InputError&) {
  }
  (void)kind;
  return 0;
}
