// What continuous collision costs (docs/continuous-collision.md): the same scene
// stepped with `contacts.continuous` on and off, runs interleaved, the least of N each.
//   pile1000: the R3 pile (1000 unit cubes dropped on the ground, 1/240 s, 10 s), sleeping off:
//             nothing moves half a cube in a step, so the stage only copies poses and tests each
//             body once per step;
//   bullets:  200 steel spheres (5 cm) flagged `bullet`, fired at 60..120 m/s in volleys at a
//             static 1 cm wall with twenty free 1 cm plates hanging in front of it, 1/240 s, 1 s:
//             every sphere is swept in every step it flies.
//   bullets200_mesh: the same with the wall a closed triangle mesh (10 cm cells, 3,440 triangles)
//             and the ground a flat mesh (8 x 8 m, 10 cm cells, 12,800 triangles) instead of the
//             box and the plane: the sweep against static meshes (sim/collision/time_of_impact.hpp, mesh_time_of_impact).
// stdout: CSV
// scene,continuous,steps,seconds,us_per_step,swept_bodies,toi_pairs,toi_hits,passed_through,state_hash usage:
// bench_ccd_cost [--repeats N]
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include "bench/bench_util.hpp"
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"
#include "tests/sim/collision/trimesh_fixtures.hpp"

using namespace simreel;

namespace {

BodyDef box(const Vec3& size, const Vec3& at, double density, BodyType type) {
  BodyDef b;
  b.name = "box";
  b.type = type;
  b.p_WB = at;
  Collider c;
  c.shape = ShapeKind::box;
  c.size = size;
  c.props_C = box_mass(size, density);
  b.add_collider(c);
  return b;
}

std::vector<BodyDef> bullets_scene(bool meshes = false) {
  std::vector<BodyDef> bodies;
  if (meshes) {
    const int n[3] = {1, 40, 20};
    bodies.push_back(trimesh_test::mesh_body(trimesh_test::cuboid(Vec3(0.005, 2, 1), n), 0.6,
                                             Quat::Identity(), Vec3(2, 0, 1)));
  } else {
    bodies.push_back(box(Vec3(0.01, 4, 2), Vec3(2, 0, 1), 2700, BodyType::static_body));
  }
  for (int k = 0; k < 20; ++k)
    bodies.push_back(
        box(Vec3(0.01, 0.3, 0.3), Vec3(1.5, -1.9 + 0.2 * k, 0.4 + 0.06 * k), 2700, BodyType::dynamic));
  SplitMix64 rng(2024);
  for (int k = 0; k < 200; ++k) {
    BodyDef b;
    b.name = "bullet";
    b.bullet = true;
    b.p_WB = Vec3(-1.0 - 0.5 * (k / 20) - rng.uniform(0, 0.3), rng.uniform(-1.8, 1.8), rng.uniform(0.3, 1.7));
    b.v_W = Vec3(rng.uniform(60, 120), rng.uniform(-5, 5), rng.uniform(-2, 2));
    Collider c;
    c.shape = ShapeKind::sphere;
    c.radius = 0.025;
    c.props_C = sphere_mass(0.025, 7800);
    b.add_collider(c);
    bodies.push_back(b);
  }
  if (meshes) {
    bodies.push_back(trimesh_test::mesh_body(trimesh_test::grid(80, 80, 0.1, -4, -4)));
    return bodies;
  }
  BodyDef g;
  g.name = "ground";
  g.type = BodyType::static_body;
  Collider p;
  p.shape = ShapeKind::plane;
  p.props_C.mass = 0;
  p.props_C.com = Vec3::Zero();
  p.props_C.inertia = Mat3::Zero();
  g.add_collider(p);
  bodies.push_back(g);
  return bodies;
}

struct Run {
  double seconds = std::numeric_limits<double>::infinity();
  long steps = 0, swept = 0, pairs = 0, hits = 0;
  int through = 0;
  uint64_t hash = 0;
};

Run run(const std::vector<BodyDef>& bodies, double dt, long steps, bool continuous, bool bullets) {
  WorldConfig c;
  c.dt = dt;
  c.contacts.sleep = false;
  c.contacts.continuous = continuous;
  World w(c, bodies);
  w.set_profiling(true);  // counters only; the stage timers are read by nobody here
  Run r;
  double sec = 0;
  std::vector<Vec3> before(w.body_count());
  for (int i = 0; i < w.body_count(); ++i) before[i] = w.centroid(i);
  for (long k = 0; k < steps; ++k) {
    const double t0 = bench::now_s();
    w.step();
    sec += bench::now_s() - t0;
    if (!bullets) continue;
    // Through the wall: a bullet's centre crossed its mid-plane x = 2 within its face.
    for (int i = 0; i < w.body_count(); ++i) {
      const Vec3 a = before[i], b = w.centroid(i);
      before[i] = b;
      if (!w.def(i).bullet || !(a.x() <= 2.0 && b.x() > 2.0)) continue;
      const Vec3 c = a + (2.0 - a.x()) / (b.x() - a.x()) * (b - a);
      r.through += std::fabs(c.y()) < 2.0 && c.z() > 0.0 && c.z() < 2.0;
    }
  }
  r.seconds = sec;
  r.steps = steps;
  r.swept = w.profile().swept_bodies;
  r.pairs = w.profile().toi_pairs;
  r.hits = w.profile().toi_hits;
  r.hash = state_hash(w);
  return r;
}

void row(const char* scene, bool continuous, const Run& r) {
  std::printf("%s,%s,%ld,%.4f,%.2f,%ld,%ld,%ld,%d,%016" PRIx64 "\n", scene, continuous ? "on" : "off",
              r.steps, r.seconds, 1e6 * r.seconds / r.steps, r.swept, r.pairs, r.hits, r.through, r.hash);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
  std::printf(
      "scene,continuous,steps,seconds,us_per_step,swept_bodies,toi_pairs,toi_hits,passed_through,state_"
      "hash\n");
  struct Case {
    const char* name;
    std::vector<BodyDef> bodies;
    double dt;
    long steps;
    bool bullets;
  };
  const Case cases[] = {{"pile1000", r3_pile(), kR3Dt, (long)std::lround(kR3Duration / kR3Dt), false},
                        {"bullets200", bullets_scene(), 1.0 / 240.0, 240, true},
                        {"bullets200_mesh", bullets_scene(true), 1.0 / 240.0, 240, true}};
  for (const Case& cs : cases) {
    Run best[2];
    for (int rep = 0; rep < repeats; ++rep)
      for (int on = 1; on >= 0; --on) {
        const Run r = run(cs.bodies, cs.dt, cs.steps, on == 1, cs.bullets);
        if (r.seconds < best[on].seconds) best[on] = r;
      }
    row(cs.name, true, best[1]);
    row(cs.name, false, best[0]);
    std::fflush(stdout);
  }
}
