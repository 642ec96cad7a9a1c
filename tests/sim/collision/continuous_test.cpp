// Continuous collision (sim/collision/time_of_impact.hpp, sim/world/continuous.cpp): no tunnelling. A 5 cm sphere
// shot at 100 m/s at a 1 cm wall (static) and at a 1 cm plate (dynamic, in free space) from
// seeded directions never passes through; it stops or rebounds as Newton's and Coulomb's impact
// laws say; momentum is kept when the plate is dynamic; a spinning box bullet, and a thin plate
// struck into a wall, do not pass through either; determinism and resume-equals-straight hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "sim/collision/time_of_impact.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/sim/collision/continuous_fixtures.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"

namespace simreel {
namespace {

using ccd_test::crossed;
using ccd_test::kRadius;
using ccd_test::kSpeed;
using ccd_test::kSteel;
using ccd_test::kThick;
constexpr double kDt = ccd_test::kShotDt;  // s
using ccd_test::shot_config;
using contact_test::box;
using contact_test::deg;
using contact_test::kPi;
using contact_test::sphere;
using contact_test::state_hash;

constexpr double kAluminium = 2700;  // kg/m^3

// One shot: direction at angle theta from the wall's normal (+x), turned phi about it; aimed at a
// point of the face within 15 cm of its centre, starting `lead` m before reaching it (so the step
// in which it arrives starts anywhere from 0 to 1.4 steps of travel away).
struct Shot {
  double theta, phi, lead;
  Vec3 aim;
  Vec3 dir() const {
    return Vec3(std::cos(theta), std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi));
  }
};

Shot random_shot(SplitMix64& rng, double max_theta = deg(70)) {
  Shot s;
  s.theta = rng.uniform(0.0, max_theta);
  s.phi = rng.uniform(0.0, 2 * kPi);
  s.lead = rng.uniform(0.02, 0.6);
  s.aim = Vec3(-0.5 * kThick, rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15));
  return s;
}

struct Outcome {
  bool through = false;                       // the sphere's centre crossed the target's mid-plane
  double depth = 0;                           // m, deepest overlap seen (World::contact_stats)
  Vec3 v_after = Vec3::Zero();                // sphere velocity at the end
  Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero();  // total momentum before and after
  long hits = 0;                              // continuous-stage moves back
};

// Target: body 0 (a 1 cm x 50 cm x 50 cm plate, static or dynamic, centred at the origin, its thin
// axis along x); the sphere is body 1.
Outcome shoot(const Shot& s, BodyType target, double restitution = 0.0, bool continuous = true,
              int steps = 30) {
  std::vector<BodyDef> bodies;
  bodies.push_back(
      box(Vec3(kThick, 0.5, 0.5), Vec3::Zero(), 0.6, restitution, kAluminium, Quat::Identity(), target));
  BodyDef ball = sphere(kRadius, s.aim - Vec3(kRadius, 0, 0) - s.lead * s.dir(), 0.6, restitution, kSteel);
  ball.v_W = kSpeed * s.dir();
  bodies.push_back(ball);
  World w(shot_config(continuous), bodies);
  w.set_profiling(true);
  Outcome o;
  o.p0 = w.total_momentum();
  Vec3 before = w.world_to_local(0, w.centroid(1));
  for (int k = 0; k < steps && !o.through; ++k) {
    w.step();
    const Vec3 now = w.world_to_local(0, w.centroid(1));
    o.through = crossed(before, now, 0.25);
    before = now;
  }
  o.depth = w.contact_stats().max_penetration;
  o.v_after = w.linear_velocity(1);
  o.p1 = w.total_momentum();
  o.hits = w.profile().toi_hits;
  return o;
}

// ------------------------------------------------------------------ the 1,000 shots
struct Tally {
  int through = 0;
  double depth = 0;
  double momentum = 0;  // largest |p1 - p0| / |p0|
  long hits = 0;
};

Tally volley(uint64_t seed, int n, BodyType target, bool continuous = true) {
  SplitMix64 rng(seed);
  Tally t;
  for (int k = 0; k < n; ++k) {
    const Shot s = random_shot(rng);
    const Outcome o = shoot(s, target, 0.0, continuous);
    t.through += o.through;
    t.depth = std::max(t.depth, o.depth);
    t.momentum = std::max(t.momentum, (o.p1 - o.p0).norm() / o.p0.norm());
    t.hits += o.hits;
  }
  return t;
}

TEST(Ccd, ThousandShotsNeverPassAStaticWall) {
  const Tally t = volley(15, 1000, BodyType::static_body);
  EXPECT_EQ(t.through, 0);
  EXPECT_LT(t.depth, 2e-3) << "deepest overlap";
  std::printf("static wall: %d through, deepest overlap %.3g m, %ld moves back\n", t.through, t.depth,
              t.hits);
}

TEST(Ccd, ThousandShotsNeverPassADynamicPlate) {
  const Tally t = volley(16, 1000, BodyType::dynamic);
  EXPECT_EQ(t.through, 0);
  // Off-centre hits set the plate spinning at up to ~45 rad/s with the ball sliding across it at
  // tens of m/s; the solver keeps each manifold's anchors for the whole step, so the ball sinks in
  // (docs/continuous-collision.md "Limits") and the sweep's last defence holds its centre
  // out of the plate: the overlap stays below the radius (2.5 cm measured in a few shots).
  EXPECT_LT(t.depth, kRadius) << "deepest overlap";
  // Contact impulses are equal and opposite, and moving a body back to its time of impact keeps
  // its velocity: momentum is kept to rounding.
  EXPECT_LT(t.momentum, 1e-12);
  std::printf("dynamic plate: %d through, deepest overlap %.3g m, momentum %.3g, %ld moves back\n", t.through,
              t.depth, t.momentum, t.hits);
}

// ------------------------------------------------------------------ the impact is physical
// Against the static wall (restitution 0): the normal velocity is stopped, and Coulomb's impulse
// law for a sphere (moment of inertia 2/5 m r^2) gives the tangential speed after the impact:
// sliding throughout, v_t - mu v_n; if it stops sliding, rolling at 5/7 v_t; whichever is larger.
TEST(Ccd, SphereStopsOnTheWallAsCoulombSays) {
  SplitMix64 rng(17);
  for (int k = 0; k < 40; ++k) {
    const Shot s = random_shot(rng);
    const Outcome o = shoot(s, BodyType::static_body, 0.0, true, 4 + (int)std::ceil(s.lead / kSpeed / kDt));
    ASSERT_FALSE(o.through);
    const double vn = kSpeed * std::cos(s.theta), vt = kSpeed * std::sin(s.theta);
    EXPECT_NEAR(o.v_after.x(), 0.0, 1e-3 * kSpeed) << "shot " << k;
    const double vt_after = std::hypot(o.v_after.y(), o.v_after.z());
    const double mu = 0.6;
    const double expected = std::max(vt - mu * vn, 5.0 / 7.0 * vt);
    EXPECT_NEAR(vt_after, expected, 0.01 * kSpeed) << "shot " << k << " theta " << s.theta;
  }
}

// Restitution 0.5 (Newton's law at the contact): the normal velocity leaves at -e v_n.
TEST(Ccd, SphereReboundsFromTheWallWithItsRestitution) {
  SplitMix64 rng(18);
  for (int k = 0; k < 40; ++k) {
    const Shot s = random_shot(rng);
    const Outcome o = shoot(s, BodyType::static_body, 0.5, true, 4 + (int)std::ceil(s.lead / kSpeed / kDt));
    ASSERT_FALSE(o.through);
    EXPECT_NEAR(o.v_after.x(), -0.5 * kSpeed * std::cos(s.theta), 0.01 * kSpeed) << "shot " << k;
  }
}

// Head-on at the free plate's centre with restitution 0: they leave together at the common
// velocity m v / (m + M) (a perfectly inelastic collision).
TEST(Ccd, HeadOnAtTheFreePlateLeavesAtTheCommonVelocity) {
  Shot s{0.0, 0.0, 0.3, Vec3(-0.5 * kThick, 0, 0)};
  const Outcome o = shoot(s, BodyType::dynamic, 0.0, true, 20);
  ASSERT_FALSE(o.through);
  const double m = 4.0 / 3.0 * kPi * std::pow(kRadius, 3) * kSteel;
  const double M = kThick * 0.5 * 0.5 * kAluminium;
  EXPECT_NEAR(o.v_after.x(), m * kSpeed / (m + M), 1e-6 * kSpeed);
  EXPECT_NEAR(o.p1.x(), o.p0.x(), 1e-12 * o.p0.x());
}

// ------------------------------------------------------------------ what speculative contacts miss
// A light 1 cm plate 3 cm in front of a 1 cm static wall (beyond the 2 cm speculative distance,
// and the plate is still at the step's start, so no contact between them is made in advance) is
// struck at 100 m/s by a heavy sphere: within the step the plate leaves at ~170 m/s. Without the
// sweep it passes through the wall; with it, neither the plate nor the sphere does.
struct StruckPlate {
  bool plate_through = false, ball_through = false;
  long hits = 0;
};

StruckPlate strike_plate(const Shot& s, bool continuous) {
  std::vector<BodyDef> bodies;
  bodies.push_back(box(Vec3(kThick, 1.0, 1.0), Vec3(0.04, 0, 0), 0.6, 0.0, kAluminium, Quat::Identity(),
                       BodyType::static_body));
  bodies.push_back(box(Vec3(kThick, 0.3, 0.3), Vec3::Zero(), 0.6, 0.0, 300.0));  // plastic foam-ish
  BodyDef ball = sphere(kRadius, s.aim - Vec3(kRadius, 0, 0) - s.lead * s.dir(), 0.6, 0.0, kSteel);
  ball.v_W = kSpeed * s.dir();
  bodies.push_back(ball);
  World w(shot_config(continuous), bodies);
  w.set_profiling(true);
  StruckPlate r;
  for (int k = 0; k < 40; ++k) {
    w.step();
    r.plate_through = r.plate_through || w.centroid(1).x() > 0.04;
    r.ball_through = r.ball_through || w.centroid(2).x() > 0.04;
  }
  r.hits = w.profile().toi_hits;
  return r;
}

TEST(Ccd, StruckThinPlateDoesNotPassTheWallBehindIt) {
  SplitMix64 rng(19);
  int plate = 0, ball = 0;
  long hits = 0;
  for (int k = 0; k < 200; ++k) {
    const Shot s = random_shot(rng, deg(30));
    const StruckPlate r = strike_plate(s, true);
    plate += r.plate_through;
    ball += r.ball_through;
    hits += r.hits;
  }
  EXPECT_EQ(plate, 0);
  EXPECT_EQ(ball, 0);
  EXPECT_GT(hits, 0);
}

// The same without the continuous stage: the plate goes through (the test above can fail).
TEST(Ccd, WithoutTheSweepTheStruckPlateTunnels) {
  SplitMix64 rng(19);
  int plate = 0;
  for (int k = 0; k < 50; ++k) plate += strike_plate(random_shot(rng, deg(30)), false).plate_through;
  EXPECT_GT(plate, 0);
}

// ------------------------------------------------------------------ a box bullet
// A 6 x 4 x 1 cm box flagged `bullet`, spinning at up to 200 rad/s in any orientation, shot at
// 100 m/s at the static 1 cm wall: never through.
TEST(Ccd, SpinningBoxBulletNeverPassesTheWall) {
  SplitMix64 rng(20);
  int through = 0;
  for (int k = 0; k < 300; ++k) {
    const Shot s = random_shot(rng);
    std::vector<BodyDef> bodies;
    bodies.push_back(box(Vec3(kThick, 1.0, 1.0), Vec3::Zero(), 0.6, 0.0, kAluminium, Quat::Identity(),
                         BodyType::static_body));
    const Quat q = Quat(
        Eigen::AngleAxisd(rng.uniform(0, 2 * kPi),
                          Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized()));
    BodyDef b = box(Vec3(0.06, 0.04, 0.01), s.aim - Vec3(0.04, 0, 0) - s.lead * s.dir(), 0.6, 0.0, kSteel, q);
    b.bullet = true;
    b.v_W = kSpeed * s.dir();
    b.w_W =
        Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized() * rng.uniform(0, 200);
    bodies.push_back(b);
    World w(shot_config(), bodies);
    Vec3 before = w.centroid(1);
    for (int j = 0; j < 30; ++j) {
      w.step();
      if (crossed(before, w.centroid(1), 0.5)) {
        ++through;
        break;
      }
      before = w.centroid(1);
    }
  }
  EXPECT_EQ(through, 0);
}

// ------------------------------------------------------------------ the time of impact itself
// Two spheres approaching head-on: the time of impact at gap `target` is a closed form.
TEST(Ccd, TimeOfImpactOfTwoSpheresIsExact) {
  ShapeRecord a, b;
  a.geom.kind = b.geom.kind = CollideKind::sphere;
  a.geom.radius = 0.1;
  b.geom.radius = 0.2;
  a.geom.bounding_radius = 0.1;
  b.geom.bounding_radius = 0.2;
  const Sweep sa = make_sweep(Vec3(0, 0, 0), Quat::Identity(), Vec3(1, 0, 0), Quat::Identity());
  const Sweep sb = make_sweep(Vec3(1, 0, 0), Quat::Identity(), Vec3(0.5, 0, 0), Quat::Identity());
  ToiInput in;
  in.a = &a.geom;
  in.b = &b.geom;
  in.sa = &sa;
  in.sb = &sb;
  in.target = 1e-4;
  in.tolerance = 1e-6;
  const ToiOutput out = time_of_impact(in);
  ASSERT_EQ(out.state, ToiOutput::hit);
  // Gap 1 - 0.3 - 1.5 t = target.
  EXPECT_NEAR(out.t, (0.7 - 1e-4) / 1.5, 1e-6 / 1.5);
  // Moving apart: no hit.
  const Sweep away = make_sweep(Vec3(1, 0, 0), Quat::Identity(), Vec3(3, 0, 0), Quat::Identity());
  in.sb = &away;
  const Sweep still = make_sweep(Vec3(0, 0, 0), Quat::Identity(), Vec3(0, 0, 0), Quat::Identity());
  in.sa = &still;
  EXPECT_EQ(time_of_impact(in).state, ToiOutput::separated);
}

// A rod (box 1 m x 2 cm x 2 cm) turning a quarter turn about its centre, and a 2 cm sphere 0.4 m
// out at 45 degrees: the rod's side reaches it when the angle between them is asin(0.02 / 0.4).
// The sweep stops before that (conservative) and within a few target gaps of it.
TEST(Ccd, RotatingRodStopsBeforeTheSphere) {
  ShapeRecord rod, ball;
  rod.geom.kind = CollideKind::box;
  rod.geom.half_extents = Vec3(0.5, 0.01, 0.01);
  rod.geom.bounding_radius = rod.geom.half_extents.norm();
  ball.geom.kind = CollideKind::sphere;
  ball.geom.radius = 0.01;
  ball.geom.bounding_radius = 0.01;
  // The rod turns 90 degrees about z; the sphere sits at angle 45 degrees, 0.4 m out.
  const Sweep sr = make_sweep(Vec3::Zero(), Quat::Identity(), Vec3::Zero(),
                              Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())));
  const Vec3 c = 0.4 * Vec3(std::cos(kPi / 4), std::sin(kPi / 4), 0);
  const Sweep sb = make_sweep(c, Quat::Identity(), c, Quat::Identity());
  ToiInput in;
  in.a = &rod.geom;
  in.sa = &sr;
  in.reach_a = rod.geom.bounding_radius;
  in.b = &ball.geom;
  in.sb = &sb;
  in.reach_b = 0.01;
  in.target = 1e-4;
  in.tolerance = 2.5e-5;
  const ToiOutput out = time_of_impact(in);
  ASSERT_EQ(out.state, ToiOutput::hit);
  // Contact when the rod's side (half width 0.01) touches the sphere (radius 0.01): the angle
  // between the rod's axis and the sphere's direction is asin(0.02 / 0.4).
  const double angle = kPi / 4 - std::asin(0.02 / 0.4);
  const double t_exact = angle / (kPi / 2);
  EXPECT_LT(out.t, t_exact);
  EXPECT_GT(out.t, t_exact - 5e-4 / (0.4 * kPi / 2));
}

// ------------------------------------------------------------------ determinism, resume
std::vector<BodyDef> bullet_scene() {
  std::vector<BodyDef> bodies;
  SplitMix64 rng(21);
  bodies.push_back(box(Vec3(kThick, 2.0, 2.0), Vec3(1.0, 0, 1.0), 0.6, 0.3, kAluminium, Quat::Identity(),
                       BodyType::static_body));
  for (int k = 0; k < 6; ++k)  // thin dynamic plates standing in the way
    bodies.push_back(box(Vec3(kThick, 0.3, 0.3), Vec3(0.5, -0.75 + 0.3 * k, 1.0), 0.6, 0.2, kAluminium));
  for (int k = 0; k < 12; ++k) {
    BodyDef b = sphere(kRadius, Vec3(-1.0 - 0.1 * k, rng.uniform(-0.8, 0.8), rng.uniform(0.7, 1.3)), 0.6, 0.4,
                       kSteel);
    b.v_W = Vec3(rng.uniform(40, 120), rng.uniform(-10, 10), rng.uniform(-5, 5));
    b.bullet = k % 2 == 0;
    bodies.push_back(b);
  }
  bodies.push_back(contact_test::ground());
  return bodies;
}

WorldConfig bullet_config() {
  WorldConfig cfg;
  cfg.dt = kDt;
  return cfg;
}

TEST(Ccd, DeterministicAndResumeEqualsStraight) {
  World a(bullet_config(), bullet_scene()), b(bullet_config(), bullet_scene());
  a.set_profiling(true);
  for (int k = 0; k < 120; ++k) a.step(), b.step();
  EXPECT_EQ(state_hash(a), state_hash(b));
  EXPECT_GT(a.profile().toi_hits, 0) << "the scene must exercise the sweep";
  // Save mid-flight, resume, and continue both: bit for bit.
  World straight(bullet_config(), bullet_scene());
  for (int k = 0; k < 20; ++k) straight.step();
  std::stringstream saved;
  straight.save_state(saved);
  World resumed(bullet_config(), bullet_scene());
  resumed.restore_state(saved);
  for (int k = 20; k < 120; ++k) straight.step(), resumed.step();
  EXPECT_EQ(state_hash(straight), state_hash(resumed));
  EXPECT_EQ(state_hash(straight), state_hash(a));
  // Two threads: the same.
  WorldConfig two = bullet_config();
  two.threads = 2;
  World c(two, bullet_scene());
  for (int k = 0; k < 120; ++k) c.step();
  EXPECT_EQ(state_hash(c), state_hash(a));
}

// Nothing fast, nothing swept: the R3 column lands without the stage running.
TEST(Ccd, SlowScenesSweepNothing) {
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  World w(cfg, r3_column(10));
  w.set_profiling(true);
  for (int k = 0; k < 480; ++k) w.step();
  EXPECT_EQ(w.profile().swept_bodies, 0);
  EXPECT_EQ(w.profile().runs[(int)Stage::continuous], 0);
}

}  // namespace
}  // namespace simreel
