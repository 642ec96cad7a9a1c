// R3 contacts: the anchors' 1000-cube pile and 20-cube tower (../shared/anchors/CONTACTS.md), plus a
// box-on-plane sanity scene (100 cubes on a 1.5 m grid dropped from z = 1), stepped 10 s at
// dt = 1/240 by simreel (one thread, sleeping off and on) and, in the same run when
// libbullet-dev is installed, by Bullet 3.24 f64 with sleeping off and with sleeping on.
//
// stdout: one CSV row per engine, scene and setting (bench/results/r3_contacts.csv).
// stderr: per-stage seconds, a second CSV (bench/results/r3_contacts_profile.csv): simreel's
//         World::profile() from a profiled re-run (whose final state hash must equal the timed
//         run's), and Bullet's phases from the timed run.
//
// Every metric is computed here from poses and velocities, the same way for both engines:
//   seconds          wall time of the stepping calls only (each step timed, sampling excluded),
//                    the least of N runs (--repeats, default 3) made in turn with the other rows'
//                    (seconds_each_run lists them); the metrics are the first run's (every run of
//                    an engine is the same computation: simreel's hash is checked in each)
//   max_speed        largest centre-of-mass speed at 10 s, m/s; moving = cubes faster than 1 cm/s
//   pen_engine       the engine's own deepest contact over the run (simreel: contact_stats(),
//                    Bullet: deepest manifold point, read after every step), m; final_pen_engine:
//                    the same at the last step (the anchors' "penetration" figure)
//   pen_ground_geom  -(lowest cube vertex z) over the run, every step (ground plane z = 0), m
//   pen_cube_geom    deepest cube-cube overlap (minimum over the 15 separating axes of two boxes,
//                    which is their penetration depth) every 0.1 s and at the end, m
//   final_pen_ground -(lowest vertex z) at 10 s: resting penetration on the plane, m
//   top_drift/sink   tower: top cube's horizontal distance from its start and its initial minus
//                    final centre height at 10 s, m
//   notes            simreel: FNV-1a hash of every body's x_W, q_WP, v_W, w_P bytes at the end.
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>
#include <string>

#include "bench/bench_util.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"

#ifdef SIMREEL_BENCH_BULLET
#include <btBulletDynamicsCommon.h>

#include "bench/bullet_phased_world.hpp"
#endif

using namespace simreel;

namespace {

constexpr long kSteps = 2400;  // 10 s at 1/240

struct Cube {
  Vec3 x, v;
  Mat3 R;
};

// Deepest overlap of two unit cubes: min over the 15 SAT axes of (rA + rB - |d . L|); 0 if apart.
double cube_cube_penetration(const Cube& a, const Cube& b) {
  const Vec3 d = b.x - a.x;
  if (d.squaredNorm() >= 3.0) return 0.0;  // farther than the sum of the bounding radii
  double pen = 1e30;
  auto axis = [&](const Vec3& L) {
    const double rA = 0.5 * (a.R.transpose() * L).cwiseAbs().sum();
    const double rB = 0.5 * (b.R.transpose() * L).cwiseAbs().sum();
    pen = std::min(pen, rA + rB - std::fabs(d.dot(L)));
  };
  for (int i = 0; i < 3; ++i) axis(a.R.col(i));
  for (int i = 0; i < 3; ++i) axis(b.R.col(i));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec3 c = a.R.col(i).cross(b.R.col(j));
      const double n = c.norm();
      if (n > 1e-6) axis(c / n);
    }
  return std::max(0.0, pen);
}

// Lowest vertex of a unit cube: centre z minus half the sum of |R(2, :)|.
double lowest_vertex_z(const Cube& c) {
  return c.x.z() - 0.5 * c.R.row(2).cwiseAbs().sum();
}

double max_ground_penetration(const std::vector<Cube>& cubes) {
  double p = 0;
  for (const Cube& c : cubes) p = std::max(p, -lowest_vertex_z(c));
  return p;
}

// Sweep along x over cubes sorted by centre x: only pairs within sqrt(3) m are tested.
double max_cube_penetration(const std::vector<Cube>& cubes) {
  std::vector<int> order(cubes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return cubes[a].x.x() < cubes[b].x.x(); });
  double p = 0;
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size(); ++j) {
      const Cube &a = cubes[order[i]], &b = cubes[order[j]];
      if (b.x.x() - a.x.x() >= 1.7321) break;
      p = std::max(p, cube_cube_penetration(a, b));
    }
  return p;
}

struct Scene {
  const char* name;
  std::vector<BodyDef> defs;  // cubes first, ground last
  bool tower;
  double dt = kR3Dt;              // s
  long steps = kSteps;            // steps in a run
  double friction = kR3Friction;  // of every cube and the ground
  bool sleeping_rows = true;      // also the sleeping-on rows (simreel and Bullet)
  int alt_substeps = 0;           // > 0: also a simreel row with this many substeps (sleeping off)
  int cubes() const { return (int)defs.size() - 1; }
  // Cube-cube overlap checked every 0.1 s of simulated time.
  long sample_every() const { return std::max(1L, std::lround(0.1 / dt)); }
};

struct Result {
  double seconds = 0;
  double cpu_seconds = 0;  // thread CPU time of the same stepping calls
  long steps = 0;
  double max_speed = 0;
  int moving = 0;
  double pen_engine = 0, final_pen_engine = 0, pen_ground = 0, pen_cube = 0, final_pen_ground = 0;
  std::vector<double> all_seconds;  // every timed run, in order
  double top_drift = NAN, top_sink = NAN;
  double drift_late = NAN;   // largest cube displacement between the run's middle and its end, m
  double drift_total = NAN;  // largest cube displacement between the start and the end, m
  int nan = 0;
  std::string notes;
};

// Run-long geometric checks, fed the cubes' states after every step.
struct Tracker {
  const Scene& scene;
  Result& r;
  std::vector<Vec3> mid;  // cube centres at the run's middle step
  void sample(long step, const std::vector<Cube>& cubes) {
    r.pen_ground = std::max(r.pen_ground, max_ground_penetration(cubes));
    if (step % scene.sample_every() == 0 || step == scene.steps)
      r.pen_cube = std::max(r.pen_cube, max_cube_penetration(cubes));
    if (step == scene.steps / 2) {
      mid.resize(cubes.size());
      for (size_t i = 0; i < cubes.size(); ++i) mid[i] = cubes[i].x;
    }
  }
  void finish(const std::vector<Cube>& cubes) {
    for (const Cube& c : cubes) {
      if (!std::isfinite(c.x.norm()) || !std::isfinite(c.v.norm()) || !std::isfinite(c.R.norm())) r.nan++;
      const double s = c.v.norm();
      r.max_speed = std::max(r.max_speed, s);
      if (s > 0.01) r.moving++;
    }
    r.final_pen_ground = max_ground_penetration(cubes);
    if (mid.size() == cubes.size()) {
      r.drift_late = r.drift_total = 0;
      for (size_t i = 0; i < cubes.size(); ++i) {
        r.drift_late = std::max(r.drift_late, (cubes[i].x - mid[i]).norm());
        r.drift_total = std::max(r.drift_total, (cubes[i].x - scene.defs[i].p_WB).norm());
      }
    }
    if (scene.tower) {
      const Vec3 p0 = scene.defs[scene.cubes() - 1].p_WB, p = cubes.back().x;
      r.top_drift = (p - p0).head<2>().norm();
      r.top_sink = p0.z() - p.z();
    }
  }
};

void print_row(const char* engine, const Scene& s, const char* setting, const Result& r) {
  std::string runs;
  for (double t : r.all_seconds) {
    char b[32];
    std::snprintf(b, sizeof b, "%s%.3f", runs.empty() ? "" : " ", t);
    runs += b;
  }
  std::printf(
      "%s,%s,%s,%d,%ld,%.4g,%.4f,%.4f,%.1f,%s,%.4e,%d,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%.4e,%d,%s\n",
      engine, s.name, setting, s.cubes(), r.steps, s.dt, r.seconds, r.cpu_seconds, r.steps / r.seconds,
      runs.c_str(), r.max_speed, r.moving, r.pen_engine, r.final_pen_engine, r.pen_ground, r.pen_cube,
      r.final_pen_ground, r.top_drift, r.top_sink, r.drift_late, r.drift_total, r.nan, r.notes.c_str());
  std::fflush(stdout);
}

void simreel_cubes(const World& w, int n, std::vector<Cube>& out) {
  out.resize(n);
  for (int i = 0; i < n; ++i) out[i] = {w.centroid(i), w.linear_velocity(i), w.rotation(i)};
}

// Returns the final state hash; with `profile`, the run is profiled and not tracked.
uint64_t simreel_run(const Scene& s, bool profile, Result* r, Profile* prof, double* wall = nullptr,
                     bool sleep = false, int substeps = 0) {
  WorldConfig c;
  c.dt = s.dt;
  c.contacts.substeps = substeps;
  c.threads = 1;
  c.contacts.sleep = sleep;
  World w(c, s.defs);
  w.set_profiling(profile);
  std::vector<Cube> cubes;
  Tracker tr{s, *r, {}};
  double sec = 0, cpu = 0;
  for (long k = 1; k <= s.steps; ++k) {
    const double t0 = bench::now_s(), c0 = bench::thread_cpu_s();
    w.step();
    cpu += bench::thread_cpu_s() - c0;
    sec += bench::now_s() - t0;
    if (!profile) {
      simreel_cubes(w, s.cubes(), cubes);
      tr.sample(k, cubes);
    }
  }
  if (profile) {
    *prof = w.profile();
    *wall = sec;
    return state_hash(w);
  }
  simreel_cubes(w, s.cubes(), cubes);
  tr.finish(cubes);
  r->seconds = sec;
  r->cpu_seconds = cpu;
  r->steps = w.steps();
  r->pen_engine = w.contact_stats().max_penetration;
  w.impl().for_each_contact([r](const Contact& c) {  // the step's and the sleeping pairs'
    for (int j = 0; j < c.count; ++j)
      r->final_pen_engine = std::max(r->final_pen_engine, -c.points[j].separation);
  });
  const uint64_t h = state_hash(w);
  char buf[160];
  std::snprintf(buf, sizeof buf, "state hash %016" PRIx64 "; substeps %d; contacts_max %d; asleep at end %d",
                h, w.substeps(), w.contact_stats().contacts_max, w.sleeping_count());
  r->notes = buf;
  return h;
}

// The profiled re-run: per-stage seconds on stderr; its hash must equal the timed runs'.
void simreel_profile(const Scene& s, Result& r, uint64_t hash) {
  Result unused;
  Profile p;
  double wall = 0;
  const uint64_t h2 = simreel_run(s, true, &unused, &p, &wall);
  r.notes += h2 == hash ? "; profiled re-run: same hash" : "; profiled re-run: DIFFERENT HASH";
  double total = 0;
  for (int i = 0; i < (int)Stage::count; ++i) total += p.seconds[i];
  for (int i = 0; i < (int)Stage::count; ++i)
    std::fprintf(stderr, "simreel,%s,%s,%.4f,%.3f,%ld,%ld\n", s.name, to_string((Stage)i), p.seconds[i],
                 wall > 0 ? p.seconds[i] / wall : 0.0, p.runs[i], p.skipped[i]);
  std::fprintf(stderr, "simreel,%s,outside_stages,%.4f,%.3f,%ld,0\n", s.name, wall - total,
               wall > 0 ? (wall - total) / wall : 0.0, p.steps);
  std::fprintf(stderr, "simreel,%s,step_wall_total,%.4f,1,%ld,0\n", s.name, wall, p.steps);
  std::fprintf(stderr, "# simreel %s: %ld pairs, %ld contact points, %ld solver bodies over %ld steps\n",
               s.name, p.pairs, p.contact_points, p.solver_bodies, p.steps);
  std::fflush(stderr);
}

// ----------------------------------------------------------------------------------------- Bullet
#ifdef SIMREEL_BENCH_BULLET
using bench::PhasedWorld;

void bullet_run(const Scene& s, bool sleeping, Result& r, double phases[PhasedWorld::n]) {
  btDefaultCollisionConfiguration cfg;
  btCollisionDispatcher disp(&cfg);
  btDbvtBroadphase bp;
  btSequentialImpulseConstraintSolver solver;
  PhasedWorld world(&disp, &bp, &solver, &cfg);
  world.setGravity(btVector3(0, 0, -9.81));
  // Bullet combines frictions as the product f_a f_b (simreel: sqrt(f_a f_b)): sqrt(0.5) on every
  // body gives each pair 0.5, as the anchors set it. Restitution 0 on all.
  const double mu = std::sqrt(s.friction);
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0);
  btBoxShape cube(btVector3(0.5, 0.5, 0.5));  // default margin 0.04, inside the box
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  auto add = [&](btCollisionShape* shape, double mass, double I, const Vec3& p) {
    btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape, btVector3(I, I, I));
    ci.m_startWorldTransform = btTransform(btQuaternion::getIdentity(), btVector3(p.x(), p.y(), p.z()));
    ci.m_friction = mu;
    ci.m_restitution = 0;
    bodies.push_back(std::make_unique<btRigidBody>(ci));
    world.addRigidBody(bodies.back().get());
    if (!sleeping) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
  };
  // Ground first, then the cubes, in the anchors' order (Bullet's solver order follows it).
  add(&plane, 0.0, 0.0, Vec3::Zero());
  for (int i = 0; i < s.cubes(); ++i) add(&cube, 1.0, 1.0 / 6.0, s.defs[i].p_WB);

  r = Result{};
  Tracker tr{s, r, {}};
  std::vector<Cube> cubes(s.cubes());
  auto read = [&] {
    for (int i = 0; i < s.cubes(); ++i) {
      const btRigidBody* b = bodies[i + 1].get();
      const btTransform& T = b->getWorldTransform();
      const btVector3 o = T.getOrigin(), v = b->getLinearVelocity();
      cubes[i].x = Vec3(o.x(), o.y(), o.z());
      cubes[i].v = Vec3(v.x(), v.y(), v.z());
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) cubes[i].R(a, c) = T.getBasis()[a][c];
    }
  };
  int points = 0, points_max = 0;
  for (long k = 1; k <= s.steps; ++k) {
    const double t0 = bench::now_s(), c0 = bench::thread_cpu_s();
    world.stepSimulation(btScalar(s.dt), 0);  // maxSubSteps 0: exactly one internal step of dt
    r.cpu_seconds += bench::thread_cpu_s() - c0;
    r.seconds += bench::now_s() - t0;
    points = 0;
    for (int m = 0; m < disp.getNumManifolds(); ++m) {
      const btPersistentManifold* pm = disp.getManifoldByIndexInternal(m);
      for (int j = 0; j < pm->getNumContacts(); ++j)
        r.pen_engine = std::max(r.pen_engine, -(double)pm->getContactPoint(j).getDistance());
      points += pm->getNumContacts();
    }
    points_max = std::max(points_max, points);
    if (k == s.steps) {
      for (int m = 0; m < disp.getNumManifolds(); ++m) {
        const btPersistentManifold* pm = disp.getManifoldByIndexInternal(m);
        for (int j = 0; j < pm->getNumContacts(); ++j)
          r.final_pen_engine = std::max(r.final_pen_engine, -(double)pm->getContactPoint(j).getDistance());
      }
    }
    read();
    tr.sample(k, cubes);
  }
  r.steps = s.steps;
  tr.finish(cubes);
  int asleep = 0;
  for (int i = 0; i < s.cubes(); ++i) asleep += bodies[i + 1]->getActivationState() == ISLAND_SLEEPING;
  char buf[200];
  std::snprintf(
      buf, sizeof buf, "SI %d iterations; split impulse %d; asleep at end %d; contact points max %d",
      world.getSolverInfo().m_numIterations, world.getSolverInfo().m_splitImpulse, asleep, points_max);
  r.notes = buf;
  for (int i = 0; i < PhasedWorld::n; ++i) phases[i] = world.t[i];
  for (auto& b : bodies) world.removeRigidBody(b.get());
}

void print_bullet_phases(const Scene& s, const char* setting, const double* t) {
  static const char* const phase[] = {"predict_motion",    "collision_detection",  "islands",
                                      "solve_constraints", "integrate_transforms", "activation"};
  double total = 0;
  for (int i = 0; i < PhasedWorld::n; ++i) total += t[i];
  for (int i = 0; i < PhasedWorld::n; ++i)
    std::fprintf(stderr, "bullet_f64_%s,%s,%s,%.4f,%.3f,%ld,0\n", setting, s.name, phase[i], t[i],
                 total > 0 ? t[i] / total : 0.0, s.steps);
  std::fflush(stderr);
}
#endif

// Keeps the first run's metrics and the least time over the runs.
void merge(Result& best, const Result& r, int rep) {
  if (rep == 0) {
    best = r;
    best.all_seconds = {r.seconds};
    return;
  }
  best.all_seconds.push_back(r.seconds);
  best.seconds = std::min(best.seconds, r.seconds);
  best.cpu_seconds = std::min(best.cpu_seconds, r.cpu_seconds);
}

// Runs interleave (simreel, Bullet sleeping off, Bullet sleeping on) `repeats` times, so that the
// machine's load drifts over all engines alike; each row reports the least stepping time.
void run_scene(const Scene& s, int repeats) {
  Result sim, slept, alt;
  uint64_t alt_hash = 0;
  uint64_t hash = 0, slept_hash = 0;
  bool same = true, slept_same = true;
#ifdef SIMREEL_BENCH_BULLET
  Result bul[2];
  double phases[2][PhasedWorld::n] = {};
#endif
  for (int rep = 0; rep < repeats; ++rep) {
    Result r;
    const uint64_t h = simreel_run(s, false, &r, nullptr);
    if (rep == 0) hash = h;
    same = same && h == hash;
    merge(sim, r, rep);
    if (s.alt_substeps > 0) {
      Result ra;
      const uint64_t ha = simreel_run(s, false, &ra, nullptr, nullptr, false, s.alt_substeps);
      if (rep == 0) alt_hash = ha;
      if (ha != alt_hash) ra.notes += "; HASH DIFFERS BETWEEN RUNS";
      merge(alt, ra, rep);
    }
    if (s.sleeping_rows) {
      Result rs;
      const uint64_t hs = simreel_run(s, false, &rs, nullptr, nullptr, true);
      if (rep == 0) slept_hash = hs;
      slept_same = slept_same && hs == slept_hash;
      merge(slept, rs, rep);
    }
#ifdef SIMREEL_BENCH_BULLET
    for (int sl = 0; sl < (s.sleeping_rows ? 2 : 1); ++sl) {
      Result b;
      double t[PhasedWorld::n];
      bullet_run(s, sl == 1, b, t);
      merge(bul[sl], b, rep);
      if (rep == 0) std::copy(t, t + PhasedWorld::n, phases[sl]);
    }
#endif
  }
  if (repeats > 1) sim.notes += same ? "; same hash in every run" : "; HASH DIFFERS BETWEEN RUNS";
  if (repeats > 1) slept.notes += slept_same ? "; same hash in every run" : "; HASH DIFFERS BETWEEN RUNS";
  // The narrow phase's stand-in (sim/collision/narrow/dev_stub.cpp) has no box-box contact: say so in the
  // row when cubes end up inside each other, so that such a row is never read as the R3 figure.
  if (sim.pen_cube > 0.1) sim.notes += "; CUBES PASS THROUGH EACH OTHER (no box-box contact)";
  simreel_profile(s, sim, hash);
  print_row("simreel", s, "sleeping_off_1thread", sim);
  if (s.sleeping_rows) print_row("simreel", s, "sleeping_on_1thread", slept);
  if (s.alt_substeps > 0) {
    char setting[64];
    std::snprintf(setting, sizeof setting, "sleeping_off_1thread_%d_substeps", s.alt_substeps);
    print_row("simreel", s, setting, alt);
  }
#ifdef SIMREEL_BENCH_BULLET
  print_row("bullet_f64", s, "sleeping_off", bul[0]);
  if (s.sleeping_rows) print_row("bullet_f64", s, "sleeping_on", bul[1]);
  print_bullet_phases(s, "sleeping_off", phases[0]);
  if (s.sleeping_rows) print_bullet_phases(s, "sleeping_on", phases[1]);
#endif
}

}  // namespace

// usage: bench_r3_contacts [--repeats N] [scene...]
//   scenes: drop100 tower20 pile1000 pyramid100 (default: all four); N timed runs of each engine (default 3)
int main(int argc, char** argv) {
  std::vector<Scene> scenes;
  int repeats = 3;
  std::vector<std::string> names;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++i]));
    else
      names.push_back(argv[i]);
  }
  auto want = [&](const char* n) {
    return names.empty() || std::find(names.begin(), names.end(), n) != names.end();
  };
  if (want("drop100")) scenes.push_back({"drop100", r3_cube_grid_drop(), false});
  if (want("tower20")) scenes.push_back({"tower20", r3_tower(20), true});
  if (want("pile1000")) scenes.push_back({"pile1000", r3_pile(), false});
  if (want("pyramid100")) {
    // Box3D's large pyramid: 200 steps of 1/60 s (automatic substeps), sleeping off. "Tower" rows:
    // the top cube's drift and sink.
    Scene p{"pyramid100", r3_pyramid(100), true, kPyramidDt, kPyramidSteps, kPyramidFriction, false, 4};
    scenes.push_back(std::move(p));
  }
  std::printf(
      "engine,scene,setting,cubes,steps,dt_s,seconds,cpu_seconds,steps_per_s,seconds_each_run,max_speed_m_s,"
      "moving_gt_"
      "1cm_s,"
      "max_pen_engine_m,final_pen_engine_m,max_pen_ground_geom_m,max_pen_cube_geom_m,final_pen_ground_geom_m,"
      "top_drift_m,top_sink_m,drift_late_max_m,drift_total_max_m,nan,notes\n");
  std::fprintf(stderr, "engine,scene,stage,seconds,fraction,runs,skipped\n");
  for (const Scene& s : scenes) run_scene(s, repeats);
}
