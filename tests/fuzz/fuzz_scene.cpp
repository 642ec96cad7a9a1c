// libFuzzer harness: the scene loader (app/scene.cpp, yaml-cpp underneath) on arbitrary text.
//
// The scene "lives" in a scratch folder holding copies of assets/ (the working directory is moved
// there once), so `file: tetra.off` loads a real mesh and nothing else on the machine is named by
// a relative path. A scene that loads must give every body a finite, positive mass and a finite
// inertia: the world would refuse it otherwise, without naming file and line.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/scene.hpp"
#include "sim/error.hpp"
#include "sim/mass_properties.hpp"
#include "tests/fuzz/fuzz_common.hpp"

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
  using namespace simreel;
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  try {
    const Scene s = load_scene_text(yaml, "scene.yaml");
    for (const BodyDef& b : s.bodies) {
      bool massive = false;
      for (const Collider& c : b.colliders) massive = massive || c.shape != ShapeKind::plane;
      if (!massive) continue;
      const MassProperties& mp = b.mass_B();
      if (!std::isfinite(mp.mass) || !(mp.mass > 0) || !all_finite(mp.com) || !mp.inertia.allFinite())
        fuzz::finding("a body with a non-finite or non-positive mass or inertia was loaded");
      if (!inertia_problem(mp.inertia, 1e-7).empty())
        fuzz::finding("a body with an unphysical inertia was loaded");
    }
  } catch (const InputError&) {
  }
  return 0;
}
