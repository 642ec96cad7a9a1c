// Broad phase at scale: the update_broad_phase stage's cost per step for N unit cubes,
// N = 1,000, 10,000 and 50,000, in three states:
//   rest_asleep  cubes resting on the ground plane (a square grid, 1.5 m apart, centres at
//                z = 0.5), sleeping on, measured once every cube is asleep;
//   rest_awake   the same with sleeping off: every box is recomputed, none leaves its fat box;
//   moving       cubes on a cubic grid 1.5 m apart with random velocities (|v_i| <= 2 m/s per
//                axis) and spins (<= 3 rad/s), no gravity and no ground: a gas in which every
//                box leaves its fat box every few steps and pairs come and go.
// World::profile() gives the stages' wall time; the stepping calls are also timed in thread CPU
// time (the machine is shared: wall time swells with its load, CPU time much less), and the broad
// phase's CPU share is estimated as its share of the wall time times the CPU time.
//
// stdout: CSV (bench/results/broad_phase_*.csv), one row per scene and N.
// usage: bench_broad_phase [--label L] [--sizes 1000,10000,50000] [scene...]
#include <time.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench/bench_util.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"

using namespace simreel;

namespace {

std::vector<BodyDef> resting_grid(int n) {
  const int side = (int)std::ceil(std::sqrt((double)n));
  std::vector<BodyDef> v;
  v.reserve(n + 1);
  for (int k = 0; k < n; ++k)
    v.push_back(r3_cube("cube" + std::to_string(k),
                        Vec3(1.5 * (k % side - 0.5 * side), 1.5 * (k / side - 0.5 * side), 0.5)));
  v.push_back(r3_ground());
  return v;
}

std::vector<BodyDef> gas(int n) {
  const int side = (int)std::ceil(std::cbrt((double)n));
  SplitMix64 rng(2026);
  std::vector<BodyDef> v;
  v.reserve(n);
  for (int k = 0; k < n; ++k) {
    BodyDef b =
        r3_cube("cube" + std::to_string(k),
                1.5 * Vec3(k % side, (k / side) % side, k / (side * side)) - Vec3::Constant(0.75 * side));
    b.v_W = Vec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    b.w_W = Vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    v.push_back(std::move(b));
  }
  return v;
}

void run(const char* label, const char* scene, int n) {
  const bool moving = !std::strcmp(scene, "moving");
  const bool sleep = !std::strcmp(scene, "rest_asleep");
  WorldConfig c;
  c.dt = kR3Dt;
  c.contacts.sleep = sleep;
  if (moving) c.gravity = Vec3::Zero();
  World w(c, moving ? gas(n) : resting_grid(n));
  // Warm-up: the resting cubes fall asleep after sleep_time (0.5 s) of stillness.
  const long warm = sleep ? 160 : 5;
  for (long k = 0; k < warm; ++k) w.step();
  const long steps = moving ? 40 : 100;
  w.set_profiling(true);
  const Profile p0 = w.profile();
  double wall = 0, cpu = 0;
  for (long k = 0; k < steps; ++k) {
    const double t0 = bench::now_s(), c0 = bench::thread_cpu_s();
    w.step();
    cpu += bench::thread_cpu_s() - c0;
    wall += bench::now_s() - t0;
  }
  const Profile& p = w.profile();
  const double bp = p.seconds[(int)Stage::update_broad_phase] - p0.seconds[(int)Stage::update_broad_phase];
  const double col = p.seconds[(int)Stage::collide] - p0.seconds[(int)Stage::collide];
  const double pairs = (double)(p.pairs - p0.pairs) / steps;
  std::printf("%s,%s,%d,%ld,%.4e,%.4e,%.4e,%.4e,%.4e,%.1f,%d,%016" PRIx64 "\n", label, scene, n, steps,
              bp / steps, col / steps, wall / steps, cpu / steps, wall > 0 ? bp / wall * cpu / steps : 0.0,
              pairs, w.sleeping_count(), state_hash(w));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string label = "current";
  std::vector<int> sizes{1000, 10000, 50000};
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--label") && i + 1 < argc) {
      label = argv[++i];
    } else if (!std::strcmp(argv[i], "--sizes") && i + 1 < argc) {
      sizes.clear();
      for (char* s = argv[++i]; *s;) {
        sizes.push_back((int)std::strtol(s, &s, 10));
        if (*s == ',') ++s;
      }
    } else if (!std::strcmp(argv[i], "rest_asleep") || !std::strcmp(argv[i], "rest_awake") ||
               !std::strcmp(argv[i], "moving")) {
      scenes.push_back(argv[i]);
    } else {
      std::fprintf(stderr,
                   "bench_broad_phase: unknown argument '%s'\n"
                   "usage: bench_broad_phase [--label L] [--sizes 1000,10000,50000] "
                   "[rest_asleep|rest_awake|moving ...]\n",
                   argv[i]);
      return 2;
    }
  }
  for (int n : sizes)
    if (n <= 0) {
      std::fprintf(stderr, "bench_broad_phase: --sizes takes positive body counts\n");
      return 2;
    }
  if (scenes.empty()) scenes = {"rest_asleep", "rest_awake", "moving"};
  std::printf(
      "version,scene,bodies,steps,broad_phase_wall_s_per_step,collide_wall_s_per_step,step_wall_s_per_step,"
      "step_cpu_s_per_step,broad_phase_cpu_s_per_step_est,pairs_per_step,asleep,state_hash\n");
  for (int n : sizes)
    for (const std::string& s : scenes) run(label.c_str(), s.c_str(), n);
}
