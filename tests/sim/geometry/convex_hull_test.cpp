// Convex hulls (sim/geometry/convex_hull.hpp): adjacency checked by polyhedron_problem(), containment of
// every input point and mass properties checked exactly against rational references
// (tests/sim/geometry/hull_exact.hpp). Self-made inputs only; the real-mesh run is convex_hull_real_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <thread>

#include "sim/geometry/convex_hull.hpp"
#include <simreel/error.hpp>
#include "tests/sim/geometry/hull_exact.hpp"

namespace simreel {
namespace {

// Deterministic uniform doubles in [0, 1) on every platform (std:: distributions are not).
struct Rng {
  uint64_t s;
  double operator()() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(s >> 11) * 0x1p-53;
  }
};

std::vector<Vec3> random_ball(int n, uint64_t seed, const Vec3& centre = Vec3::Zero(), double r = 1) {
  Rng rng{seed};
  std::vector<Vec3> pts;
  while ((int)pts.size() < n) {
    const Vec3 p(2 * rng() - 1, 2 * rng() - 1, 2 * rng() - 1);
    if (p.squaredNorm() <= 1) pts.push_back(centre + r * p);
  }
  return pts;
}

double rel_err(const Mat3& a, const Mat3& b) {
  return (a - b).norm() / b.norm();
}

// Everything a hull must satisfy: a valid polyhedron; vertices that are input points; hull mode's
// double mass properties equal to the exact rational ones over the same triangles, and to those of
// the exact hull (built with exact predicates from the points near the surface), to 1e-12. With
// `contains`, also every input point inside or on every hull triangle's plane, exactly (not asked
// of near-coplanar input: qhull merges facets that are coplanar to rounding, and a sliver of a
// merged facet's fan may then have a point of the same facet a few ulps above its plane).
void expect_good_hull(const std::vector<Vec3>& pts, bool contains = true) {
  const ConvexPolyhedron p = convex_polyhedron(pts);
  // Offsets are absolute: far from the origin, planarity is only as good as |position| * ulp.
  double far = 0, size = 0;
  for (const Vec3& v : p.vertices)
    far = std::max(far, v.norm()), size = std::max(size, (v - p.centroid).norm());
  EXPECT_EQ(polyhedron_problem(p, 1e-9 * std::max(1.0, far / size)), "");
  const TriangleMesh h = convex_hull(pts);
  // Vertices are input points, unchanged.
  std::set<std::array<double, 3>> input;
  for (const Vec3& v : pts) input.insert({v.x(), v.y(), v.z()});
  for (const Vec3& v : p.vertices) EXPECT_TRUE(input.count({v.x(), v.y(), v.z()}));
  for (const Vec3& v : h.vertices) EXPECT_TRUE(input.count({v.x(), v.y(), v.z()}));

  if (contains) {
    const test::Containment c = test::hull_containment(h, pts);
    EXPECT_EQ(c.outside, 0) << "max height outside " << c.max_distance;
  }

  MeshMassOptions o;
  o.mode = MassMode::hull;
  o.density = 1.0;
  const MeshReport r = analyze_mesh(h, o);
  const test::ExactSolid ex = test::exact_solid(h);
  EXPECT_LT(std::fabs(r.volume - ex.volume) / ex.volume, 1e-12);
  EXPECT_LT((r.props.com - ex.centroid).norm() / size, 1e-12);
  EXPECT_LT(rel_err(r.props.inertia, ex.inertia), 1e-12);

  // The exact hull: points clearly inside the computed one (by 1e-9 of its size, far above its
  // rounding) cannot be on the exact hull, the rest go through exact_hull().
  std::vector<Vec3> near;
  for (const Vec3& v : pts) {
    double out = -INFINITY;
    for (const auto& f : p.faces) out = std::max(out, f.normal.dot(v) - f.offset);
    if (out > -1e-9 * size) near.push_back(v);
  }
  const test::ExactSolid exh = test::exact_solid(test::exact_hull(near));
  EXPECT_LT(std::fabs(r.volume - exh.volume) / exh.volume, 1e-12);
  EXPECT_LT((r.props.com - exh.centroid).norm() / size, 1e-12);
  EXPECT_LT(rel_err(r.props.inertia, exh.inertia), 1e-12);

  // The polyhedron's centroid is the same volume centroid; its inner radius the nearest face.
  EXPECT_LT((p.centroid - ex.centroid).norm() / size, 1e-12);
  double inner = INFINITY;
  for (const auto& f : p.faces) inner = std::min(inner, f.offset - f.normal.dot(ex.centroid));
  EXPECT_NEAR(p.inner_radius, inner, 1e-12 * std::max(size, far));
  EXPECT_GT(p.inner_radius, 0);
}

TEST(ConvexHull, BoxIsSixQuads) {
  // Corners, points on edges and faces (all exactly coplanar), and interior points.
  std::vector<Vec3> pts;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k <= 4; ++k) pts.push_back(Vec3(0.5 * i, 0.25 * j, 0.75 * k) + Vec3(3, -2, 1));
  const ConvexPolyhedron p = convex_polyhedron(pts);
  EXPECT_EQ(polyhedron_problem(p), "");
  EXPECT_EQ(p.vertices.size(), 8u);
  EXPECT_EQ(p.faces.size(), 6u);
  EXPECT_EQ(p.edge_count(), 12);
  for (const auto& f : p.faces) {
    EXPECT_NEAR(f.normal.cwiseAbs().maxCoeff(), 1.0, 1e-15);
    int n = 0, e = f.edge;
    do ++n, e = p.edges[e].next;
    while (e != f.edge);
    EXPECT_EQ(n, 4);
  }
  EXPECT_LT((p.centroid - Vec3(4, -1.5, 2.5)).norm(), 1e-14);
  EXPECT_NEAR(p.inner_radius, 0.5, 1e-14);
  const TriangleMesh h = convex_hull(pts);
  EXPECT_EQ(h.triangles.size(), 12u);
  const test::ExactSolid ex = test::exact_solid(h);
  EXPECT_EQ(ex.volume, 2.0 * 1.0 * 3.0);
  expect_good_hull(pts);
}

TEST(ConvexHull, RandomPointsInABall) {
  for (uint64_t seed : {1, 2, 3}) expect_good_hull(random_ball(3000, seed));
  // Far from the origin, small: precision must not depend on where the body is.
  expect_good_hull(random_ball(2000, 7, Vec3(1e5, -3e4, 2e5), 0.01));
}

TEST(ConvexHull, PointsOnASphere) {
  // Cospherical to rounding: every point is a hull vertex.
  Rng rng{11};
  std::vector<Vec3> pts;
  for (int i = 0; i < 4000; ++i) {
    const double z = 2 * rng() - 1, phi = 2 * std::numbers::pi * rng();
    const double s = std::sqrt(1 - z * z);
    pts.push_back(Vec3(s * std::cos(phi), s * std::sin(phi), z));
  }
  expect_good_hull(pts);
  EXPECT_EQ(convex_polyhedron(pts).vertices.size(), pts.size());
}

TEST(ConvexHull, ExactlyCosphericalAndCoplanarLatticePoints) {
  // Integer points with x^2 + y^2 + z^2 = 25^2 (exactly cospherical, many in common planes: the
  // six points (+-25, 0, 0)... and all the lattice circles), plus the lattice inside.
  std::vector<Vec3> pts;
  for (int x = -25; x <= 25; ++x)
    for (int y = -25; y <= 25; ++y)
      for (int z = -25; z <= 25; ++z) {
        const int r2 = x * x + y * y + z * z;
        if (r2 == 625 || (r2 < 400 && (x + y + z) % 5 == 0)) pts.push_back(Vec3(x, y, z));
      }
  expect_good_hull(pts);
}

TEST(ConvexHull, CylinderWithManyCoplanarCapPoints) {
  // Two caps of 240 points each on exact planes z = 0 and z = 1 (and rings of points inside
  // them): each cap is one 240-gon face.
  std::vector<Vec3> pts;
  for (int i = 0; i < 240; ++i) {
    const double t = 2 * std::numbers::pi * i / 240;
    for (double r : {1.0, 0.5, 0.25})
      for (double z : {0.0, 1.0}) pts.push_back(Vec3(r * std::cos(t), r * std::sin(t), z));
  }
  const ConvexPolyhedron p = convex_polyhedron(pts);
  EXPECT_EQ(polyhedron_problem(p), "");
  EXPECT_EQ(p.vertices.size(), 480u);
  EXPECT_EQ(p.faces.size(), 242u);
  expect_good_hull(pts);
}

// A CAD-like gear: a cycloidal disc profile sampled finely (long runs of nearly collinear points
// along its flanks), extruded, with points on the side walls, then turned and moved by a generic
// rigid motion, so the caps are coplanar only to rounding (how CAD exports write a tilted part),
// and some points nudged by a few ulps. This is the input that blew up the old hull.
std::vector<Vec3> cad_gear(int samples, int rings, uint64_t seed) {
  const double R = 1.0, e = 0.04, lobes = 11;  // disc radius, eccentricity, lobe count
  std::vector<Eigen::Vector2d> prof;
  for (int i = 0; i < samples; ++i) {
    const double t = 2 * std::numbers::pi * i / samples;
    // Epitrochoid-like cycloidal profile.
    const double x = R * std::cos(t) - e * std::cos((lobes + 1) * t);
    const double y = R * std::sin(t) - e * std::sin((lobes + 1) * t);
    prof.emplace_back(x, y);
  }
  const Mat3 rot =
      (Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()) * Eigen::AngleAxisd(0.06, Vec3::UnitX()))
          .toRotationMatrix();
  const Vec3 shift(1.2, 0.58, 1.31);
  Rng rng{seed};
  std::vector<Vec3> pts;
  for (int k = 0; k < rings; ++k) {
    const double z = 0.3 * k / (rings - 1);
    for (const auto& q : prof) {
      Vec3 v = rot * Vec3(q.x(), q.y(), z) + shift;
      if (rng() < 0.1)  // a few ulps of noise, as a CAD export's decimal round trip leaves
        for (int i = 0; i < 3; ++i) v[i] = std::nextafter(v[i], rng() < 0.5 ? -INFINITY : INFINITY);
      pts.push_back(v);
    }
  }
  // The centre bore's points (inside).
  for (int i = 0; i < 200; ++i) {
    const double t = 2 * std::numbers::pi * i / 200;
    for (double z : {0.0, 0.3}) pts.push_back(rot * Vec3(0.2 * std::cos(t), 0.2 * std::sin(t), z) + shift);
  }
  return pts;
}

TEST(ConvexHull, NearCoplanarCadGear) {
  const std::vector<Vec3> pts = cad_gear(600, 2, 5);
  const auto t0 = std::chrono::steady_clock::now();
  const ConvexPolyhedron p = convex_polyhedron(pts);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, 1.0);
  EXPECT_EQ(polyhedron_problem(p), "");
  expect_good_hull(pts, false);
}

TEST(ConvexHull, ManyPointsAreFastAndDeterministic) {
  const std::vector<Vec3> pts = random_ball(200000, 3);
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh a = convex_hull(pts);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, 3.0);
  const TriangleMesh b = convex_hull(pts);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(ConvexHull, ThreadSafe) {
  // Each call has its own qhull state: hulls on two threads at once equal the serial ones.
  const std::vector<Vec3> p1 = random_ball(20000, 21), p2 = cad_gear(2000, 2, 22);
  const TriangleMesh s1 = convex_hull(p1), s2 = convex_hull(p2);
  TriangleMesh t1, t2;
  std::thread th1([&] {
    for (int i = 0; i < 5; ++i) t1 = convex_hull(p1);
  });
  std::thread th2([&] {
    for (int i = 0; i < 5; ++i) t2 = convex_hull(p2);
  });
  th1.join();
  th2.join();
  EXPECT_EQ(s1.triangles, t1.triangles);
  EXPECT_EQ(s2.triangles, t2.triangles);
}

void expect_input_error(const std::vector<Vec3>& pts, const std::string& words) {
  try {
    (void)convex_polyhedron(pts);
    ADD_FAILURE() << "no InputError for " << words;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)convex_hull(pts), InputError);
}

TEST(ConvexHull, DegenerateInputIsAnInputError) {
  expect_input_error({}, "at least 4");
  expect_input_error({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, "at least 4");
  expect_input_error(std::vector<Vec3>(10, Vec3(1, 2, 3)), "coincide");
  std::vector<Vec3> line, plane, tilted;
  for (int i = 0; i < 50; ++i) line.push_back(Vec3(1, 2, 3) * (0.1 * i));
  expect_input_error(line, "line");
  for (int i = 0; i < 50; ++i) plane.push_back(Vec3(std::cos(i), std::sin(i * 1.3), 0));
  expect_input_error(plane, "plane");
  // Coplanar to rounding only (a tilted plane): an InputError either way, never a hull of nothing.
  const Mat3 rot = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (const Vec3& v : plane) tilted.push_back(rot * v + Vec3(0.1, 0.2, 0.3));
  EXPECT_THROW((void)convex_polyhedron(tilted), InputError);
  std::vector<Vec3> bad = random_ball(20, 1);
  bad[7].y() = NAN;
  expect_input_error(bad, "finite");
  bad[7].y() = INFINITY;
  expect_input_error(bad, "finite");
}

TEST(ConvexHull, NearlyFlatButValidSetsGiveAValidHullOrAnInputError) {
  // Thickness from 1e-6 down to 1e-16 of the size: never a crash, a hang or an invalid polyhedron
  // (convex_polyhedron() checks its result and throws rather than return a broken one); the hull's
  // triangles for mass properties are always given when qhull finds a volume.
  for (double th : {1e-6, 1e-9, 1e-12, 1e-14, 1e-16}) {
    std::vector<Vec3> pts = random_ball(500, 9);
    for (Vec3& v : pts) v.z() *= th;
    try {
      const ConvexPolyhedron p = convex_polyhedron(pts);
      // All rules but "no coplanar neighbours", which a thin rim can break (see convex_polyhedron()).
      const std::string bad = polyhedron_problem(p);
      if (bad.find("joins two coplanar faces") == std::string::npos) {
        EXPECT_EQ(bad, "") << "thickness " << th;
      }
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos) << e.what();
    }
    if (th >= 1e-12) {
      EXPECT_NO_THROW((void)convex_hull(pts));
    }
  }
}

}  // namespace
}  // namespace simreel
