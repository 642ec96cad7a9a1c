// A scratch folder of the test now running, private to it.
//
// ctest -j runs every test in its own process at the same time, so two tests writing
// "/tmp/x/bad.yaml" race (CI saw one test read another's file). Each test gets
// <tmp>/simreel-tests/<Suite>.<Test>-<pid>, emptied when first asked for.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace simreel::test {

inline std::filesystem::path scratch_dir() {
  namespace fs = std::filesystem;
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = t ? std::string(t->test_suite_name()) + "." + t->name() : "no-test";
  const fs::path dir = fs::temp_directory_path() / "simreel-tests" / (name + "-" + std::to_string(getpid()));
  static fs::path made;  // emptied once per test, not on every call
  if (made != dir) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    made = dir;
  }
  return dir;
}

inline std::string scratch(const std::string& file) {
  return (scratch_dir() / file).string();
}

// Writes `text` to a file of that name in the scratch folder; returns its path.
inline std::string scratch_file(const std::string& name, const std::string& text) {
  const std::string p = scratch(name);
  std::ofstream(p) << text;
  return p;
}

}  // namespace simreel::test
