// The article's interface (space conversions, centroid and origin, forces), the NaN guard and
// determinism across thread counts.
#include <gtest/gtest.h>

#include <cstring>

#include <simreel/error.hpp>
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/fixtures/state_hash.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

// An L-shaped body of two boxes, so the centroid is away from the origin and P differs from B.
BodyDef l_body() {
  BodyDef b;
  b.name = "ell";
  for (auto [size, at] :
       {std::pair{Vec3(2, 1, 1), Vec3(1, 0.5, 0.5)}, std::pair{Vec3(1, 1, 1), Vec3(0.5, 1.5, 0.5)}}) {
    Collider c;
    c.size = size;
    c.props_C = box_mass(size, 10.0);
    c.p_BC = at;
    b.add_collider(c);
  }
  b.p_WB = Vec3(3, -2, 7);
  b.q_WB = Quat(Eigen::AngleAxisd(1.1, Vec3(1, 1, 0).normalized()));
  b.w_W = Vec3(0.3, -2, 1);
  b.v_W = Vec3(1, 2, 3);
  return b;
}

TEST(World, SpaceConversionsRoundTrip) {
  World w(WorldConfig{}, {l_body()});
  const Vec3 p(0.3, -1.2, 2.5);
  EXPECT_LT((w.world_to_local(0, w.local_to_world(0, p)) - p).norm(), 1e-14 * 10);
  EXPECT_LT((w.world_to_local_vec(0, w.local_to_world_vec(0, p)) - p).norm(), 1e-15 * 10);
  // The body origin maps to the position given; the local centroid to the world centroid.
  EXPECT_LT((w.local_to_world(0, Vec3::Zero()) - Vec3(3, -2, 7)).norm(), 1e-14 * 10);
  EXPECT_LT((w.local_to_world(0, w.local_centroid(0)) - w.centroid(0)).norm(), 1e-14 * 10);
  EXPECT_LT((w.local_centroid(0) - Vec3(5.0 / 6, 5.0 / 6, 0.5)).norm(), 1e-15);
  // A vector ignores the position; the rotation's inverse is its transpose.
  EXPECT_LT((w.rotation(0) * w.inverse_rotation(0) - Mat3::Identity()).norm(), 1e-15);
  EXPECT_LT((w.angular_velocity(0) - Vec3(0.3, -2, 1)).norm(), 1e-15 * 3);
}

TEST(World, OriginAndCentroidStayConsistentThroughSteps) {
  World w(WorldConfig{}, {l_body()});
  for (int k = 0; k < 100; ++k) w.step();
  const Vec3 p = w.origin_position(0);
  w.set_origin_position(0, p);
  EXPECT_LT((w.origin_position(0) - p).norm(), 1e-13 * p.norm());
  EXPECT_LT((w.centroid(0) - (p + w.rotation(0) * w.local_centroid(0))).norm(), 1e-13 * p.norm());
}

TEST(World, ForceAtTheCentroidMakesNoTorque) {
  World w(WorldConfig{}, {l_body()});
  const Vec3 L0 = w.angular_momentum(0);
  w.apply_force(0, Vec3(10, -4, 3), w.centroid(0));
  w.step();
  // The default integrator conserves L exactly in the absence of torque, up to RK4's truncation.
  EXPECT_LT((w.angular_momentum(0) - L0).norm(), 1e-10 * L0.norm());
}

TEST(World, WorldInverseInertiaIsTheInverseOfTheWorldInertia) {
  World w(WorldConfig{}, {l_body()});
  for (int k = 0; k < 10; ++k) w.step();
  EXPECT_LT((w.inverse_inertia_world(0) * w.inertia_world(0) - Mat3::Identity()).norm(), 1e-14);
}

TEST(World, ZeroAngularVelocityStaysFiniteInEveryIntegrator) {
  // The article normalises w to get the rotation axis, which is NaN for w = 0.
  for (Integrator m : {Integrator::seed, Integrator::euler_gyro, Integrator::rk4, Integrator::splitting,
                       Integrator::automatic}) {
    WorldConfig c;
    c.integrator = m;
    BodyDef b = l_body();
    b.w_W = Vec3::Zero();
    World w(c, {b});
    const Quat q0 = w.orientation(0);
    for (int k = 0; k < 10; ++k) w.step();
    EXPECT_TRUE(w.orientation(0).coeffs().allFinite()) << to_string(m);
    EXPECT_LT((w.orientation(0).coeffs() - q0.coeffs()).norm(), 1e-15) << to_string(m);
  }
}

TEST(World, NonFiniteStateStopsTheRunNamingBodyAndTime) {
  // With two threads the check runs on each thread's own bodies; "victim" is in the second chunk.
  for (int threads : {1, 2}) {
    std::vector<BodyDef> bodies = {l_body(), l_body()};
    bodies[1].name = "victim";
    WorldConfig c;
    c.threads = threads;
    World w(c, bodies);
    for (int k = 0; k < 3; ++k) w.step();
    w.apply_force(1, Vec3(std::numeric_limits<double>::infinity(), 0, 0), w.centroid(1));
    try {
      w.step();
      ADD_FAILURE() << "infinite force went unnoticed with " << threads << " threads";
    } catch (const StateError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("victim"), std::string::npos) << msg;
      EXPECT_NE(msg.find("t = 0.0166"), std::string::npos) << msg;  // 4 steps of 1/240 s
    }
  }
}

TEST(World, BadBodiesAreRejected) {
  BodyDef b = l_body();
  b.q_WB = Quat(2, 0, 0, 0);
  EXPECT_THROW(World(WorldConfig{}, {b}), InputError);
  BodyDef empty;
  empty.name = "empty";
  EXPECT_THROW(World(WorldConfig{}, {empty}), InputError);
  WorldConfig c;
  c.dt = 0;
  EXPECT_THROW(World(c, {l_body()}), InputError);
}

TEST(World, StaticBodiesNeverMove) {
  BodyDef s = l_body();
  s.type = BodyType::static_body;
  World w(WorldConfig{}, {s, l_body()});
  const Vec3 p = w.origin_position(0);
  for (int k = 0; k < 100; ++k) w.step();
  EXPECT_EQ(w.origin_position(0), p);
  EXPECT_EQ(w.dynamic_count(), 1);
}

TEST(World, ThreadCountDoesNotChangeOneBit) {
  uint64_t hashes[3];
  for (int t = 1; t <= 3; ++t) {
    WorldConfig c;
    c.threads = t;
    World w(c, r2_free_boxes(500));
    for (int k = 0; k < 200; ++k) w.step();
    hashes[t - 1] = state_hash(w);
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

// rk4 and auto step torque-free bodies four at a time in vector lanes and the rest one by one;
// which bodies share a block depends on the body count and the thread split. A body must come out
// bit-identical either way: each alone in its own world against all nine (two full blocks and one
// body left over) together.
TEST(World, ABodyStepsTheSameAloneAsInABlock) {
  std::vector<BodyDef> defs = r2_free_boxes(9);
  defs[4].w_W = Vec3(0, 0, 0);  // zero spin must not differ between lane and scalar either
  for (Integrator m : {Integrator::rk4, Integrator::automatic}) {
    WorldConfig c;
    c.integrator = m;
    World all(c, defs);
    for (int k = 0; k < 100; ++k) all.step();
    for (int i = 0; i < 9; ++i) {
      World one(c, {defs[i]});
      for (int k = 0; k < 100; ++k) one.step();
      const MotionState &a = one.impl().state(0), &b = all.impl().state(i);
      const bool same =
          std::memcmp(a.q_WP.coeffs().data(), b.q_WP.coeffs().data(), 4 * sizeof(double)) == 0 &&
          std::memcmp(a.x_W.data(), b.x_W.data(), 3 * sizeof(double)) == 0 &&
          std::memcmp(a.v_W.data(), b.v_W.data(), 3 * sizeof(double)) == 0 &&
          std::memcmp(a.w_P.data(), b.w_P.data(), 3 * sizeof(double)) == 0;
      EXPECT_TRUE(same) << to_string(m) << " body " << i;
    }
  }
}

TEST(World, StateFitsIn256Bytes) {
  EXPECT_LE(sizeof(MotionState) + sizeof(Wrench), 256u);
}

}  // namespace
}  // namespace simreel
