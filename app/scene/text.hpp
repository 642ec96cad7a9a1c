// Small output helpers for the command line: JSON, a progress bar, files that appear whole or not at all.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

// Progress on stderr: on a terminal, frames done, frames/s and time left on one line redrawn in
// place; otherwise (a log, CI) a plain line every 10% or every 10 s. Nothing with `quiet`.
class Progress {
 public:
  Progress(const char* what, long total, bool quiet);
  void update(long done);
  void finish();

 private:
  const char* what_;
  long total_;
  bool on_, tty_;
  long next_share_ = 1;  ///< plain mode: the next tenth to report
  std::chrono::steady_clock::time_point t0_, last_;
};

// Writes to "<path>.partial-<pid>" beside the target; commit() renames it into place, and the
// destructor removes it if commit() was never reached. Readers never see a half-written file.
// A symlink is followed: the file it points at is replaced, the link stays. A target that is not
// a regular file (a device such as /dev/null, a FIFO) is written through, never replaced. Temp
// files of processes that no longer exist (killed with SIGKILL) are removed on the way.
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
  bool done_ = false, through_ = false;
};

// Removes "<name>.partial-<pid>..." files beside `path` whose process no longer exists.
void remove_stale_partials(const std::string& path);

// SIGINT, SIGTERM, SIGHUP and SIGQUIT while alive set a flag instead of ending the process: the
// first signal's number is kept and any that follow are ignored, so a run stops between steps
// and finishes its outputs however many signals arrive. The handlers stay until the process ends
// (a late signal must not kill it while it exits). Exit codes are 128 + the first signal: 130 for
// SIGINT, 143 for SIGTERM, 129 for SIGHUP, 131 for SIGQUIT.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  const std::atomic<int>& flag() const;
  int signal() const { return flag().load(); }
};

// A file name's extension in lower case, with its dot: "Mesh.OBJ" -> ".obj" ("" without one).
std::string lower_extension(const std::string& path);

// Creates the parent folder of `path` if needed; returns false with a message if it cannot.
bool ensure_parent_dir(const std::string& path, std::string* err);

}  // namespace simreel
