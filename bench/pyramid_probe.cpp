// The large pyramid with one setting at a time, for tuning the contact solver: process
// CPU seconds of the stepping (one thread), the largest cube displacement between the run's middle
// and its end (the "settled" criterion: < 1 cm), the top cube's sink, the fastest cube at the end,
// the deepest contact, the substeps taken and the solver's per-stage seconds.
//   bench_pyramid_probe [--base N] [--steps N] [--substeps N] [--hertz H] [--damping Z]
//                       [--iterations N] [--passes N] [--push V] [--profile] [--impacts]
// (--impacts: the steps with impact substeps, on stderr)
// One CSV row on stdout: base,steps,substeps,hertz,damping,iterations,passes,cpu_s,drift_late_m,
// top_sink_m,max_speed_m_s,moving_gt_1cm_s,max_pen_m,notes
#include <ctime>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench/bench_util.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"
#include "sim/world/world_impl.hpp"

using namespace simreel;

namespace {

double cpu_s() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  int base = 100;
  long steps = kPyramidSteps;
  bool profile = false, impacts = false;
  WorldConfig cfg;
  cfg.dt = kPyramidDt;
  cfg.threads = 1;
  cfg.contacts.sleep = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return bench::option_value(i, argc, argv); };
    if (a == "--base")
      base = std::atoi(next());
    else if (a == "--steps")
      steps = std::atol(next());
    else if (a == "--substeps")
      cfg.contacts.substeps = std::atoi(next());
    else if (a == "--hertz")
      cfg.contacts.contact_hertz = std::atof(next());
    else if (a == "--damping")
      cfg.contacts.damping_ratio = std::atof(next());
    else if (a == "--iterations")
      cfg.contacts.iterations = std::atoi(next());
    else if (a == "--passes")
      cfg.contacts.passes = std::atoi(next());
    else if (a == "--push")
      cfg.contacts.max_push_out = std::atof(next());
    else if (a == "--profile")
      profile = true;
    else if (a == "--impacts")
      impacts = true;
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const std::vector<BodyDef> defs = r3_pyramid(base);
  const int n = (int)defs.size() - 1;  // cubes first, ground last
  World w(cfg, defs);
  w.set_profiling(profile);
  std::vector<Vec3> mid(n);
  double cpu = 0;
  int substeps_max = 0;
  long last_impacts = 0;
  for (long k = 0; k < steps; ++k) {
    const double t0 = cpu_s();
    w.step();
    cpu += cpu_s() - t0;
    substeps_max = std::max(substeps_max, w.substeps());
    if (impacts && w.profile().impact_substeps != last_impacts) {
      std::fprintf(stderr, "  step %ld: impact substeps %ld\n", k,
                   w.profile().impact_substeps - last_impacts);
      last_impacts = w.profile().impact_substeps;
    }
    if (k + 1 == steps / 2)
      for (int i = 0; i < n; ++i) mid[i] = w.impl().state(i).x_W;
  }
  double drift = 0, vmax = 0;
  int moving = 0, nan = 0, worst = 0, over5 = 0;
  for (int i = 0; i < n; ++i) {
    const MotionState& s = w.impl().state(i);
    if (!std::isfinite(s.x_W.squaredNorm())) ++nan;
    const double d = (s.x_W - mid[i]).norm();
    over5 += d > 0.005;
    if (d > drift) drift = d, worst = i;
    const double v = s.v_W.norm();
    vmax = std::max(vmax, v);
    moving += v > 0.01;
  }
  const double sink = defs[n - 1].p_WB.z() - w.impl().state(n - 1).x_W.z();
  std::printf("%d,%ld,%d,%g,%g,%d,%d,%.3f,%.3e,%.3e,%.3e,%d,%.3e,%s\n", base, steps, substeps_max,
              cfg.contacts.contact_hertz, cfg.contacts.damping_ratio, cfg.contacts.iterations,
              cfg.contacts.passes, cpu, drift, sink, vmax, moving, w.contact_stats().max_penetration,
              nan ? "NaN" : "");
  {
    const Vec3 d = w.impl().state(worst).x_W - mid[worst];
    const Vec3 x0 = defs[worst].p_WB;
    std::fprintf(stderr, "  worst cube %d at (%.1f, %.1f): drift (%.2e, %.2e, %.2e); %d cubes drift > 5 mm\n",
                 worst, x0.x(), x0.z(), d.x(), d.y(), d.z(), over5);
  }
  std::fprintf(stderr, "  impact substeps %ld, sweeps %ld; state hash %016llx\n", w.profile().impact_substeps,
               w.profile().sweeps, (unsigned long long)state_hash(w));
  if (profile) {
    const Profile& p = w.profile();
    for (int k = 0; k < (int)Stage::count; ++k)
      if (p.seconds[k] > 0) std::fprintf(stderr, "  %-22s %8.4f s\n", to_string((Stage)k), p.seconds[k]);
  }
  return 0;
}
