// Static triangle meshes as colliders (sim/geometry/trimesh.*, sim/geometry/bvh.*, sim/collision/narrow/triangles.cpp,
// sim/world/mesh_pairs.cpp), against closed forms and against the plane's own pair functions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "sim/geometry/bvh.hpp"
#include "sim/collision/narrow/internal.hpp"
#include "sim/collision/narrow/mesh.hpp"
#include "sim/dynamics/mesh_collider.hpp"
#include "sim/mass/primitives.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/geometry/trimesh.hpp"
#include "tests/sim/collision/collide_shapes.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"
#include "tests/sim/collision/trimesh_fixtures.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

using namespace contact_test;
using namespace trimesh_test;
constexpr double g = 9.81;

// ------------------------------------------------------------------ the tree

// Every query returns exactly the boxes that overlap it (brute force), each once, and the tree is
// balanced (median splits: depth <= log2(n / leaf) + 2).
TEST(Bvh, QueryFindsExactlyTheOverlappingBoxes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-10, 10), S(0, 1);
  const int n = 5000;
  std::vector<Vec3> lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    lo[i] = Vec3(U(rng), U(rng), U(rng));
    hi[i] = lo[i] + Vec3(S(rng), S(rng), S(rng));
  }
  Bvh t;
  t.build(lo, hi);
  EXPECT_LE(t.depth(), (int)std::ceil(std::log2(n / (double)Bvh::kLeafSize)) + 2);
  for (int q = 0; q < 300; ++q) {
    const Vec3 a(U(rng), U(rng), U(rng));
    const Vec3 b = a + 3 * Vec3(S(rng), S(rng), S(rng));
    std::vector<int> got, want;
    t.query(a, b, [&](int i) { got.push_back(i); });
    for (int i = 0; i < n; ++i)
      if (!(lo[i].x() > b.x() || a.x() > hi[i].x() || lo[i].y() > b.y() || a.y() > hi[i].y() ||
            lo[i].z() > b.z() || a.z() > hi[i].z()))
        want.push_back(i);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, want) << "query " << q;
  }
}

// ------------------------------------------------------------------ edges

// A flat grid's inner edges are inactive and its rim active; a ridge (convex fold of 20 degrees)
// is active on both sides, a valley (concave) inactive, a fold of 2 degrees (below the 5 degree
// threshold) inactive.
TEST(TriMesh, EdgesAreActiveWhereConvexAndOnTheBoundary) {
  const TriMeshShape flat = make_trimesh_shape(*grid(4, 4, 1.0, 0, 0));
  int inner_active = 0, rim = 0;
  for (const MeshTriangle& T : flat.triangles)
    for (int k = 0; k < 3; ++k) {
      const bool boundary = T.out_nb[k].isZero();
      rim += boundary;
      if (!boundary && (T.active >> k & 1)) ++inner_active;
      if (boundary) {
        EXPECT_TRUE(T.active >> k & 1);
      }
    }
  EXPECT_EQ(inner_active, 0);
  EXPECT_EQ(rim, 16);
  auto fold = [](double deg_) {  // two cells folded along x = 1 by deg_ (> 0: ridge)
    const double s = std::tan(deg_ * M_PI / 180);
    return make_trimesh_shape(
        *grid(2, 1, 1.0, 0, 0, [s](double x, double) { return -s * std::fabs(x - 1); }));
  };
  auto fold_edge_active = [](const TriMeshShape& m) {
    int active = 0, total = 0;
    for (const MeshTriangle& T : m.triangles)
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = m.vertices[T.v[k]], b = m.vertices[T.v[(k + 1) % 3]];
        if (std::fabs(a.x() - 1) < 1e-12 && std::fabs(b.x() - 1) < 1e-12)
          ++total, active += T.active >> k & 1;
      }
    EXPECT_EQ(total, 2);
    return active;
  };
  EXPECT_EQ(fold_edge_active(fold(20)), 2);
  EXPECT_EQ(fold_edge_active(fold(-20)), 0);
  EXPECT_EQ(fold_edge_active(fold(2)), 0);
}

// ------------------------------------------------------------------ narrow phase against the plane

CollideShape shape_of(CollideKind k) {
  using namespace collide_shapes;
  const Vec3 h(0.21, 0.13, 0.09);
  switch (k) {
    case CollideKind::sphere:
      return sphere(0.13);
    case CollideKind::capsule:
      return capsule(0.07, 0.2);
    case CollideKind::cylinder:
      return cylinder(0.15, 0.1);
    case CollideKind::ellipsoid:
      return ellipsoid(Vec3(0.2, 0.12, 0.08));
    case CollideKind::box:
      return box(h);
    default:
      return hull(make_box_polyhedron(h));
  }
}

// A shape on (or just into, or just above) a finely triangulated flat grid touches it exactly as
// it touches the plane z = 0 (plane pair functions, collide.cpp): one manifold, normal +z, the same
// deepest separation (1e-9 m) and the same support polygon (each plane point found in the mesh's
// manifold, 1e-9 m), whatever the pose and wherever the shape sits over the triangles' edges.
TEST(TriMeshCollide, EveryShapeOnAFlatGridTouchesAsOnThePlane) {
  TriMeshShape tm = make_trimesh_shape(*grid(40, 40, 0.05, -1, -1));
  const CollideShape mesh = collide_shapes::mesh(tm);
  const CollideShape plane = collide_shapes::plane();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-0.5, 0.5), A(-M_PI, M_PI);
  int checked = 0;
  for (CollideKind k : {CollideKind::sphere, CollideKind::capsule, CollideKind::cylinder,
                        CollideKind::ellipsoid, CollideKind::box, CollideKind::hull}) {
    const CollideShape s = shape_of(k);
    for (int it = 0; it < 200; ++it) {
      // Resting poses (a face, side or end down) and random tilts.
      Quat q = Quat::Identity();
      if (it % 4 == 1) q = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()));
      if (it % 4 >= 2) q = Quat(Eigen::AngleAxisd(A(rng), Vec3(U(rng), U(rng), U(rng)).normalized()));
      q = Quat(Eigen::AngleAxisd(A(rng), Vec3::UnitZ())) * q;
      Pose xb;
      xb.R = q.toRotationMatrix();
      xb.p = Vec3(U(rng), U(rng), 0);
      // Height so the lowest point is at depth d in [-1 mm, +1 mm] (negative: overlap).
      collide_detail::Support sup(s, xb);
      const double lowest = sup.support_W(Vec3(0, 0, -1)).z() - sup.margin;
      xb.p.z() += -lowest + 1e-3 * (2 * std::fmod(it * 0.618, 1.0) - 1);
      PairCache cache;
      Manifold ref;
      const int nref = collide(plane, Pose{}, s, xb, 0.01, cache, ref);
      Manifold got[kMaxMeshManifolds];
      const Aabb box = ShapeTable::bounds(s, xb);
      const int nm = collide_mesh(mesh, Pose{}, s, xb, box.lo - Vec3::Constant(0.01),
                                  box.hi + Vec3::Constant(0.01), 0.01, got);
      ASSERT_EQ(nm, nref > 0 ? 1 : 0) << to_string(k) << " " << it;
      if (nref == 0) continue;
      EXPECT_NEAR(got[0].normal_W.z(), 1.0, 1e-12) << to_string(k) << " " << it;
      double dref = INFINITY, dgot = INFINITY;
      for (int i = 0; i < ref.count; ++i) dref = std::min(dref, ref.points[i].separation);
      for (int i = 0; i < got[0].count; ++i) dgot = std::min(dgot, got[0].points[i].separation);
      EXPECT_NEAR(dgot, dref, 1e-9) << to_string(k) << " " << it;
      // The plane's points (its reduction of the same candidates) lie in the mesh's manifold's
      // support polygon: each is one of its points, or (a reduced box face) a corner it also has.
      if (ref.count <= 2 || k == CollideKind::cylinder)
        for (int i = 0; i < ref.count; ++i) {
          double best = INFINITY;
          for (int j = 0; j < got[0].count; ++j)
            best = std::min(best, (got[0].points[j].p_W - ref.points[i].p_W).norm());
          EXPECT_LT(best, 1e-9) << to_string(k) << " " << it << " point " << i;
        }
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

using namespace contact_test;
using namespace trimesh_test;

// ------------------------------------------------------------------ several faces at once

// A sphere in the crease of a floor and a wall (one L-shaped mesh, 90 degree concave fold) touches
// both: two manifolds, normals +z and +x, each 1 mm deep (closed form: the distances to the two
// planes). Inner edges of each face are inactive and give nothing extra.
TEST(TriMeshCollide, SphereInACreaseGetsOneManifoldPerFace) {
  const auto L = param_grid(20, 10, -1, 1, -0.5, 0.5,
                            [](double u, double v) { return u < 0 ? Vec3(0, v, -u) : Vec3(u, v, 0); });
  TriMeshShape tm = make_trimesh_shape(*L);
  const CollideShape mesh = collide_shapes::mesh(tm);
  const CollideShape s = collide_shapes::sphere(0.1);
  for (double y : {0.0, 0.05, 0.0123}) {
    Pose xb;
    xb.p = Vec3(0.099, y, 0.099);
    Manifold m[kMaxMeshManifolds];
    const int n =
        collide_mesh(mesh, Pose{}, s, xb, xb.p - Vec3::Constant(0.12), xb.p + Vec3::Constant(0.12), 0.01, m);
    ASSERT_EQ(n, 2) << y;
    int floor = m[0].normal_W.z() > 0.5 ? 0 : 1;
    EXPECT_NEAR((m[floor].normal_W - Vec3::UnitZ()).norm(), 0, 1e-12);
    EXPECT_NEAR((m[1 - floor].normal_W - Vec3::UnitX()).norm(), 0, 1e-12);
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(m[k].count, 1);
      EXPECT_NEAR(m[k].points[0].separation, -1e-3, 1e-12);
    }
  }
}

// A sphere near the edges and corners of a closed box mesh (the 1 cm x 50 x 50 cm wall of
// tests/sim/collision/continuous_mesh_test.cpp, 5 cm cells), within a speculative distance as large as a fast
// ball's (10 cm): every contact along an edge's or a vertex's own normal (not a face normal) is
// at the sphere's nearest point of the box, closed form: normal (q - c) / |q - c| and separation
// |q - c| - r with c the centre q clamped to the box. A vertex farther along a convex edge is not
// the nearest point; its contact, tilted along the edge, is a ghost (a ball sliding off the edge
// was kicked away from the face by one: CcdMesh.SphereSlidingOffTheMeshWallsEdgeKeepsItsVelocity).
// And apart, the deepest point is that one (the mesh never reports less than the distance).
TEST(TriMeshCollide, SphereEdgeAndVertexContactsOnABoxAreAtItsNearestPoint) {
  const Vec3 h(0.005, 0.25, 0.25);
  const int cells[3] = {1, 10, 10};
  TriMeshShape tm = make_trimesh_shape(*cuboid(h, cells));
  const CollideShape mesh = collide_shapes::mesh(tm);
  const CollideShape s = collide_shapes::sphere(0.025);
  const double spec = 0.1;
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> U(-1, 1), D(0, 0.03);
  int edge_contacts = 0;
  double worst = 0;
  for (int it = 0; it < 2000; ++it) {
    // Past an edge or a corner: two or three coordinates beyond the box, by up to 3 cm.
    Vec3 q(U(rng) * h.x(), U(rng) * h.y(), U(rng) * h.z());
    const int a = it % 3, b = (it / 3) % 3;
    q[a] = (U(rng) < 0 ? -1 : 1) * (h[a] + D(rng));
    if (b != a) q[b] = (U(rng) < 0 ? -1 : 1) * (h[b] + D(rng));
    if (it % 7 == 0)
      q = Vec3((U(rng) < 0 ? -1 : 1) * (h.x() + D(rng)), (U(rng) < 0 ? -1 : 1) * (h.y() + D(rng)),
               (U(rng) < 0 ? -1 : 1) * (h.z() + D(rng)));
    const Vec3 c = q.cwiseMax(-h).cwiseMin(h);
    const double dist = (q - c).norm();
    if (dist < 1e-6) continue;
    const Vec3 n_true = (q - c) / dist;
    Pose xb;
    xb.p = q;
    Manifold m[kMaxMeshManifolds];
    const int nm = collide_mesh(mesh, Pose{}, s, xb, q - Vec3::Constant(s.radius + spec),
                                q + Vec3::Constant(s.radius + spec), spec, m);
    double deepest = INFINITY;
    for (int i = 0; i < nm; ++i) {
      for (int j = 0; j < m[i].count; ++j) deepest = std::min(deepest, m[i].points[j].separation);
      if (m[i].normal_W.cwiseAbs().maxCoeff() > 1 - 1e-12) continue;  // a face's normal
      ++edge_contacts;
      for (int j = 0; j < m[i].count; ++j) {
        const double err = std::max((m[i].normal_W - n_true).norm(),
                                    std::fabs(m[i].points[j].separation - (dist - s.radius)));
        worst = std::max(worst, err);
        EXPECT_LT(err, 1e-9) << "sphere at " << q.transpose() << ": normal " << m[i].normal_W.transpose()
                             << " separation " << m[i].points[j].separation << ", nearest "
                             << n_true.transpose() << " at " << dist - s.radius;
      }
    }
    // (Apart only: a sphere sunk into the 1 cm wall has its centre within a radius of the far face,
    // whose face contact, one-sided as it is, then counts too.)
    if (dist >= s.radius && dist - s.radius <= spec) {
      EXPECT_NEAR(deepest, dist - s.radius, 1e-9) << q.transpose();
    }
  }
  std::printf(
      "[measure] sphere near a box mesh's edges and corners: %d edge or vertex contacts, worst %.2e\n",
      edge_contacts, worst);
  EXPECT_GT(edge_contacts, 500);
}

// ------------------------------------------------------------------ in the world

// A sphere rolling (2 m/s, diagonally, so it crosses edges of all three directions) across a flat
// floor of 2 cm cells keeps its vertical velocity below 1 mm/s (the figure) and its speed
// as on a plane (1e-3, contact_test's rolling test). Without internal-edge handling it bumps.
TEST(TriMeshWorld, SphereRollingAcrossAFineFlatMeshDoesNotBump) {
  const double r = 0.1, v0 = 2.0;
  BodyDef b = sphere(r, Vec3(-1.5, -0.3, r), 0.6, 0);
  b.v_W = Vec3(v0, 0.25 * v0, 0);
  b.w_W = Vec3(-0.25 * v0 / r, v0 / r, 0);  // rolling: w = n x v / r
  World w(WorldConfig{}, {mesh_body(grid(200, 100, 0.02, -2, -1)), b});
  const double speed0 = b.v_W.norm();
  double vz = 0, lowest = 0;
  while (w.time() < 1.5) {
    w.step();
    if (w.time() < 0.1) continue;  // the first contact settles
    vz = std::max(vz, std::fabs(w.linear_velocity(1).z()));
    lowest = std::min(lowest, w.centroid(1).z() - r);
  }
  const double speed = w.linear_velocity(1).norm();
  std::printf(
      "[measure] sphere rolling on a 2 cm mesh: max |vz| %.3e m/s, speed %.6f (rel %.2e), deepest %.3e m\n",
      vz, speed, speed / speed0 - 1, -lowest);
  EXPECT_LT(vz, 1e-3);
  EXPECT_NEAR(speed / speed0, 1.0, 1e-3);
  EXPECT_LT(-lowest, 1e-3);
}

// A box sliding across the same kind of mesh stops after v0^2 / (2 mu g), as on a plane (1%,
// contact_test's tolerance), and rests level.
TEST(TriMeshWorld, BoxSlidingOnAFineMeshStopsAfterV0SquaredOverTwoMuG) {
  const double mu = 0.5, v0 = 3.0, s = 0.2;
  BodyDef b = box(Vec3::Constant(s), Vec3(0, 0.013, s / 2), mu, 0);
  b.v_W = Vec3(v0, 0, 0);
  World w(WorldConfig{}, {mesh_body(grid(75, 25, 0.02, -0.5, -0.25), mu), b});
  const double x0 = w.centroid(1).x();
  double vz = 0;
  for (int k = 0; k < 480; ++k) {
    w.step();
    if (w.time() > 0.1) vz = std::max(vz, std::fabs(w.linear_velocity(1).z()));
  }
  const double dist = w.centroid(1).x() - x0;
  const double expect = v0 * v0 / (2 * mu * g);
  const Vec3 up = w.rotation(1).col(2);
  std::printf(
      "[measure] box sliding on a 2 cm mesh: distance %.6f m, v0^2/(2 mu g) %.6f m, rel %.2e; max |vz| "
      "%.3e\n",
      dist, expect, dist / expect - 1, vz);
  EXPECT_NEAR(dist / expect, 1.0, 0.01);
  EXPECT_LT(w.linear_velocity(1).norm(), 1e-3);
  EXPECT_LT(vz, 1e-2);
  EXPECT_GT(up.z(), 1 - 1e-6);
}

// A sphere released on a triangulated 20 degree incline rolls down at 5/7 g sin(theta) (0.5%, as on
// a plane in contact_test); the mesh is tilted by its body's pose.
TEST(TriMeshWorld, SphereRollsDownATriangulatedInclineAtFiveSeventhsGSinTheta) {
  const double theta = deg(20), r = 0.1;
  const Quat q(Eigen::AngleAxisd(theta, Vec3::UnitX()));
  const Vec3 n = q * Vec3::UnitZ();
  const Vec3 down = q * Vec3(0, -1, 0);
  World w(WorldConfig{}, {mesh_body(grid(40, 240, 0.025, -0.5, -5.0), 0.5, q), sphere(r, r * n, 0.5, 0)});
  std::vector<double> ts, vs;
  double off = 0;
  while (w.time() < 1.5) {
    w.step();
    if (w.time() < 0.25) continue;
    ts.push_back(w.time());
    vs.push_back(down.dot(w.linear_velocity(1)));
    off = std::max(off, std::fabs(n.dot(w.linear_velocity(1))));
  }
  const double a = fit_line(ts, vs).b, expect = 5.0 / 7.0 * g * std::sin(theta);
  std::printf("[measure] incline mesh: a = %.6f, 5/7 g sin = %.6f, rel %.2e; max normal speed %.3e\n", a,
              expect, a / expect - 1, off);
  EXPECT_NEAR(a / expect, 1.0, 5e-3);
  EXPECT_LT(off, 1e-3);
}

// A box dropped across the ridge of a roof (two 15 degree slopes: the ridge's edges are active,
// so the box meets the ridge through GJK/EPA's edge contact) tips onto the right-hand slope and
// rests flat on it (mu 0.8 > tan 15 degrees): a face normal along the slope's normal (1e-3 rad),
// its centre half its size above the slope's plane (within 1 mm: the soft contact's sink).
TEST(TriMeshWorld, BoxDroppedOnARidgeRestsFlatOnOneSlope) {
  const double a = deg(15), h = 0.1;
  const auto roof =
      grid(40, 20, 0.05, -1, -0.5, [a](double x, double) { return -std::tan(a) * std::fabs(x); });
  World w(WorldConfig{}, {mesh_body(roof, 0.8), box(Vec3::Constant(2 * h), Vec3(0.06, 0.01, 0.25), 0.8, 0)});
  while (w.time() < 3) w.step();
  const Vec3 n(std::sin(a), 0, std::cos(a));  // the right-hand slope's normal
  double best = 0;
  for (int k = 0; k < 3; ++k) best = std::max(best, std::fabs(w.rotation(1).col(k).dot(n)));
  const double height = n.dot(w.centroid(1));  // the slope's plane passes through the origin
  std::printf(
      "[measure] box on a ridge: face normal off the slope's by %.3e rad, centre %.6f m above it, speed "
      "%.2e\n",
      std::acos(std::min(1.0, best)), height, w.linear_velocity(1).norm());
  EXPECT_GT(w.centroid(1).x(), 0.0);  // on the right-hand slope
  EXPECT_GT(best, std::cos(1e-3));
  EXPECT_NEAR(height, h, 1e-3);
  EXPECT_LT(w.linear_velocity(1).norm(), 1e-2);
}

// Every dynamic shape kind dropped onto bumpy terrain (a coarse height field with convex and
// concave edges, so every path runs: faces, active edges and vertices by GJK/EPA, internal edges)
// lands, never sinks deeper than 1 cm into it, and is still above it after 3 s. (Measured 5.6 mm:
// the cylinder, struck by the box, tumbling across a crease at 0.9 m/s; the landings at 3.4 m/s
// sink at most 3.1 mm.)
TEST(TriMeshWorld, EveryShapeLandsOnBumpyTerrain) {
  const auto terrain = grid(16, 16, 0.25, -2, -2,
                            [](double x, double y) { return 0.15 * std::sin(2 * x) * std::cos(1.5 * y); });
  const TriMeshShape tm = make_trimesh_shape(*terrain);
  std::vector<BodyDef> bodies{mesh_body(terrain, 0.6)};
  std::vector<Vec3> at;
  for (int k = 0; k < 6; ++k) at.push_back(Vec3(-1.2 + 0.5 * k, 0.3 * std::sin(k), 0.6));
  bodies.push_back(sphere(0.15, at[0]));
  bodies.push_back(capsule(0.08, 0.4, at[1]));
  bodies.push_back(box(Vec3(0.3, 0.2, 0.15), at[2], 0.6, 0, 1000,
                       Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()))));
  {
    BodyDef c;
    c.name = "cylinder";
    c.p_WB = at[3];
    c.q_WB = Quat(Eigen::AngleAxisd(1.2, Vec3::UnitX()));
    Collider k;
    k.shape = ShapeKind::cylinder;
    k.radius = 0.15;
    k.height = 0.1;
    k.props_C = cylinder_mass(0.15, 0.1, 1000);
    c.add_collider(k);
    bodies.push_back(c);
  }
  {
    BodyDef e;
    e.name = "ellipsoid";
    e.p_WB = at[4];
    Collider k;
    k.shape = ShapeKind::ellipsoid;
    k.radii = Vec3(0.2, 0.12, 0.08);
    k.props_C = ellipsoid_mass(k.radii, 1000);
    e.add_collider(k);
    bodies.push_back(e);
  }
  {
    // A mesh on a dynamic body collides as its hull: an octahedron.
    auto oct = std::make_shared<TriangleMesh>();
    oct->vertices = {Vec3(0.15, 0, 0),  Vec3(-0.15, 0, 0), Vec3(0, 0.15, 0),
                     Vec3(0, -0.15, 0), Vec3(0, 0, 0.15),  Vec3(0, 0, -0.15)};
    oct->triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    BodyDef o;
    o.name = "octahedron";
    o.p_WB = at[5];
    o.add_collider(mesh_collider(oct, 1000));
    bodies.push_back(o);
  }
  World w(WorldConfig{}, bodies);
  double deepest = 0;
  while (w.time() < 3) {
    w.step();
    for (const Contact& c : w.impl().contacts())
      for (int j = 0; j < c.count; ++j) deepest = std::max(deepest, -c.points[j].separation);
  }
  std::printf("[measure] shapes on bumpy terrain: deepest overlap %.3e m over 3 s\n", deepest);
  EXPECT_LT(deepest, 1e-2);
  for (int i = 1; i < w.body_count(); ++i) {
    const Vec3 c = w.centroid(i);
    const double ground = 0.15 * std::sin(2 * c.x()) * std::cos(1.5 * c.y());
    EXPECT_GT(c.z(), ground) << w.def(i).name;          // above the terrain, not through it
    EXPECT_LT(c.z(), ground + 0.3) << w.def(i).name;    // and landed
    EXPECT_LT(std::fabs(c.x()), 2.0) << w.def(i).name;  // on it
  }
  (void)tm;
}

// Saved state round-trips with mesh contacts present (several manifolds of one pair included): a
// resumed run equals the straight one bit for bit.
TEST(TriMeshWorld, ResumeEqualsStraightRunWithMeshContacts) {
  auto bodies = [] {
    const auto L = param_grid(20, 10, -1, 1, -0.5, 0.5,
                              [](double u, double v) { return u < 0 ? Vec3(0, v, -u) : Vec3(u, v, 0); });
    BodyDef ball = sphere(0.1, Vec3(0.3, 0, 0.1), 0.6, 0);
    ball.v_W = Vec3(-1.0, 0.2, 0);  // rolls into the crease
    BodyDef cube = box(Vec3::Constant(0.2), Vec3(0.6, 0.2, 0.1), 0.5, 0);
    cube.v_W = Vec3(-1.5, 0, 0);
    return std::vector<BodyDef>{mesh_body(L), ball, cube};
  };
  World straight(WorldConfig{}, bodies());
  while (straight.time() < 0.3) straight.step();
  int multi = 0;
  for (size_t k = 1; k < straight.impl().contacts().size(); ++k)
    multi += straight.impl().contacts()[k].key() == straight.impl().contacts()[k - 1].key();
  std::stringstream saved;
  straight.save_state(saved);
  World resumed(WorldConfig{}, bodies());
  resumed.restore_state(saved);
  while (straight.time() < 1.5) {
    straight.step();
    resumed.step();
    for (size_t k = 1; k < straight.impl().contacts().size(); ++k)
      multi += straight.impl().contacts()[k].key() == straight.impl().contacts()[k - 1].key();
  }
  EXPECT_GT(multi, 0);  // the pair of the ball and the L had two manifolds at some step
  EXPECT_EQ(state_hash(straight), state_hash(resumed));
}

}  // namespace
}  // namespace simreel
