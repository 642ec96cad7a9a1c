// Narrow-phase cost per call (sim/collide): CSV "case,ns_per_call,points_per_call" on stdout.
// Each case runs 1024 slightly different poses (seeded), 200 sweeps, minimum of 7 timed runs.
//   box_plane           a unit cube resting face-down on the ground (4 points)
//   box_box_resting     a cube resting on a cube, fresh cache every call (full SAT + clip)
//   box_box_cached      the same with the pair's cache kept between calls (as the world does)
//   box_box_separated   cubes 5 cm apart beyond a 1 cm margin, cache kept (early out)
//   box_box_separated_nocache  the same without the cache (full SAT to find the separating axis)
//   sphere_sphere, sphere_box, capsule_box_lying (2 points), hull_hull (two unit cubes given as
//   hulls: the general polyhedron path), cylinder_box (GJK, then EPA when overlapping)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "bench/bench_util.hpp"
#include "sim/collide/manifold.hpp"

using namespace simreel;

namespace {

struct Pair {
  Pose xa, xb;
  PairCache cache;
};

Mat3 small_rotation(std::mt19937_64& g, double eps) {
  std::uniform_real_distribution<double> U(-eps, eps);
  return Eigen::AngleAxisd(U(g), Vec3(U(g), U(g), 1).normalized()).toRotationMatrix();
}

void run_case(const char* name, const CollideShape& a, const CollideShape& b, const Vec3& offset, double spec,
              bool keep_cache, double rot_eps = 0.01, const Mat3& Rb0 = Mat3::Identity()) {
  // COLLIDE_BENCH_ONLY=name runs one case (for profiling).
  const char* only = std::getenv("COLLIDE_BENCH_ONLY");
  if (only && std::strcmp(only, name) != 0) return;
  std::mt19937_64 g(42);
  std::uniform_real_distribution<double> U(-1e-3, 1e-3);
  std::vector<Pair> pairs(1024);
  for (Pair& p : pairs) {
    p.xa.R = small_rotation(g, rot_eps);
    p.xa.p = Vec3(U(g), U(g), U(g));
    p.xb.R = small_rotation(g, rot_eps) * Rb0;
    p.xb.p = offset + Vec3(U(g), U(g), U(g));
  }
  long points = 0, calls = 0;
  Manifold m;
  const int sweeps = 200;
  const bench::Timing t = bench::time_runs(7, [&] {
    points = calls = 0;
    for (int s = 0; s < sweeps; ++s)
      for (Pair& p : pairs) {
        PairCache fresh;
        PairCache& c = keep_cache ? p.cache : fresh;
        points += collide(a, p.xa, b, p.xb, spec, c, m);
        ++calls;
      }
  });
  std::printf("%s,%.1f,%.2f\n", name, t.min * 1e9 / (double)calls, (double)points / (double)calls);
}

}  // namespace

int main() {
  CollideShape plane, cube, sph, cap, cyl, hull_cube;
  plane.kind = CollideKind::plane;
  const ConvexPolyhedron box_poly = make_box_polyhedron(Vec3::Constant(0.5));
  cube.kind = CollideKind::box;
  cube.half_extents = Vec3::Constant(0.5);
  cube.hull = &box_poly;
  cube.bounding_radius = 0.5 * std::sqrt(3.0);
  hull_cube = cube;
  hull_cube.kind = CollideKind::hull;
  sph.kind = CollideKind::sphere;
  sph.radius = 0.5;
  sph.bounding_radius = 0.5;
  cap.kind = CollideKind::capsule;
  cap.radius = 0.2;
  cap.half_length = 0.4;
  cap.bounding_radius = 0.6;
  cyl.kind = CollideKind::cylinder;
  cyl.radius = 0.3;
  cyl.half_length = 0.4;
  cyl.bounding_radius = 0.5;
  const double spec = 0.01;
  std::printf("case,ns_per_call,points_per_call\n");
  const Mat3 lie = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix();  // capsule axis along x
  run_case("box_plane", plane, cube, Vec3(0, 0, 0.499), spec, true);
  run_case("box_box_resting", cube, cube, Vec3(0.05, 0.02, 0.999), spec, false);
  run_case("box_box_cached", cube, cube, Vec3(0.05, 0.02, 0.999), spec, true);
  run_case("box_box_separated", cube, cube, Vec3(0.05, 0.02, 1.05), spec, true);
  run_case("box_box_separated_nocache", cube, cube, Vec3(0.05, 0.02, 1.05), spec, false);
  run_case("sphere_sphere", sph, sph, Vec3(0.3, 0.2, 0.9), spec, true);
  run_case("sphere_box", sph, cube, Vec3(0.3, 0.2, 0.99), spec, true);
  run_case("capsule_box_lying", cube, cap, Vec3(0.1, 0.0, 0.699), spec, true, 0.01, lie);
  run_case("hull_hull", hull_cube, hull_cube, Vec3(0.05, 0.02, 0.999), spec, true);
  run_case("cylinder_box", cube, cyl, Vec3(0.1, 0.0, 0.899), spec, true);
  return 0;
}
