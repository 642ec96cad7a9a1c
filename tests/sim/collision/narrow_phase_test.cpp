// Narrow phase (sim/collision/narrow) against closed forms. Tolerances: the closed-form pairs (plane,
// sphere, capsule, box clipping) are exact up to rounding of a few dozen operations on O(1)
// numbers: 1e-12. GJK on curved shapes stops at a relative gap of 1e-12 in |v|^2, so distances are
// good to ~1e-6 relative at worst (1e-9 typical); EPA stops when the support gains <= 1e-9 * size.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <new>
#include <random>

#include "sim/collision/narrow/internal.hpp"
#include "sim/collision/narrow/manifold.hpp"
#include "sim/collision/narrow/mesh.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "sim/geometry/trimesh.hpp"
#include "tests/sim/collision/collide_shapes.hpp"
#include "tests/sim/collision/trimesh_fixtures.hpp"

// Counts heap allocations in this test binary (to check that collide() never allocates). GCC
// flags free() on memory from operator new even when operator new is this malloc wrapper.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
static std::atomic<long> g_allocations{0};
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
// The nothrow forms too (std::get_temporary_buffer, behind std::stable_partition and
// std::stable_sort, allocates through them): replaced and counted like the others, else their
// memory came from the runtime's operator new and went back through the free() above
// (AddressSanitizer: alloc-dealloc-mismatch), and their allocations went uncounted.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace simreel {
namespace {

constexpr double kExact = 1e-12;
constexpr double kPi = 3.14159265358979323846;
using namespace collide_shapes;

// A polyhedron from vertices and face loops (counter-clockwise seen from outside).
ConvexPolyhedron make_polyhedron(const std::vector<Vec3>& v, const std::vector<std::vector<int>>& loops) {
  ConvexPolyhedron p;
  p.vertices = v;
  std::map<std::pair<int, int>, int> he;
  for (int f = 0; f < (int)loops.size(); ++f) {
    const auto& L = loops[f];
    const int n = (int)L.size();
    for (int k = 0; k < n; ++k) {
      const int a = L[k], b = L[(k + 1) % n];
      int idx;
      auto it = he.find({b, a});
      if (it != he.end()) {
        idx = it->second ^ 1;
      } else {
        idx = (int)p.edges.size();
        p.edges.resize(p.edges.size() + 2);
      }
      he[{a, b}] = idx;
      p.edges[idx].origin = a;
      p.edges[idx].twin = idx ^ 1;
      p.edges[idx].face = f;
    }
    for (int k = 0; k < n; ++k)
      p.edges[he[{L[k], L[(k + 1) % n]}]].next = he[{L[(k + 1) % n], L[(k + 2) % n]}];
    ConvexPolyhedron::Face face;
    face.normal = (v[L[1]] - v[L[0]]).cross(v[L[2]] - v[L[0]]).normalized();
    face.offset = face.normal.dot(v[L[0]]);
    face.edge = he[{L[0], L[1]}];
    p.faces.push_back(face);
  }
  Vec3 c = Vec3::Zero();
  for (const Vec3& x : v) c += x;
  p.centroid = c / (double)v.size();  // the vertex mean is the volume centroid for these shapes
  p.inner_radius = INFINITY;
  for (const auto& f : p.faces)
    p.inner_radius = std::min(p.inner_radius, f.offset - f.normal.dot(p.centroid));
  p.build_adjacency();
  return p;
}

ConvexPolyhedron octahedron(double r) {
  std::vector<Vec3> v = {Vec3(r, 0, 0),  Vec3(-r, 0, 0), Vec3(0, r, 0),
                         Vec3(0, -r, 0), Vec3(0, 0, r),  Vec3(0, 0, -r)};
  std::vector<std::vector<int>> loops;
  for (int sx : {1, -1})
    for (int sy : {1, -1})
      for (int sz : {1, -1}) {
        const int X = sx > 0 ? 0 : 1, Y = sy > 0 ? 2 : 3, Z = sz > 0 ? 4 : 5;
        if (sx * sy * sz > 0)
          loops.push_back({X, Y, Z});
        else
          loops.push_back({X, Z, Y});
      }
  return make_polyhedron(v, loops);
}

// The corner tetrahedron scaled by s, its centroid moved to the origin.
ConvexPolyhedron tetrahedron(double s) {
  const Vec3 c = Vec3::Constant(s / 4);
  std::vector<Vec3> v = {Vec3(0, 0, 0) - c, Vec3(s, 0, 0) - c, Vec3(0, s, 0) - c, Vec3(0, 0, s) - c};
  return make_polyhedron(v, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
}

// A right prism over a regular n-gon of circumradius r, height 2 hz (faces with n vertices).
ConvexPolyhedron prism(int n, double r, double hz) {
  std::vector<Vec3> v;
  for (int k = 0; k < n; ++k)
    v.push_back(Vec3(r * std::cos(2 * kPi * k / n), r * std::sin(2 * kPi * k / n), -hz));
  for (int k = 0; k < n; ++k)
    v.push_back(Vec3(r * std::cos(2 * kPi * k / n), r * std::sin(2 * kPi * k / n), hz));
  std::vector<std::vector<int>> loops;
  std::vector<int> bottom, top;
  for (int k = 0; k < n; ++k) bottom.push_back(n - 1 - k), top.push_back(n + k);
  loops.push_back(bottom);
  loops.push_back(top);
  for (int k = 0; k < n; ++k) loops.push_back({k, (k + 1) % n, n + (k + 1) % n, n + k});
  return make_polyhedron(v, loops);
}

Pose pose(const Vec3& p, const Mat3& R = Mat3::Identity()) {
  Pose x;
  x.R = R;
  x.p = p;
  return x;
}
Mat3 rot(double angle, const Vec3& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Manifold run(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb,
             double spec = 0.0) {
  PairCache cache;
  Manifold m;
  collide(a, xa, b, xb, spec, cache, m);
  return m;
}

// Index of the manifold point nearest to p.
int nearest(const Manifold& m, const Vec3& p) {
  int k = -1;
  double best = INFINITY;
  for (int i = 0; i < m.count; ++i)
    if ((m.points[i].p_W - p).norm() < best) best = (m.points[i].p_W - p).norm(), k = i;
  return k;
}
// Every expected point is in the manifold (within tol) with the given separation.
void expect_points(const Manifold& m, const std::vector<Vec3>& pts, double sep, double tol) {
  ASSERT_EQ(m.count, (int)pts.size());
  for (const Vec3& p : pts) {
    const int k = nearest(m, p);
    EXPECT_LT((m.points[k].p_W - p).norm(), tol) << p.transpose();
    EXPECT_NEAR(m.points[k].separation, sep, tol);
  }
}

// ---------------------------------------------------------------- plane pairs

TEST(Collide, SphereOnPlaneIsExact) {
  const Pose xg = pose(Vec3(0, 0, 0.25), rot(0.3, Vec3(1, 2, 0)));
  const Vec3 n = xg.R.col(2);
  const Vec3 c = xg.p + 0.49 * n + Vec3(0.3, -0.2, 0.1).cross(n);
  const Manifold m = run(plane(), xg, sphere(0.5), pose(c));
  ASSERT_EQ(m.count, 1);
  EXPECT_LT((m.normal_W - n).norm(), kExact);
  EXPECT_NEAR(m.points[0].separation, -0.01, kExact);
  EXPECT_LT((m.points[0].p_W - (c - 0.495 * n)).norm(), kExact);
  // Reversed order: same point, normal negated.
  const Manifold r = run(sphere(0.5), pose(c), plane(), xg);
  ASSERT_EQ(r.count, 1);
  EXPECT_EQ(r.normal_W, Vec3(-m.normal_W));
  EXPECT_EQ(r.points[0].p_W, m.points[0].p_W);
}

TEST(Collide, EllipsoidOnTiltedPlaneMatchesClosedForm) {
  // The support of an ellipsoid R diag(r) S^2 along -n is at distance h = |diag(r) R^T n| from
  // its centre; the touching point x has the outward normal n there: grad of x^T A^-1 x, A = R
  // diag(r^2) R^T, is parallel to -n. Both checked independently of the code's formula.
  const Vec3 r(0.3, 0.5, 0.8);
  const Mat3 Re = rot(0.7, Vec3(1, -1, 2));
  const Pose xg = pose(Vec3(0.1, 0.2, -0.3), rot(0.4, Vec3(0, 1, 0)));
  const Vec3 n = xg.R.col(2);
  const double h = r.cwiseProduct(Re.transpose() * n).norm();
  const Vec3 c = xg.p + (h - 0.02) * n + Vec3(0.5, 0.5, 0).cross(n);
  const Manifold m = run(plane(), xg, ellipsoid(r), pose(c, Re));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.02, kExact);
  const Vec3 x = m.points[0].p_W - 0.01 * n - c;  // B's (the ellipsoid's) surface point: midpoint + (s/2) n
  const Vec3 xl = Re.transpose() * x;
  EXPECT_NEAR(xl.cwiseQuotient(r).squaredNorm(), 1.0, kExact);  // on the surface
  const Vec3 grad = Re * xl.cwiseQuotient(r.cwiseProduct(r));
  EXPECT_LT(grad.normalized().cross(-n).norm(), kExact);  // outward normal is -n
  EXPECT_LT(grad.dot(n), 0);
}

TEST(Collide, TiltedCylinderTouchesAtItsRim) {
  const double r = 0.3, hl = 0.5, th = 0.4;
  const Mat3 R = rot(th, Vec3::UnitX());  // axis a = (0, -sin th, cos th)
  const Vec3 c(0.2, 0.1, hl * std::cos(th) + r * std::sin(th) - 0.003);
  const Manifold m = run(plane(), pose(Vec3::Zero()), cylinder(r, hl), pose(c, R), 0.0);
  ASSERT_EQ(m.count, 1);
  const Vec3 x = c + Vec3(0, hl * std::sin(th) - r * std::cos(th), -hl * std::cos(th) - r * std::sin(th));
  EXPECT_NEAR(m.points[0].separation, -0.003, kExact);
  EXPECT_LT((m.points[0].p_W - (x + Vec3(0, 0, 0.0015))).norm(), kExact);
}

TEST(Collide, StandingCylinderRestsOnFourRimPoints) {
  const Manifold m = run(plane(), pose(Vec3::Zero()), cylinder(0.3, 0.5), pose(Vec3(0, 0, 0.499)), 0.0);
  ASSERT_EQ(m.count, 4);
  double area = 0;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].separation, -0.001, kExact);
    EXPECT_NEAR(std::hypot(m.points[i].p_W.x(), m.points[i].p_W.y()), 0.3, kExact);
    const Vec3 a = m.points[i].p_W, b = m.points[(i + 1) % 4].p_W;
    area += a.x() * b.y() - a.y() * b.x();
  }
  (void)area;
  // A square inscribed in the rim: the four points are pairwise 0.3 sqrt(2) or 0.6 apart.
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double d = (m.points[i].p_W - m.points[j].p_W).norm();
      EXPECT_TRUE(std::fabs(d - 0.3 * std::sqrt(2.0)) < 1e-12 || std::fabs(d - 0.6) < 1e-12) << d;
    }
}

TEST(Collide, CapsuleOnPlaneTouchesWithBothEnds) {
  const Mat3 R = rot(kPi / 2, Vec3::UnitY());
  const Manifold m = run(plane(), pose(Vec3::Zero()), capsule(0.1, 0.4), pose(Vec3(0, 0, 0.099), R));
  expect_points(m, {Vec3(-0.4, 0, -0.0005), Vec3(0.4, 0, -0.0005)}, -0.001, kExact);
}

TEST(Collide, BoxFaceDownOnPlaneGivesItsFourCorners) {
  const Vec3 h(0.5, 0.3, 0.2);
  const Manifold m = run(plane(), pose(Vec3::Zero()), box(h), pose(Vec3(1, 2, 0.19)), 0.005);
  std::vector<Vec3> pts;
  for (int i = 0; i < 4; ++i)
    pts.push_back(Vec3(1 + ((i & 1) ? 0.5 : -0.5), 2 + ((i & 2) ? 0.3 : -0.3), -0.005));
  expect_points(m, pts, -0.01, kExact);
  for (int i = 0; i < m.count; ++i) EXPECT_LT(m.points[i].id, 4u);  // the bottom vertices 0..3
}

TEST(Collide, HullOnPlaneKeepsFourOfItsVertices) {
  // An octahedron resting on a face has three vertices on the plane.
  const ConvexPolyhedron o = octahedron(1.0);
  const Vec3 nf = Vec3(1, 1, 1).normalized();
  const Mat3 R =
      Eigen::Quaterniond::FromTwoVectors(-nf, -Vec3::UnitZ()).toRotationMatrix();  // face (+,+,+) down
  // Face offset of the unit octahedron: 1/sqrt(3).
  const Manifold m =
      run(plane(), pose(Vec3::Zero()), hull(o), pose(Vec3(0, 0, 1 / std::sqrt(3.0) - 0.01), R), 0.0);
  ASSERT_EQ(m.count, 3);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.points[i].separation, -0.01, kExact);
}

// ---------------------------------------------------------------- round pairs

TEST(Collide, SpheresAndCapsules) {
  Manifold m = run(sphere(0.5), pose(Vec3::Zero()), sphere(0.25), pose(Vec3(0.3, 0.4, 0)));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.25, kExact);
  EXPECT_LT((m.normal_W - Vec3(0.6, 0.8, 0)).norm(), kExact);
  // Crossed capsules: closest points of the axes.
  const Mat3 Rx = rot(kPi / 2, Vec3::UnitY());
  m = run(capsule(0.1, 1), pose(Vec3::Zero(), Rx), capsule(0.2, 1), pose(Vec3(0.3, 0.2, 0.25)));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, 0.2 - 0.3, kExact);  // axes 0.2 apart at x = 0.3, z = 0
  // Parallel capsules side by side: two points at the ends of the overlap.
  m = run(capsule(0.1, 1), pose(Vec3::Zero(), Rx), capsule(0.1, 1), pose(Vec3(0.5, 0, 0.19), Rx));
  expect_points(m, {Vec3(-0.5, 0, 0.095), Vec3(1, 0, 0.095)}, -0.01, kExact);
  // Sphere against a capsule's side.
  m = run(sphere(0.2), pose(Vec3(0.3, 0, 0.25)), capsule(0.1, 1), pose(Vec3::Zero(), Rx));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.05, kExact);
  EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), kExact);
}

TEST(Collide, SphereAgainstBoxOutsideAndInside) {
  const CollideShape b = box(Vec3(1, 0.5, 0.25));
  const Mat3 R = rot(0.3, Vec3(1, 1, 1));
  const Pose xb = pose(Vec3(0.1, 0.2, 0.3), R);
  // Near the corner (+,+,+): distance to the corner.
  const Vec3 corner = xb.apply(Vec3(1, 0.5, 0.25));
  const Vec3 dir = R * Vec3(1, 2, 3).normalized();
  Manifold m = run(sphere(0.1), pose(corner + 0.15 * dir), b, xb, 0.1);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, 0.05, kExact);
  EXPECT_LT((m.normal_W + dir).norm(), kExact);
  // Centre inside, nearest face +x at 0.05: depth 0.05 + r.
  m = run(sphere(0.1), pose(xb.apply(Vec3(0.95, 0.1, 0))), b, xb);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.15, kExact);
  EXPECT_LT((m.normal_W + R.col(0)).norm(), kExact);
  // The same as a hull: the same answer.
  const CollideShape h = hull(make_box_polyhedron(Vec3(1, 0.5, 0.25)));
  const Manifold mh = run(sphere(0.1), pose(xb.apply(Vec3(0.95, 0.1, 0))), h, xb);
  ASSERT_EQ(mh.count, 1);
  EXPECT_NEAR(mh.points[0].separation, -0.15, kExact);
  EXPECT_LT((mh.points[0].p_W - m.points[0].p_W).norm(), kExact);
}

// ---------------------------------------------------------------- box and hull pairs

TEST(Collide, BoxOnBoxAlignedRotatedAndOffset) {
  const CollideShape big = box(Vec3(2, 2, 0.5)), cube = box(Vec3::Constant(0.5));
  const Pose xa = pose(Vec3::Zero());
  // Aligned, 1 cm deep.
  Manifold m = run(big, xa, cube, pose(Vec3(0.2, 0.1, 0.99)));
  std::vector<Vec3> pts;
  for (int i = 0; i < 4; ++i)
    pts.push_back(Vec3(0.2 + ((i & 1) ? 0.5 : -0.5), 0.1 + ((i & 2) ? 0.5 : -0.5), 0.495));
  expect_points(m, pts, -0.01, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  // Rotated 45 degrees about z.
  const Mat3 R = rot(kPi / 4, Vec3::UnitZ());
  m = run(big, xa, cube, pose(Vec3(0, 0, 0.99), R));
  pts.clear();
  for (int i = 0; i < 4; ++i)
    pts.push_back(R * Vec3((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, 0) + Vec3(0, 0, 0.495));
  expect_points(m, pts, -0.01, kExact);
  // Overhanging the edge x = 2: clipped at x = 2.
  m = run(big, xa, cube, pose(Vec3(1.8, 0, 0.99)));
  expect_points(m, {Vec3(1.3, -0.5, 0.495), Vec3(1.3, 0.5, 0.495), Vec3(2, -0.5, 0.495), Vec3(2, 0.5, 0.495)},
                -0.01, kExact);
  // Equal cubes stacked, upper one on top: normal from A (lower) to B (upper) is +z.
  m = run(cube, xa, cube, pose(Vec3(0.05, 0, 0.98)));
  ASSERT_EQ(m.count, 4);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.points[i].separation, -0.02, kExact);
}

TEST(Collide, CrossedBoxesTouchEdgeToEdge) {
  const double a = 0.5, pen = 0.01;
  const CollideShape c = box(Vec3::Constant(a));
  const Pose xa = pose(Vec3::Zero(), rot(kPi / 4, Vec3::UnitX()));  // top edge along x at z = a sqrt 2
  const Pose xb =
      pose(Vec3(0, 0, 2 * a * std::sqrt(2.0) - pen), rot(kPi / 4, Vec3::UnitY()));  // bottom edge along y
  const Manifold m = run(c, xa, c, xb);
  ASSERT_EQ(m.count, 1);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(m.points[0].separation, -pen, 1e-12);
  EXPECT_LT((m.points[0].p_W - Vec3(0, 0, a * std::sqrt(2.0) - pen / 2)).norm(), 1e-12);
}

TEST(Collide, CapsuleLyingOnBoxGivesTwoPoints) {
  const CollideShape b = box(Vec3(1, 1, 0.5));
  const Mat3 R = rot(kPi / 2, Vec3::UnitY());  // capsule axis along x
  // Touching (cores apart from the box: the GJK branch), 5 mm deep, and 1 cm above with a 2 cm margin.
  for (double gap : {-0.005, 0.01}) {
    const Manifold m = run(capsule(0.1, 0.5), pose(Vec3(0.2, 0, 0.6 + gap), R), b, pose(Vec3::Zero()), 0.02);
    expect_points(m, {Vec3(-0.3, 0, 0.5 + gap / 2), Vec3(0.7, 0, 0.5 + gap / 2)}, gap, kExact);
    EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), kExact);
  }
  // Overhanging the edge: the segment is clipped at x = 1.
  const Manifold m = run(capsule(0.1, 0.5), pose(Vec3(0.8, 0, 0.595), R), b, pose(Vec3::Zero()), 0.0);
  expect_points(m, {Vec3(0.3, 0, 0.4975), Vec3(1, 0, 0.4975)}, -0.005, kExact);
  // Core sunk into the box (deep): SAT branch, still two points on the top face.
  const Manifold d = run(capsule(0.1, 0.5), pose(Vec3(0.2, 0, 0.45), R), b, pose(Vec3::Zero()), 0.0);
  expect_points(d, {Vec3(-0.3, 0, 0.425), Vec3(0.7, 0, 0.425)}, -0.15, kExact);
}

TEST(Collide, HullPairs) {
  // An octahedron standing on a vertex on a box: one point at the vertex.
  const CollideShape o = hull(octahedron(1.0)), b = box(Vec3(2, 2, 0.5));
  Manifold m = run(b, pose(Vec3::Zero()), o, pose(Vec3(0.3, 0.2, 1.49)));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.01, kExact);
  EXPECT_LT((m.points[0].p_W - Vec3(0.3, 0.2, 0.495)).norm(), kExact);
  // A tetrahedron on its base face on the box: three points at its base corners.
  const ConvexPolyhedron t = tetrahedron(1.0);
  m = run(b, pose(Vec3::Zero()), hull(t), pose(Vec3(0, 0, 0.5 + 0.25 - 0.01)));
  std::vector<Vec3> pts;
  for (int i = 0; i < 3; ++i) pts.push_back(t.vertices[i] + Vec3(0, 0, 0.745));
  expect_points(m, pts, -0.01, kExact);
  // Tetrahedron base down on the octahedron's top vertex, the vertex under the base's interior.
  m = run(o, pose(Vec3::Zero()), hull(t), pose(Vec3(0, 0, 1 + 0.25 - 0.02)));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.02, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  // Two octahedra face to face ((+,+,+) against the other's (-,-,-)): the triangles overlap in a
  // hexagon, reduced to 4 points, all at the same depth.
  const Vec3 nf = Vec3(1, 1, 1).normalized();
  const double off = 1 / std::sqrt(3.0);
  m = run(o, pose(Vec3::Zero()), o, pose((2 * off - 0.01) * nf), 0.0);
  ASSERT_EQ(m.count, 4);
  EXPECT_LT((m.normal_W - nf).norm(), kExact);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.points[i].separation, -0.01, kExact);
}

// ---------------------------------------------------------------- properties

// Pairs used by the property tests: (A, pose A, B, pose B), all touching or nearly.
struct Case {
  CollideShape a;
  Pose xa;
  CollideShape b;
  Pose xb;
};
std::vector<Case> cases() {
  const Mat3 Rx = rot(kPi / 2, Vec3::UnitY());
  return {
      {box(Vec3(2, 2, 0.5)), pose(Vec3::Zero()), box(Vec3::Constant(0.5)),
       pose(Vec3(0.3, 0.1, 0.99), rot(0.2, Vec3::UnitZ()))},
      {sphere(0.3), pose(Vec3(0.2, 0.9, 0.1)), box(Vec3(1, 0.7, 0.4)),
       pose(Vec3::Zero(), rot(0.1, Vec3(1, 0, 1)))},
      {capsule(0.1, 0.5), pose(Vec3(0.2, 0, 0.595), Rx), box(Vec3(1, 1, 0.5)), pose(Vec3::Zero())},
      {sphere(0.2), pose(Vec3(0, 0.1, 0.68)), cylinder(0.3, 0.5), pose(Vec3::Zero())},
      {cylinder(0.3, 0.5), pose(Vec3(0.05, 0, 1.3)), ellipsoid(Vec3(0.3, 0.4, 0.8)), pose(Vec3(0, 0, 0.01))},
      {box(Vec3::Constant(0.5)), pose(Vec3::Zero()), hull(octahedron(1.0)), pose(Vec3(0.1, 0.2, 1.49))},
      {capsule(0.1, 0.5), pose(Vec3(0.2, 0.1, 0.3)), capsule(0.2, 0.3), pose(Vec3(0.1, 0.05, -0.25), Rx)},
  };
}

TEST(Collide, SwappingTheOrderNegatesTheNormalAndKeepsThePoints) {
  for (const Case& c : cases()) {
    const Manifold m = run(c.a, c.xa, c.b, c.xb, 0.01), r = run(c.b, c.xb, c.a, c.xa, 0.01);
    SCOPED_TRACE(std::string(to_string(c.a.kind)) + "-" + to_string(c.b.kind));
    ASSERT_GT(m.count, 0);
    ASSERT_EQ(m.count, r.count);
    EXPECT_LT((m.normal_W + r.normal_W).norm(), 1e-9);
    for (int i = 0; i < m.count; ++i) {
      const int k = nearest(r, m.points[i].p_W);
      EXPECT_LT((r.points[k].p_W - m.points[i].p_W).norm(), 1e-9);
      EXPECT_NEAR(r.points[k].separation, m.points[i].separation, 1e-9);
    }
  }
}

TEST(Collide, SameInputsGiveBitIdenticalOutputs) {
  for (const Case& c : cases()) {
    PairCache c1, c2;
    Manifold m1, m2;
    std::memset((void*)&m1, 0, sizeof m1), std::memset((void*)&m2, 0, sizeof m2);
    collide(c.a, c.xa, c.b, c.xb, 0.01, c1, m1);
    collide(c.a, c.xa, c.b, c.xb, 0.01, c2, m2);
    EXPECT_EQ(std::memcmp((const void*)&m1, (const void*)&m2, sizeof m1), 0);
    // And again with the cache the first call left.
    PairCache c3 = c1;
    collide(c.a, c.xa, c.b, c.xb, 0.01, c1, m1);
    collide(c.a, c.xa, c.b, c.xb, 0.01, c3, m2);
    EXPECT_EQ(std::memcmp((const void*)&m1, (const void*)&m2, sizeof m1), 0);
  }
}

TEST(Collide, FeatureIdsPersistUnderSmallMotion) {
  const CollideShape a = box(Vec3(2, 2, 0.5)), b = box(Vec3::Constant(0.5));
  const Pose xa = pose(Vec3::Zero());
  // Overhanging, so the manifold has clip points as well as vertices.
  Pose xb = pose(Vec3(1.8, 0.3, 0.99), rot(0.3, Vec3::UnitZ()));
  PairCache cache;
  Manifold m0, m1;
  collide(a, xa, b, xb, 0.01, cache, m0);
  ASSERT_EQ(m0.count, 4);
  for (const Vec3& d : {Vec3(1e-4, 0, 0), Vec3(0, -1e-4, 0), Vec3(0, 0, 1e-4)}) {
    Pose x = xb;
    x.p += d;
    x.R = rot(1e-4, Vec3(1, 2, 3)) * x.R;
    collide(a, xa, b, x, 0.01, cache, m1);
    ASSERT_EQ(m1.count, m0.count);
    for (int i = 0; i < m0.count; ++i) {
      const int k = nearest(m1, m0.points[i].p_W);
      EXPECT_EQ(m1.points[k].id, m0.points[i].id);
    }
  }
  std::vector<uint32_t> ids;
  for (int i = 0; i < m0.count; ++i) ids.push_back(m0.points[i].id);
  std::sort(ids.begin(), ids.end());
  EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());  // unique
}

TEST(Collide, SpeculativeDistance) {
  const CollideShape a = box(Vec3(2, 2, 0.5)), b = box(Vec3::Constant(0.5));
  const Pose xa = pose(Vec3::Zero()), xb = pose(Vec3(0, 0, 1.01));
  EXPECT_EQ(run(a, xa, b, xb, 0.005).count, 0);
  const Manifold m = run(a, xa, b, xb, 0.02);
  ASSERT_EQ(m.count, 4);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.points[i].separation, 0.01, kExact);
  for (const Case& c : cases()) {
    // Pull B away along the normal: 0 points beyond the margin, a positive separation inside it.
    const Manifold m0 = run(c.a, c.xa, c.b, c.xb, 0.01);
    ASSERT_GT(m0.count, 0);
    double smin = INFINITY;
    for (int i = 0; i < m0.count; ++i) smin = std::min(smin, m0.points[i].separation);
    Pose x = c.xb;
    x.p += (0.05 - smin) * m0.normal_W;
    SCOPED_TRACE(std::string(to_string(c.a.kind)) + "-" + to_string(c.b.kind));
    EXPECT_EQ(run(c.a, c.xa, c.b, x, 0.04).count, 0);
    const Manifold m1 = run(c.a, c.xa, c.b, x, 0.06);
    ASSERT_GT(m1.count, 0);
    for (int i = 0; i < m1.count; ++i) EXPECT_GT(m1.points[i].separation, 0.0);
  }
}

TEST(Collide, GjkPairsMatchClosedForms) {
  // Sphere over a cylinder's top face, beside its side, and sunk 2 cm into its top (EPA).
  const CollideShape cy = cylinder(0.3, 0.5);
  Manifold m = run(sphere(0.2), pose(Vec3(0.1, 0, 0.75)), cy, pose(Vec3::Zero()), 0.1);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, 0.05, 1e-9);
  m = run(sphere(0.2), pose(Vec3(0.3, 0.4, 0.1)), cy, pose(Vec3::Zero()), 0.1);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, 0.5 - 0.5, 1e-9);
  EXPECT_EQ(run(sphere(0.2), pose(Vec3(0.6, 0.8, 0.1)), cy, pose(Vec3::Zero()), 0.1).count, 0);  // 0.5 apart
  m = run(sphere(0.2), pose(Vec3(0.36, 0.48, 0.1)), cy, pose(Vec3::Zero()), 0.2);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, 0.6 - 0.5, 1e-9);
  m = run(sphere(0.2), pose(Vec3(0.1, 0, 0.68)), cy, pose(Vec3::Zero()), 0.0);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.02, 1e-7);
  EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), 1e-6);
  // Ellipsoid against a box along each axis, apart and overlapping.
  const Vec3 r(0.3, 0.4, 0.8);
  const CollideShape e = ellipsoid(r), b = box(Vec3::Constant(0.5));
  for (int k = 0; k < 3; ++k)
    for (double gap : {0.03, -0.03}) {
      Vec3 c = Vec3::Zero();
      c[k] = 0.5 + r[k] + gap;
      m = run(b, pose(Vec3::Zero()), e, pose(c), 0.1);
      ASSERT_EQ(m.count, 1);
      EXPECT_NEAR(m.points[0].separation, gap, 1e-7) << k;
      EXPECT_NEAR(m.normal_W[k], 1.0, 1e-6);
    }
  // Cylinder lying on its side on a box (box first: the swapped order): both ends of the line.
  m = run(b, pose(Vec3::Zero()), cy, pose(Vec3(0, 0, 0.5 + 0.3 - 0.01), rot(kPi / 2, Vec3::UnitX())), 0.0);
  expect_points(m, {Vec3(0, -0.5, 0.495), Vec3(0, 0.5, 0.495)}, -0.01, 1e-9);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), 1e-9);
}

// Random rotation from a seeded generator.
Mat3 random_rotation(std::mt19937_64& g) {
  std::normal_distribution<double> N;
  Eigen::Quaterniond q(N(g), N(g), N(g), N(g));
  return q.normalized().toRotationMatrix();
}

TEST(Collide, RandomBoxPairsAgreeWithGjkEpa) {
  // Independent oracle: GJK/EPA on the boxes' support functions (half extents, not the polyhedron
  // code). B is placed along a random direction so the boxes overlap by 0..5 mm: the SAT depth of
  // the deepest manifold point equals the EPA depth (within 1e-6 m: EPA's stopping tolerance of
  // 1e-9 * size plus the clip's rounding); apart by 0..5 mm the manifold's points are never closer
  // than the true distance.
  std::mt19937_64 g(12345);
  std::uniform_real_distribution<double> U(0.2, 1.0), D(-0.005, 0.005);
  int checked = 0;
  for (int it = 0; it < 400; ++it) {
    const CollideShape a = box(Vec3(U(g), U(g), U(g))), b = box(Vec3(U(g), U(g), U(g)));
    const Pose xa = pose(Vec3::Zero(), random_rotation(g));
    Pose xb = pose(Vec3::Zero(), random_rotation(g));
    std::normal_distribution<double> N;
    const Vec3 dir = Vec3(N(g), N(g), N(g)).normalized();
    // Find the touching distance along dir by bisection on GJK's overlap.
    double lo = 0, hi = 5;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      xb.p = mid * dir;
      bool ov;
      collide_detail::gjk_distance(collide_detail::Support(a, xa), collide_detail::Support(b, xb), ov);
      (ov ? lo : hi) = mid;
    }
    const double target = D(g);
    xb.p = (hi + target) * dir;
    const collide_detail::CoreDistance ref =
        collide_detail::core_distance(collide_detail::Support(a, xa), collide_detail::Support(b, xb));
    const Manifold m = run(a, xa, b, xb, 0.01);
    ASSERT_GT(m.count, 0) << it;
    double smin = INFINITY;
    for (int i = 0; i < m.count; ++i) smin = std::min(smin, m.points[i].separation);
    if (ref.separation < 0) {
      EXPECT_NEAR(smin, ref.separation, 1e-6) << it;
      ++checked;
    } else {
      EXPECT_GE(smin, ref.separation - 1e-9) << it;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Collide, RandomSphereHullPairsAgreeWithGjk) {
  // Oracle: GJK from the sphere's centre to the hull (apart), or the least face depth (inside).
  std::mt19937_64 g(777);
  std::uniform_real_distribution<double> U(-1.5, 1.5), R(0.05, 0.5);
  const CollideShape h = hull(octahedron(1.0)), t = hull(tetrahedron(1.5));
  for (int it = 0; it < 500; ++it) {
    const CollideShape& H = (it & 1) ? h : t;
    const Pose xh = pose(Vec3(0.1, 0, 0), random_rotation(g));
    const CollideShape s = sphere(R(g));
    const Pose xs = pose(Vec3(U(g), U(g), U(g)));
    const Manifold m = run(s, xs, H, xh, 10.0);
    ASSERT_EQ(m.count, 1);
    const CollideShape pt = sphere(0.0);
    bool ov;
    const auto d =
        collide_detail::gjk_distance(collide_detail::Support(pt, xs), collide_detail::Support(H, xh), ov);
    double ref;
    if (!ov && d.separation > 1e-9) {
      ref = d.separation - s.radius;
    } else {
      const Vec3 c = xh.apply_inverse(xs.p);
      double dmax = -INFINITY;
      for (const auto& f : H.hull->faces) dmax = std::max(dmax, f.normal.dot(c) - f.offset);
      ref = dmax - s.radius;
    }
    EXPECT_NEAR(m.points[0].separation, ref, 1e-9) << it;
  }
}

TEST(Collide, HullPathMatchesBoxPath) {
  // The general polyhedron code (boxes given as hulls) against the closed-form box code, on the
  // crossed-edges case and on random resting-like pairs: the same normal and deepest separation.
  const double a = 0.5, pen = 0.01;
  const CollideShape hc = hull(make_box_polyhedron(Vec3::Constant(a)));
  const Pose xa = pose(Vec3::Zero(), rot(kPi / 4, Vec3::UnitX()));
  const Pose xb = pose(Vec3(0, 0, 2 * a * std::sqrt(2.0) - pen), rot(kPi / 4, Vec3::UnitY()));
  const Manifold m = run(hc, xa, hc, xb);
  ASSERT_EQ(m.count, 1);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(m.points[0].separation, -pen, 1e-12);
  EXPECT_LT((m.points[0].p_W - Vec3(0, 0, a * std::sqrt(2.0) - pen / 2)).norm(), 1e-12);
  std::mt19937_64 g(99);
  std::uniform_real_distribution<double> U(-0.3, 0.3), H(0.2, 0.8);
  for (int it = 0; it < 200; ++it) {
    const Vec3 h1(H(g), H(g), H(g)), h2(H(g), H(g), H(g));
    const CollideShape b1 = box(h1), b2 = box(h2), p1 = hull(make_box_polyhedron(h1)),
                       p2 = hull(make_box_polyhedron(h2));
    const Pose x1 = pose(Vec3::Zero(), rot(U(g), Vec3(U(g), U(g), 1)));
    const Pose x2 = pose(Vec3(U(g), U(g), h1.z() + h2.z() + 0.3 * U(g)), rot(U(g), Vec3(U(g), U(g), 1)));
    const Manifold mb = run(b1, x1, b2, x2, 0.01), mh = run(p1, x1, p2, x2, 0.01);
    ASSERT_EQ(mb.count, mh.count) << it;
    if (mb.count == 0) continue;
    EXPECT_LT((mb.normal_W - mh.normal_W).norm(), 1e-9) << it;
    for (int i = 0; i < mb.count; ++i) {
      const int k = nearest(mh, mb.points[i].p_W);
      EXPECT_LT((mh.points[k].p_W - mb.points[i].p_W).norm(), 1e-9) << it;
      EXPECT_NEAR(mh.points[k].separation, mb.points[i].separation, 1e-9) << it;
    }
  }
}

TEST(Collide, RestingEqualCubesKeepTheirReferenceFace) {
  // Two equal cubes face to face: A's top and B's bottom tie as axes. With the cache the
  // reference face must not flip from step to step (ids unchanged) under 1e-5 jitter.
  const CollideShape c = box(Vec3::Constant(0.5)), hc = hull(make_box_polyhedron(Vec3::Constant(0.5)));
  for (const CollideShape* s : {&c, &hc}) {
    std::mt19937_64 g(5);
    std::uniform_real_distribution<double> U(-1e-5, 1e-5);
    PairCache cache;
    Manifold m0, m;
    collide(*s, pose(Vec3::Zero()), *s, pose(Vec3(0.1, 0.05, 0.999)), 0.01, cache, m0);
    ASSERT_EQ(m0.count, 4);
    for (int it = 0; it < 200; ++it) {
      const Pose xa = pose(Vec3(U(g), U(g), U(g)), rot(U(g), Vec3(1, 2, 3)));
      const Pose xb = pose(Vec3(0.1 + U(g), 0.05 + U(g), 0.999 + U(g)), rot(U(g), Vec3(3, 1, 2)));
      collide(*s, xa, *s, xb, 0.01, cache, m);
      ASSERT_EQ(m.count, 4);
      EXPECT_GT(m.normal_W.z(), 0.999);
      for (int i = 0; i < 4; ++i) EXPECT_EQ(m.points[nearest(m, m0.points[i].p_W)].id, m0.points[i].id) << it;
    }
  }
}

// `shapes[0..3)` as A against `shapes[0..nb)` as B at random orientations, placed touching to
// within +-5 mm along a random direction (bisection on GJK's overlap test), 300 pairs. Overlapping:
// the deepest point never reports less depth than EPA, and more only within the axis hysteresis
// bounds; at least `min_exact` of them equal EPA's depth to 1e-6 m. Apart: never closer than GJK.
void check_against_gjk_epa(const CollideShape (&shapes)[3], int nb, uint64_t seed, double min_exact) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> D(-0.005, 0.005);
  std::normal_distribution<double> N;
  int checked = 0, exact = 0, apart = 0, apart_exact = 0;
  for (int it = 0; it < 300; ++it) {
    const CollideShape& a = shapes[it % 3];
    const CollideShape& b = shapes[(it / 3) % nb];
    const Pose xa = pose(Vec3::Zero(), random_rotation(g));
    Pose xb = pose(Vec3::Zero(), random_rotation(g));
    const Vec3 dir = Vec3(N(g), N(g), N(g)).normalized();
    double lo = 0, hi = 5;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      xb.p = mid * dir;
      bool ov;
      collide_detail::gjk_distance(collide_detail::Support(a, xa), collide_detail::Support(b, xb), ov);
      (ov ? lo : hi) = mid;
    }
    xb.p = (hi + D(g)) * dir;
    const auto ref =
        collide_detail::core_distance(collide_detail::Support(a, xa), collide_detail::Support(b, xb));
    const Manifold m = run(a, xa, b, xb, 0.01);
    ASSERT_GT(m.count, 0) << it;
    double smin = INFINITY;
    for (int i = 0; i < m.count; ++i) smin = std::min(smin, m.points[i].separation);
    // The axis choice prefers faces (hysteresis: an edge pair wins only when it separates more
    // than the best face by 10% of |face| + tol, B's face A's by 2% + tol, tol = 1e-3 x the inner
    // radii), so the depth reported may exceed the minimum within those bounds, never fall short
    // of it; apart, the gap reported may fall short of GJK's within the same bounds (a
    // speculative point that stops a body early by at most that much, less on every step).
    const double tol = 1e-3 * (a.hull->inner_radius + b.hull->inner_radius);
    if (ref.separation < 0) {
      EXPECT_LE(smin, ref.separation + 1e-6) << it;
      EXPECT_GE(smin, (ref.separation - 2 * tol) / (0.9 * 0.98) - 1e-6) << it;
      exact += std::fabs(smin - ref.separation) < 1e-6;
      ++checked;
    } else {
      EXPECT_GE(smin, (ref.separation - 2 * tol) / (1.1 * 1.02) - 1e-9) << it;
      EXPECT_LE(smin, ref.separation + 1e-6) << it;
      apart_exact += std::fabs(smin - ref.separation) < 1e-6;
      ++apart;
    }
  }
  EXPECT_GT(checked, 80);
  EXPECT_GT(exact, checked * min_exact);
  EXPECT_GT(apart_exact, apart * min_exact) << apart_exact << " of " << apart;
}

TEST(Collide, RandomHullPairsAgreeWithGjkEpa) {
  // Octahedra, tetrahedra and boxes as hulls, touching to within +-5 mm along a random direction;
  // overlapping: the deepest point's separation equals EPA's depth (1e-6 m).
  const CollideShape shapes[3] = {hull(octahedron(0.7)), hull(tetrahedron(1.2)),
                                  hull(make_box_polyhedron(Vec3(0.3, 0.5, 0.4)))};
  check_against_gjk_epa(shapes, 3, 2024, 0.9);
}

TEST(Collide, EveryPairIsFiniteAndBoundedEvenWhenDeepOrConcentric) {
  // All 7 x 7 kind pairs (plane only as A or B against the others) at random poses, including
  // coincident centres: finite output, at most 4 points, unit normal, and it returns.
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> U(-0.6, 0.6);
  const CollideShape shapes[] = {plane(),
                                 sphere(0.3),
                                 capsule(0.2, 0.4),
                                 cylinder(0.3, 0.4),
                                 ellipsoid(Vec3(0.2, 0.3, 0.5)),
                                 box(Vec3(0.3, 0.4, 0.5)),
                                 hull(octahedron(0.6))};
  for (int it = 0; it < 20000; ++it) {
    const CollideShape& a = shapes[it % 7];
    const CollideShape& b = shapes[(it / 7) % 7];
    const bool concentric = (it / 49) % 4 == 0;
    const Pose xa = pose(Vec3::Zero(), random_rotation(g));
    const Pose xb = pose(concentric ? Vec3::Zero() : Vec3(U(g), U(g), U(g)), random_rotation(g));
    const Manifold m = run(a, xa, b, xb, 0.05);
    ASSERT_LE(m.count, 4);
    if (a.kind == CollideKind::plane && b.kind == CollideKind::plane) continue;
    ASSERT_TRUE(all_finite(m.normal_W)) << to_string(a.kind) << "-" << to_string(b.kind);
    EXPECT_NEAR(m.normal_W.norm(), 1.0, 1e-9) << to_string(a.kind) << "-" << to_string(b.kind);
    // Overlapping (by GJK/EPA on the support functions) means at least one point, and the
    // deepest point is never shallower than that depth (1e-6 m: EPA's accuracy on curved shapes).
    if (a.kind != CollideKind::plane && b.kind != CollideKind::plane) {
      const collide_detail::Support A(a, xa), B(b, xb);
      const auto d = collide_detail::core_distance(A, B);
      const double truth = d.separation - A.margin - B.margin;
      if (d.ok && truth < -1e-6) {
        EXPECT_GE(m.count, 1) << to_string(a.kind) << "-" << to_string(b.kind) << " " << it;
        double smin = INFINITY;
        for (int i = 0; i < m.count; ++i) smin = std::min(smin, m.points[i].separation);
        EXPECT_LE(smin, truth + 1e-6) << to_string(a.kind) << "-" << to_string(b.kind) << " " << it;
      }
    }
    for (int i = 0; i < m.count; ++i) {
      ASSERT_TRUE(all_finite(m.points[i].p_W));
      ASSERT_TRUE(std::isfinite(m.points[i].separation));
      EXPECT_LE(m.points[i].separation, 0.05);
    }
  }
}

TEST(Collide, TestPolyhedraAreValid) {
  EXPECT_EQ(polyhedron_problem(octahedron(1.0)), "");
  EXPECT_EQ(polyhedron_problem(tetrahedron(1.0)), "");
  EXPECT_EQ(polyhedron_problem(prism(100, 1.0, 0.2)), "");
}

TEST(Collide, FacesWithMoreThan64VerticesAreDecimated) {
  // A 100-gon prism standing on a box (its bottom face is the incident face: clipped as a
  // 50-vertex sub-polygon) and a box standing on the prism (reference face with 100 side
  // planes): 4 points at the right depth, inside the 100-gon's circumcircle.
  const CollideShape pr = hull(prism(100, 0.5, 0.2)), b = box(Vec3(1, 1, 0.5));
  Manifold m = run(b, pose(Vec3::Zero()), pr, pose(Vec3(0, 0, 0.699)));
  ASSERT_EQ(m.count, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].separation, -0.001, kExact);
    EXPECT_LE(std::hypot(m.points[i].p_W.x(), m.points[i].p_W.y()), 0.5 + kExact);
    EXPECT_GT(std::hypot(m.points[i].p_W.x(), m.points[i].p_W.y()), 0.45);
  }
  const CollideShape small = box(Vec3(0.2, 0.2, 0.2));
  m = run(pr, pose(Vec3::Zero()), small, pose(Vec3(0.1, 0, 0.399)));
  expect_points(
      m, {Vec3(-0.1, -0.2, 0.1995), Vec3(-0.1, 0.2, 0.1995), Vec3(0.3, -0.2, 0.1995), Vec3(0.3, 0.2, 0.1995)},
      -0.001, kExact);
}

TEST(Collide, CylinderOnBoxStandsLiesAndRolls) {
  const CollideShape cy = cylinder(0.3, 0.4), b = box(Vec3(1, 1, 0.5));
  const Pose xb = pose(Vec3::Zero());
  // Standing on its end, 1 mm deep: 4 rim points.
  Manifold m = run(cy, pose(Vec3(0.1, 0.2, 0.899)), b, xb, 0.0);
  ASSERT_EQ(m.count, 4);
  EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].separation, -0.001, 1e-9);
    EXPECT_NEAR((m.points[i].p_W - Vec3(0.1, 0.2, 0.4995)).norm(), 0.3, 1e-9);
  }
  // Lying on its side: the two ends of the line of contact.
  m = run(cy, pose(Vec3(0, 0, 0.799), rot(kPi / 2, Vec3::UnitX())), b, xb, 0.0);
  expect_points(m, {Vec3(0, -0.4, 0.4995), Vec3(0, 0.4, 0.4995)}, -0.001, 1e-9);
  // Tilted on its rim: the exact rim point (as on a plane).
  const double th = 0.4, r = 0.3, hl = 0.4;
  const Vec3 c(0.2, 0.1, 0.5 + hl * std::cos(th) + r * std::sin(th) - 0.003);
  m = run(cy, pose(c, rot(th, Vec3::UnitX())), b, xb, 0.0);
  ASSERT_EQ(m.count, 1);
  const Vec3 x = c + Vec3(0, hl * std::sin(th) - r * std::cos(th), -hl * std::cos(th) - r * std::sin(th));
  EXPECT_NEAR(m.points[0].separation, -0.003, 1e-9);
  EXPECT_LT((m.points[0].p_W - (x + Vec3(0, 0, 0.0015))).norm(), 1e-9);
}

TEST(Collide, EllipsoidOnBoxFaceIsExact) {
  // Rotated ellipsoid sunk 2 mm into a box's top face: the exact support point and depth (as on
  // a plane), not EPA's polytope approximation of the curved surface.
  const Vec3 r(0.3, 0.5, 0.8);
  const Mat3 Re = rot(0.7, Vec3(1, -1, 2));
  const Vec3 n = Vec3::UnitZ();
  const double h = r.cwiseProduct(Re.transpose() * n).norm();
  const Vec3 c(0.1, -0.2, 0.5 + h - 0.002);
  const Manifold m = run(box(Vec3(1, 1, 0.5)), pose(Vec3::Zero()), ellipsoid(r), pose(c, Re), 0.0);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].separation, -0.002, kExact);
  const Vec3 p = c - Re * r.cwiseProduct(r).cwiseProduct(Re.transpose() * n) / h;  // deepest point
  EXPECT_LT((m.points[0].p_W - (p + Vec3(0, 0, 0.001))).norm(), kExact);
}

// A hull of n random points on an ellipsoid (triangular faces, none coplanar), centred.
ConvexPolyhedron random_hull(int n, const Vec3& radii, uint64_t seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> N;
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) pts.push_back(Vec3(N(g), N(g), N(g)).normalized().cwiseProduct(radii));
  const TriangleMesh m = convex_hull(pts);
  // Keep only the vertices the triangles use.
  std::vector<int> remap(m.vertices.size(), -1);
  std::vector<Vec3> v;
  std::vector<std::vector<int>> loops;
  for (const auto& t : m.triangles) {
    std::vector<int> L;
    for (int k : t) {
      if (remap[k] < 0) remap[k] = (int)v.size(), v.push_back(m.vertices[k]);
      L.push_back(remap[k]);
    }
    loops.push_back(L);
  }
  ConvexPolyhedron p = make_polyhedron(v, loops);
  // The vertex mean is not the volume centroid here, but any interior point serves SAT.
  return p;
}

TEST(Collide, RandomMeshHullsAgreeWithGjkEpa) {
  // Hulls of 40 random points (about 76 triangular faces) against each other and against boxes,
  // touching within +-5 mm: as RandomHullPairsAgreeWithGjkEpa.
  const ConvexPolyhedron h1 = random_hull(40, Vec3(0.5, 0.4, 0.3), 1),
                         h2 = random_hull(40, Vec3(0.3, 0.6, 0.4), 2);
  ASSERT_EQ(polyhedron_problem(h1, 1e-9), "");
  ASSERT_EQ(polyhedron_problem(h2, 1e-9), "");
  const CollideShape shapes[3] = {hull(h1), hull(h2), box(Vec3(0.3, 0.2, 0.4))};
  check_against_gjk_epa(shapes, 2, 77, 0.8);
}

// ---------------------------------------------------------------- cylinder and capsule pairs

// Signed distance from x to a cylinder's or capsule's surface (closed form, independent of the
// narrow phase): the oracle for "this point is on that surface".
double surface_distance(const CollideShape& s, const Pose& x, const Vec3& p) {
  const Vec3 q = x.apply_inverse(p);
  if (s.kind == CollideKind::capsule) {
    const double z = std::clamp(q.z(), -s.half_length, s.half_length);
    return (q - Vec3(0, 0, z)).norm() - s.radius;
  }
  const double dr = std::hypot(q.x(), q.y()) - s.radius, dz = std::fabs(q.z()) - s.half_length;
  return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0)) + std::min(std::max(dr, dz), 0.0);
}
// Every point's two surface points (p -+ s/2 n) lie on A's and B's surfaces.
void expect_on_surfaces(const Manifold& m, const CollideShape& a, const Pose& xa, const CollideShape& b,
                        const Pose& xb, double tol) {
  for (int i = 0; i < m.count; ++i) {
    const ManifoldPoint& q = m.points[i];
    EXPECT_NEAR(surface_distance(a, xa, q.p_W - 0.5 * q.separation * m.normal_W), 0.0, tol) << "point " << i;
    EXPECT_NEAR(surface_distance(b, xb, q.p_W + 0.5 * q.separation * m.normal_W), 0.0, tol) << "point " << i;
  }
}

TEST(Collide, CylinderCapOnCapGivesTheLensCorners) {
  // Equal coins (r 0.3), B 2 mm into A's top with its centre 5 cm off: the lens's corners along
  // the centre line (A's rim at +x, B's rim at -x) and across it (the two rims' crossings).
  const double r = 0.3, hl = 0.1, pen = 0.002, d = 0.05;
  const CollideShape a = cylinder(r, hl);
  Manifold m = run(a, pose(Vec3::Zero()), a, pose(Vec3(d, 0, 2 * hl - pen), rot(0.3, Vec3::UnitZ())));
  const double z = hl - pen / 2, yc = std::sqrt(r * r - d * d / 4);
  expect_points(m, {Vec3(r, 0, z), Vec3(d - r, 0, z), Vec3(d / 2, yc, z), Vec3(d / 2, -yc, z)}, -pen, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  // Unequal discs (0.3 under 0.2) 0.25 apart along a direction at 0.7 rad: A's rim point towards
  // B, B's rim point towards A, and the crossings at a = (d^2 + ra^2 - rb^2) / 2d along the line.
  const double ra = 0.3, rb = 0.2, dd = 0.25;
  const Vec3 u(std::cos(0.7), std::sin(0.7), 0), w(-std::sin(0.7), std::cos(0.7), 0);
  const CollideShape b = cylinder(rb, hl);
  const Pose xb = pose(dd * u + Vec3(0, 0, 2 * hl - pen));
  m = run(a, pose(Vec3::Zero()), b, xb);
  const double aa = (dd * dd + ra * ra - rb * rb) / (2 * dd), h = std::sqrt(ra * ra - aa * aa);
  const Vec3 zz(0, 0, z);
  expect_points(m, {ra * u + zz, (dd - rb) * u + zz, aa * u + h * w + zz, aa * u - h * w + zz}, -pen, kExact);
  // Each on the lens boundary: on one circle, inside the other.
  for (int i = 0; i < m.count; ++i) {
    const Vec3 p(m.points[i].p_W.x(), m.points[i].p_W.y(), 0);
    const double da = p.norm() - ra, db = (p - dd * u).norm() - rb;
    EXPECT_NEAR(std::min(std::fabs(da), std::fabs(db)), 0.0, kExact);
    EXPECT_LE(std::max(da, db), kExact);
  }
  expect_on_surfaces(m, a, pose(Vec3::Zero()), b, xb, kExact);
  // A small can wholly on a coin: four points of the can's rim.
  const CollideShape can = cylinder(0.1, 0.15);
  m = run(a, pose(Vec3::Zero()), can, pose(Vec3(0.1, 0.05, hl + 0.15 - pen)));
  ASSERT_EQ(m.count, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].separation, -pen, kExact);
    EXPECT_NEAR((m.points[i].p_W - Vec3(0.1, 0.05, z)).norm(), 0.1, kExact);
  }
}

TEST(Collide, TiltedCapOnCapReportsTheLensDeepestPoint) {
  // B tilted by 1 degree about y, 5 cm off, its cap's lowest point 2 mm into A's top. Oracle: the
  // deepest of A's rim points under B's disc and B's rim points over A's disc, sampled densely
  // (the depth is linear over the lens, so its maximum is on the lens's boundary).
  const double r = 0.3, hl = 0.1;
  const CollideShape a = cylinder(r, hl);
  for (double tilt : {0.2, 1.0, 2.0}) {
    const Mat3 R = rot(tilt * kPi / 180, Vec3(1, 0.4, 0));
    const Pose xb = pose(Vec3(0.05, 0.03, 2 * hl + r * std::sin(tilt * kPi / 180) - 0.002), R);
    const Manifold m = run(a, pose(Vec3::Zero()), a, xb, 0.05);
    ASSERT_GE(m.count, 4) << tilt;
    const Vec3 nb = R.col(2), cb = xb.p - hl * nb;  // B's lower cap
    double deepest = -INFINITY;
    const int N = 200000;
    for (int k = 0; k < N; ++k) {
      const double phi = 2 * kPi * k / N;
      const Vec3 pa(r * std::cos(phi), r * std::sin(phi), hl);  // A's rim; B's plane above it
      const double t = nb.dot(cb - pa) / nb.z();
      if ((pa + t * Vec3::UnitZ() - cb).norm() <= r) deepest = std::max(deepest, -t);
      const Vec3 pb = cb + r * (std::cos(phi) * R.col(0) + std::sin(phi) * R.col(1));
      if (std::hypot(pb.x(), pb.y()) <= r) deepest = std::max(deepest, hl - pb.z());
    }
    double smin = INFINITY;
    for (int i = 0; i < m.count; ++i) smin = std::min(smin, m.points[i].separation);
    // Sampling error: the kink at a crossing, r tilt 2 pi / N < 1e-6. The lens's deepest point is
    // added when 1e-5 x size deeper than the four support points (at 0.2 deg it is 2.4e-6 deeper,
    // left out: the four keep their ids under small tilts); at 1 and 2 deg it must be there.
    EXPECT_GE(smin, -deepest - 1e-6) << tilt;
    EXPECT_LE(smin, -deepest + 1e-5 * 2 * a.bounding_radius) << tilt;
    if (tilt >= 1) {
      EXPECT_NEAR(smin, -deepest, 1e-6) << tilt;
    }
    expect_on_surfaces(m, a, pose(Vec3::Zero()), a, xb, 1e-12);
  }
}

TEST(Collide, CylinderSideOnCapIsTheClippedLine) {
  // B (r 0.1, 0.8 long) lying along x on A's top (r 0.3), 1 mm deep, its line 5 cm off the centre:
  // the line clipped by A's rim, |x| <= sqrt(0.3^2 - 0.05^2). Either order.
  const CollideShape a = cylinder(0.3, 0.1), b = cylinder(0.1, 0.4);
  const Pose xa = pose(Vec3::Zero()), xb = pose(Vec3(0.1, 0.05, 0.2 - 0.001), rot(kPi / 2, Vec3::UnitY()));
  const double xc = std::sqrt(0.09 - 0.0025);
  Manifold m = run(a, xa, b, xb);
  expect_points(m, {Vec3(-xc, 0.05, 0.0995), Vec3(xc, 0.05, 0.0995)}, -0.001, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  expect_on_surfaces(m, a, xa, b, xb, kExact);
  m = run(b, xb, a, xa);
  expect_points(m, {Vec3(-xc, 0.05, 0.0995), Vec3(xc, 0.05, 0.0995)}, -0.001, kExact);
  EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), kExact);
  // A short one wholly on the cap: its line's two ends.
  const CollideShape s = cylinder(0.05, 0.1);
  m = run(a, xa, s, pose(Vec3(0, 0.1, 0.15 - 0.001), rot(kPi / 2, Vec3::UnitY())));
  expect_points(m, {Vec3(-0.1, 0.1, 0.0995), Vec3(0.1, 0.1, 0.0995)}, -0.001, kExact);
}

TEST(Collide, ParallelCylindersTouchAlongTheirOverlap) {
  const CollideShape a = cylinder(0.2, 0.5);
  const Mat3 Rx = rot(kPi / 2, Vec3::UnitY());
  const Pose xa = pose(Vec3::Zero(), Rx), xb = pose(Vec3(0.3, 0, 0.399), Rx);
  const Manifold m = run(a, xa, a, xb);
  expect_points(m, {Vec3(-0.2, 0, 0.1995), Vec3(0.5, 0, 0.1995)}, -0.001, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  expect_on_surfaces(m, a, xa, a, xb, kExact);
}

TEST(Collide, CapsuleOnCylinderCapAndAlongItsSide) {
  const CollideShape cy = cylinder(0.3, 0.1), ca = capsule(0.03, 0.2);
  const Pose xc = pose(Vec3::Zero());
  // Lying across the cap (along x, 10 cm off the centre), 1 mm deep: its segment clipped by the rim.
  const Pose xl = pose(Vec3(0.1, 0.1, 0.1 + 0.03 - 0.001), rot(kPi / 2, Vec3::UnitY()));
  Manifold m = run(ca, xl, cy, xc);
  expect_points(m, {Vec3(-0.1, 0.1, 0.0995), Vec3(std::sqrt(0.08), 0.1, 0.0995)}, -0.001, kExact);
  EXPECT_LT((m.normal_W + Vec3::UnitZ()).norm(), kExact);
  expect_on_surfaces(m, ca, xl, cy, xc, kExact);
  // Standing on its end on the cap: the end's sphere against the cap's plane.
  const Pose xs = pose(Vec3(0.1, 0, 0.1 + 0.2 * std::cos(0.3) + 0.03 - 0.001), rot(0.3, Vec3::UnitX()));
  m = run(ca, xs, cy, xc);
  ASSERT_EQ(m.count, 1);
  const Vec3 end = xs.p - 0.2 * xs.R.col(2);
  EXPECT_NEAR(m.points[0].separation, -0.001, kExact);
  EXPECT_LT((m.points[0].p_W - Vec3(end.x(), end.y(), 0.0995)).norm(), kExact);
  // Upright beside the side, 1 mm deep: the ends of the overlap along the axis.
  const Pose xu = pose(Vec3(0.3 + 0.03 - 0.001, 0, 0.05));
  m = run(ca, xu, cy, xc);
  expect_points(m, {Vec3(0.2995, 0, -0.1), Vec3(0.2995, 0, 0.1)}, -0.001, kExact);
  EXPECT_LT((m.normal_W + Vec3::UnitX()).norm(), kExact);
  expect_on_surfaces(m, ca, xu, cy, xc, kExact);
}

TEST(Collide, CylinderRimRollsOnACapWithoutFacets) {
  // B tilted by th on its rim on A's top, 3 mm deep, turned about the vertical in 1e-3 rad steps
  // (rolling round): one point, the exact rim point (the plane closed form) at every step.
  const CollideShape a = cylinder(1.0, 0.1), b = cylinder(0.3, 0.2);
  const double th = 0.4, r = 0.3, hl = 0.2;
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const double psi = 1e-3 * k;
    const Mat3 Rz = rot(psi, Vec3::UnitZ());
    const Vec3 c(0.1, 0.05, 0.1 + hl * std::cos(th) + r * std::sin(th) - 0.003);
    const Pose xb = pose(c, Rz * rot(th, Vec3::UnitX()));
    const Manifold m = run(a, pose(Vec3::Zero()), b, xb);
    ASSERT_EQ(m.count, 1) << k;
    EXPECT_EQ(m.points[0].id, collide_detail::kIdCapRim);
    const Vec3 x =
        c + Rz * Vec3(0, hl * std::sin(th) - r * std::cos(th), -hl * std::cos(th) - r * std::sin(th));
    worst = std::max(worst, (m.points[0].p_W - (x + Vec3(0, 0, 0.0015))).norm());
    worst = std::max(worst, std::fabs(m.points[0].separation + 0.003));
  }
  EXPECT_LT(worst, kExact);
}

// The point of a rim circle nearest a line (brute force over 20000 samples, then golden-section
// search): the oracle for a rim on a side.
double rim_to_line(const Vec3& o, const Vec3& e1, const Vec3& e2, double r, const Vec3& p, const Vec3& u,
                   Vec3* best) {
  auto f = [&](double phi) {
    const Vec3 x = o + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const Vec3 d = x - p;
    return (d - d.dot(u) * u).norm();
  };
  int kb = 0;
  const int N = 20000;
  for (int k = 1; k < N; ++k)
    if (f(2 * kPi * k / N) < f(2 * kPi * kb / N)) kb = k;
  double lo = 2 * kPi * (kb - 1) / N, hi = 2 * kPi * (kb + 1) / N;
  const double gr = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 200; ++it) {
    const double m1 = hi - gr * (hi - lo), m2 = lo + gr * (hi - lo);
    (f(m1) < f(m2) ? hi : lo) = (f(m1) < f(m2) ? m2 : m1);
  }
  const double phi = 0.5 * (lo + hi);
  *best = o + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
  return f(phi);
}

TEST(Collide, CylinderRimOnASideIsExactAndSmooth) {
  // A lying along x (r 0.3); B (r 0.2) tilted 30 degrees, its rim 2 mm into A's side, B's centre
  // moved along x and turned about its own axis in small steps (rolling along A). Oracle: the rim
  // point nearest A's axis (brute force + golden section): separation and point to 1e-9.
  const CollideShape a = cylinder(0.3, 1.0), b = cylinder(0.2, 0.05);
  const Pose xa = pose(Vec3::Zero(), rot(kPi / 2, Vec3::UnitY()));
  int exact = 0;
  Vec3 prev = Vec3::Zero();
  for (int k = 0; k < 60; ++k) {
    const Mat3 R = rot(0.5, Vec3::UnitX()) * rot(0.01 * k, Vec3::UnitZ());
    const Vec3 c(-0.3 + 0.01 * k, 0.1, 0.3 + 0.05 * std::cos(0.5) + 0.2 * std::sin(0.5) - 0.002);
    const Pose xb = pose(c, R);
    const Manifold m = run(a, xa, b, xb, 0.01);
    ASSERT_EQ(m.count, 1) << k;
    Vec3 q;
    const Vec3 o = c - 0.05 * R.col(2);
    const double d = rim_to_line(o, R.col(0), R.col(1), 0.2, Vec3::Zero(), Vec3::UnitX(), &q);
    EXPECT_NEAR(m.points[0].separation, d - 0.3, 1e-9) << k;
    const Vec3 nS = Vec3(0, q.y(), q.z()).normalized();
    // The oracle's golden section finds the minimum's place only to ~sqrt(eps) (the distance is
    // flat there): 1e-7 for the point, 1e-9 for the separation.
    EXPECT_LT((m.points[0].p_W - (q - 0.5 * (d - 0.3) * nS)).norm(), 1e-7) << k;
    exact += m.points[0].id == collide_detail::kIdRimSide;
    if (k > 0) {
      EXPECT_LT((m.points[0].p_W - prev).norm(), 0.02) << k;  // moves with the body
    }
    prev = m.points[0].p_W;
  }
  EXPECT_EQ(exact, 60);
}

TEST(Collide, CylinderRimAgainstARimIsExact) {
  // A standing (r 0.3); B (r 0.2) placed so that its rim meets A's top rim at pa = (0.3, 0, 0.1)
  // along n = (1, 0, 1)/sqrt 2: pa is A's support point along n, B's rim point pa + gap n is B's
  // support point along -n, and the rims' tangents there (y and tB) are both perpendicular to n.
  // So the slab between them separates the two: apart, the distance is gap exactly. Overlapping
  // (gap < 0) the rim pair is a stationary pair and the depth is EPA's.
  const CollideShape a = cylinder(0.3, 0.1), b = cylinder(0.2, 0.1);
  const Pose xa = pose(Vec3::Zero());
  const Vec3 n = Vec3(1, 0, 1).normalized(), pa(0.3, 0, 0.1);
  const Vec3 tB = (Vec3::UnitY() + n.cross(Vec3::UnitY())).normalized();
  for (double beta : {0.6, 1.0}) {
    const Vec3 uB = (std::cos(beta) * n + std::sin(beta) * tB.cross(n)).normalized();
    const Vec3 radial = (-n + std::cos(beta) * uB).normalized();  // -n without its uB part
    Mat3 Rb;
    Rb.col(0) = radial, Rb.col(1) = uB.cross(radial), Rb.col(2) = uB;
    for (double gap : {0.003, 0.0005, -0.001}) {
      const Pose xb = pose(pa + gap * n - 0.2 * radial + 0.1 * uB, Rb);
      const Manifold m = run(a, xa, b, xb, 0.01);
      ASSERT_EQ(m.count, 1) << beta << " " << gap;
      EXPECT_EQ(m.points[0].id, collide_detail::kIdRimRim);
      expect_on_surfaces(m, a, xa, b, xb, 1e-9);
      if (gap > 0) {
        EXPECT_NEAR(m.points[0].separation, gap, 1e-12);
        EXPECT_LT((m.normal_W - n).norm(), 1e-9);
        EXPECT_LT((m.points[0].p_W - (pa + 0.5 * gap * n)).norm(), 1e-9);
      } else {
        const auto ref =
            collide_detail::core_distance(collide_detail::Support(a, xa), collide_detail::Support(b, xb));
        EXPECT_NEAR(m.points[0].separation, ref.separation, 1e-7);  // EPA: 1e-9 x size on the depth
        EXPECT_LT((m.normal_W - n).norm(), 1e-3);
      }
    }
  }
}

TEST(Collide, CrossedCylindersTouchAtTheirAxesClosestPoints) {
  const CollideShape a = cylinder(0.2, 0.5), b = cylinder(0.1, 0.4);
  const Pose xa = pose(Vec3::Zero(), rot(kPi / 2, Vec3::UnitY()));
  const Pose xb = pose(Vec3(0.1, -0.05, 0.299), rot(kPi / 2, Vec3::UnitX()) * rot(0.2, Vec3::UnitY()));
  const Manifold m = run(a, xa, b, xb);
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].id, collide_detail::kIdCrossed);
  EXPECT_NEAR(m.points[0].separation, -0.001, kExact);
  EXPECT_LT((m.normal_W - Vec3::UnitZ()).norm(), kExact);
  // B's axis runs at 0.2 rad from -y through (0.1, -0.05): it crosses A's (the x axis) at
  // x = 0.1 - 0.05 tan(0.2).
  EXPECT_LT((m.points[0].p_W - Vec3(0.1 - 0.05 * std::tan(0.2), 0, 0.1995)).norm(), kExact);
}

// Random cylinder-cylinder and capsule-cylinder poses touching within +-5 mm along a random
// direction (bisection on GJK's overlap test); orientations fully random, or B's axis within 2
// degrees of A's (caps on caps, sides along sides), or within 2 degrees of perpendicular (a side on
// a cap). Oracle GJK/EPA on the support functions. Overlapping: the deepest point is never
// shallower than EPA's depth (1e-6, and for caps on caps 1e-5 x size: the lens's deepest point is
// left out while within that of the four others' depth); apart, never closer than GJK's distance.
// The points from an exact feature pair (every id but kIdGeneric) lie on both surfaces (closed-form
// distance, 1e-9; a capsule within ~2.6 degrees of lying on a cap has its points where the clip
// put its ball's centre, inside the capsule by at most r (1 - cos 2.6 deg) = 1e-3 r).
struct PairStats {
  int overlapping = 0, exact_depth = 0, apart = 0, exact_gap = 0, generic = 0, multi = 0;
  std::map<uint32_t, int> tags;
};
PairStats random_cylinder_pairs(const CollideShape& a, const CollideShape& b, int family, uint64_t seed,
                                int count) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> D(-0.005, 0.005), T(-1, 1);
  std::normal_distribution<double> N;
  PairStats st;
  for (int it = 0; it < count; ++it) {
    const Pose xa = pose(Vec3::Zero(), random_rotation(g));
    Mat3 Rb = random_rotation(g);
    if (family > 0) {
      const Vec3 axis = Vec3(N(g), N(g), N(g)).normalized();
      Rb = xa.R * rot(family == 2 ? kPi / 2 : 0.0, Vec3::UnitX()) * rot(T(g) * 2 * kPi / 180, axis) *
           rot(T(g) * kPi, Vec3::UnitZ());
    }
    Pose xb = pose(Vec3::Zero(), Rb);
    Vec3 dir = Vec3(N(g), N(g), N(g)).normalized();
    if (family > 0 && it % 2 == 0) dir = (xa.R.col(2) + 0.3 * dir).normalized();  // over a cap
    double lo = 0, hi = 5;
    const collide_detail::Support SA(a, xa), SB(b, xb);
    for (int k = 0; k < 60; ++k) {
      xb.p = 0.5 * (lo + hi) * dir;
      const auto d = collide_detail::core_distance(SA, SB);
      (d.separation - SA.margin - SB.margin < 0 ? lo : hi) = 0.5 * (lo + hi);
    }
    xb.p = (hi + D(g)) * dir;
    const auto ref = collide_detail::core_distance(SA, SB);
    const double truth = ref.separation - SA.margin - SB.margin;
    const Manifold m = run(a, xa, b, xb, 0.01);
    if (truth < 0.01 - 1e-9) {
      EXPECT_GT(m.count, 0) << it;
    }
    if (m.count == 0) continue;
    double smin = INFINITY;
    bool lens = false;
    for (int i = 0; i < m.count; ++i) {
      smin = std::min(smin, m.points[i].separation);
      lens = lens || (m.points[i].id & 0xFFF8) == collide_detail::kIdLens;
      const uint32_t tag =
          m.points[i].id >= 0x40 && m.points[i].id < 0x50 ? m.points[i].id : m.points[i].id & 0xFFF8;
      ++st.tags[tag];
      if (m.points[i].id == collide_detail::kIdGeneric) {
        ++st.generic;
      } else {
        const ManifoldPoint& q = m.points[i];
        const double tol_a = (q.id & 0xFFF8) == collide_detail::kIdCapsuleCap ? 1e-3 * a.radius : 1e-9;
        EXPECT_NEAR(surface_distance(a, xa, q.p_W - 0.5 * q.separation * m.normal_W), 0.0, tol_a)
            << it << " id " << q.id;
        EXPECT_NEAR(surface_distance(b, xb, q.p_W + 0.5 * q.separation * m.normal_W), 0.0, 1e-9)
            << it << " id " << q.id;
      }
    }
    st.multi += m.count > 1;
    if (truth < 0) {
      ++st.overlapping;
      const double size = a.bounding_radius + b.bounding_radius;
      EXPECT_LE(smin, truth + std::max(1e-6, lens ? 1e-5 * size : 0.0)) << it;
      st.exact_depth += std::fabs(smin - truth) < 1e-6;
    } else {
      ++st.apart;
      EXPECT_GE(smin, truth - 1e-9) << it;
      st.exact_gap += std::fabs(smin - truth) < 1e-6;
    }
  }
  return st;
}

TEST(Collide, RandomCylinderPairsAgreeWithGjkEpa) {
  const CollideShape coin = cylinder(0.3, 0.05), can = cylinder(0.1, 0.15), caps = capsule(0.05, 0.2);
  for (int family = 0; family < 3; ++family) {
    for (int pair = 0; pair < 3; ++pair) {
      const CollideShape& a = pair == 2 ? caps : coin;
      const CollideShape& b = pair == 0 ? coin : can;
      const PairStats st = random_cylinder_pairs(a, b, family, 100 + 10 * family + pair, 300);
      std::string tags;
      for (const auto& [t, n] : st.tags) tags += " " + std::to_string(t) + ":" + std::to_string(n);
      std::printf(
          "[measure] family %d %s-%s: %d overlapping (%d at EPA's depth), %d apart (%d at GJK's gap), "
          "%d multi-point, %d generic points; tags%s\n",
          family, to_string(a.kind), to_string(b.kind), st.overlapping, st.exact_depth, st.apart,
          st.exact_gap, st.multi, st.generic, tags.c_str());
      EXPECT_GT(st.overlapping, 100);
      EXPECT_GT(st.apart, 100);
    }
  }
}

TEST(Collide, CylinderFeatureIdsPersistUnderSmallMotion) {
  const CollideShape coin = cylinder(0.3, 0.1), log = cylinder(0.1, 0.4), caps = capsule(0.03, 0.2);
  const Mat3 Ry = rot(kPi / 2, Vec3::UnitY());
  const Case cs[] = {
      {coin, pose(Vec3::Zero()), coin, pose(Vec3(0.05, 0.02, 0.199), rot(0.3, Vec3::UnitZ()))},
      {coin, pose(Vec3::Zero()), log, pose(Vec3(0.1, 0.05, 0.199), Ry)},
      {log, pose(Vec3::Zero(), Ry), log, pose(Vec3(0.3, 0, 0.199), Ry)},
      {caps, pose(Vec3(0.1, 0.1, 0.129), Ry), coin, pose(Vec3::Zero())},
      {caps, pose(Vec3(0.329, 0, 0.05)), coin, pose(Vec3::Zero())},
  };
  int k = 0;
  for (const Case& c : cs) {
    SCOPED_TRACE(k++);
    PairCache cache;
    Manifold m0, m1;
    collide(c.a, c.xa, c.b, c.xb, 0.01, cache, m0);
    ASSERT_GE(m0.count, 2);
    for (const Vec3& d : {Vec3(1e-5, 0, 0), Vec3(0, -1e-5, 0), Vec3(0, 0, 1e-5)}) {
      Pose x = c.xb;
      x.p += d;
      x.R = rot(1e-5, Vec3(1, 2, 3)) * x.R;
      collide(c.a, c.xa, c.b, x, 0.01, cache, m1);
      ASSERT_EQ(m1.count, m0.count);
      for (int i = 0; i < m0.count; ++i) {
        const int j = nearest(m1, m0.points[i].p_W);
        EXPECT_EQ(m1.points[j].id, m0.points[i].id);
        EXPECT_LT((m1.points[j].p_W - m0.points[i].p_W).norm(), 1e-4);
      }
    }
    std::vector<uint32_t> ids;
    for (int i = 0; i < m0.count; ++i) ids.push_back(m0.points[i].id);
    std::sort(ids.begin(), ids.end());
    EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
  }
}

TEST(Collide, NeverAllocates) {
  const CollideShape shapes[] = {plane(),
                                 sphere(0.3),
                                 capsule(0.2, 0.4),
                                 cylinder(0.3, 0.4),
                                 ellipsoid(Vec3(0.2, 0.3, 0.5)),
                                 box(Vec3(0.3, 0.4, 0.5)),
                                 hull(octahedron(0.6))};
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> U(-0.4, 0.4);
  std::vector<Pose> poses;
  for (int i = 0; i < 200; ++i) poses.push_back(pose(Vec3(U(g), U(g), 0.5 + U(g)), random_rotation(g)));
  const long before = g_allocations.load();
  int total = 0;
  for (int i = 0; i < 200; ++i) {
    PairCache cache;
    Manifold m;
    total += collide(shapes[i % 7], pose(Vec3::Zero()), shapes[(i / 7) % 7], poses[i], 0.05, cache, m);
  }
  // And the multi-point cylinder and capsule cases (caps on caps, a side on a cap, parallel sides,
  // a capsule on a cap and along a side).
  const CollideShape coin = cylinder(0.3, 0.1), log = cylinder(0.1, 0.4), caps = capsule(0.03, 0.2);
  const Mat3 Ry = rot(kPi / 2, Vec3::UnitY());
  const Pose xs[5][2] = {{pose(Vec3::Zero()), pose(Vec3(0.05, 0.02, 0.199))},
                         {pose(Vec3::Zero()), pose(Vec3(0.1, 0.05, 0.199), Ry)},
                         {pose(Vec3::Zero(), Ry), pose(Vec3(0.3, 0, 0.199), Ry)},
                         {pose(Vec3(0.1, 0.1, 0.129), Ry), pose(Vec3::Zero())},
                         {pose(Vec3(0.329, 0, 0.05)), pose(Vec3::Zero())}};
  const CollideShape* ss[5][2] = {
      {&coin, &coin}, {&coin, &log}, {&log, &log}, {&caps, &coin}, {&caps, &coin}};
  int multi = 0;
  for (int i = 0; i < 5; ++i) {
    PairCache cache;
    Manifold m;
    multi += collide(*ss[i][0], xs[i][0], *ss[i][1], xs[i][1], 0.05, cache, m) >= 2;
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(total, 0);
  EXPECT_EQ(multi, 5);
}

// Against a static triangle mesh too: a capsule and a box lying across a fine grid (1 cm cells),
// enough candidate points to fill a cluster and make the collector reduce it on the way.
TEST(Collide, MeshNeverAllocates) {
  const TriMeshShape tm = make_trimesh_shape(*trimesh_test::grid(60, 60, 0.01, -0.3, -0.3));
  const CollideShape mesh = collide_shapes::mesh(tm);
  const CollideShape cap = capsule(0.02, 0.2);
  const CollideShape slab = box(Vec3(0.2, 0.15, 0.02));
  const Mat3 Rx = rot(kPi / 2, Vec3::UnitY());  // the capsule's axis along x: lying
  const long before = g_allocations.load();
  int points = 0;
  for (int i = 0; i < 20; ++i) {
    const double shift = 0.003 * i;
    Manifold m[kMaxMeshManifolds];
    const Pose xc = pose(Vec3(shift, -shift, 0.0199), Rx);
    const int nc =
        collide_mesh(mesh, Pose{}, cap, xc, Vec3(-0.25, -0.05, -0.01), Vec3(0.25, 0.05, 0.05), 0.01, m);
    for (int k = 0; k < nc; ++k) points += m[k].count;
    const Pose xs = pose(Vec3(shift, shift, 0.0199));
    const int ns =
        collide_mesh(mesh, Pose{}, slab, xs, Vec3(-0.25, -0.2, -0.01), Vec3(0.25, 0.2, 0.05), 0.01, m);
    for (int k = 0; k < ns; ++k) points += m[k].count;
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(points, 0);
}

}  // namespace
}  // namespace simreel
