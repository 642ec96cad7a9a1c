// A ball joint's motor and friction (JointMotor and JointDef::friction on a spherical joint;
// docs/joints.md) against closed forms of rigid-body mechanics written out here: Euler's equations
// for the torque that holds a constant angular velocity (w x I w), constant torque spinning a body
// up about a principal axis, the exponential approach e(t) = e0 exp(-t / tau) of a rotation held at
// w = e / tau (a turn about a fixed axis), and Coulomb friction decelerating each of a spherical
// body's three rates at F / I until each stops.
//
// The body's principal axes are the world's at the start, so its body-frame angular velocity w_P
// is the joint's rate in the child's axes, and an orientation's distance from the closed form is
// the angle of q_expected^-1 q.
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "tests/fixtures/joint_bodies.hpp"

namespace simreel {
namespace {

using test::Bodies;

double angle_between(const Quat& a, const Quat& b) {
  return 2 * std::asin(std::min(1.0, (a.conjugate() * b).vec().norm()));
}

Quat exp_rotation(const Vec3& r) {
  const double a = r.norm();
  return a > 0 ? Quat(Eigen::AngleAxisd(a, r / a)) : Quat::Identity();
}

// One body on a ball joint to the world at `anchor`; its centre of mass at x, principal moments I,
// turning at w_P (body axes = world axes at the start).
struct Ball {
  Bodies b;
  Articulations art;
  double g;
  Ball(const Vec3& I, const Vec3& x, const Vec3& anchor, const Vec3& w_P, double gravity,
       const std::optional<JointMotor>& motor, double friction = 0, bool reversed = false)
      : g(gravity) {
    b.add("body", 1.0, I, x);
    b.state[0].w_P = w_P;
    b.state[0].v_W = w_P.cross(x - anchor);
    JointDef j;
    j.name = "ball";
    j.type = JointType::spherical;
    j.parent = reversed ? 0 : -1;
    j.child = reversed ? -1 : 0;
    j.anchor_W = anchor;
    j.motor = motor;
    j.friction = friction;
    std::vector<std::string> warnings;
    art.build({j}, {}, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
  bool step(double dt = 1.0 / 60) { return art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()); }
  const MotionState& s() const { return b.state[0]; }
  Vec3 torque() const { return Vec3(art.force(0, 0), art.force(0, 1), art.force(0, 2)); }
};

JointMotor speed_motor(const Vec3& w, double max_torque) {
  JointMotor m;
  m.mode = JointMotor::Mode::speed;
  m.angular_velocity = w;
  m.max_force = max_torque;
  return m;
}

JointMotor position_motor(const Vec3& r, double tau, double cap, double max_torque) {
  JointMotor m;
  m.mode = JointMotor::Mode::position;
  m.rotation = r;
  m.time_constant = tau;
  m.speed = cap;
  m.max_force = max_torque;
  return m;
}

TEST(BallMotor, SpeedMotorHoldsATurnAboutAFixedAxisWithEulersTorque) {
  // Pivot at the centre of mass, asymmetric body, target w not along a principal axis: held, the
  // body turns as exp(t [w]) and the motor supplies Euler's torque w x I w (w' = 0) in body axes.
  // Tolerances: 1e-10 rad over 3 s (the integrator at its tolerance), 1e-9 relative on the torque.
  const Vec3 I(0.3, 0.2, 0.1), w(1, 2, -0.5);
  Ball p(I, Vec3(0, 0, 1), Vec3(0, 0, 1), w, 9.81, speed_motor(w, 100));
  const Vec3 tau = w.cross(I.cwiseProduct(w));
  double eq = 0, ew = 0, et = 0;
  for (int i = 1; i <= 180; ++i) {
    ASSERT_TRUE(p.step());
    const double t = i / 60.0;
    eq = std::max(eq, angle_between(exp_rotation(t * w), p.s().q_WP));
    ew = std::max(ew, (p.s().w_P - w).norm());
    et = std::max(et, (p.torque() - tau).norm() / tau.norm());
  }
  std::printf("ball speed motor: orientation %.1e rad, rate %.1e rad/s, torque %.1e relative\n", eq, ew, et);
  EXPECT_LT(eq, 1e-10);
  EXPECT_LT(ew, 1e-10);
  EXPECT_LT(et, 1e-9);
}

TEST(BallMotor, SaturatedSpeedMotorSpinsUpAtItsTorqueThenHolds) {
  // From rest, target (0, 0, 5) rad/s about the third principal axis with a 0.2 N m bound:
  // w_z = T t / I3 (2 rad/s^2) until 5 rad/s at t1 = 2.5 s, then held; the other two rates are
  // held at 0 by no torque. Angle at 4 s: T t1^2 / (2 I3) + W (4 - t1) = 13.75 rad.
  const Vec3 I(0.3, 0.2, 0.1);
  const double T = 0.2, W = 5, t1 = I.z() * W / T;
  Ball p(I, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 9.81, speed_motor(Vec3(0, 0, W), T));
  double ew = 0, et = 0;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(p.step());
    const double t = i / 60.0;
    const double wz = t < t1 ? T * t / I.z() : W;
    ew = std::max(ew, (p.s().w_P - Vec3(0, 0, wz)).norm());
    if (std::abs(t - t1) > 0.02) et = std::max(et, std::abs(p.torque().z() - (t < t1 ? T : 0.0)));
    et = std::max(et, p.torque().head<2>().norm());
  }
  const double angle = T * t1 * t1 / (2 * I.z()) + W * (4 - t1);
  const double eq = angle_between(exp_rotation(Vec3(0, 0, angle)), p.s().q_WP);
  std::printf("saturated ball motor: rate %.1e rad/s, torque %.1e N m, angle at 4 s %.1e rad\n", ew, et, eq);
  EXPECT_LT(ew, 1e-10);
  EXPECT_LT(et, 1e-10);
  EXPECT_LT(eq, 1e-9);
}

TEST(BallMotor, PositionMotorTurnsToItsTargetExponentiallyUnderGravity) {
  // A rod hanging from the pivot, gravity on, target rotation r (0.8 rad about a skew axis),
  // started at the motor's rate r / tau: held, the rest still to go is r exp(-t / tau), so the
  // rotation from the start is exp((1 - exp(-t / tau)) r), whatever gravity's load (the motor
  // takes it, within its 50 N m). Tolerance 1e-9 rad: the integrator, over 3 s.
  const Vec3 r = 0.8 * Vec3(1, 1, 0.5).normalized();
  const double tau = 0.25;
  Ball p(Vec3(0.02, 0.02, 0.004), Vec3(0, 0, -0.5), Vec3::Zero(), r / tau, 9.81,
         position_motor(r, tau, std::numeric_limits<double>::infinity(), 50));
  double eq = 0;
  for (int i = 1; i <= 180; ++i) {
    ASSERT_TRUE(p.step());
    const double t = i / 60.0;
    eq = std::max(eq, angle_between(exp_rotation((1 - std::exp(-t / tau)) * r), p.s().q_WP));
  }
  std::printf("ball position motor under gravity: %.1e rad\n", eq);
  EXPECT_LT(eq, 1e-9);
  // At the target (after 6 s, e^-24 of r left), the motor holds the rod against gravity: its
  // torque is the weight's moment, in body axes.
  for (int i = 0; i < 180; ++i) ASSERT_TRUE(p.step());
  const Vec3 arm = p.s().x_W;  // pivot to centre
  const Vec3 load_W = arm.cross(Vec3(0, 0, -9.81));
  const Vec3 hold_P = p.s().q_WP.conjugate() * (-load_W);
  EXPECT_LT((p.torque() - hold_P).norm(), 1e-9 * load_W.norm()) << p.torque().transpose();
}

TEST(BallMotor, PositionMotorRunsAtItsSpeedCapThenApproachesExponentially) {
  // |r| = 2 rad, cap 1 rad/s, tau 0.5 s, started at the cap along r: the angle runs at 1 rad/s
  // until 0.5 rad (cap * tau) is left at t1 = 1.5 s, then that rest decays as exp(-(t - t1)/tau).
  // Tolerance 1e-9 rad (the kink at t1 is in the target's derivative only).
  const Vec3 axis = Vec3(1, -1, 2).normalized();
  const double R = 2, cap = 1, tau = 0.5, t1 = (R - cap * tau) / cap;
  Ball p(Vec3(0.3, 0.2, 0.1), Vec3::Zero(), Vec3::Zero(), cap * axis, 0,
         position_motor(R * axis, tau, cap, 100));
  double eq = 0;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(p.step());
    const double t = i / 60.0;
    const double a = t < t1 ? cap * t : R - cap * tau * std::exp(-(t - t1) / tau);
    eq = std::max(eq, angle_between(exp_rotation(a * axis), p.s().q_WP));
  }
  std::printf("ball position motor with a speed cap: %.1e rad\n", eq);
  EXPECT_LT(eq, 1e-9);
}

TEST(BallMotor, WrittenTheOtherWayRoundItsTargetIsTheWorldsRelativeToTheBody) {
  // [body, world]: the motor drives the world's motion relative to the body, so a speed target w
  // turns the body at -w, and a position target r takes it to the rotation exp(-r).
  const Vec3 w(0, 0.5, 2);
  Ball p(Vec3(0.3, 0.2, 0.1), Vec3::Zero(), Vec3::Zero(), -w, 0, speed_motor(w, 100), 0, true);
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(p.step());
  EXPECT_LT(angle_between(exp_rotation(-w), p.s().q_WP), 1e-10);
  const Vec3 r(0.3, -0.2, 0.4);
  Ball q(Vec3(0.3, 0.2, 0.1), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 0,
         position_motor(r, 0.1, std::numeric_limits<double>::infinity(), 100), 0, true);
  for (int i = 0; i < 180; ++i) ASSERT_TRUE(q.step());  // 30 time constants: e^-30 of r left
  EXPECT_LT(angle_between(exp_rotation(-r), q.s().q_WP), 1e-10);
}

TEST(BallMotor, TargetAccelerationIsTheTargetRatesDerivative) {
  // The held row's right-hand side is d/dt of the target rate along the motion: compared with a
  // central difference of target_rate along q(t) = q0 exp(t w) (exact for constant w), at random
  // poses and rates, uncapped and capped. Tolerance 1e-7 relative (the difference's h^2 ~ 1e-8).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 40; ++trial) {
    Mechanism::Dof d;
    d.motor = 2;
    d.iq = 0;
    d.time_constant = 0.3;
    d.speed = trial % 2 ? 0.5 : std::numeric_limits<double>::infinity();
    d.target = exp_rotation(2.5 * Vec3(u(rng), u(rng), u(rng)).normalized() * std::abs(u(rng)));
    const Quat q0 = exp_rotation(3.0 * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.0));
    const Vec3 w = 2 * Vec3(u(rng), u(rng), u(rng));
    const double h = 1e-5;
    auto at = [&](double t, double* q) {
      const Quat r = q0 * exp_rotation(t * w);
      q[0] = r.w(), q[1] = r.x(), q[2] = r.y(), q[3] = r.z();
    };
    double qa[4], qb[4], qc[4], v[3] = {w.x(), w.y(), w.z()};
    at(-h, qa);
    at(0, qb);
    at(h, qc);
    for (int k = 0; k < 3; ++k) {
      d.ball = k;
      d.iv = k;
      const double fd = (d.target_rate(qc) - d.target_rate(qa)) / (2 * h);
      const double an = d.target_acceleration(qb, v);
      EXPECT_NEAR(an, fd, 1e-7 * (1 + std::abs(fd))) << "trial " << trial << " component " << k;
    }
  }
}

TEST(BallFriction, EachRateDeceleratesAtFOverIUntilItStops) {
  // A body with equal principal moments I on a pivot at its centre (no gyroscopic torque), turning
  // at (3, -1, 0) rad/s with friction F = 0.05 N m about each axis: each rate falls at F / I =
  // 0.5 rad/s^2 independently, w_y stopping at 2 s and w_x at 6 s, then both stay stopped; the
  // third, never moving, is held by friction with no torque. Tolerance 1e-12 rad/s (piecewise
  // linear: the integrator is exact, the stops are events located to round-off).
  const double I = 0.1, F = 0.05;
  Ball p(Vec3(I, I, I), Vec3::Zero(), Vec3::Zero(), Vec3(3, -1, 0), 0, std::nullopt, F);
  double ew = 0, et = 0;
  for (int i = 1; i <= 480; ++i) {
    ASSERT_TRUE(p.step());
    const double t = i / 60.0, a = F / I;
    const Vec3 we(std::max(3 - a * t, 0.0), std::min(-1 + a * t, 0.0), 0);
    ew = std::max(ew, (p.s().w_P - we).norm());
    const Vec3 te(t < 6 ? -F : 0.0, t < 2 ? F : 0.0, 0);
    if (std::abs(t - 2) > 0.02 && std::abs(t - 6) > 0.02) et = std::max(et, (p.torque() - te).norm());
  }
  std::printf("ball friction: rates %.1e rad/s, torque %.1e N m\n", ew, et);
  EXPECT_LT(ew, 1e-12);
  EXPECT_LT(et, 1e-12);
}

TEST(BallFriction, HoldsALimbWhileItCanAndSlipsWhenItCannot) {
  // A rod tilted 0.4 rad about x from hanging, released at rest: gravity's moment about the pivot
  // is m g d sin(0.4) about x. Friction 1% above it holds the rod still for good; 1% below, it
  // slips, accelerating at (m g d sin(0.4) - F) / I_p.
  const double d = 0.5, th = 0.4, g = 9.81, I1 = 0.02, Ip = I1 + d * d;
  const double load = d * g * std::sin(th);
  const Quat q0(Eigen::AngleAxisd(th, Vec3::UnitX()));
  const Vec3 x = q0 * Vec3(0, 0, -d);
  for (const double f : {1.01, 0.99}) {
    Bodies b;
    b.add("rod", 1.0, Vec3(I1, I1, 0.004), x, q0);
    JointDef j;
    j.type = JointType::spherical;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3::Zero();
    j.friction = f * load;
    Articulations art;
    std::vector<std::string> w;
    art.build({j}, {}, b.defs, b.model, b.state, w);
    const double T = 0.01;  // short: gravity's moment changes by 0.04% of the net over it
    ASSERT_TRUE(art.step(T, Vec3(0, 0, -g), nullptr, b.state.data()));
    const double moved = angle_between(q0, b.state[0].q_WP);
    if (f > 1) {
      EXPECT_EQ(moved, 0.0);
      EXPECT_NEAR(art.force(0, 0), load, 1e-12 * load);  // all of the load, about the body's x
    } else {
      const double expected = 0.5 * (load - f * load) / Ip * T * T;
      EXPECT_NEAR(moved, expected, 2e-3 * expected);
    }
  }
}

}  // namespace
}  // namespace simreel
