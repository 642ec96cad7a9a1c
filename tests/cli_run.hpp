// Running the built simreel command as a script would (tests that define SIMREEL_BIN): its exit
// code and everything it printed, stdout and stderr together.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace simreel::test {

struct Result {
  int code;         ///< exit status, -1 if killed by a signal
  std::string out;  ///< stdout and stderr together
};

// A shell command line's exit code and everything it printed (stdout and stderr).
inline Result shell(const std::string& command) {
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int st = pclose(p);
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

#ifdef SIMREEL_BIN
// `env` is prepended as `env VARS...` (e.g. "LP_NUM_THREADS=1" or "-u CI").
inline Result run(const std::string& args, const std::string& env = "") {
  return shell((env.empty() ? "" : "env " + env + " ") + std::string(SIMREEL_BIN) + " " + args);
}
#endif

// A whole file's bytes ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace simreel::test
