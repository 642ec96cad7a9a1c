// Compound bodies in the broad phase (sim/collision/compound.hpp): a compound's tree finds every
// shape whose box overlaps a query or reaches a plane; a world's results are the same bit for bit
// whatever ContactSettings::compound_shapes is (pairs, sleeping, continuous collision, threads, a
// resume); and a body of many shapes that touches nothing costs the broad phase one box.
#include "sim/collision/compound.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <vector>

#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"

namespace simreel {
namespace {

using namespace contact_test;

// A body of n shapes of every convex kind, scattered in a 2 m cube at random orientations.
BodyDef scattered_body(int n, SplitMix64& r, const Vec3& at) {
  BodyDef b;
  b.name = "scattered";
  b.p_WB = at;
  for (int i = 0; i < n; ++i) {
    Collider c;
    switch (i % 5) {
      case 0:
        c = box_collider(Vec3(r.uniform(0.05, 0.3), r.uniform(0.05, 0.3), r.uniform(0.05, 0.3)), 500);
        break;
      case 1:
        c = sphere_collider(r.uniform(0.03, 0.2), 500);
        break;
      case 2:
        c = capsule_collider(r.uniform(0.03, 0.1), r.uniform(0.25, 0.5), 500);
        break;
      case 3:
        c = cylinder_collider(r.uniform(0.03, 0.15), r.uniform(0.05, 0.4), 500);
        break;
      default:
        c = ellipsoid_collider(Vec3(r.uniform(0.05, 0.2), r.uniform(0.05, 0.2), r.uniform(0.05, 0.2)), 500);
    }
    c.p_BC = Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
    c.q_BC = Quat(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)).normalized();
    b.add_collider(c);
  }
  return b;
}

// The tree against brute force: at random poses and speeds, every shape whose box (its tight world
// box grown by its margin, as the world makes it) overlaps a random query box, or reaches a random
// plane's side, is reported, and the compound's box holds every shape's box.
TEST(CompoundProxies, QueriesFindEveryShapeWhoseBoxMeetsThem) {
  SplitMix64 r(3);
  std::vector<BodyDef> defs{scattered_body(200, r, Vec3::Zero())};
  World w(WorldConfig{}, defs);
  std::vector<BodyModel> models{w.impl().model(0)};
  std::vector<std::string> notes;
  ShapeTable st(std::vector<BodyDef>{w.impl().def(0)}, models, notes);
  BodyExtents ext;
  ext.build(st, 1);
  std::vector<int> sweep(st.size());
  for (int k = 0; k < st.size(); ++k) sweep[k] = k;
  CompoundProxies cp;
  cp.build(st, ext, sweep, 8, 1);
  ASSERT_EQ(cp.count(), 1);
  ASSERT_EQ((int)cp.members(0).size(), 200);
  const double spec = 0.02, dt = 1.0 / 60;
  long reported = 0, needed = 0;
  for (int trial = 0; trial < 50; ++trial) {
    MotionState s;
    s.x_W = Vec3(r.uniform(-1e3, 1e3), r.uniform(-10, 10), r.uniform(-10, 10));
    s.q_WP = Quat(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)).normalized();
    s.v_W = Vec3(r.uniform(-20, 20), r.uniform(-20, 20), r.uniform(-20, 20)) * (trial % 2);
    s.w_P = Vec3(r.uniform(-30, 30), r.uniform(-30, 30), r.uniform(-30, 30)) * (trial % 3 ? 1 : 0);
    const Aabb outer = cp.place(0, s.q_WP.toRotationMatrix(), s.x_W, s.v_W.norm(), s.w_P.norm(), spec, dt);
    std::vector<Aabb> boxes(st.size());
    for (int k = 0; k < st.size(); ++k) {
      const Aabb b = ShapeTable::bounds(st[k].geom, ShapeTable::world_pose(st[k], s));
      const double margin = spec + (s.v_W.norm() + ext.shape_reach[k] * s.w_P.norm()) * dt;
      EXPECT_DOUBLE_EQ(margin, cp.member_margin(0, ext.shape_reach[k]));
      boxes[k] = Aabb{b.lo - Vec3::Constant(margin), b.hi + Vec3::Constant(margin)};
      ASSERT_TRUE(contains(outer, boxes[k])) << "trial " << trial << " shape " << k;
    }
    for (int q = 0; q < 20; ++q) {
      const Vec3 c = s.x_W + Vec3(r.uniform(-2, 2), r.uniform(-2, 2), r.uniform(-2, 2));
      const Vec3 h(r.uniform(0.001, 0.5), r.uniform(0.001, 0.5), r.uniform(0.001, 0.5));
      const Aabb box{c - h, c + h};
      std::vector<char> got(st.size(), 0);
      cp.query(0, box, [&](int k) { got[k] = 1, ++reported; });
      for (int k = 0; k < st.size(); ++k)
        if (boxes[k].overlaps(box)) {
          ++needed;
          ASSERT_TRUE(got[k]) << "trial " << trial << " shape " << k;
        }
      const Vec3 n = Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)).normalized();
      const double d = n.dot(c);
      std::fill(got.begin(), got.end(), 0);
      cp.query_plane(0, n, d, [&](int k) { got[k] = 1; });
      for (int k = 0; k < st.size(); ++k) {
        if (!box_reaches_plane(n, d, boxes[k])) continue;
        ASSERT_TRUE(got[k]) << "plane, trial " << trial << " shape " << k;
      }
    }
  }
  // The queries are not the whole compound: the tree turns most shapes away.
  EXPECT_GT(needed, 100);
  EXPECT_LT(reported, 3 * needed + 50 * 20 * 4);
}

// A scene with compounds of every kind: a static wall of 10 boxes; a body of 12 spheres and boxes
// dropped onto 6 loose boxes; a rod of 10 boxes thrown at the wall at 40 m/s (swept by continuous
// collision); a ball shot through the dropped body's place; all on the ground, falling asleep.
std::vector<BodyDef> rubble() {
  std::vector<BodyDef> b{ground()};
  BodyDef wall;
  wall.name = "wall";
  wall.type = BodyType::static_body;
  wall.p_WB = Vec3(4, 0, 0);
  for (int i = 0; i < 10; ++i) {
    Collider c = box_collider(Vec3(0.2, 0.4, 1.0), 1000);
    c.p_BC = Vec3(0, -2 + 0.4 * i, 0.5);
    wall.add_collider(c);
  }
  b.push_back(wall);
  for (int i = 0; i < 6; ++i)
    b.push_back(box(Vec3::Constant(0.3), Vec3(-0.4 + 0.3 * (i % 3), 0.16 * (i / 3), 0.15)));
  BodyDef lump;
  lump.name = "lump";
  lump.p_WB = Vec3(0, 0, 1.2);
  lump.q_WB = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 0).normalized()));
  for (int i = 0; i < 12; ++i) {
    Collider c = i % 2 ? box_collider(Vec3(0.15, 0.2, 0.1), 800) : sphere_collider(0.09, 800);
    c.p_BC = Vec3(0.2 * (i % 4) - 0.3, 0.2 * (i / 4) - 0.2, 0.05 * (i % 3));
    lump.add_collider(c);
  }
  lump.w_W = Vec3(1, -2, 0.5);
  b.push_back(lump);
  BodyDef rod;
  rod.name = "rod";
  rod.p_WB = Vec3(1.5, 1.0, 0.5);
  for (int i = 0; i < 10; ++i) {
    Collider c = box_collider(Vec3(0.08, 0.08, 0.08), 2000);
    c.p_BC = Vec3(0, 0.08 * i - 0.36, 0);
    rod.add_collider(c);
  }
  rod.v_W = Vec3(40, 0, 1);
  rod.w_W = Vec3(0, 0, 3);
  b.push_back(rod);
  BodyDef ball = sphere(0.05, Vec3(-3, 0, 0.6));
  ball.name = "ball";
  ball.v_W = Vec3(30, 0, 0);
  b.push_back(ball);
  return b;
}

struct Trace {
  std::vector<uint64_t> hashes;
  std::vector<size_t> contacts;
  long swept = 0, moves = 0;
  int asleep = 0;
  std::string saved;
};

Trace run_rubble(int compound_shapes, int threads, double t_end, const std::string* resume_from = nullptr) {
  WorldConfig c;
  c.threads = threads;
  c.contacts.compound_shapes = compound_shapes;
  World w(c, rubble());
  if (resume_from) {
    std::istringstream is(*resume_from);
    w.restore_state(is);
  }
  Trace t;
  while (w.time() < t_end - 1e-9) {
    w.step();
    t.contacts.push_back(w.impl().contacts().size());
    if (w.impl().steps() % 24 == 0) t.hashes.push_back(state_hash(w));
    if (!resume_from && w.impl().steps() == 480) {
      std::ostringstream os;
      w.save_state(os);
      t.saved = os.str();
    }
  }
  t.hashes.push_back(state_hash(w));
  t.swept = w.impl().profile().swept_bodies;
  t.moves = w.impl().profile().fat_box_moves;
  t.asleep = w.sleeping_count();
  return t;
}

TEST(Compound, ResultsDoNotDependOnWhichBodiesAreCompounds) {
  const Trace plain = run_rubble(0, 1, 4.0);
  // The scene does what it is for: contacts, sweeps, sleep.
  EXPECT_GT(plain.swept, 0);
  EXPECT_GE(plain.asleep, 6);
  EXPECT_GT(*std::max_element(plain.contacts.begin(), plain.contacts.end()), (size_t)8);
  for (int cs : {2, 8, 11}) {
    for (int threads : {1, 2}) {
      const Trace t = run_rubble(cs, threads, 4.0);
      EXPECT_EQ(t.hashes, plain.hashes) << "compound_shapes " << cs << ", threads " << threads;
      EXPECT_EQ(t.contacts, plain.contacts) << "compound_shapes " << cs << ", threads " << threads;
      EXPECT_LT(t.moves, plain.moves) << "compound_shapes " << cs;
    }
  }
  // Resumed at 2 s (a compound asleep, another awake) into a world with compounds.
  const Trace resumed = run_rubble(8, 1, 4.0, &plain.saved);
  ASSERT_FALSE(resumed.hashes.empty());
  EXPECT_EQ(resumed.hashes.back(), plain.hashes.back());
}

// 2,000 spheres in one body falling for 60 steps far above the ground: one fat box a step at most
// (none once its margin leads its fall) against 2,000 at the start without the compound.
TEST(Compound, AFreeBodyOfManyShapesEntersTheBroadPhaseOnce) {
  SplitMix64 r(5);
  BodyDef cloud;
  cloud.name = "cloud";
  cloud.p_WB = Vec3(0, 0, 100);
  for (int i = 0; i < 2000; ++i) {
    Collider c = sphere_collider(0.05, 1000);
    c.p_BC = Vec3(r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-3, 3));
    cloud.add_collider(c);
  }
  for (int cs : {8, 0}) {
    WorldConfig c;
    c.contacts.compound_shapes = cs;
    World w(c, std::vector<BodyDef>{ground(), cloud});
    const double z0 = w.impl().state(1).x_W.z();
    for (int i = 0; i < 60; ++i) w.step();
    const Profile& p = w.impl().profile();
    if (cs > 0)
      EXPECT_LE(p.fat_box_moves, 61);
    else
      EXPECT_GE(p.fat_box_moves, 2000);
    EXPECT_EQ(w.impl().contacts().size(), 0u);
    EXPECT_NEAR(w.impl().state(1).x_W.z() - z0, -0.5 * 9.81 * 0.25 * 0.25, 1e-9);
  }
}

}  // namespace
}  // namespace simreel
