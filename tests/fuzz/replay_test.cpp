// Every hostile input found so far, replayed in the default build (no fuzzer, no sanitizers
// needed): tests/data/hostile/ (hand-made hostile files) through import_mesh and every mass
// mode, and tests/fuzz/crashes/HARNESS/ (what the fuzzers found, then fixed) through the harness's
// own code (tests/fuzz/targets.hpp). Each must end in an InputError or a finite success: a crash,
// an abort (finding()) or any other exception fails the test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/fuzz/targets.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().extension() != ".py" && e.path().extension() != ".md")
        out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

const fs::path kSource = SIMREEL_SOURCE_DIR;

TEST(Replay, HostileFilesGiveAnInputErrorOrAFiniteMesh) {
  const auto files = files_in(kSource / "tests/data/hostile");
  ASSERT_GE(files.size(), 15u);
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.filename().string());
    try {
      const ImportedMesh im = import_mesh(p.string());
      for (MassMode mode : {MassMode::solid, MassMode::shell, MassMode::hull}) {
        MeshMassOptions opt;
        opt.mode = mode;
        try {
          fuzz::check_report(analyze_mesh(im.mesh, opt));
        } catch (const InputError&) {
        }
      }
    } catch (const InputError&) {
    }
    // And through the reader of its extension, as the fuzz harness does.
    const std::string ext = p.extension().string().substr(1);
    if (ext == "obj" || ext == "off" || ext == "stl" || ext == "ply") {
      const std::string b = bytes_of(p);
      fuzz::reader(ext.c_str(), reinterpret_cast<const uint8_t*>(b.data()), b.size());
    }
  }
}

TEST(Replay, FuzzerFindingsStayFixed) {
  int n = 0;
  for (const char* h : {"scene", "obj", "off", "stl", "ply", "mass"})
    for (const fs::path& p : files_in(kSource / "tests/fuzz/crashes" / h)) {
      SCOPED_TRACE(p.string());
      const std::string b = bytes_of(p);
      const auto* d = reinterpret_cast<const uint8_t*>(b.data());
      const std::string_view name = h;
      if (name == "scene")
        fuzz::scene(d, b.size());
      else if (name == "mass")
        fuzz::mass(d, b.size());
      else
        fuzz::reader(h, d, b.size());
      ++n;
    }
  std::printf("replayed %d fuzzer findings\n", n);
}

}  // namespace
}  // namespace simreel
