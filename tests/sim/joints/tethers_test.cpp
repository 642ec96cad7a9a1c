// Distance joints (rods, ropes, springs) and pulleys (sim/joints/articulation.hpp, Mechanism::Tether;
// docs/joints.md) against closed forms written out here from textbook mechanics: the simple
// pendulum's elliptic-integral period, a rope's inelastic (and partly elastic) catch, the point
// where a whirled rope goes slack and the parabola after it, Atwood's machine with a massive
// pulley, a block and tackle, and a mass on a spring. Tolerances are 1e-8 and tighter: the
// mechanisms are integrated at the default tolerance of 1e-10 and each closed form is exact.
//
// Each body hangs from its centre of mass, so a rod or rope pulls through it and it never turns:
// it moves as a point mass, which is what every closed form here assumes.
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <simreel/error.hpp>

#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double g = 9.81;

using test::Bodies;

struct Rig {
  Bodies b;
  Articulations art;
  std::vector<JointDef> joints;
  Vec3 gravity = Vec3(0, 0, -g);
  void build() {
    std::vector<std::string> warnings;
    art.build(joints, {}, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
  bool step(double dt) { return art.step(dt, gravity, nullptr, b.state.data()); }
  // Frames of 1/60 s up to time t (the last one shortened to land on it).
  void run_to(double& now, double t) {
    while (now < t - 1e-15) {
      const double dt = std::min(1.0 / 60, t - now);
      ASSERT_TRUE(step(dt));
      now += dt;
    }
  }
};

JointDef distance(int parent, int child, const Vec3& a, const Vec3& b) {
  JointDef j;
  j.name = "d" + std::to_string(child);
  j.type = JointType::distance;
  j.parent = parent;
  j.child = child;
  j.anchor_W = a;
  j.anchor2_W = b;
  return j;
}

const Vec3 kSmall(1e-3, 1e-3, 1e-3);  // kg m^2: a small ball's inertia (it never turns here)

// A rod of length L from the origin to a bob released from rest at theta0 in the x-z plane: a
// simple pendulum, T = 4 K(sin(theta0/2)) sqrt(L/g). Its bob crosses the bottom (x = 0) at T/4 and
// 3T/4 at full speed, so the crossing time is read from x there: dt = x / v.
TEST(Tethers, RodPendulumKeepsTheEllipticPeriodAndItsEnergy) {
  const double L = 1.3;
  for (double deg : {10.0, 90.0, 170.0}) {
    const double th = deg * kPi / 180;
    Rig r;
    const Vec3 x0(L * std::sin(th), 0, -L * std::cos(th));
    const int bob = r.b.add("bob", 1.0, kSmall, x0);
    r.joints.push_back(distance(-1, bob, Vec3::Zero(), x0));
    r.build();
    const double T = ref::pendulum_period(th, 1.0 * L * L, 1.0, g, L);
    const double E0 = r.b.energy(g);
    double now = 0;
    for (double at : {0.25, 0.75}) {
      r.run_to(now, at * T);
      const MotionState& s = r.b.state[bob];
      const double late = s.x_W.x() / s.v_W.x();  // s: how far past (before) the bottom it is
      std::printf("rod pendulum %5.1f deg: bottom at %.2f T off by %.1e T\n", deg, at, late / T);
      EXPECT_LT(std::abs(late), (deg == 170 ? 1e-7 : 1e-8) * T) << deg << " deg at " << at << " T";
      EXPECT_NEAR(s.x_W.norm(), L, 1e-12);
      EXPECT_NEAR(s.w_P.norm(), 0, 1e-12);  // pulled through its centre: it never turns
    }
    r.run_to(now, 60);
    // The hinge pendulum's bound (articulation_test): the rod's row and projection cost no more.
    const double dE = std::abs(r.b.energy(g) - E0) / (1.0 * g * L);
    std::printf("rod pendulum %5.1f deg: |dE| after 60 s %.1e m g L\n", deg, dE);
    EXPECT_LT(dE, 1e-7) << deg << " deg";
    EXPECT_LT(r.art.gap(r.b.state.data()), 1e-12);
  }
}

// A ball tied by a 1 m rope to the origin, released from rest at (0.6, 0, 0): it falls freely
// 0.8 m until the rope is taut along n = (0.6, 0, -0.8); the catch (restitution 0) removes the
// speed along n, (0.8 v)^2 of v^2 = 2 g 0.8, and keeps the rest; then the ball swings, the rope
// taut, its energy kept.
TEST(Tethers, SlackRopeCatchesTheBallAndTakesOnlyItsRadialSpeed) {
  Rig r;
  const int ball = r.b.add("ball", 2.0, kSmall, Vec3(0.6, 0, 0));
  JointDef j = distance(-1, ball, Vec3::Zero(), Vec3(0.6, 0, 0));
  j.max_length = 1.0;
  r.joints.push_back(j);
  r.build();
  const double E0 = r.b.energy(g);
  const double v2 = 2 * g * 0.8, lost = 0.5 * 2.0 * 0.64 * v2;
  const double t_catch = std::sqrt(2 * 0.8 / g);
  double now = 0;
  r.run_to(now, t_catch - 0.01);
  EXPECT_NEAR(r.b.state[ball].x_W.z(), -0.5 * g * now * now, 1e-12);  // free fall while slack
  EXPECT_EQ(r.art.force(0), 0.0);
  r.run_to(now, 2.0);
  // The catch is exact (located to 1e-12 of a step); the swing after it drifts as a pendulum's.
  EXPECT_NEAR(r.b.energy(g), E0 - lost, 1e-8 * 2.0 * g);
  EXPECT_NEAR(r.b.state[ball].x_W.norm(), 1.0, 1e-12);
  EXPECT_LT(r.art.force(0), 0);  // pulling
  r.run_to(now, 10.0);
  EXPECT_NEAR(r.b.energy(g), E0 - lost, 1e-7 * 2.0 * g);
}

// No gravity: a ball 0.5 m from the rope's anchor flies outward at 1 m/s; the 1 m rope catches it
// at t = 0.5 s and returns -e times its speed: at t = 1 s it is at 1 - 0.5 e (e = 0.5), or rests
// at the rope's end (e = 0).
TEST(Tethers, RopeRestitutionReturnsThatFractionOfTheSpeed) {
  for (double e : {0.0, 0.5, 1.0}) {
    Rig r;
    r.gravity.setZero();
    const int ball = r.b.add("ball", 1.0, kSmall, Vec3(0.5, 0, 0));
    r.b.state[ball].v_W = Vec3(1, 0, 0);
    JointDef j = distance(-1, ball, Vec3::Zero(), Vec3(0.5, 0, 0));
    j.max_length = 1.0;
    j.restitution = e;
    r.joints.push_back(j);
    r.build();
    double now = 0;
    r.run_to(now, 1.0);
    EXPECT_NEAR(r.b.state[ball].x_W.x(), 1 - 0.5 * e, 1e-10) << "e = " << e;
    EXPECT_NEAR(r.b.state[ball].v_W.x(), -e, 1e-10) << "e = " << e;
  }
}

// A ball on a 1 m rope whirled from the bottom at v0^2 = 3.5 g L: the rope's tension
// m v^2 / L + m g cos(theta) (theta from the downward vertical, v^2 = v0^2 - 2 g L (1 - cos theta))
// reaches zero at cos theta = (2 g L - v0^2) / (3 g L) = -1/2, theta = 120 deg, with v^2 = g L / 2;
// then the ball flies a parabola from there. Every state read while the rope is slack must lie on
// that parabola: x' is the slack point's, and the time since it is (v_s,z - z') / g.
TEST(Tethers, WhirledRopeGoesSlackWhereItsTensionVanishes) {
  Rig r;
  const double L = 1, v0 = std::sqrt(3.5 * g * L);
  const int ball = r.b.add("ball", 1.0, kSmall, Vec3(0, 0, -L));
  r.b.state[ball].v_W = Vec3(v0, 0, 0);
  JointDef j = distance(-1, ball, Vec3::Zero(), Vec3(0, 0, -L));
  j.max_length = L;
  r.joints.push_back(j);
  r.build();
  const double th = 2 * kPi / 3, vs = std::sqrt(g * L / 2);
  const Vec3 ps(L * std::sin(th), 0, -L * std::cos(th));
  const Vec3 vsv = vs * Vec3(std::cos(th), 0, std::sin(th));
  const double E0 = r.b.energy(g);
  int slack_frames = 0;
  for (int f = 0; f < 120 && slack_frames < 5; ++f) {
    ASSERT_TRUE(r.step(1.0 / 60));
    const MotionState& s = r.b.state[ball];
    if (r.art.force(0) != 0) {
      EXPECT_NEAR(s.x_W.norm(), L, 1e-12);
      continue;
    }
    if (s.x_W.norm() > L - 1e-9 && s.x_W.z() < 0) continue;  // the catch's frame or before the whirl
    ++slack_frames;
    const double tau = (vsv.z() - s.v_W.z()) / g;
    EXPECT_NEAR(s.v_W.x(), vsv.x(), 1e-8);
    const Vec3 p = ps + vsv * tau - Vec3(0, 0, 0.5 * g * tau * tau);
    EXPECT_LT((s.x_W - p).norm(), 1e-8) << "frame " << f;
    EXPECT_NEAR(r.b.energy(g), E0, 1e-9 * g);
  }
  EXPECT_EQ(slack_frames, 5);
}

// Atwood's machine: m1 = 2 kg and m2 = 1 kg on a rope over a wheel (a disc, I = M r^2 / 2 with
// M = 1 kg, r = 0.1 m) on a revolute axle, the rope not slipping on it:
// a = (m1 - m2) g / (m1 + m2 + I/r^2), tensions m1 (g - a) and m2 (g + a).
TEST(Tethers, AtwoodMachineAcceleratesAtTheClosedForm) {
  Rig r;
  const double m1 = 2, m2 = 1, M = 1, rad = 0.1, I = 0.5 * M * rad * rad;
  const int wheel = r.b.add("wheel", M, Vec3(0.25 * M * rad * rad, I, 0.25 * M * rad * rad), Vec3::Zero());
  const int b1 = r.b.add("m1", m1, kSmall, Vec3(-rad, 0, -1));
  const int b2 = r.b.add("m2", m2, kSmall, Vec3(rad, 0, -0.7));
  JointDef axle;
  axle.name = "axle";
  axle.type = JointType::revolute;
  axle.parent = -1;
  axle.child = wheel;
  axle.anchor_W = Vec3::Zero();
  axle.axis_W = Vec3(0, 1, 0);
  r.joints.push_back(axle);
  JointDef rope;
  rope.name = "rope";
  rope.type = JointType::pulley;
  rope.parent = b1;
  rope.child = b2;
  rope.anchor_W = r.b.state[b1].x_W;
  rope.anchor2_W = r.b.state[b2].x_W;
  rope.pulley_anchor_W[0] = Vec3(-rad, 0, 0);
  rope.pulley_anchor_W[1] = Vec3(rad, 0, 0);
  rope.wheel = wheel;
  r.joints.push_back(rope);
  r.build();
  const double a = ref::atwood_acceleration(m1, m2, I, rad, g);
  const auto T = ref::atwood_tensions(m1, m2, I, rad, g);
  double now = 0;
  r.run_to(now, 0.5);
  std::printf("Atwood: m1 off the closed form by %.1e m after 0.5 s\n",
              r.b.state[b1].x_W.z() - (-1 - 0.5 * a * now * now));
  EXPECT_NEAR(r.b.state[b1].x_W.z(), -1 - 0.5 * a * now * now, 1e-10);
  EXPECT_NEAR(r.b.state[b2].x_W.z(), -0.7 + 0.5 * a * now * now, 1e-10);
  EXPECT_NEAR(r.b.state[b1].v_W.z(), -a * now, 1e-10);
  // The wheel turns with the rope: its rim moves at the rope's speed.
  EXPECT_NEAR(std::abs(r.art.speed(0)) * rad, a * now, 1e-10);
  EXPECT_NEAR(r.art.position(1, 0) - 1, 0.5 * a * now * now, 1e-10);  // run 0 paid out
  // Tensions: the rows' forces along each run (pulling), and the pull on m2 at its anchor.
  EXPECT_NEAR(-r.art.force(1, 0), T[0], 1e-9 * T[0]);
  EXPECT_NEAR(-r.art.force(1, 1), T[1], 1e-9 * T[1]);
  Vec3 F, tau;
  r.art.reaction(1, r.b.state.data(), r.gravity, F, tau);
  EXPECT_LT((F - Vec3(0, 0, T[1])).norm(), 1e-9 * T[1]);
  // The axle carries the wheel's weight and both runs' pulls.
  r.art.reaction(0, r.b.state.data(), r.gravity, F, tau);
  EXPECT_NEAR(F.z(), M * g + T[0] + T[1], 1e-9 * (T[0] + T[1]));
}

// A block and tackle without inertia: L0 + 2 L1 keeps its length, so m0 moves twice as far as m1;
// from energy, m0's downward acceleration is a0 = g (m0 - m1/2) / (m0 + m1/4).
TEST(Tethers, BlockAndTackleTradesDistanceForForce) {
  Rig r;
  const double m0 = 1, m1 = 3;
  const int b0 = r.b.add("b0", m0, kSmall, Vec3(-1, 0, -1));
  const int b1 = r.b.add("b1", m1, kSmall, Vec3(1, 0, -1.5));
  JointDef rope;
  rope.name = "tackle";
  rope.type = JointType::pulley;
  rope.parent = b0;
  rope.child = b1;
  rope.anchor_W = r.b.state[b0].x_W;
  rope.anchor2_W = r.b.state[b1].x_W;
  rope.pulley_anchor_W[0] = Vec3(-1, 0, 0);
  rope.pulley_anchor_W[1] = Vec3(1, 0, 0);
  rope.ratio = 2;
  r.joints.push_back(rope);
  r.build();
  const double a0 = g * (m0 - m1 / 2) / (m0 + m1 / 4);  // < 0: m0 rises
  double now = 0;
  r.run_to(now, 0.4);
  EXPECT_NEAR(r.b.state[b0].x_W.z(), -1 - 0.5 * a0 * now * now, 1e-10);
  EXPECT_NEAR(r.b.state[b1].x_W.z(), -1.5 + 0.25 * a0 * now * now, 1e-10);
  // The rope's tension T holds m0: m0 a0 = m0 g - T; it pulls m1 up with 2 T.
  EXPECT_NEAR(-r.art.force(0), m0 * (g - a0), 1e-9 * m0 * g);
}

// A 2 kg mass on a spring (k = 50 N/m, rest 1 m) hanging from the origin, released at rest at its
// rest length: it oscillates about the stretch m g / k with omega = sqrt(k / m):
// z(t) = -1 - (m g / k) (1 - cos omega t).
TEST(Tethers, SpringDistanceJointOscillatesAtSqrtKOverM) {
  Rig r;
  const double m = 2, k = 50;
  const int bob = r.b.add("bob", m, kSmall, Vec3(0, 0, -1));
  JointDef j = distance(-1, bob, Vec3::Zero(), Vec3(0, 0, -1));
  j.spring = JointSpring{k, 0, 1};
  r.joints.push_back(j);
  r.build();
  const double w = std::sqrt(k / m), s = m * g / k;
  double now = 0;
  for (double t : {0.3, 1.1, 2.9}) {
    r.run_to(now, t);
    EXPECT_NEAR(r.b.state[bob].x_W.z(), -1 - s * (1 - std::cos(w * t)), 1e-9) << t;
  }
}

// Two rods in a chain (world -> b1 -> b2, each through the bodies' centres): a double pendulum of
// point masses. No closed-form trajectory, but its energy is conserved and neither rod stretches.
TEST(Tethers, RodChainKeepsEnergyAndLengths) {
  Rig r;
  const int b1 = r.b.add("b1", 1.0, kSmall, Vec3(1, 0, 0));
  const int b2 = r.b.add("b2", 0.5, kSmall, Vec3(1.8, 0, 0));
  r.joints.push_back(distance(-1, b1, Vec3::Zero(), Vec3(1, 0, 0)));
  r.joints.push_back(distance(b1, b2, Vec3(1, 0, 0), Vec3(1.8, 0, 0)));
  r.build();
  const double E0 = r.b.energy(g);
  double now = 0, worst = 0;
  for (int s = 1; s <= 20; ++s) {
    r.run_to(now, s);
    worst = std::max(worst, std::abs(r.b.energy(g) - E0));
    EXPECT_LT(r.art.gap(r.b.state.data()), 1e-12);
  }
  EXPECT_LT(worst, 1e-8 * 1.5 * g);
}

TEST(Tethers, BadDefinitionsAreRefusedWithTheJointsName) {
  auto refuse = [](JointDef j, const char* what) {
    Rig r;
    r.b.add("a", 1, kSmall, Vec3(0, 0, -1));
    r.b.add("b", 1, kSmall, Vec3(1, 0, -1));
    j.name = "rope";
    r.joints.push_back(j);
    std::vector<std::string> w;
    try {
      r.art.build(r.joints, {}, r.b.defs, r.b.model, r.b.state, w);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("joint 'rope'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  JointDef d = distance(-1, 0, Vec3(0, 0, -1), Vec3(0, 0, -1));
  refuse(d, "anchors coincide");
  d = distance(-1, 0, Vec3::Zero(), Vec3(0, 0, -1));
  d.max_length = 0.5;
  refuse(d, "max_length must be at least");
  d.max_length.reset();
  d.limits = JointLimits{-1, 1, 0};
  refuse(d, "min_length and max_length");
  JointDef p;
  p.type = JointType::pulley;
  p.parent = 0;
  p.child = 1;
  p.anchor_W = Vec3(0, 0, -1);
  p.anchor2_W = Vec3(1, 0, -1);
  p.pulley_anchor_W[0] = Vec3(0, 0, 0);
  p.pulley_anchor_W[1] = Vec3(1, 0, 0);
  p.wheel = 0;
  refuse(p, "cannot also hang");
}

}  // namespace
}  // namespace simreel
