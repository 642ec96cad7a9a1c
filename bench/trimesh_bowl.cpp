// 10,000 spheres poured into a static triangle-mesh bowl. Prints CSV on stdout: the
// step rate, the peak memory (resident set, from getrusage) before and after, and how many
// spheres escaped the bowl (through its surface or over its rim), plus the deepest overlap.
// Usage: bench_trimesh_bowl [SPHERES=10000] [SECONDS=3]
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bench/bench_util.hpp"
#include "sim/mass/primitives.hpp"
#include "sim/geometry/trimesh.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"
#include "tests/sim/collision/trimesh_fixtures.hpp"

using namespace simreel;

static double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 10000;
  const double seconds = argc > 2 ? std::atof(argv[2]) : 3.0;
  const double R = 2.0, r = 0.05, spacing = 0.12, pour_radius = 1.5;
  const int n_theta = 24, n_phi = 96;
  std::vector<BodyDef> bodies;
  bodies.push_back(trimesh_test::mesh_body(trimesh_test::bowl(R, n_theta, n_phi), 0.5));
  // Spheres on a grid inside a cylinder over the bowl, layer by layer from z = 0.85 m (above the bowl's
  // surface at the cylinder's edge, 0.68 m), each nudged by a fixed pseudo-random offset (no perfect
  // columns).
  uint64_t seed = 12345;
  auto jitter = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(seed >> 11) / (double)(1ull << 53) - 0.5) * 0.02;
  };
  const int m = (int)std::floor(pour_radius / spacing);
  for (int layer = 0; (int)bodies.size() <= n; ++layer)
    for (int i = -m; i <= m && (int)bodies.size() <= n; ++i)
      for (int j = -m; j <= m && (int)bodies.size() <= n; ++j) {
        const double x = i * spacing, y = j * spacing;
        if (std::hypot(x, y) > pour_radius) continue;
        BodyDef b;
        b.name = "s" + std::to_string(bodies.size());
        b.p_WB = Vec3(x + jitter(), y + jitter(), 0.85 + layer * spacing);
        Collider c;
        c.shape = ShapeKind::sphere;
        c.radius = r;
        c.props_C = sphere_mass(r, 1000);
        c.friction = 0.5;
        b.add_collider(c);
        bodies.push_back(std::move(b));
      }
  const double rss0 = peak_rss_mb();
  WorldConfig cfg;
  World w(cfg, std::move(bodies));
  const double rss1 = peak_rss_mb();
  const int steps = (int)std::lround(seconds / cfg.dt);
  w.set_profiling(true);
  const double t0 = bench::now_s();
  for (int k = 0; k < steps; ++k) w.step();
  const double wall = bench::now_s() - t0;
  const double rss2 = peak_rss_mb();
  int escaped = 0, above_rim = 0;
  const Vec3 centre(0, 0, R);
  for (int i = 1; i < w.body_count(); ++i) {
    const Vec3 c = w.centroid(i);
    // Through the surface (centre further than R - r from the bowl's centre, beyond 2 mm), off
    // the rim (outside the rim's circle), or below the bottom.
    const bool out =
        (c.z() < R && (c - centre).norm() > R - r + 2e-3) || std::hypot(c.x(), c.y()) > R || c.z() < 0;
    escaped += out;
    above_rim += c.z() > R;
  }
  const TriMeshShape& tm = *w.impl().shapes()[0].geom.mesh;
  std::printf(
      "name,spheres,triangles,steps,dt,sim_seconds,wall_seconds,steps_per_s,body_steps_per_s,rss_before_mb,"
      "rss_"
      "world_mb,rss_peak_mb,escaped,above_rim,sleeping,max_penetration_m,contacts_max\n");
  std::printf("bowl_pour,%d,%zu,%d,%.6f,%.3f,%.3f,%.3f,%.0f,%.1f,%.1f,%.1f,%d,%d,%d,%.6f,%d\n",
              w.body_count() - 1, tm.triangles.size(), steps, cfg.dt, seconds, wall, steps / wall,
              steps * (w.body_count() - 1) / wall, rss0, rss1, rss2, escaped, above_rim, w.sleeping_count(),
              w.contact_stats().max_penetration, w.contact_stats().contacts_max);
  // Where the time went (stderr: the CSV stays one table).
  const Profile& pf = w.profile();
  for (int s = 0; s < (int)Stage::count; ++s)
    if (pf.seconds[s] > 0) std::fprintf(stderr, "%s %.3f s\n", to_string((Stage)s), pf.seconds[s]);
  return escaped == 0 ? 0 : 1;
}
