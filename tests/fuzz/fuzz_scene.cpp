// libFuzzer harness: the scene loader (app/scene/scene.cpp, yaml-cpp underneath) on arbitrary text.
//
// The scene "lives" in a scratch folder holding copies of assets/ (the working directory is moved
// there once), so `file: tetra.off` loads a real mesh and nothing else on the machine is named by
// a relative path.
#include <unistd.h>

#include <filesystem>

#include "tests/fuzz/targets.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  namespace fs = std::filesystem;
  const fs::path assets = fs::path(SIMREEL_SOURCE_DIR) / "assets";
  const fs::path dir = fs::temp_directory_path() / ("simreel-fuzz-scene-" + std::to_string(getpid()));
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(assets))
    if (e.is_regular_file())
      fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing);
  fs::current_path(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  simreel::fuzz::scene(data, size);
  return 0;
}
