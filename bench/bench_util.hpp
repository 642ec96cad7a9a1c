// Timing helpers for bench/: warm-up run, then the minimum and median of N timed runs.
#pragma once
#include <time.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <chrono>
#include <vector>

namespace simreel::bench {

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
// CPU seconds of the calling thread so far: steadier than wall time on a machine shared with other
// work (the benches that step on the calling thread quote it beside the wall time).
inline double thread_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
struct Timing {
  double min = 0, median = 0;
  int repeats = 0;
};
// f() runs once untimed (warm-up), then `repeats` timed runs.
template <typename F>
Timing time_runs(int repeats, F f) {
  f();
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const double t0 = now_s();
    f();
    t.push_back(now_s() - t0);
  }
  std::sort(t.begin(), t.end());
  return {t.front(), t[t.size() / 2], repeats};
}

// The value after option argv[i] (advancing i to it); a missing value exits 2 naming the option.
inline const char* option_value(int& i, int argc, char** argv) {
  if (i + 1 >= argc) {
    std::fprintf(stderr, "%s needs a value\n", argv[i]);
    std::exit(2);
  }
  return argv[++i];
}

}  // namespace simreel::bench
