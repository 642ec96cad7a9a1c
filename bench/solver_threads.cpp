// Thread scaling of the contact stages (two threads solving large islands in parallel):
// the large pyramid (tests/fixtures/reference_scenes r3_pyramid(100): 5,050 unit cubes, sleeping off, 200
// steps of 1/60 s) and the R3 pile (1000 cubes, dt 1/240, sleeping off, --pile-steps steps),
// stepped with 1 and with 2 threads in turn, --repeats times each (1, 2, 1, 2, ...), so both
// see the same machine load. The final state hash must be the same for every thread count (the
// graph colouring makes the result independent of it; a mismatch is reported and exits 1).
//
// stdout: CSV, one row per scene and run: scene,threads,run,seconds,hash, then per scene the
//         median seconds per thread count and the ratio median(1 thread) / median(2 threads).
// stderr: per-stage seconds of one profiled run per scene and thread count (World::profile()).
// Options: --repeats N (default 5), --pyramid-steps N (200), --pile-steps N (600), --base N (100),
//          --threads N (the second thread count, default 2), --only pyramid|pile, --no-backoff (the
//          pool splits every run however busy the machine: WorldConfig::thread_backoff).
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "bench/bench_util.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"

using namespace simreel;

namespace {

struct Scene {
  std::string name;
  std::vector<BodyDef> bodies;
  double dt;
  long steps;
};

bool g_backoff = true;  // --no-backoff: the pool never runs a stage on the calling thread alone

// The CPU time of the whole process so far (every thread's), s.
double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// Steps the scene; returns the wall time of the stepping calls (the world's construction, which
// starts the worker threads and collides once, is left out), their CPU time over all threads in
// *cpu and the pool's runs on the calling thread alone (back-off) in *alone.
double run(const Scene& s, int threads, bool profile, uint64_t* hash, double* cpu = nullptr,
           long* alone = nullptr) {
  WorldConfig cfg;
  cfg.dt = s.dt;
  cfg.threads = threads;
  cfg.contacts.sleep = false;
  cfg.thread_backoff = g_backoff;
  World w(cfg, s.bodies);
  w.set_profiling(profile);
  const double t0 = bench::now_s(), c0 = process_cpu_s();
  for (long k = 0; k < s.steps; ++k) w.step();
  const double t = bench::now_s() - t0;
  if (cpu) *cpu = process_cpu_s() - c0;
  if (alone) *alone = w.profile().pool_alone_runs;
  *hash = state_hash(w);
  if (profile) {
    const Profile& p = w.profile();
    std::fprintf(stderr, "%s threads %d, profiled run (%.3f s):\n", s.name.c_str(), threads, t);
    std::fprintf(stderr, "  pool runs %ld, of which on one thread (back-off) %ld\n", p.pool_runs,
                 p.pool_alone_runs);
    for (int k = 0; k < (int)Stage::count; ++k)
      if (p.seconds[k] > 0) std::fprintf(stderr, "  %-22s %8.4f s\n", to_string((Stage)k), p.seconds[k]);
  }
  return t;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 5, base = 100, threads2 = 2;
  long pyramid_steps = kPyramidSteps, pile_steps = 600;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return bench::option_value(i, argc, argv); };
    if (a == "--repeats")
      repeats = std::atoi(next());
    else if (a == "--base")
      base = std::atoi(next());
    else if (a == "--pyramid-steps")
      pyramid_steps = std::atol(next());
    else if (a == "--pile-steps")
      pile_steps = std::atol(next());
    else if (a == "--threads")
      threads2 = std::atoi(next());
    else if (a == "--only")
      only = next();
    else if (a == "--no-backoff")
      g_backoff = false;
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (repeats < 1 || base < 1 || threads2 < 1 || pyramid_steps < 1 || pile_steps < 1) {
    std::fprintf(stderr, "options must be positive\n");
    return 2;
  }
  std::vector<Scene> scenes;
  if (only.empty() || only == "pyramid")
    scenes.push_back({"pyramid" + std::to_string(base), r3_pyramid(base), kPyramidDt, pyramid_steps});
  if (only.empty() || only == "pile") scenes.push_back({"pile", r3_pile(), kR3Dt, pile_steps});
  std::printf("scene,threads,run,seconds,cpu_seconds,alone_runs,hash\n");
  bool same = true;
  for (const Scene& s : scenes) {
    std::vector<double> t1, t2, c1, c2;
    uint64_t h1 = 0, h2 = 0, h;
    for (int r = 0; r < repeats; ++r) {
      for (int threads : {1, threads2}) {
        double cpu = 0;
        long alone = 0;
        const double t = run(s, threads, false, &h, &cpu, &alone);
        (threads == 1 ? t1 : t2).push_back(t);
        (threads == 1 ? c1 : c2).push_back(cpu);
        (threads == 1 ? h1 : h2) = h;
        same = same && h == h1;
        std::printf("%s,%d,%d,%.4f,%.4f,%ld,%016" PRIx64 "\n", s.name.c_str(), threads, r, t, cpu, alone, h);
        std::fflush(stdout);
      }
    }
    const double m1 = median(t1), m2 = median(t2);
    std::printf("%s,1,median,%.4f,%.4f,,%016" PRIx64 "\n", s.name.c_str(), m1, median(c1), h1);
    std::printf("%s,%d,median,%.4f,%.4f,,%016" PRIx64 "\n", s.name.c_str(), threads2, m2, median(c2), h2);
    std::printf("%s,ratio,median,%.3f,,,%s\n", s.name.c_str(), m2 > 0 ? m1 / m2 : 0.0,
                h1 == h2 ? "same_hash" : "HASH_DIFFERS");
    std::fflush(stdout);
    for (int threads : {1, threads2}) {
      run(s, threads, true, &h);
      same = same && h == h1;
    }
  }
  if (!same) std::fprintf(stderr, "the final state differs between thread counts\n");
  return same ? 0 : 1;
}
