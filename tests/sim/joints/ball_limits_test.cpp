// A ball joint's cone and twist stops and its spring (sim/joints/ball_limits.cpp, BallLimits,
// JointSpring on a spherical joint; docs/joints.md) against closed forms written out here from
// rigid-body mechanics, never from simreel's code: constant-rate rotation between stops (a
// triangle wave), Newton's restitution on the stopped angle alone, the static balance of a limb
// resting on its cone, the workless constraint of a frictionless wall, and the isochronous
// torsional oscillator theta'' = -(k / I) theta (a ball joint's spring pulls the rotation vector
// back linearly, so a planar swing is harmonic at any amplitude).
//
// The body throughout is a rod of mass m whose centre of mass is d from the pivot (the origin),
// principal moments (I1, I1, I3) with its third axis along the rod. Angles are read from the
// bodies' orientations with the test's own formulas.
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/fixtures/joint_bodies.hpp"

namespace simreel {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double m = 1, d = 0.5, I1 = 0.02, I3 = 0.004;
constexpr double Ip = I1 + m * d * d;  // about a perpendicular axis through the pivot (Steiner)

using test::Bodies;

// The rod from the pivot along `dir` (unit), its third principal axis along it, turning at w
// (world, about the pivot).
struct Limb {
  Bodies b;
  Articulations art;
  double g;
  Limb(const Vec3& dir, const Vec3& w_W, double gravity, const BallLimits* limits,
       const JointSpring* spring = nullptr, bool reversed = false)
      : g(gravity) {
    const Quat q = Quat::FromTwoVectors(Vec3::UnitZ(), dir);
    b.add("rod", m, Vec3(I1, I1, I3), d * dir, q);
    b.state[0].w_P = q.conjugate() * w_W;
    b.state[0].v_W = w_W.cross(d * dir);
    JointDef j;
    j.name = "shoulder";
    j.type = JointType::spherical;
    j.parent = reversed ? 0 : -1;  // reversed: written [rod, world]
    j.child = reversed ? -1 : 0;
    j.anchor_W = Vec3::Zero();
    j.axis_W = dir;
    if (limits) j.ball_limits = *limits;
    if (spring) j.spring = *spring;
    std::vector<std::string> warnings;
    art.build({j}, {}, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
  bool step(double dt = 1.0 / 60) { return art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()); }
  const MotionState& s() const { return b.state[0]; }
  Vec3 rod() const { return s().x_W / d; }  // unit, pivot to centre
  double energy() const { return b.energy(g); }
  const Mechanism& mech() const { return art.mechanisms()[0]; }
};

// The triangle wave of a rate w bouncing elastically between -c and c, starting at 0 upwards.
double triangle(double t, double w, double c) {
  const double P = 4 * c / w;
  const double s = std::fmod(t, P) * w;  // the path travelled in this period
  if (s <= c) return s;
  if (s <= 3 * c) return 2 * c - s;
  return s - 4 * c;
}

TEST(BallLimits, ConeReversesASwingElastically) {
  // Hanging along -z, no gravity, turning about +y at w: the rod swings at the constant rate w
  // (a principal axis) until its tilt reaches the cone, and with restitution 1 back and forth
  // between the cone's two sides: a triangle wave of period 4 c / w.
  const double w = 2, c = 0.5;
  BallLimits L;
  L.cone = c;
  L.restitution = 1;
  Limb r(-Vec3::UnitZ(), Vec3(0, w, 0), 0, &L);
  const double E0 = r.energy();
  double worst = 0, worst_E = 0;
  for (int f = 1; f <= 180; ++f) {
    ASSERT_TRUE(r.step());
    const double t = f / 60.0;
    // A right-handed turn about +y moves -z towards -x.
    const double th = std::atan2(-r.rod().x(), -r.rod().z());
    worst = std::max(worst, std::abs(th - triangle(t, w, c)));
    worst_E = std::max(worst_E, std::abs(r.energy() - E0) / E0);
  }
  std::printf("cone, e = 1: angle error %.1e rad, energy %.1e, events %ld\n", worst, worst_E,
              r.mech().events);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_E, 1e-10);
  EXPECT_EQ(r.mech().events, 6);  // hits at 0.25, 0.75, ..., 2.75 s
  EXPECT_LT(r.art.angular_gap(r.b.state.data()), 1e-10);
}

TEST(BallLimits, ConeTakesOnlyTheSwingRateWithRestitution) {
  // Restitution e keeps -e times the swing rate: the energy after the first stop is e^2 of the
  // start's, and the rod swings back at e w from the cone (t1 = c / w) until the other side.
  const double w = 2, c = 0.5;
  for (double e : {0.0, 0.5}) {
    BallLimits L;
    L.cone = c;
    L.restitution = e;
    Limb r(-Vec3::UnitZ(), Vec3(0, w, 0), 0, &L);
    const double E0 = r.energy(), t1 = c / w;
    for (int f = 1; f <= 60; ++f) {
      ASSERT_TRUE(r.step());
      const double t = f / 60.0;
      const double th = std::atan2(-r.rod().x(), -r.rod().z());
      const double expect = t < t1 ? w * t : c - e * w * (t - t1);
      EXPECT_NEAR(th, expect, 1e-9) << "e = " << e << " at t = " << t;
      if (t > t1) {
        EXPECT_NEAR(r.energy(), e * e * E0, 1e-12) << "e = " << e;
      }
    }
    if (e == 0) {
      EXPECT_EQ(r.mech().tethers[0].taut, 1);  // resting on the cone
    }
  }
}

TEST(BallLimits, TwistStopsReverseASpin) {
  // Hanging along -z, no gravity, spinning at 3 rad/s about +z: the twist about the joint's axis
  // (-z) runs at -3 rad/s between the stops -0.4 and 0.6 (elastic), a triangle wave.
  const double w = 3, lo = -0.4, hi = 0.6;
  BallLimits L;
  L.twist_lower = lo;
  L.twist_upper = hi;
  L.restitution = 1;
  Limb r(-Vec3::UnitZ(), Vec3(0, 0, w), 0, &L);
  const double E0 = r.energy();
  double worst = 0;
  for (int f = 1; f <= 120; ++f) {
    ASSERT_TRUE(r.step());
    const double t = f / 60.0;
    const Vec3 x = r.s().q_WP * Vec3::UnitX();
    const double psi = -std::atan2(x.y(), x.x());  // about -z
    // The path travelled down from hi (the start, 0, is hi along it), folded between the stops.
    const double span = hi - lo, s = std::fmod(hi + w * t, 2 * span);
    const double expect = s <= span ? hi - s : lo + (s - span);
    worst = std::max(worst, std::abs(psi - expect));
    EXPECT_NEAR(r.energy(), E0, 1e-10 * E0);
  }
  std::printf("twist, e = 1: angle error %.1e rad, events %ld\n", worst, r.mech().events);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GE(r.mech().events, 5);
}

TEST(BallLimits, AJointWrittenTheOtherWayRoundTwistsTheOtherWay) {
  // Written [rod, world], the joint's twist is the world's relative to the rod: minus the rod's.
  // Stops at [-0.6, 0.4] that way round are the rod's [-0.4, 0.6]: the same motion, bit for bit.
  BallLimits L, R;
  L.twist_lower = -0.4;
  L.twist_upper = 0.6;
  R.twist_lower = -0.6;
  R.twist_upper = 0.4;
  L.cone = R.cone = 0.5;
  L.restitution = R.restitution = 0.7;
  const Vec3 dir = Vec3(1, 0, -1).normalized(), w(1.5, 2, 3);
  Limb a(dir, w, 9.81, &L), b(dir, w, 9.81, &R, nullptr, true);
  for (int f = 0; f < 180; ++f) {
    ASSERT_TRUE(a.step());
    ASSERT_TRUE(b.step());
  }
  EXPECT_GE(a.mech().events, 3);
  EXPECT_EQ(a.s().q_WP.coeffs(), b.s().q_WP.coeffs());
  EXPECT_EQ(a.s().w_P, b.s().w_P);
}

TEST(BallLimits, LimbRestsOnItsConeHeldByTheStop) {
  // Held out horizontally along +x and let go under gravity, restitution 0: the rod falls until
  // its tilt is the cone's 0.4 rad and rests there. The stop then holds gravity's moment about
  // the pivot, m g d cos(c) about -y, and all the kinetic energy m g d sin(c) is gone.
  const double c = 0.4, g = 9.81;
  BallLimits L;
  L.cone = c;
  Limb r(Vec3::UnitX(), Vec3::Zero(), g, &L);
  for (int f = 0; f < 120; ++f) ASSERT_TRUE(r.step());
  const Vec3 rod = r.rod();
  EXPECT_NEAR(std::atan2(rod.cross(Vec3::UnitX()).norm(), rod.x()), c, 1e-12);
  EXPECT_NEAR(rod.z(), -std::sin(c), 1e-12);
  EXPECT_NEAR(r.energy(), -m * g * d * std::sin(c), 1e-12);
  Vec3 F, T;
  r.art.reaction(0, r.b.state.data(), Vec3(0, 0, -g), F, T);
  EXPECT_NEAR((F - Vec3(0, 0, m * g)).norm(), 0, 1e-9);
  EXPECT_NEAR((T - Vec3(0, -m * g * d * std::cos(c), 0)).norm(), 0, 1e-9) << T.transpose();
}

// Steps `frames` frames and, over the steps that begin and end on the stop (tether 0 held, no
// event between), measures the largest energy change (m g d) and counts those in which the rod
// moved (|w| > 0.5 rad/s); `on_held` sees each such moving step (with its count).
struct HeldRun {
  int moving = 0;
  double worst_E = 0;
};
template <class F>
HeldRun run_held(Limb& r, int frames, F&& on_held) {
  HeldRun out;
  for (int f = 0; f < frames; ++f) {
    const double E0 = r.energy();
    const long ev = r.mech().events;
    const bool held0 = r.mech().tethers[0].taut != 0;
    if (!r.step()) {
      ADD_FAILURE() << "the step failed at frame " << f;
      return out;
    }
    if (!(held0 && r.mech().tethers[0].taut != 0 && r.mech().events == ev)) continue;
    out.worst_E = std::max(out.worst_E, std::abs(r.energy() - E0) / (m * r.g * d));
    if (r.s().w_P.norm() > 0.5) on_held(++out.moving);
  }
  return out;
}

TEST(BallLimits, ConeIsAWorklessWallWhileItHolds) {
  // Held out along +x, swung sideways at 3 rad/s under gravity, restitution 0: the rod reaches
  // the cone obliquely, loses its rate into the wall and then slides round the wall, pressed on
  // it by gravity, like a pendulum on a conical rim. A frictionless wall does no work: while the
  // stop holds the energy is constant, and the tilt is the cone's.
  const double c = 0.4, g = 9.81;
  BallLimits L;
  L.cone = c;
  Limb r(Vec3::UnitX(), Vec3(0, 0, 3), g, &L);
  double worst_tilt = 0;
  const HeldRun h = run_held(r, 300, [&](int) {
    const Vec3 rod = r.rod();
    worst_tilt = std::max(worst_tilt, std::abs(std::atan2(rod.cross(Vec3::UnitX()).norm(), rod.x()) - c));
  });
  std::printf("on the cone's wall: %d frames held and moving, energy %.1e m g d, tilt %.1e rad\n", h.moving,
              h.worst_E, worst_tilt);
  EXPECT_GE(h.moving, 60);
  EXPECT_LT(h.worst_E, 1e-10);
  EXPECT_LT(worst_tilt, 1e-12);
}

TEST(BallLimits, TwistStopIsWorklessWhileItHolds) {
  // Held out along +x, spun at 2 rad/s about its own axis, swung sideways at 3 rad/s and let fall
  // under gravity, restitution 0: the twist reaches its stop (0.3 rad) and stays on it while the
  // rod swings round the pivot as a spherical pendulum, the stop turning with it. Held, the stop
  // does no work.
  const double g = 9.81;
  BallLimits L;
  L.twist_lower = -0.3;
  L.twist_upper = 0.3;
  Limb r(Vec3::UnitX(), Vec3(2, 0, 3), g, &L);
  const HeldRun h = run_held(r, 240, [&](int k) {
    if (k != 20) return;
    // The stop's torque, against the rod's rate of change of angular momentum about the pivot
    // less gravity's moment (a central difference over 2e-4 s: 1e-8 of the torque).
    Limb p = r;
    const Vec3 L0 = p.b.angular_momentum();
    ASSERT_TRUE(p.step(1e-4));
    Vec3 F, T;
    p.art.reaction(0, p.b.state.data(), Vec3(0, 0, -g), F, T);
    const Vec3 gravity_moment = p.s().x_W.cross(Vec3(0, 0, -m * g));
    ASSERT_TRUE(p.step(1e-4));
    const Vec3 T_fd = (p.b.angular_momentum() - L0) / 2e-4 - gravity_moment;
    EXPECT_LT((T - T_fd).norm(), 1e-6) << T.transpose() << " against " << T_fd.transpose();
  });
  std::printf("on the twist stop: %d frames held and moving, energy %.1e m g d\n", h.moving, h.worst_E);
  EXPECT_GE(h.moving, 30);
  EXPECT_LT(h.worst_E, 1e-10);
}

TEST(BallLimits, AngleStopReversesATurnElastically) {
  // The whole rotation's angle (MJCF's ball range): turning at a constant 2 rad/s about +y, or
  // spinning at 2 rad/s about the rod's own axis, the angle grows at the rate until 0.5 rad, and
  // with restitution 1 the turn reverses through the start to the other side: a triangle wave.
  for (const Vec3& w : {Vec3(0, 2, 0), Vec3(0, 0, 2)}) {
    BallLimits L;
    L.angle = 0.5;
    L.restitution = 1;
    Limb r(-Vec3::UnitZ(), w, 0, &L);
    const Quat q0 = r.s().q_WP;
    double worst = 0;
    for (int f = 1; f <= 120; ++f) {
      ASSERT_TRUE(r.step());
      // The signed turn about w's direction since the start.
      const Quat rel = r.s().q_WP * q0.conjugate();
      const double turn = 2 * std::atan2(rel.vec().dot(w.normalized()), rel.w());
      worst = std::max(worst, std::abs(turn - triangle(f / 60.0, 2, 0.5)));
    }
    EXPECT_LT(worst, 1e-9) << "turning about " << w.transpose();
    EXPECT_EQ(r.mech().events, 4);  // at 0.25, 0.75, 1.25, 1.75 s
  }
}

TEST(BallLimits, AngleStopIsWorklessWhileItHolds) {
  // Held out along +x, swung sideways at 3 rad/s under gravity, restitution 0: the rotation's
  // angle reaches its 0.5 rad stop and the rod then moves on the stop's boundary (every rotation
  // of angle 0.5 from the start), pressed on it by gravity; held, the stop does no work.
  const double g = 9.81;
  BallLimits L;
  L.angle = 0.5;
  Limb r(Vec3::UnitX(), Vec3(0, 0, 3), g, &L);
  const HeldRun h = run_held(r, 300, [](int) {});
  std::printf("on the angle stop: %d frames held and moving, energy %.1e m g d\n", h.moving, h.worst_E);
  EXPECT_GE(h.moving, 30);
  EXPECT_LT(h.worst_E, 1e-10);
}

// The swing and twist of a rod about the joint's axis a (world, at t = 0), from its rotation
// since the start: R a makes the swing angle with a, and the twist is the angle about a of the
// quaternion's part along a (swing-twist decomposition).
void swing_twist(const Quat& rel, const Vec3& a, double& swing, double& twist) {
  Quat q = rel.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Vec3 c = q * a;
  swing = std::atan2(a.cross(c).norm(), a.dot(c));
  twist = 2 * std::atan2(a.dot(q.vec()), q.w());
}

TEST(BallLimits, ElasticLimbInGravityKeepsItsEnergyWithinItsStops) {
  // A limb (cone 0.6 rad, twist +-0.5 rad, restitution 1) hanging along -z, thrown with a turn in
  // every direction under gravity: it beats against both stops. Elastic stops and a smooth joint
  // keep the energy; the angles stay inside the stops.
  const double g = 9.81;
  BallLimits L;
  L.cone = 0.6;
  L.twist_lower = -0.5;
  L.twist_upper = 0.5;
  L.restitution = 1;
  const Vec3 a = -Vec3::UnitZ();
  Limb r(a, Vec3(2.5, 1.5, 2.0), g, &L);
  const Quat q0 = r.s().q_WP;
  const double E0 = r.energy();
  double worst_E = 0, over = 0;
  for (int f = 0; f < 600; ++f) {
    ASSERT_TRUE(r.step());
    worst_E = std::max(worst_E, std::abs(r.energy() - E0) / (m * g * d));
    double sw, tw;
    swing_twist(r.s().q_WP * q0.conjugate(), a, sw, tw);
    over = std::max({over, sw - L.cone, tw - L.twist_upper, L.twist_lower - tw});
  }
  std::printf("elastic limb, 10 s: energy %.1e m g d, past a stop %.1e rad, events %ld, steps %ld\n", worst_E,
              over, r.mech().events, r.art.internal_steps());
  EXPECT_LT(worst_E, 1e-8);
  EXPECT_LT(over, 1e-9);
  EXPECT_GE(r.mech().events, 20);
}

TEST(BallSpring, SwingsHarmonicallyAtAnyAmplitude) {
  // No gravity, a spring k on the ball joint, thrown about +y at w0: the rod turns about +y only
  // and theta'' = -(k / Ip) theta exactly, so theta = (w0 / W) sin(W t), W = sqrt(k / Ip), here
  // with an amplitude of 1.58 rad.
  const double k = 2.7, w0 = 5, W = std::sqrt(k / Ip);
  JointSpring sp;
  sp.stiffness = k;
  Limb r(-Vec3::UnitZ(), Vec3(0, w0, 0), 0, nullptr, &sp);
  const double E0 = r.energy();
  double worst = 0, worst_E = 0;
  for (int f = 1; f <= 300; ++f) {
    ASSERT_TRUE(r.step());
    const double t = f / 60.0;
    const double th = std::atan2(-r.rod().x(), -r.rod().z());
    worst = std::max(worst, std::abs(th - (w0 / W) * std::sin(W * t)));
    worst_E = std::max(worst_E, std::abs(r.energy() + r.art.spring_energy() - E0) / E0);
  }
  std::printf("ball spring: angle error %.1e rad (amplitude %.2f), energy %.1e\n", worst, w0 / W, worst_E);
  // The integrator's tolerance (1e-10 a step, relative) over ~10^3 internal steps.
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(worst_E, 1e-8);
}

TEST(BallSpring, KeepsEnergyInThreeDimensionsUnderGravity) {
  // The spring's potential k |phi|^2 / 2 with the torque -k phi: a tumbling limb under gravity
  // keeps kinetic + gravitational + spring energy; with damping c it loses exactly the power
  // c |w_rel|^2 (checked through the energy falling, never rising).
  const double g = 9.81;
  JointSpring sp;
  sp.stiffness = 4;
  Limb r(Vec3(1, 0, -1).normalized(), Vec3(3, -2, 4), g, nullptr, &sp);
  const double E0 = r.energy() + r.art.spring_energy();
  double worst = 0;
  for (int f = 0; f < 600; ++f) {
    ASSERT_TRUE(r.step());
    worst = std::max(worst, std::abs(r.energy() + r.art.spring_energy() - E0) / (m * g * d));
  }
  std::printf("ball spring in 3D, 10 s: energy %.1e m g d\n", worst);
  EXPECT_LT(worst, 1e-8);
  sp.damping = 0.05;
  Limb rd(Vec3(1, 0, -1).normalized(), Vec3(3, -2, 4), g, nullptr, &sp);
  double prev = rd.energy() + rd.art.spring_energy();
  for (int f = 0; f < 600; ++f) {
    ASSERT_TRUE(rd.step());
    const double E = rd.energy() + rd.art.spring_energy();
    EXPECT_LE(E, prev + 1e-12);
    prev = E;
  }
  EXPECT_LT(prev, E0 - 0.1);
}

}  // namespace
}  // namespace simreel
