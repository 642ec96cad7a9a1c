// Detailed hulls (hundreds to thousands of vertices): a hull capped at N vertices
// (convex_polyhedron's max_vertices, the scene's hull_vertices), hill-climbing support against a
// scan, and hulls too detailed for the separating-axis test colliding through GJK/EPA and their
// supporting faces (polyhedra.cpp): resting at the height their geometry gives, at rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <set>

#include "sim/collision/narrow/internal.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"

namespace simreel {
namespace {

using namespace contact_test;

// n points on the ellipsoid with semi-axes r (every one an extreme point: the worst case for a hull).
std::vector<Vec3> ellipsoid_points(int n, const Vec3& r, uint64_t seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> N;
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) pts.push_back(Vec3(N(g), N(g), N(g)).normalized().cwiseProduct(r));
  return pts;
}

TEST(DetailedHull, CapKeepsAValidInnerHullOfAtMostThatManyVertices) {
  const std::vector<Vec3> pts = ellipsoid_points(3000, Vec3(0.5, 0.4, 0.3), 1);
  HullReduction full;
  const ConvexPolyhedron all = convex_polyhedron(pts, 0, &full);
  EXPECT_EQ(full.vertices_before, 3000);
  EXPECT_EQ(full.vertices, 3000);
  std::set<std::tuple<double, double, double>> input;
  for (const Vec3& p : pts) input.insert({p.x(), p.y(), p.z()});
  double last_ratio = 0;
  for (int cap : {16, 64, 256}) {
    HullReduction r;
    const ConvexPolyhedron h = convex_polyhedron(pts, cap, &r);
    EXPECT_EQ(polyhedron_problem(h), "") << cap;
    EXPECT_LE((int)h.vertices.size(), cap);
    EXPECT_GE((int)h.vertices.size(), cap - 8) << "the cap is used, not undershot";
    EXPECT_EQ(r.vertices_before, 3000);
    EXPECT_EQ(r.vertices, (int)h.vertices.size());
    for (const Vec3& v : h.vertices)
      EXPECT_TRUE(input.count({v.x(), v.y(), v.z()})) << "a vertex not an input point";
    // An inner hull: smaller, and closer to the full one as the cap grows (an ellipsoid is the
    // worst case; 64 vertices keep 89% of it).
    EXPECT_NEAR(r.volume_ratio, polyhedron_volume(h) / polyhedron_volume(all), 1e-12);
    EXPECT_LT(r.volume_ratio, 1.0);
    EXPECT_GT(r.volume_ratio, last_ratio);
    last_ratio = r.volume_ratio;
  }
  EXPECT_GT(last_ratio, 0.95);
  // A cap above the hull's size changes nothing.
  HullReduction r;
  const ConvexPolyhedron same = convex_polyhedron(pts, 5000, &r);
  EXPECT_EQ(same.vertices.size(), all.vertices.size());
  EXPECT_EQ(r.volume_ratio, 1.0);
}

// Climbing from the seeds reaches the maximum the scan finds (to rounding: both are d . v of hull
// vertices; a near-tie on a flat patch may stop at another vertex of the same value).
TEST(DetailedHull, ClimbingSupportFindsTheScansMaximum) {
  for (int n : {100, 3000}) {
    const ConvexPolyhedron h = convex_polyhedron(ellipsoid_points(n, Vec3(0.5, 0.4, 0.3), 2));
    ASSERT_GT((int)h.vertices.size(), ConvexPolyhedron::kScanVertices);
    ASSERT_EQ(h.vertex_edge.size(), h.vertices.size());
    std::mt19937_64 g(9);
    std::normal_distribution<double> N;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 d(N(g), N(g), N(g));
      double best = -INFINITY;
      for (const Vec3& v : h.vertices) best = std::max(best, d.dot(v));
      EXPECT_NEAR(d.dot(h.vertices[h.support(d)]), best, 1e-14 * d.norm()) << n << " points, direction " << k;
    }
  }
}

// A cylinder of radius 0.3 m and height 0.2 m as a hull of two 750-point rims (each cap one face
// of 750 vertices, 2,250 edges: 5 million edge pairs, far past the separating-axis test's limit).
std::shared_ptr<const ConvexPolyhedron> rim_hull() {
  std::vector<Vec3> pts;
  for (int i = 0; i < 750; ++i) {
    const double a = 2 * M_PI * i / 750;
    pts.push_back(Vec3(0.3 * std::cos(a), 0.3 * std::sin(a), -0.1));
    pts.push_back(Vec3(0.3 * std::cos(a + 0.002), 0.3 * std::sin(a + 0.002), 0.1));
  }
  return std::make_shared<const ConvexPolyhedron>(convex_polyhedron(pts));
}

BodyDef hull_body(const std::shared_ptr<const ConvexPolyhedron>& h, const Vec3& at, const Quat& q) {
  BodyDef b;
  b.name = "hull";
  b.p_WB = at;
  b.q_WB = q;
  Collider c;
  c.shape = ShapeKind::mesh;
  c.hulls = {h};
  c.props_C = cylinder_collider(0.3, 0.2, 800).props_C;  // (the hull is one to 1e-5 of its volume)
  b.add_collider(c);
  return b;
}

// Two of them stacked on the ground, the upper one 3 cm off-centre, turned 40 degrees and
// dropped from 1 cm: they come to rest where their geometry says (heights 0.1 and 0.3 m, each
// contact sunk by at most the solver's slop), and stay there (no creep or rocking from a
// reference face that changes from step to step).
TEST(DetailedHull, StackOfDetailedHullsRestsWhereItsGeometrySays) {
  const auto h = rim_hull();
  ASSERT_GT((long)h->edge_count() * h->edge_count(), 16384L);
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3::UnitZ()));
  std::vector<BodyDef> bodies{ground(), hull_body(h, Vec3(0, 0, 0.1), Quat::Identity()),
                              hull_body(h, Vec3(0.03, -0.01, 0.31), turn)};
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  World w(cfg, bodies);
  while (w.time() < 2.0) w.step();
  const Vec3 x1 = w.origin_position(1), x2 = w.origin_position(2);
  for (int k = 0; k < 240; ++k) w.step();
  const Vec3 y1 = w.origin_position(1), y2 = w.origin_position(2);
  const double slop = cfg.contacts.linear_slop;
  EXPECT_NEAR(y1.z(), 0.1, 2 * slop);
  EXPECT_NEAR(y2.z(), 0.3, 4 * slop);
  EXPECT_NEAR(y2.x(), 0.03, 1e-3);
  EXPECT_LT((y1 - x1).norm(), 1e-5) << "the lower hull creeps";
  EXPECT_LT((y2 - x2).norm(), 1e-5) << "the upper hull creeps";
  EXPECT_LT(w.linear_velocity(2).norm(), 1e-4);
  EXPECT_LT(w.angular_velocity(2).norm(), 1e-3);
  int pair_points = 0;
  for (const Contact& c : w.impl().contacts())
    if (c.body_a + c.body_b == 3) pair_points = c.count;
  EXPECT_GE(pair_points, 3) << "a face on a face";
}

// The profile names which pair kinds the narrow phase ran on and what they cost: the stack's
// plane-hull and hull-hull pairs once a step each (profiling on), nothing with profiling off.
TEST(DetailedHull, ProfileNamesThePairKinds) {
  const auto h = rim_hull();
  for (bool on : {true, false}) {
    World w(WorldConfig{}, {ground(), hull_body(h, Vec3(0, 0, 0.1), Quat::Identity()),
                            hull_body(h, Vec3(0.03, -0.01, 0.3), Quat::Identity())});
    w.set_profiling(on);
    for (int k = 0; k < 50; ++k) w.step();
    const Profile& p = w.impl().profile();
    const int plane = (int)CollideKind::plane, hull = (int)CollideKind::hull;
    EXPECT_STREQ(narrow_kind_name(plane), "plane");
    EXPECT_STREQ(narrow_kind_name(hull), "hull");
    long total = 0;
    for (int a = 0; a < Profile::kNarrowKinds; ++a)
      for (int b = 0; b < Profile::kNarrowKinds; ++b) total += p.narrow_calls[a][b];
    if (on) {
      EXPECT_EQ(p.narrow_calls[hull][hull], 50);
      EXPECT_EQ(p.narrow_calls[plane][hull], 50);  // (the upper hull is far above the ground)
      EXPECT_EQ(total, 100);
      EXPECT_GT(p.narrow_seconds[hull][hull], 0.0);
    } else {
      EXPECT_EQ(total, 0);
    }
  }
}

// The detailed path's manifold against GJK's distance: two hulls 3 mm apart (within the
// speculative distance) at random orientations report a separation within the facets' size of
// GJK's, and the normal within a few degrees of GJK's (the reference face's).
TEST(DetailedHull, ManifoldAgreesWithGjkDistance) {
  const ConvexPolyhedron h = convex_polyhedron(ellipsoid_points(1500, Vec3(0.5, 0.4, 0.3), 4));
  CollideShape s;
  s.kind = CollideKind::hull;
  s.hull = &h;
  s.bounding_radius = 0.5;
  std::mt19937_64 g(11);
  std::normal_distribution<double> N;
  for (int k = 0; k < 50; ++k) {
    Pose xa, xb;
    xa.R = Quat(N(g), N(g), N(g), N(g)).normalized().toRotationMatrix();
    xb.R = Quat(N(g), N(g), N(g), N(g)).normalized().toRotationMatrix();
    const Vec3 dir = Vec3(N(g), N(g), N(g)).normalized();
    // Place B along dir so that the gap is 3 mm (bisection on GJK's distance).
    double lo = 0, hi = 2;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      xb.p = mid * dir;
      bool ov;
      const collide_detail::CoreDistance d =
          collide_detail::gjk_distance(collide_detail::Support(s, xa), collide_detail::Support(s, xb), ov);
      (ov || d.separation < 0.003 ? lo : hi) = mid;
    }
    xb.p = hi * dir;
    bool ov;
    const collide_detail::CoreDistance d =
        collide_detail::gjk_distance(collide_detail::Support(s, xa), collide_detail::Support(s, xb), ov);
    ASSERT_FALSE(ov);
    PairCache cache;
    Manifold m;
    const int n = collide(s, xa, s, xb, 0.02, cache, m);
    ASSERT_GE(n, 1) << k;
    double smin = INFINITY;
    for (int i = 0; i < n; ++i) smin = std::min(smin, m.points[i].separation);
    EXPECT_NEAR(smin, d.separation, 2e-3) << k;
    EXPECT_GT(m.normal_W.dot(d.normal), std::cos(10 * M_PI / 180)) << k;
  }
}

}  // namespace
}  // namespace simreel
