// Small output helpers for the command line: JSON, a progress bar, files that appear whole or not at all.
#pragma once
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/types.hpp"

namespace simreel {

// Minimal JSON building: numbers with 17 significant digits (round-trip exact), escaped strings.
std::string json_string(const std::string& s);
std::string json_number(double v);  ///< non-finite values become null
std::string json_vec(const Vec3& v);
std::string json_mat(const Mat3& m);
std::string json_strings(const std::vector<std::string>& v);

// Frames done, frames/s and time left on one terminal line; silent unless stderr is a terminal.
class Progress {
 public:
  Progress(const char* what, long total, bool quiet);
  void update(long done);
  void finish();

 private:
  const char* what_;
  long total_;
  bool on_;
  std::chrono::steady_clock::time_point t0_, last_;
};

// Writes to "<path>.partial-<pid>" beside the target; commit() renames it into place, and the
// destructor removes it if commit() was never reached. Readers never see a half-written file.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  ///< throws std::runtime_error if it cannot be created
  ~AtomicFile();
  FILE* get() { return f_; }
  const std::string& temp_path() const { return tmp_; }
  void commit();

 private:
  std::string path_, tmp_;
  FILE* f_ = nullptr;
  bool done_ = false;
};

// Creates the parent folder of `path` if needed; returns false with a message if it cannot.
bool ensure_parent_dir(const std::string& path, std::string* err);

}  // namespace simreel
