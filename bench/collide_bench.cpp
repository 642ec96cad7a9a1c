// Narrow-phase cost per call (sim/collision/narrow): CSV "case,ns_per_call,points_per_call" on stdout.
// Each case runs 1024 slightly different poses (seeded), 200 sweeps (fewer for the detailed hulls),
// minimum of 7 timed runs.
//   box_plane           a unit cube resting face-down on the ground (4 points)
//   box_box_resting     a cube resting on a cube, fresh cache every call (full SAT + clip)
//   box_box_cached      the same with the pair's cache kept between calls (as the world does)
//   box_box_separated   cubes 5 cm apart beyond a 1 cm margin, cache kept (early out)
//   box_box_separated_nocache  the same without the cache (full SAT to find the separating axis)
//   sphere_sphere, sphere_box, capsule_box_lying (2 points), hull_hull (two unit cubes given as
//   hulls: the general polyhedron path), cylinder_box (GJK/EPA, then the rim against the face),
//   hull40_plane, box_hull40, hull40_hull40 (a 40-point mesh hull, ~76 faces, resting)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>
#include <vector>

#include "bench/bench_util.hpp"
#include "sim/collision/narrow/internal.hpp"
#include "sim/collision/narrow/manifold.hpp"
#include "sim/geometry/convex_hull.hpp"

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
              bool keep_cache, double rot_eps = 0.01, const Mat3& Rb0 = Mat3::Identity(), int sweeps = 200) {
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

// A hull of 40 random points on an ellipsoid (triangular faces) in ConvexPolyhedron form.
ConvexPolyhedron random_hull(uint64_t seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> N;
  std::vector<Vec3> pts;
  for (int i = 0; i < 40; ++i)
    pts.push_back(Vec3(N(g), N(g), N(g)).normalized().cwiseProduct(Vec3(0.5, 0.4, 0.3)));
  const TriangleMesh m = convex_hull(pts);
  ConvexPolyhedron p;
  std::vector<int> remap(m.vertices.size(), -1);
  std::map<std::pair<int, int>, int> he;
  for (const auto& t : m.triangles) {
    int L[3];
    for (int k = 0; k < 3; ++k) {
      if (remap[t[k]] < 0) remap[t[k]] = (int)p.vertices.size(), p.vertices.push_back(m.vertices[t[k]]);
      L[k] = remap[t[k]];
    }
    const int f = (int)p.faces.size();
    for (int k = 0; k < 3; ++k) {
      const int a = L[k], b = L[(k + 1) % 3];
      auto it = he.find({b, a});
      const int idx = it != he.end() ? (it->second ^ 1) : (int)p.edges.size();
      if (it == he.end()) p.edges.resize(p.edges.size() + 2);
      he[{a, b}] = idx;
      p.edges[idx].origin = a, p.edges[idx].twin = idx ^ 1, p.edges[idx].face = f;
    }
    for (int k = 0; k < 3; ++k)
      p.edges[he[{L[k], L[(k + 1) % 3]}]].next = he[{L[(k + 1) % 3], L[(k + 2) % 3]}];
    ConvexPolyhedron::Face face;
    const Vec3 &a = p.vertices[L[0]], &b = p.vertices[L[1]], &c = p.vertices[L[2]];
    face.normal = (b - a).cross(c - a).normalized();
    face.offset = face.normal.dot(a);
    face.edge = he[{L[0], L[1]}];
    p.faces.push_back(face);
  }
  for (const Vec3& v : p.vertices) p.centroid += v / (double)p.vertices.size();
  p.inner_radius = INFINITY;
  for (const auto& f : p.faces)
    p.inner_radius = std::min(p.inner_radius, f.offset - f.normal.dot(p.centroid));
  p.build_adjacency();
  return p;
}

// The height at which a copy of `s` offset by (0.05, 0.02) above `s` touches it: bisection on
// GJK's overlap from [0, above].
double touching_height(const CollideShape& s, double above) {
  double lo = 0, hi = above;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    Pose xa, xb;
    xb.p = Vec3(0.05, 0.02, mid);
    bool ov;
    collide_detail::gjk_distance(collide_detail::Support(s, xa), collide_detail::Support(s, xb), ov);
    (ov ? lo : hi) = mid;
  }
  return hi;
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
  // A 40-point mesh hull (about 76 faces) resting with its lowest vertex 1 mm into the ground and
  // into a unit cube's top face.
  const ConvexPolyhedron rh = random_hull(1);
  CollideShape mesh;
  mesh.kind = CollideKind::hull;
  mesh.hull = &rh;
  mesh.bounding_radius = 0.5;
  const double low = -rh.vertices[rh.support(-Vec3::UnitZ())].z();
  const double high = rh.vertices[rh.support(Vec3::UnitZ())].z();
  run_case("hull40_plane", plane, mesh, Vec3(0, 0, low - 0.001), spec, true, 1e-4);
  run_case("box_hull40", cube, mesh, Vec3(0.1, 0.0, 0.5 + low - 0.001), spec, true, 1e-4);
  // Two of them stacked, 1 mm deeper than touching.
  run_case("hull40_hull40", mesh, mesh, Vec3(0.05, 0.02, touching_height(mesh, high + low + 0.1) - 0.001),
           spec, true, 1e-4);
  // Detailed meshes: 3,000 points on an ellipsoid (every one an extreme point, as on a scanned
  // smooth part), the full hull and the hull capped at 256 and 64 vertices, resting on the ground
  // and on one another (cache kept, as the world does).
  {
    std::mt19937_64 g(5);
    std::normal_distribution<double> N;
    std::vector<Vec3> pts;
    for (int i = 0; i < 3000; ++i)
      pts.push_back(Vec3(N(g), N(g), N(g)).normalized().cwiseProduct(Vec3(0.5, 0.4, 0.3)));
    for (int cap : {0, 256, 64}) {
      HullReduction red;
      const ConvexPolyhedron big = convex_polyhedron(pts, cap, &red);
      CollideShape hs;
      hs.kind = CollideKind::hull;
      hs.hull = &big;
      hs.bounding_radius = 0.5;
      const double lo3 = -big.vertices[big.support(-Vec3::UnitZ())].z();
      const double hi3 = big.vertices[big.support(Vec3::UnitZ())].z();
      char name[64];
      std::snprintf(name, sizeof name, "hull3000cap%d_plane", cap);
      std::fprintf(stderr, "# cap %d: %d vertices, %zu faces, volume %.4f of the full hull's\n", cap,
                   red.vertices, big.faces.size(), red.volume_ratio);
      const int sw = cap == 0 ? 2 : cap == 256 ? 20 : 200;
      run_case(name, plane, hs, Vec3(0, 0, lo3 - 0.001), spec, true, 1e-4, Mat3::Identity(), sw);
      const double h = touching_height(hs, hi3 + lo3 + 0.1);
      std::snprintf(name, sizeof name, "hull3000cap%d_hull3000cap%d", cap, cap);
      run_case(name, hs, hs, Vec3(0.05, 0.02, h - 0.001), spec, true, 1e-4, Mat3::Identity(), sw);
    }
  }
  return 0;
}
