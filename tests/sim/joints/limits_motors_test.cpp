// Joint limits, motors and Coulomb joint friction (sim/joints/articulation.hpp, docs/joints.md)
// against closed forms written out in each test from the textbook mechanics, never from simreel's
// code: constant-acceleration and constant-rate kinematics, energy and angular-momentum balances,
// the impulsive response of a two-link chain through its 2x2 mass matrix, the bouncing ball, the
// Coulomb-damped linear oscillator, the exponential approach of a first-order servo and the Watt
// governor in its rotating frame. Where a closed form needs a definite integral (a pendulum's fall
// time, the chain's time to its stop) the test evaluates it by Gauss-Legendre quadrature to round-off.
//
// Sign conventions used throughout: a revolute coordinate is a right-handed turn about the joint's
// axis (a turn about +y moves a bob hanging at (0, 0, -d) towards -x), a prismatic one a shift along
// its axis, and force(j) is the generalised force that the joint's stops, motor and friction apply
// along +q (a spring's force is not part of it). The mechanisms are advanced in 1/60 s frames
// unless a test says otherwise; the modes switch at events located inside a frame, so the frames
// deliberately do not fall on the closed forms' switching times.
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>

#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

constexpr double kPi = std::numbers::pi;

using test::Bodies;

JointDef hinge(int parent, int child, const Vec3& anchor, const Vec3& axis) {
  JointDef j;
  j.name = "j" + std::to_string(child);
  j.type = JointType::revolute;
  j.parent = parent;
  j.child = child;
  j.anchor_W = anchor;
  j.axis_W = axis;
  return j;
}

void build(Articulations& art, Bodies& b, const std::vector<JointDef>& joints) {
  std::vector<std::string> warnings;
  art.build(joints, {}, b.defs, b.model, b.state, warnings);
  // Every test gives its bodies velocities its joints allow: nothing is projected away.
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

// A bob of mass m (isotropic inertia Icm about its centre) at distance d from a hinge about +y at
// the origin, placed at angle phi0 from the downward vertical (a right-handed turn about +y:
// position (-d sin phi0, 0, -d cos phi0)), turning at rate w0 about the hinge. Its angle from the
// downward vertical is phi0 + q; gravity's generalised force on q is -m g d sin(phi0 + q).
struct Pendulum {
  static constexpr double m = 1, Icm = 1e-3, d = 1, g = 9.81;
  static constexpr double Ip = Icm + m * d * d;  // about the hinge (Steiner)
  static constexpr double mgd = m * g * d;
  Bodies b;
  Articulations art;
  Pendulum(double phi0, double w0, const JointDef& extras) {
    const Vec3 x(-d * std::sin(phi0), 0, -d * std::cos(phi0));
    b.add("bob", m, Vec3::Constant(Icm), x);
    b.state[0].w_P = Vec3(0, w0, 0);
    b.state[0].v_W = Vec3(0, w0, 0).cross(x);
    JointDef j = extras;
    j.name = "pivot";
    j.type = JointType::revolute;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3::Zero();
    j.axis_W = Vec3::UnitY();
    build(art, b, {j});
  }
  bool step(double dt) { return art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()); }
};

// A wheel spinning about +z through its centre of mass (I about the axis), no gravity: q'' is the
// joint's generalised force (plus any spring's) divided by I.
struct Flywheel {
  static constexpr double I = 0.02;
  Bodies b;
  Articulations art;
  Flywheel(double w0, const JointDef& extras) {
    b.add("wheel", 1.0, Vec3(0.01, 0.01, I), Vec3::Zero());
    b.state[0].w_P = Vec3(0, 0, w0);
    JointDef j = extras;
    j.name = "axle";
    j.type = JointType::revolute;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3::Zero();
    j.axis_W = Vec3::UnitZ();
    build(art, b, {j});
  }
  bool step(double dt) { return art.step(dt, Vec3::Zero(), nullptr, b.state.data()); }
};

// Composite 5-point Gauss-Legendre quadrature of a smooth f over [a, b] in n panels (exact for
// polynomials of degree 9 per panel: for the analytic integrands here, round-off at n = 200).
double integrate(const std::function<double(double)>& f, double a, double b, int n = 200) {
  static constexpr double x[5] = {0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                  0.9061798459386640};
  static constexpr double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                  0.2369268850561891, 0.2369268850561891};
  const double h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double c = a + (i + 0.5) * h;
    for (int k = 0; k < 5; ++k) sum += w[k] * f(c + 0.5 * h * x[k]);
  }
  return 0.5 * h * sum;
}

// Root of f on [a, b] (f(a), f(b) of opposite signs) by bisection to the last bit.
double bisect(const std::function<double(double)>& f, double a, double b) {
  double fa = f(a);
  for (int i = 0; i < 200; ++i) {
    const double c = 0.5 * (a + b);
    if (c == a || c == b) break;
    const double fc = f(c);
    if ((fc < 0) == (fa < 0)) {
      a = c;
      fa = fc;
    } else {
      b = c;
    }
  }
  return 0.5 * (a + b);
}

// ------------------------------------------------------------------------------------------------
// Motors
// ------------------------------------------------------------------------------------------------

// A pendulum (1 kg bob 1 m from a horizontal hinge) driven over the top by a speed motor at
// w = 2 rad/s with a 20 N m bound, above the largest load m g d = 9.81 N m, and started at w. The
// motor can always hold the rate, so it holds it exactly: q = w t, q' = w, and the torque it
// applies is the one that cancels gravity's, tau = +m g d sin q (gravity's generalised force on a
// right-handed turn about +y is -m g d sin q; the bob's own inertia enters no torque at constant
// rate). Held exactly, q'' = 0 and the integrator's error is round-off (1e-13 rad over 10 s): the
// tolerances (1e-9 rad, 1e-9 rad/s, 1e-9 m g d) are four orders above it and far below what they
// guard: without the motor the pendulum (2 J of kinetic energy) would not climb past 0.65 rad, a
// motor that let its rate sag under the load by 1e-6 would be 1e-5 rad behind within 10 s, and a
// torque read-out that missed any part of the load would be off by a fraction of m g d.
TEST(JointMotor, SpeedMotorTurnsAPendulumOverTheTopAtExactlyItsSpeed) {
  const double w = 2, Tmax = 20;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = w, .max_force = Tmax};
  Pendulum p(0, w, x);
  double eq = 0, ev = 0, ef = 0;
  for (int i = 1; i <= 600; ++i) {  // 10 s: 20 rad, over three revolutions
    ASSERT_TRUE(p.step(1.0 / 60));
    const double t = i / 60.0, q = p.art.position(0);
    eq = std::max(eq, std::abs(q - w * t));
    ev = std::max(ev, std::abs(p.art.speed(0) - w));
    ef = std::max(ef, std::abs(p.art.force(0) - p.mgd * std::sin(q)) / p.mgd);
  }
  std::printf("speed motor, loaded: |q - w t| %.1e rad, |q' - w| %.1e rad/s, torque %.1e m g d\n", eq, ev,
              ef);
  EXPECT_GT(p.art.position(0), 6 * kPi);
  EXPECT_LT(eq, 1e-9);
  EXPECT_LT(ev, 1e-9);
  EXPECT_LT(ef, 1e-9);
}

// A flywheel (I = 0.02 kg m^2) at rest in zero gravity, a speed motor of target w = 3 rad/s and
// bound T = 0.07 N m: it cannot hold the target from rest, so it pushes with exactly T, the wheel
// accelerating at T / I, until the rate reaches w at t* = I w / T = 0.857 s (inside a frame); from
// then on it holds w with no torque (nothing loads the wheel). Closed form:
//   t < t*:  q = T t^2 / (2 I),  q' = T t / I,  force = T;
//   t > t*:  q = w t - w^2 I / (2 T),  q' = w,  force = 0.
// Both phases are polynomials of degree <= 2 that Runge-Kutta integrates exactly, and the switch is
// an event located to ~1e-12 s: tolerance 1e-10 rad, 1e-10 rad/s, 1e-12 T on the force. A switch
// missed by one internal step (~0.1 s) would be off by ~w * 0.1 s = 0.3 rad; a motor that overshot
// w, or that eased into the target, by far more than 1e-10.
TEST(JointMotor, SaturatedSpeedMotorAcceleratesAtMaxTorqueThenHolds) {
  const double w = 3, T = 0.07;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = w, .max_force = T};
  Flywheel f(0, x);
  const double I = Flywheel::I, ts = I * w / T;
  double eq = 0, ev = 0, ef = 0;
  for (int i = 1; i <= 120; ++i) {
    ASSERT_TRUE(f.step(1.0 / 60));
    const double t = i / 60.0;
    const bool before = t < ts;
    const double qe = before ? T * t * t / (2 * I) : w * t - w * w * I / (2 * T);
    const double ve = before ? T * t / I : w;
    const double fe = before ? T : 0;
    eq = std::max(eq, std::abs(f.art.position(0) - qe));
    ev = std::max(ev, std::abs(f.art.speed(0) - ve));
    ef = std::max(ef, std::abs(f.art.force(0) - fe) / T);
  }
  std::printf("speed motor, saturated then holding: q %.1e rad, q' %.1e rad/s, force %.1e T\n", eq, ev, ef);
  EXPECT_LT(eq, 1e-10);
  EXPECT_LT(ev, 1e-10);
  EXPECT_LT(ef, 1e-12);
}

// The pendulum hanging at rest, a speed motor of target 5 rad/s and bound T = 5 N m, below the
// largest gravity load m g d = 9.81 N m: the motor can never hold its target, so it pushes with
// exactly +T all the time, also while the pendulum swings back (q' < 0 < target). The pendulum then
// moves in the potential m g d (1 - cos q) - T q, and
//   H = 1/2 I_p q'^2 + m g d (1 - cos q) - T q = 0
// at every instant; it swings between 0 and the root q_max of m g d (1 - cos q) = T q. Tolerance
// 1e-8 m g d on H (the integrator's error over 10 s is 3e-10 m g d); a push that switched off or
// reversed on the back-swing would change H by T x (swing) ~ 5 J, one 1% off by 5e-3 m g d; and
// force() must read T to 1e-12.
TEST(JointMotor, SpeedMotorBelowTheLoadPushesWithExactlyItsBound) {
  const double T = 5, target = 5;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = target, .max_force = T};
  Pendulum p(0, 0, x);
  const double mgd = p.mgd, Ip = p.Ip;
  const double qe = std::asin(T / mgd);  // the swing's centre; q_max is beyond it
  const double q_max = bisect([&](double q) { return mgd * (1 - std::cos(q)) - T * q; }, qe, kPi);
  double eH = 0, ef = 0, hi = -1, lo = 1, vmax = 0;
  bool back = false;
  for (int i = 1; i <= 600; ++i) {
    ASSERT_TRUE(p.step(1.0 / 60));
    const double q = p.art.position(0), v = p.art.speed(0);
    eH = std::max(eH, std::abs(0.5 * Ip * v * v + mgd * (1 - std::cos(q)) - T * q) / mgd);
    ef = std::max(ef, std::abs(p.art.force(0) - T) / T);
    hi = std::max(hi, q);
    lo = std::min(lo, q);
    vmax = std::max(vmax, v);
    back = back || v < -0.5;
  }
  std::printf("speed motor below the load: H %.1e m g d, force %.1e T, swing [%.6f, %.6f] (q_max %.6f)\n", eH,
              ef, lo, hi, q_max);
  ASSERT_TRUE(back);        // it did swing back under the push
  ASSERT_LT(vmax, target);  // and never reached the target rate
  EXPECT_LT(eH, 1e-8);
  EXPECT_LT(ef, 1e-12);
  EXPECT_LT(hi, q_max + 1e-9);  // sampled at frames: never beyond the closed-form turning point
  EXPECT_GT(hi, q_max - 1e-2);  // and close to it at some frame (1/60 s from a turning point)
  EXPECT_GT(lo, -1e-9);         // nor below the start
}

// The pendulum driven by a speed motor at w = 2.5 rad/s whose bound T = 8 N m is below the largest
// gravity load (m g d = 9.81 N m): the motor alternates between holding its speed and pushing with
// its bound. Started at the bottom at w, it holds q' = w (torque m g d sin q) while |m g d sin q| <= T,
// i.e. until q_r = asin(T / m g d) = 0.953 rad, where it lets go and pushes with exactly +T: the
// pendulum then moves in V+ = m g d (1 - cos q) - T q, with H = 1/2 I_p q'^2 + V+ constant, slows
// over the top (1/2 I_p w^2 = 3.13 J against a 1.47 J barrier) and comes back to w at q_c, the root
// of V+(q) = V+(q_r) in (pi - q_r, pi + q_r), where |m g d sin q_c| < T: it holds again, until the
// braking it needs reaches -T at pi + q_r; there it pushes with exactly -T, speeds up in
// V- = m g d (1 - cos q) + T q and returns to w at q_c2 in (2 pi - q_r, 2 pi + q_r), holds to
// 2 pi + q_r, and so on. Each pushing phase lasts integral dq / sqrt(2 (H - V(q)) / I_p) over its
// range (quadrature; the rate stays >= 1.8 rad/s). Checked over 10 s (two releases a turn: 8
// releases, 16 switches): while holding, q against the schedule (1e-8 rad: it places each release and
// recapture in time to ~4e-9 s) and the torque m g d sin q (1e-9 m g d); while pushing, H (1e-9
// m g d) and the torque +-T (1e-12). Frames within 1e-6 s of a switch are not classified. A motor
// that held past its bound would show a torque above T; one that released late, recaptured late or
// pushed the wrong way would leave the schedule by far more than 1e-8 rad.
TEST(JointMotor, SpeedMotorLetsGoAtItsBoundAndRecapturesItsSpeed) {
  const double w = 2.5, T = 8;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = w, .max_force = T};
  Pendulum p(0, w, x);
  const double mgd = p.mgd, Ip = p.Ip;
  const double qr = std::asin(T / mgd);
  auto V = [&](double q, int s) { return mgd * (1 - std::cos(q)) - s * T * q; };
  ASSERT_GT(0.5 * Ip * w * w, V(kPi - qr, 1) - V(qr, 1));  // the push carries it over the top
  struct Phase {
    int push;       // 0 holding, +-1 pushing with +-T
    double t0, q0;  // start (the rate is w there)
    double t1, q1;  // end
  };
  std::vector<Phase> phases;
  double t = 0, q = 0;
  while (t < 11) {
    // Holding: up to the next angle where |m g d sin q| = T (q_r or pi + q_r, modulo 2 pi).
    double qe = qr;
    while (qe <= q + 1e-9) qe += kPi;
    const int s = std::sin(qe) > 0 ? 1 : -1;
    phases.push_back({0, t, q, t + (qe - q) / w, qe});
    t = phases.back().t1;
    q = qe;
    // Pushing with s T from q (rate w) until the rate is w again.
    const double q0 = q, H = 0.5 * Ip * w * w + V(q0, s);
    const double q1 = bisect([&](double u) { return V(u, s) - V(q0, s); }, q0 + kPi - 2 * qr, q0 + kPi);
    EXPECT_LT(std::abs(mgd * std::sin(q1)), T);  // it can hold there
    const double dt = integrate([&](double u) { return 1 / std::sqrt(2 * (H - V(u, s)) / Ip); }, q0, q1);
    phases.push_back({s, t, q0, t + dt, q1});
    t += dt;
    q = q1;
  }
  double eq = 0, ehf = 0, eH = 0, ef = 0;
  int held = 0, pushed = 0, releases = 0;
  for (const Phase& ph : phases) releases += ph.push != 0 && ph.t0 < 10;
  for (int i = 1; i <= 600; ++i) {
    ASSERT_TRUE(p.step(1.0 / 60));
    const double tt = i / 60.0, qq = p.art.position(0), v = p.art.speed(0), f = p.art.force(0);
    size_t n = 0;
    while (phases[n].t1 <= tt) ++n;
    const Phase& ph = phases[n];
    if (std::min(tt - ph.t0, ph.t1 - tt) < 1e-6) continue;
    if (ph.push == 0) {
      ++held;
      eq = std::max({eq, std::abs(qq - (ph.q0 + w * (tt - ph.t0))), std::abs(v - w)});
      ehf = std::max(ehf, std::abs(f - mgd * std::sin(qq)) / mgd);
    } else {
      ++pushed;
      const double H = 0.5 * Ip * w * w + V(ph.q0, ph.push);
      eH = std::max(eH, std::abs(0.5 * Ip * v * v + V(qq, ph.push) - H) / mgd);
      ef = std::max(ef, std::abs(f - ph.push * T) / T);
    }
  }
  std::printf(
      "speed motor at its bound: %d releases in 10 s; held %d frames, pushed %d; while held q %.1e rad, "
      "torque %.1e m g d; while pushing H %.1e m g d, torque %.1e T\n",
      releases, held, pushed, eq, ehf, eH, ef);
  ASSERT_GE(releases, 6);
  ASSERT_GT(held, 100);
  ASSERT_GT(pushed, 100);
  EXPECT_LT(eq, 1e-8);
  EXPECT_LT(ehf, 1e-9);
  EXPECT_LT(eH, 1e-9);
  EXPECT_LT(ef, 1e-12);
}

// A position motor (target 1 rad, time constant tau = 0.5 s, no speed cap, bound 30 N m) on the
// pendulum, started hanging with q' = 1 rad / tau, the target rate at q = 0: the motor holds
// q' = (position - q) / tau exactly whatever gravity does, so
//   q = position (1 - exp(-t / tau)),   q' = (position / tau) exp(-t / tau),
// and its torque is what that motion needs beyond gravity: tau_m = I_p q'' + m g d sin q with
// q'' = -q' / tau (at most 8.3 N m, inside the bound). Tolerance 1e-9 rad on q (the ODE q' = (p - q)/tau
// integrated at 1e-10 per step) and 1e-7 m g d on the torque; a motor acting as a servo of finite
// gain would sag under gravity's m g d sin q by far more (a gain of 1e4 N m s/rad: 1e-4 rad/s).
TEST(JointMotor, PositionMotorApproachesExponentiallyUnderLoad) {
  const double target = 1.0, tau = 0.5;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::position,
                       .speed = std::numeric_limits<double>::infinity(),
                       .position = target,
                       .time_constant = tau,
                       .max_force = 30};
  Pendulum p(0, target / tau, x);
  double eq = 0, ev = 0, ef = 0;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(p.step(1.0 / 60));
    const double t = i / 60.0, q = p.art.position(0);
    const double e = std::exp(-t / tau);
    const double qd = target / tau * e, qdd = -qd / tau;
    eq = std::max(eq, std::abs(q - target * (1 - e)));
    ev = std::max(ev, std::abs(p.art.speed(0) - qd));
    ef = std::max(ef, std::abs(p.art.force(0) - (p.Ip * qdd + p.mgd * std::sin(q))) / p.mgd);
  }
  std::printf("position motor: q %.1e rad, q' %.1e rad/s, torque %.1e m g d\n", eq, ev, ef);
  EXPECT_LT(eq, 1e-9);
  EXPECT_LT(ev, 1e-9);
  EXPECT_LT(ef, 1e-7);
}

// A universal joint with a motor on each angle: a body hanging 0.5 m below the joint (axis x in
// the parent, axis2 y in the child), under gravity, its first angle held at 1.5 rad/s by a speed
// motor and its second driven to 0.4 rad by a position motor (time constant 0.2 s, no speed cap),
// started at both motors' target rates: each angle follows its motor's law exactly whatever the
// load, q1 = 1.5 t and q2 = 0.4 (1 - exp(-t / 0.2)), while the torques stay within their bounds.
// With a bound of 0.05 N m under the load the first motor saturates and pushes with exactly it.
TEST(JointMotor, UniversalJointsMotorsDriveEachAngle) {
  for (double bound : {100.0, 0.05}) {
    Bodies b;
    const Vec3 x(0, 0, -0.5);
    b.add("gimbal", 1, Vec3(0.02, 0.03, 0.04), x);
    const Vec3 w = 1.5 * Vec3::UnitX() + 2.0 * Vec3::UnitY();
    b.state[0].w_P = w;
    b.state[0].v_W = w.cross(x);
    JointDef j;
    j.name = "cardan";
    j.type = JointType::universal;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3::Zero();
    j.axis_W = Vec3::UnitX();
    j.axis2_W = Vec3::UnitY();
    j.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = 1.5, .max_force = bound};
    j.motor2 = JointMotor{.mode = JointMotor::Mode::position,
                          .speed = std::numeric_limits<double>::infinity(),
                          .position = 0.4,
                          .time_constant = 0.2,
                          .max_force = 100};
    Articulations art;
    build(art, b, {j});
    double e1 = 0, e2 = 0, over = 0;
    int saturated = 0;
    for (int i = 1; i <= 180; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -9.81), nullptr, b.state.data()));
      const double t = i / 60.0;
      e1 = std::max(e1, std::abs(art.position(0, 0) - 1.5 * t));
      e2 = std::max(e2, std::abs(art.position(0, 1) - 0.4 * (1 - std::exp(-t / 0.2))));
      over = std::max(over, std::abs(art.force(0, 0)) - bound);
      if (std::abs(std::abs(art.force(0, 0)) - bound) < 1e-12) ++saturated;
    }
    std::printf("universal motors, bound %g N m: q1 %.1e rad, q2 %.1e rad, %d frames saturated\n", bound, e1,
                e2, saturated);
    EXPECT_LE(over, 1e-12);
    if (bound > 1) {
      EXPECT_LT(e1, 1e-9);
      EXPECT_LT(e2, 1e-9);
      EXPECT_EQ(saturated, 0);
    } else {
      EXPECT_GT(e1, 1e-3);  // it could not hold its speed
      EXPECT_GT(saturated, 10);
    }
  }
}

// The same with a speed cap of 0.8 rad/s, target 1.5 rad: the target rate clamp((1.5 - q)/0.5,
// -0.8, 0.8) is the cap until q = 1.5 - 0.8 * 0.5 = 1.1, reached at t_c = 1.1 / 0.8 = 1.375 s
// (mid-frame); then the exponential. Started at the cap:
//   t < t_c:  q = 0.8 t,                                   tau_m = m g d sin q
//   t > t_c:  q = 1.5 - 0.4 exp(-(t - t_c)/0.5),  q' = 0.8 exp(-(t - t_c)/0.5),
//             tau_m = I_p (-q' / 0.5) + m g d sin q.
// The rate is continuous at t_c, the acceleration jumps (0 to -1.6 rad/s^2): an unlocated switch
// would show as ~1.6 * dt^2 / 2 ~ 1e-4 rad. Tolerances as above.
TEST(JointMotor, PositionMotorRunsAtItsSpeedCapThenApproachesExponentially) {
  const double target = 1.5, tau = 0.5, cap = 0.8;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::position,
                       .speed = cap,
                       .position = target,
                       .time_constant = tau,
                       .max_force = 30};
  Pendulum p(0, cap, x);
  const double tc = (target - cap * tau) / cap;
  double eq = 0, ev = 0, ef = 0;
  for (int i = 1; i <= 300; ++i) {
    ASSERT_TRUE(p.step(1.0 / 60));
    const double t = i / 60.0, q = p.art.position(0);
    double qe, ve, fe;
    if (t < tc) {
      qe = cap * t;
      ve = cap;
      fe = p.mgd * std::sin(q);
    } else {
      const double e = std::exp(-(t - tc) / tau);
      qe = target - cap * tau * e;
      ve = cap * e;
      fe = p.Ip * (-ve / tau) + p.mgd * std::sin(q);
    }
    eq = std::max(eq, std::abs(q - qe));
    ev = std::max(ev, std::abs(p.art.speed(0) - ve));
    ef = std::max(ef, std::abs(p.art.force(0) - fe) / p.mgd);
  }
  std::printf("position motor with a speed cap: q %.1e rad, q' %.1e rad/s, torque %.1e m g d\n", eq, ev, ef);
  EXPECT_LT(eq, 1e-9);
  EXPECT_LT(ev, 1e-9);
  EXPECT_LT(ef, 1e-7);
}

// ------------------------------------------------------------------------------------------------
// Limits
// ------------------------------------------------------------------------------------------------

// The pendulum released at rest from phi0 = -1 rad (a right-handed turn about +y from hanging),
// swinging towards the bottom, with a plastic stop (restitution 0) at phi_s = -0.3 rad (q = 0.7),
// before the bottom, so gravity keeps it on the stop. Closed forms:
//   - it reaches the stop at t_s = integral_{phi0}^{phi_s} dphi / phi'(phi),
//     phi'^2 = 2 m g d (cos phi - cos phi0) / I_p (quadrature; the 1/sqrt end point removed by
//     phi = phi0 + s^2), with the rate v_s = phi'(phi_s);
//   - the impact takes all of the kinetic energy m g d (cos phi_s - cos phi0): afterwards q = 0.7
//     and q' = 0 exactly, the energy is -m g d cos phi_s;
//   - resting, the stop holds gravity's load: force = +m g d sin phi_s (< 0: the upper stop pushes
//     down the coordinate).
// Tolerances: 1e-9 m g d on the energy (before: the integrator; after: exact), 1e-12 on the resting
// coordinate and rate (a stop holds exactly; the brief's round-off), 1e-9 relative on the force,
// and 1e-9 rad on the position 1e-6 s before the closed-form impact time (the event is in the right
// place: 1e-9 rad at v_s ~ 3.4 rad/s is 3e-10 s).
TEST(JointLimits, PendulumStopsDeadOnAPlasticStop) {
  const double phi0 = -1.0, phis = -0.3;
  JointDef x;
  x.limits = JointLimits{.lower = -0.5, .upper = phis - phi0, .restitution = 0};
  const double mgd = Pendulum::mgd, Ip = Pendulum::Ip;
  const double k = 2 * mgd / Ip;
  // cos(phi0 + s^2) - cos(phi0) = -2 sin(phi0 + s^2/2) sin(s^2/2), free of cancellation near s = 0.
  auto dcos = [&](double s) { return -2 * std::sin(phi0 + 0.5 * s * s) * std::sin(0.5 * s * s); };
  const double ts =
      integrate([&](double s) { return 2 * s / std::sqrt(k * dcos(s)); }, 0, std::sqrt(phis - phi0));
  const double vs = std::sqrt(k * (std::cos(phis) - std::cos(phi0)));
  const double E_before = -mgd * std::cos(phi0), E_after = -mgd * std::cos(phis);
  const double qs = phis - phi0;
  {
    Pendulum p(phi0, 0, x);
    double eE = 0, eq = 0, ev = 0, ef = 0;
    int after = 0;
    for (int i = 1; i <= 180; ++i) {
      ASSERT_TRUE(p.step(1.0 / 60));
      const double t = i / 60.0;
      if (t < ts) {
        eE = std::max(eE, std::abs(p.b.energy(p.g) - E_before) / mgd);
        ef = std::max(ef, std::abs(p.art.force(0)) / mgd);  // nothing touched yet
      } else {
        ++after;
        eE = std::max(eE, std::abs(p.b.energy(p.g) - E_after) / mgd);
        eq = std::max(eq, std::abs(p.art.position(0) - qs));
        ev = std::max(ev, std::abs(p.art.speed(0)));
        ef = std::max(ef, std::abs(p.art.force(0) - mgd * std::sin(phis)) / (mgd * std::abs(std::sin(phis))));
      }
    }
    std::printf(
        "plastic stop: impact at %.9f s (v %.6f rad/s); energy %.1e m g d, resting q %.1e rad, q' %.1e "
        "rad/s, force %.1e\n",
        ts, vs, eE, eq, ev, ef);
    ASSERT_GT(after, 100);
    EXPECT_LT(eE, 1e-9);
    EXPECT_LT(eq, 1e-12);
    EXPECT_LT(ev, 1e-12);
    EXPECT_LT(ef, 1e-9);
  }
  {
    // Just before the closed-form impact: still approaching, at the closed-form rate; just after:
    // resting.
    const double dt = 1e-6;
    Pendulum p(phi0, 0, x);
    ASSERT_TRUE(p.step(ts - dt));
    const double gap = qs - p.art.position(0);
    const double acc = -mgd * std::sin(phis) / Ip;  // > 0: the stop is approached accelerating
    const double gap_e = vs * dt - 0.5 * acc * dt * dt;
    std::printf("plastic stop: gap 1e-6 s before %.6e rad (closed form %.6e), rate %.9f (%.9f)\n", gap, gap_e,
                p.art.speed(0), vs - acc * dt);
    EXPECT_NEAR(gap, gap_e, 1e-9);
    EXPECT_NEAR(p.art.speed(0), vs - acc * dt, 1e-8);
    ASSERT_TRUE(p.step(2 * dt));
    EXPECT_NEAR(p.art.position(0), qs, 1e-12);
    EXPECT_NEAR(p.art.speed(0), 0, 1e-12);
  }
}

// Two links in zero gravity, hinged about +y: link 1 (1 kg, centre 0.5 m from the fixed pivot,
// 0.08 kg m^2 about it) and link 2 (0.5 kg, centre 0.4 m beyond the elbow at 1 m, 0.02 kg m^2),
// bent at beta0 = 1.2 rad at the start, turning (q1' = 0.5, q2' = -2 rad/s: straightening), with a
// plastic stop on the elbow at beta_s = 0.4 rad (q2 = -0.8). With relative angles the mass matrix is
//   M11 = A + B + 2 C cos beta,  M12 = B + C cos beta,  M22 = B,
//   A = I1 + m1 c1^2 + m2 l1^2,  B = I2 + m2 c2^2,  C = m2 l1 c2,
// and q1 is cyclic: L = M11 q1' + M12 q2' (the angular momentum about the pivot, which has no
// moment there) and E are constant, which gives q2' as a function of beta alone,
//   q2'^2 = (2 E - L^2 / M11) / (M22 - M12^2 / M11),
// so the impact time t_i = integral dbeta / |q2'| and q1 at impact = integral (L/(M11 |q2'|) + M12/M11)
// dbeta over [beta_s, beta0] (quadrature). The stop's impulse acts on q2 only: the pivot's reaction
// has no moment about it either, so L is unchanged through the impact; with q2' = 0 after it,
//   q1' = L / M11(beta_s),  kinetic energy lost = 1/2 (e_2^T M^-1 e_2)^-1 q2'^2 = E - L^2 / (2 M11(beta_s)).
// The chain then turns rigidly, and the centrifugal load straightens it into its stop, which holds it
// with the generalised force C q1'^2 sin beta_s (from Lagrange's equation for q2 at q2' = q2'' = 0).
// Tolerances: L within 1e-9 relative over the whole run (an impulse that ignored the coupling, zeroing
// q2' and leaving q1', would change L by M12 q2' / L ~ 200%), q2 and q2' on the stop to 1e-12, the
// energy lost to 1e-8 relative, q1 after the impact within 1e-8 rad of q1_i + q1' (t - t_i) (which
// also places the impact in time: the shoulder's rate drops from 0.760 to 0.148 rad/s there, so
// 1e-8 rad is 1.6e-8 s), the holding force to 1e-9 relative.
TEST(JointLimits, ElbowStopKeepsTheChainsAngularMomentum) {
  const double m1 = 1, c1 = 0.5, l1 = 1, I1 = 0.08, m2 = 0.5, c2 = 0.4, I2 = 0.02;
  const double beta0 = 1.2, betas = 0.4, u1 = 0.5, u2 = -2.0;
  Bodies b;
  const Vec3 com1(0, 0, -c1), P2(0, 0, -l1), e2(-std::sin(beta0), 0, -std::cos(beta0));
  const Vec3 com2 = P2 + c2 * e2, Y = Vec3::UnitY();
  b.add("upper", m1, Vec3::Constant(I1), com1);
  b.add("lower", m2, Vec3::Constant(I2), com2);
  b.state[0].w_P = u1 * Y;
  b.state[0].v_W = (u1 * Y).cross(com1);
  b.state[1].w_P = (u1 + u2) * Y;
  b.state[1].v_W = (u1 * Y).cross(com2) + (u2 * Y).cross(com2 - P2);
  JointDef shoulder = hinge(-1, 0, Vec3::Zero(), Y), elbow = hinge(0, 1, P2, Y);
  elbow.limits = JointLimits{.lower = betas - beta0, .upper = 0.5, .restitution = 0};
  Articulations art;
  build(art, b, {shoulder, elbow});

  const double A = I1 + m1 * c1 * c1 + m2 * l1 * l1, B = I2 + m2 * c2 * c2, C = m2 * l1 * c2;
  auto M11 = [&](double be) { return A + B + 2 * C * std::cos(be); };
  auto M12 = [&](double be) { return B + C * std::cos(be); };
  const double L = M11(beta0) * u1 + M12(beta0) * u2;
  const double E = 0.5 * (M11(beta0) * u1 * u1 + 2 * M12(beta0) * u1 * u2 + B * u2 * u2);
  auto rate2 = [&](double be) {  // |q2'| at elbow angle beta before the impact
    return std::sqrt((2 * E - L * L / M11(be)) / (B - M12(be) * M12(be) / M11(be)));
  };
  const double ti = integrate([&](double be) { return 1 / rate2(be); }, betas, beta0);
  const double q1i =
      integrate([&](double be) { return L / (M11(be) * rate2(be)) + M12(be) / M11(be); }, betas, beta0);
  const double w_after = L / M11(betas);
  // The energy lost, both ways: through the impulse on q2 (M^-1 at beta_s) and through L.
  Eigen::Matrix2d M;
  M << M11(betas), M12(betas), M12(betas), B;
  const double v2 = rate2(betas);
  const double lost = 0.5 * v2 * v2 / M.inverse()(1, 1);
  ASSERT_NEAR(lost / (E - 0.5 * L * L / M11(betas)), 1, 1e-12);  // the closed forms agree
  const double hold = C * w_after * w_after * std::sin(betas);

  const double L0 = b.angular_momentum().y();
  ASSERT_NEAR(L0, L, 1e-12 * std::abs(L));  // the set-up matches the mass matrix written above
  double eL = 0, eq = 0, ev = 0, eq1 = 0, ew = 0, eE = 0, ef = 0;
  int after = 0;
  for (int i = 1; i <= 120; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
    const double t = i / 60.0;
    eL = std::max(eL, std::abs(b.angular_momentum().y() - L) / std::abs(L));
    if (t > ti) {
      ++after;
      eq = std::max(eq, std::abs(art.position(1) - (betas - beta0)));
      ev = std::max(ev, std::abs(art.speed(1)));
      ew = std::max(ew, std::abs(art.speed(0) - w_after) / w_after);
      eq1 = std::max(eq1, std::abs(art.position(0) - (q1i + w_after * (t - ti))));
      eE = std::max(eE, std::abs((E - b.energy(0)) / lost - 1));
      ef = std::max(ef, std::abs(art.force(1) - hold) / hold);
    } else {
      EXPECT_EQ(art.force(1), 0) << t;  // free of its stops before the impact
    }
  }
  std::printf(
      "elbow stop: impact at %.9f s, L %.1e, elbow q %.1e rad, q' %.1e rad/s, shoulder rate %.1e, "
      "q1 %.1e rad, energy lost %.1e, holding force %.1e (relative)\n",
      ti, eL, eq, ev, ew, eq1, eE, ef);
  ASSERT_GT(after, 30);
  EXPECT_LT(eL, 1e-9);
  EXPECT_LT(eq, 1e-12);
  EXPECT_LT(ev, 1e-12);
  EXPECT_LT(ew, 1e-9);
  EXPECT_LT(eq1, 1e-8);
  EXPECT_LT(eE, 1e-8);
  EXPECT_LT(ef, 1e-9);
  EXPECT_EQ(art.force(0), 0);  // the shoulder has no stop, motor or friction
}

// A flywheel in zero gravity at 2.1 rad/s between stops at -0.5 and +0.3 rad, restitution 0.6: it
// turns at constant rate between the stops and each impact reverses its rate to -0.6 times itself,
// so after n impacts |q'| = 2.1 * 0.6^n and q is piecewise linear with the impact times
// t_1 = 0.3 / 2.1, t_{n+1} = t_n + 0.8 / (2.1 * 0.6^n). Nothing here is integrated approximately
// (q'' = 0 between impacts) and each impact is located to ~1e-12 s, so the tolerances are 1e-10
// rad and 1e-9 relative on the rate; a restitution applied as 0.6 +- 1% would be off by 1e-2.
TEST(JointLimits, FlywheelBouncesBetweenItsStopsWithItsRestitution) {
  const double v0 = 2.1, lo = -0.5, hi = 0.3, e = 0.6;
  JointDef x;
  x.limits = JointLimits{.lower = lo, .upper = hi, .restitution = e};
  Flywheel f(v0, x);
  // Impact schedule: (time, rate after).
  std::vector<double> t_imp = {0}, v_after = {v0}, q_at = {0};
  while (t_imp.back() < 10) {
    const double v = v_after.back();
    const double to = v > 0 ? hi : lo;
    t_imp.push_back(t_imp.back() + (to - q_at.back()) / v);
    v_after.push_back(-e * v);
    q_at.push_back(to);
  }
  double eq = 0, ev = 0, ef = 0;
  int bounces = 0;
  for (int i = 1; i <= 300; ++i) {
    ASSERT_TRUE(f.step(1.0 / 60));
    const double t = i / 60.0;
    size_t n = 0;
    while (n + 1 < t_imp.size() && t_imp[n + 1] <= t) ++n;
    bounces = (int)n;
    eq = std::max(eq, std::abs(f.art.position(0) - (q_at[n] + v_after[n] * (t - t_imp[n]))));
    ev = std::max(ev, std::abs(f.art.speed(0) / v_after[n] - 1));
    ef = std::max(ef, std::abs(f.art.force(0)));
  }
  std::printf("flywheel between stops: %d impacts in 5 s; q %.1e rad, rate %.1e relative, force %.1e\n",
              bounces, eq, ev, ef);
  EXPECT_EQ(bounces, 4);
  EXPECT_LT(eq, 1e-10);
  EXPECT_LT(ev, 1e-9);
  EXPECT_EQ(ef, 0);  // between impacts nothing touches: the stops push only at the impacts
}

// A 2 kg body on a vertical slider dropped from rest 0.5 m above its lower stop (restitution 0.5):
// the bouncing ball. It hits at v_1 = sqrt(2 g h) at t_1 = sqrt(2 h / g), leaves each impact at
// u_n = 0.5^n v_1 and flies for 2 u_n / g; a rebound under 1e-6 m/s rests on the stop. With
// v_1 = 3.132 m/s, u_21 = 1.49e-6 m/s is the last bounce and the 22nd impact (rebound 7.5e-7)
// rests: at t_rest = t_1 + sum_{n=1}^{21} 2 u_n / g. The motion between frames is a parabola per
// bounce: q = -h + u_n (t - t_n) - g (t - t_n)^2 / 2, q' = u_n - g (t - t_n). Checked:
//   - every frame against the parabolas (1e-9 m, 1e-9 m/s: q'' is constant, so only the impact
//     times err, by ~1e-12 s each);
//   - a quarter of the way into the 21st bounce (t_21 + u_21 / (2 g), 7.6e-8 s after its impact),
//     q' = u_21 / 2 = 7.5e-7 m/s to 1e-8 (so the 21st bounce happened, on time), and a quarter of
//     the way into the would-be 22nd, q' = 0 and q = -h (it rested instead: a threshold read on
//     the approach rate rather than the rebound would bounce once more, at 7.5e-7 / 2 there).
//     The 1e-8 is not slack: q is stored at 0.5 m, whose round-off (1.1e-16 m) at these rates
//     (1e-6 m/s) places the last impacts only to ~1e-10 s, g times that ~1e-9 m/s;
//   - resting: q = -h and q' = 0 to 1e-12, and the stop holds the weight, force = m g (1e-9).
TEST(JointLimits, SliderBouncesOnItsStopAsTheBouncingBall) {
  const double m = 2, g = 9.81, h = 0.5, e = 0.5;
  auto make = [&](Bodies& b, Articulations& art) {
    b.add("ball", m, Vec3::Constant(0.1), Vec3(0, 0, 1));
    JointDef j;
    j.name = "slider";
    j.type = JointType::prismatic;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3(0, 0, 1);
    j.axis_W = Vec3::UnitZ();
    j.limits = JointLimits{.lower = -h, .upper = 0.2, .restitution = e};
    build(art, b, {j});
  };
  const double v1 = std::sqrt(2 * g * h);
  std::vector<double> tn = {std::sqrt(2 * h / g)}, un;  // impact n at tn[n-1], leaving at un[n-1]
  for (double u = e * v1; u >= 1e-6; u *= e) {
    un.push_back(u);
    tn.push_back(tn.back() + 2 * u / g);
  }
  const int N = (int)un.size();
  const double t_rest = tn.back();
  ASSERT_EQ(N, 21);
  ASSERT_GT(un.back() / 1e-6, 1.2);  // no bounce near the threshold
  ASSERT_LT(e * un.back() / 1e-6, 0.8);
  auto closed = [&](double t, double& q, double& v) {
    if (t < tn[0]) {
      q = -0.5 * g * t * t;
      v = -g * t;
      return;
    }
    int n = 0;  // the last impact at or before t
    while (n + 1 < (int)tn.size() && tn[n + 1] <= t) ++n;
    if (n >= N) {
      q = -h;
      v = 0;
      return;
    }
    const double s = t - tn[n];
    q = -h + un[n] * s - 0.5 * g * s * s;
    v = un[n] - g * s;
  };
  {
    Bodies b;
    Articulations art;
    make(b, art);
    double eq = 0, ev = 0, rq = 0, rv = 0, rf = 0, ff = 0;
    int resting = 0;
    for (int i = 1; i <= 120; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
      const double t = i / 60.0;
      double q, v;
      closed(t, q, v);
      eq = std::max(eq, std::abs(art.position(0) - q));
      ev = std::max(ev, std::abs(art.speed(0) - v));
      if (t > t_rest) {
        ++resting;
        rq = std::max(rq, std::abs(art.position(0) + h));
        rv = std::max(rv, std::abs(art.speed(0)));
        rf = std::max(rf, std::abs(art.force(0) / (m * g) - 1));
      } else {
        ff = std::max(ff, std::abs(art.force(0)));
      }
    }
    std::printf(
        "bouncing slider: %d bounces, rest at %.9f s; q %.1e m, q' %.1e m/s; resting q %.1e, q' %.1e, "
        "force %.1e m g; force in flight %.1e N\n",
        N, t_rest, eq, ev, rq, rv, rf, ff);
    ASSERT_GT(resting, 30);
    EXPECT_LT(eq, 1e-9);
    EXPECT_LT(ev, 1e-9);
    EXPECT_LT(rq, 1e-12);
    EXPECT_LT(rv, 1e-12);
    EXPECT_LT(rf, 1e-9);
  }
  {
    Bodies b;
    Articulations art;
    make(b, art);
    const double t21 = tn[N - 1] + un[N - 1] / (2 * g);
    ASSERT_TRUE(art.step(t21, Vec3(0, 0, -g), nullptr, b.state.data()));
    std::printf("bouncing slider: a quarter into bounce 21, q' %.6e m/s (closed form %.6e)\n", art.speed(0),
                un[N - 1] / 2);
    EXPECT_NEAR(art.speed(0), un[N - 1] / 2, 1e-8);
    const double t22 = t_rest + e * un[N - 1] / (2 * g);
    ASSERT_TRUE(art.step(t22 - t21, Vec3(0, 0, -g), nullptr, b.state.data()));
    std::printf("bouncing slider: a quarter into the would-be bounce 22, q %.3e m, q' %.3e m/s\n",
                art.position(0) + h, art.speed(0));
    EXPECT_NEAR(art.speed(0), 0, 1e-12);
    EXPECT_NEAR(art.position(0), -h, 1e-12);
  }
}

// A speed motor that drives the flywheel (zero gravity) into a stop with restitution 0.6. The motor
// holds w = 2 rad/s up to the stop at 0.31 rad (t_1 = 0.155 s, no torque needed); the impact reverses
// the rate to -0.6 w, after which the motor cannot hold its target and pushes with its bound
// T = 0.02 N m towards it: the wheel decelerates at a = T / I = 1 rad/s^2, comes back to the stop at
// the rate it left it (still under w) and bounces again, the bouncing ball with g -> T / I:
//   u_n = 0.6^n w,  t_{n+1} = t_n + 2 u_n / a,  q = 0.31 - u_n s + a s^2 / 2,  q' = -u_n + a s,
// until the rebound 0.6 u_28 = 7.4e-7 rad/s is under 1e-6 and it rests on the stop at t = 6.155 s,
// the stop taking the motor's push (their sum, force(), is then 0; while bouncing it is T).
// Tolerances 1e-9 rad and rad/s (q'' is constant in each phase; only the located impact times err)
// and exact rest. A motor that kept "holding" its target through the impact would wipe out the
// rebound (q' back to +w at the stop: a 3.2 rad/s error, or a step that cannot get off the stop).
TEST(JointLimits, SpeedMotorDrivesAFlywheelIntoABouncyStop) {
  const double w = 2, T = 0.02, hi = 0.31, e = 0.6;
  JointDef x;
  x.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = w, .max_force = T};
  x.limits = JointLimits{.lower = -1, .upper = hi, .restitution = e};
  Flywheel f(w, x);
  const double a = T / Flywheel::I;
  std::vector<double> tn = {hi / w}, un;
  for (double u = e * w; u >= 1e-6; u *= e) {
    un.push_back(u);
    tn.push_back(tn.back() + 2 * u / a);
  }
  const int N = (int)un.size();
  ASSERT_EQ(N, 28);
  ASSERT_GT(un.back() / 1e-6, 1.2);
  ASSERT_LT(e * un.back() / 1e-6, 0.8);
  double eq = 0, ev = 0, ef = 0, rq = 0, rv = 0, rf = 0;
  int resting = 0;
  for (int i = 1; i <= 480; ++i) {
    ASSERT_TRUE(f.step(1.0 / 60)) << "at t = " << i / 60.0 << " s, q = " << f.art.position(0);
    const double t = i / 60.0, q = f.art.position(0), v = f.art.speed(0), F = f.art.force(0);
    if (t < tn[0]) {
      eq = std::max(eq, std::abs(q - w * t));
      ev = std::max(ev, std::abs(v - w));
      ef = std::max(ef, std::abs(F) / T);
    } else if (t < tn[N]) {
      int n = 0;
      while (tn[n + 1] <= t) ++n;
      const double s = t - tn[n];
      eq = std::max(eq, std::abs(q - (hi - un[n] * s + 0.5 * a * s * s)));
      ev = std::max(ev, std::abs(v - (-un[n] + a * s)));
      ef = std::max(ef, std::abs(F - T) / T);
    } else {
      ++resting;
      rq = std::max(rq, std::abs(q - hi));
      rv = std::max(rv, std::abs(v));
      rf = std::max(rf, std::abs(F) / T);
    }
  }
  std::printf(
      "motor into a bouncy stop: %d bounces, rest at %.6f s; q %.1e rad, q' %.1e rad/s, force %.1e T; "
      "resting q %.1e, q' %.1e, force %.1e T\n",
      N, tn[N], eq, ev, ef, rq, rv, rf);
  ASSERT_GT(resting, 60);
  EXPECT_LT(eq, 1e-9);
  EXPECT_LT(ev, 1e-9);
  EXPECT_LT(ef, 1e-12);
  EXPECT_LT(rq, 1e-12);
  EXPECT_LT(rv, 1e-12);
  EXPECT_LT(rf, 1e-12);
}

// ------------------------------------------------------------------------------------------------
// Friction
// ------------------------------------------------------------------------------------------------

// A flywheel (I = 0.02 kg m^2) spun at w0 = 5 rad/s in zero gravity with friction F = 0.031 N m:
// it decelerates at exactly F / I and stops at t_s = I w0 / F = 3.2258 s (mid-frame) after turning
// I w0^2 / (2 F) = 8.0645 rad; nothing loads it then, so it stays exactly still and friction
// applies nothing. Closed form:
//   t < t_s:  q = w0 t - F t^2 / (2 I),  q' = w0 - F t / I,  force = -F;
//   t > t_s:  q = I w0^2 / (2 F),        q' = 0,             force = 0.
// q'' is constant in each phase (integrated exactly) and the stop is an event: tolerance 1e-10 rad
// and rad/s; after the stop q' and q's change between frames to 1e-12 (stuck is exact). A wheel
// that overshot zero and reversed, or crept under chattering friction, would show ~F/I * dt ~ 0.03
// rad/s.
TEST(JointFriction, FlywheelCoastsToAStopAndStaysThere) {
  const double w0 = 5, F = 0.031;
  JointDef x;
  x.friction = F;
  Flywheel f(w0, x);
  const double I = Flywheel::I, ts = I * w0 / F, qs = I * w0 * w0 / (2 * F);
  double eq = 0, ev = 0, ef = 0, drift = 0, sv = 0, sf = 0;
  double prev = 0;
  int stopped = 0;
  for (int i = 1; i <= 300; ++i) {
    ASSERT_TRUE(f.step(1.0 / 60));
    const double t = i / 60.0, q = f.art.position(0);
    if (t < ts) {
      eq = std::max(eq, std::abs(q - (w0 * t - F * t * t / (2 * I))));
      ev = std::max(ev, std::abs(f.art.speed(0) - (w0 - F * t / I)));
      ef = std::max(ef, std::abs(f.art.force(0) + F) / F);
    } else {
      eq = std::max(eq, std::abs(q - qs));
      sv = std::max(sv, std::abs(f.art.speed(0)));
      sf = std::max(sf, std::abs(f.art.force(0)));
      if (stopped++ > 0) drift = std::max(drift, std::abs(q - prev));
    }
    prev = q;
  }
  std::printf(
      "friction flywheel: stop at %.6f s after %.6f rad; q %.1e rad, q' %.1e rad/s, force %.1e F; "
      "stopped: q' %.1e, drift %.1e rad, force %.1e N m\n",
      ts, qs, eq, ev, ef, sv, drift, sf);
  ASSERT_GT(stopped, 60);
  EXPECT_LT(eq, 1e-10);
  EXPECT_LT(ev, 1e-10);
  EXPECT_LT(ef, 1e-12);
  EXPECT_LT(sv, 1e-12);
  EXPECT_LT(drift, 1e-12);
  EXPECT_LT(sf, 1e-12 * F);
}

// The pendulum at rest at phi0 = 0.2 rad, where gravity's load is m g d sin 0.2 = 1.949 N m:
//   - with friction 2.5 N m it never moves (q = 0, q' = 0 to 1e-12 over 2 s) and friction holds
//     the whole load: force = +m g d sin phi0 (1e-12 relative: holding is exact);
//   - with friction 1.5 N m it slides back; while q' < 0, friction pushes +1.5 N m, so
//     H = 1/2 I_p q'^2 - m g d cos phi - F phi is constant (1e-9 m g d); it turns at the root phi_1
//     of m g d (cos phi - cos phi0) + F (phi - phi0) = 0 below phi0 (0.107 rad), where gravity's
//     pull m g d sin phi_1 = 1.05 N m is within 1.5: it sticks there for good, friction then holding
//     m g d sin phi (at the angle where it is: 1e-12 relative). phi_1 within 1e-9 rad (the slide is
//     integrated at 1e-10 per step); a stick decided late by one internal step, or friction
//     reversing at the turn, would move it by 1e-3 rad or more.
TEST(JointFriction, PendulumHeldByStaticFrictionOrSlidingToItsStickingPoint) {
  const double phi0 = 0.2, mgd = Pendulum::mgd, Ip = Pendulum::Ip;
  {
    JointDef x;
    x.friction = 2.5;
    Pendulum p(phi0, 0, x);
    double eq = 0, ev = 0, ef = 0;
    for (int i = 1; i <= 120; ++i) {
      ASSERT_TRUE(p.step(1.0 / 60));
      eq = std::max(eq, std::abs(p.art.position(0)));
      ev = std::max(ev, std::abs(p.art.speed(0)));
      ef = std::max(ef, std::abs(p.art.force(0) / (mgd * std::sin(phi0)) - 1));
    }
    std::printf("static friction: q %.1e rad, q' %.1e rad/s, force %.1e\n", eq, ev, ef);
    EXPECT_LT(eq, 1e-12);
    EXPECT_LT(ev, 1e-12);
    EXPECT_LT(ef, 1e-12);
  }
  {
    const double F = 1.5;
    JointDef x;
    x.friction = F;
    Pendulum p(phi0, 0, x);
    const double phi1 =
        bisect([&](double ph) { return mgd * (std::cos(ph) - std::cos(phi0)) + F * (ph - phi0); },
               std::asin(F / mgd) * 2 - phi0 - 0.05, std::asin(F / mgd));
    ASSERT_LT(mgd * std::sin(phi1), F);
    const double H0 = -mgd * std::cos(phi0) - F * phi0;
    double eH = 0, eq = 0, ev = 0, ef = 0, slide_f = 0;
    int stuck = 0;
    bool moving = true;
    for (int i = 1; i <= 180; ++i) {  // 3 s: the slide takes about half a period, 1 s
      ASSERT_TRUE(p.step(1.0 / 60));
      const double ph = phi0 + p.art.position(0), v = p.art.speed(0);
      if (moving && v < 0) {
        eH = std::max(eH, std::abs(0.5 * Ip * v * v - mgd * std::cos(ph) - F * ph - H0) / mgd);
        slide_f = std::max(slide_f, std::abs(p.art.force(0) - F) / F);
      } else {
        moving = false;
        ++stuck;
        eq = std::max(eq, std::abs(ph - phi1));
        ev = std::max(ev, std::abs(v));
        // Friction holds exactly the load where the pendulum is.
        ef = std::max(ef, std::abs(p.art.force(0) / (mgd * std::sin(ph)) - 1));
      }
    }
    std::printf(
        "sliding friction: H %.1e m g d, force while sliding %.1e F; stuck at %.9f rad (closed form "
        "%.9f): %.1e rad, q' %.1e, holding force %.1e\n",
        eH, slide_f, phi0 + p.art.position(0), phi1, eq, ev, ef);
    ASSERT_GT(stuck, 60);
    EXPECT_LT(eH, 1e-9);
    EXPECT_LT(slide_f, 1e-12);
    EXPECT_LT(eq, 1e-9);
    EXPECT_LT(ev, 1e-12);
    EXPECT_LT(ef, 1e-12);
  }
}

// The Coulomb-damped linear oscillator: the flywheel on a torsion spring k = 3 N m/rad whose rest
// angle is 0.31 rad (so it starts 0.31 rad from rest, x = q - 0.31 = -0.31), released at rest, with
// friction F = 0.1 N m. Each half-cycle is a harmonic oscillation at w = sqrt(k / I) about the centre
// shifted by friction, c_n = sign(x_n) F / k, from the turning point x_n to x_{n+1} = 2 c_n - x_n:
//   x(t) = c_n + (x_n - c_n) cos(w (t - t_n)),  t_n = n pi / w  (half-period pi sqrt(I/k) exactly),
// so the amplitude drops by exactly 2 F / k per half-cycle, and the motion stops at the first
// turning point with |x_n| <= F / k: here -0.31, 0.2433, -0.1767, 0.11, -0.0433, then -0.0233 (stuck,
// at t_5 = 5 pi / w = 1.2825 s). While sliding, friction's force is -F sign(q') = F sign(x_n); stuck,
// it holds the spring: force = k x (1e-12 F). Sampled every 1/240 s and exactly at each turning point:
// 1e-8 rad on x at all of them (the brief's figure; the integrator is at 1e-10), rates at the turning
// points to 1e-8 rad/s, and the stuck state to 1e-12. A half-period off by one internal step, or an
// amplitude drop of 2F/k +- 1%, would be 1e-3-scale.
TEST(JointFriction, CoulombDampedOscillatorLosesTwoFOverKEachHalfCycle) {
  const double k = 3, F = 0.1, rest = 0.31;
  JointDef x;
  x.spring = JointSpring{.stiffness = k, .damping = 0, .rest = rest};
  x.friction = F;
  Flywheel f(0, x);
  const double I = Flywheel::I, w = std::sqrt(k / I);
  std::vector<double> xn = {-rest};
  while (std::abs(xn.back()) > F / k) {
    const double c = std::copysign(F / k, xn.back());
    xn.push_back(2 * c - xn.back());
  }
  const int halves = (int)xn.size() - 1;
  ASSERT_EQ(halves, 5);
  for (double a : xn) ASSERT_GT(std::abs(std::abs(a) - F / k), 0.005);  // none near the threshold
  auto closed = [&](double t, double& xe, double& ve, double& fe) {
    const int n = std::min((int)std::floor(t * w / kPi), halves);
    if (n >= halves) {
      xe = xn[halves];
      ve = 0;
      fe = k * xn[halves];
      return;
    }
    const double c = std::copysign(F / k, xn[n]), s = w * (t - n * kPi / w);
    xe = c + (xn[n] - c) * std::cos(s);
    ve = -(xn[n] - c) * w * std::sin(s);
    fe = std::copysign(F, xn[n]);
  };
  // Sample times: every 1/240 s, and each turning point.
  std::vector<double> times;
  for (int i = 1; i <= 480; ++i) times.push_back(i / 240.0);
  for (int n = 1; n <= halves; ++n) times.push_back(n * kPi / w);
  std::sort(times.begin(), times.end());
  double t = 0, ex = 0, ev = 0, ef = 0, tx = 0, tv = 0, sx = 0, sv = 0, sf = 0;
  for (double ts : times) {
    if (ts - t < 1e-12) continue;
    ASSERT_TRUE(f.step(ts - t));
    t = ts;
    double xe, ve, fe;
    closed(t, xe, ve, fe);
    const double xs = f.art.position(0) - rest, vs = f.art.speed(0);
    ex = std::max(ex, std::abs(xs - xe));
    ev = std::max(ev, std::abs(vs - ve));
    const bool turning = std::abs(t * w / kPi - std::round(t * w / kPi)) < 1e-9;
    if (turning) {
      tx = std::max(tx, std::abs(xs - xe));
      tv = std::max(tv, std::abs(vs));
    } else if (t * w / kPi < halves) {
      ef = std::max(ef, std::abs(f.art.force(0) - fe) / F);
    } else {
      sx = std::max(sx, std::abs(xs - xn[halves]));
      sv = std::max(sv, std::abs(vs));
      // Friction holds exactly the spring's load where the wheel is (k x, x as simulated: the
      // closed form's x_5 differs from it by the integrator's 1e-10 rad, k times that 3e-9 F).
      sf = std::max(sf, std::abs(f.art.force(0) - k * xs) / F);
      (void)fe;
    }
  }
  std::printf(
      "Coulomb oscillator: x %.1e rad, q' %.1e rad/s, sliding force %.1e F; turning points x %.1e, q' %.1e; "
      "stuck x %.1e, q' %.1e, force %.1e F\n",
      ex, ev, ef, tx, tv, sx, sv, sf);
  EXPECT_LT(ex, 1e-8);
  EXPECT_LT(ev, 1e-7);
  EXPECT_LT(ef, 1e-12);
  EXPECT_LT(tx, 1e-8);
  EXPECT_LT(tv, 1e-8);
  EXPECT_LT(sx, 1e-8);
  EXPECT_LT(sv, 1e-12);
  EXPECT_LT(sf, 1e-12);
}

// Friction and stops together: the flywheel (zero gravity) at 2 rad/s between stops at -0.5 and
// +0.3 rad (restitution 0.6) with friction F = 0.005 N m. Between impacts friction decelerates it
// at F / I = 0.25 rad/s^2 against the motion, whichever way that is; each impact reverses the rate to
// -0.6 times the approach rate. Leg by leg (from q_a at rate v_a, towards the stop at distance D):
// it reaches the stop when v_a^2 > 2 (F/I) D, after s = (|v_a| - sqrt(v_a^2 - 2 (F/I) D)) / (F/I), at
// the rate sqrt(v_a^2 - 2 (F/I) D); otherwise it stops at q_a + sign(v_a) v_a^2 / (2 F/I) and stays
// (nothing loads it). Here: upper stop at 1.962 rad/s, lower at 0.993, then it stops at 0.2097 rad,
// short of the upper stop, at t = 3.27 s. Tolerances 1e-10 (piecewise quadratics, exact for the
// integrator), friction's force -F sign(q') to 1e-12 F. Friction that kept pushing its pre-impact
// way after a rebound would speed the wheel up on that leg by 2 F/I: 0.03 rad/s per frame.
TEST(JointFriction, FrictionOpposesTheMotionAfterEveryRebound) {
  const double v0 = 2, lo = -0.5, hi = 0.3, e = 0.6, F = 0.005;
  JointDef x;
  x.limits = JointLimits{.lower = lo, .upper = hi, .restitution = e};
  x.friction = F;
  Flywheel f(v0, x);
  const double dec = F / Flywheel::I;
  struct Leg {
    double t, q, v;  // start time, coordinate and rate
  };
  std::vector<Leg> legs = {{0, 0, v0}};
  double t_stop = 0, q_stop = 0;
  for (;;) {
    const Leg L = legs.back();
    const double dir = L.v > 0 ? 1 : -1, to = dir > 0 ? hi : lo, D = std::abs(to - L.q);
    const double disc = L.v * L.v - 2 * dec * D;
    if (disc <= 0) {
      t_stop = L.t + std::abs(L.v) / dec;
      q_stop = L.q + dir * L.v * L.v / (2 * dec);
      break;
    }
    const double s = (std::abs(L.v) - std::sqrt(disc)) / dec;
    legs.push_back({L.t + s, to, -dir * e * std::sqrt(disc)});
  }
  ASSERT_EQ(legs.size(), 3u);
  double eq = 0, ev = 0, ef = 0, sq = 0, sv = 0, sf = 0;
  int stopped = 0;
  for (int i = 1; i <= 300; ++i) {
    ASSERT_TRUE(f.step(1.0 / 60));
    const double t = i / 60.0, q = f.art.position(0), v = f.art.speed(0);
    if (t < t_stop) {
      size_t n = 0;
      while (n + 1 < legs.size() && legs[n + 1].t <= t) ++n;
      const Leg& L = legs[n];
      const double dir = L.v > 0 ? 1 : -1, s = t - L.t;
      eq = std::max(eq, std::abs(q - (L.q + L.v * s - dir * dec * s * s / 2)));
      ev = std::max(ev, std::abs(v - (L.v - dir * dec * s)));
      ef = std::max(ef, std::abs(f.art.force(0) + dir * F) / F);
    } else {
      ++stopped;
      sq = std::max(sq, std::abs(q - q_stop));
      sv = std::max(sv, std::abs(v));
      sf = std::max(sf, std::abs(f.art.force(0)) / F);
    }
  }
  std::printf(
      "friction between stops: stop at %.6f rad at %.6f s; q %.1e rad, q' %.1e rad/s, force %.1e F; "
      "stopped q %.1e, q' %.1e, force %.1e F\n",
      q_stop, t_stop, eq, ev, ef, sq, sv, sf);
  ASSERT_GT(stopped, 60);
  EXPECT_LT(eq, 1e-10);
  EXPECT_LT(ev, 1e-10);
  EXPECT_LT(ef, 1e-12);
  EXPECT_LT(sq, 1e-10);
  EXPECT_LT(sv, 1e-12);
  EXPECT_LT(sf, 1e-12);
}

// ------------------------------------------------------------------------------------------------
// Watt governor
// ------------------------------------------------------------------------------------------------

// A vertical spindle (2 kg, principal moments 0.05, 0.05, 0.03 kg m^2) on a hinge about +z, driven
// by a speed motor at w = 6 rad/s (bound 100 N m, never reached), carrying a ball (0.5 kg, isotropic
// 1e-4 kg m^2) on a massless arm of L = 0.5 m hinged on the spindle's axis about the spindle's x.
// With the spindle's rate held at w the arm's angle theta from the downward vertical moves in the
// rotating frame's potential U = -m g L cos theta - 1/2 w^2 m L^2 sin^2 theta (the ball's isotropic
// inertia adds a constant), so
//   - the steady angle is acos(g / (w^2 L)) (ref::watt_governor_angle_compound with J_a = I_ball,
//     J_n = I_ball + m L^2: the isotropic part cancels) = 0.9942 rad;
//   - started off it at theta_0, the arm oscillates with the Jacobi integral
//       h = 1/2 (I_ball + m L^2) theta'^2 + U(theta)
//     constant, between theta_0 and acos(2 g / (w^2 L) - cos theta_0) (U(cos) is a parabola in
//     cos theta symmetric about g / (w^2 L));
//   - the motor supplies d L_z / dt with L_z = (I_spindle,z + I_ball + m L^2 sin^2 theta) w:
//       tau = w m L^2 sin(2 theta) theta'.
// Only an exactly held w makes h an invariant: with a free spindle (L_z conserved) w changes by ~40%
// over this swing. Tolerances: steady, the arm stays within 1e-9 rad of the steady angle for 5 s
// (it starts there to round-off; an equilibrium off by even 1e-6 rad would oscillate by that much);
// swinging, h to 1e-9 m g L, the spindle's rate to 1e-9, the swing's extremes sampled at 1/600 s
// within [closed form - 1e-4, closed form + 1e-9] rad (a sample is at most 1/1200 s from a turning
// point: (theta'' dt^2 / 2) ~ 2e-5 rad below it), the motor's torque to 1e-7 of its largest value.
TEST(JointMotor, WattGovernorHoldsItsSteadyAngleAndSwingsWithTheJacobiIntegral) {
  const double Ms = 2, m = 0.5, Ib = 1e-4, L = 0.5, w = 6, g = 9.81;
  const Vec3 Is(0.05, 0.05, 0.03);
  const double th_star = ref::watt_governor_angle_compound(w, m, L, Ib, Ib + m * L * L, g);
  ASSERT_NEAR(std::cos(th_star), g / (w * w * L), 1e-15);
  auto make = [&](Bodies& b, Articulations& art, double th0) {
    b.add("spindle", Ms, Is, Vec3::Zero());
    const Vec3 r(0, L * std::sin(th0), -L * std::cos(th0));
    b.add("ball", m, Vec3::Constant(Ib), r);
    const Vec3 W(0, 0, w);
    b.state[0].w_P = W;
    b.state[1].w_P = W;
    b.state[1].v_W = W.cross(r);
    JointDef spindle = hinge(-1, 0, Vec3::Zero(), Vec3::UnitZ());
    spindle.motor = JointMotor{.mode = JointMotor::Mode::speed, .speed = w, .max_force = 100};
    JointDef arm = hinge(0, 1, Vec3::Zero(), Vec3::UnitX());  // +x turns the ball at +y upwards
    build(art, b, {spindle, arm});
  };
  {
    Bodies b;
    Articulations art;
    make(b, art, th_star);
    double eq = 0, ew = 0, ef = 0;
    for (int i = 1; i <= 300; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
      eq = std::max(eq, std::abs(art.position(1)));
      ew = std::max(ew, std::abs(art.speed(0) - w));
      ef = std::max(ef, std::abs(art.force(0)));
    }
    std::printf(
        "Watt governor at its steady angle %.9f rad: arm %.1e rad, spindle rate %.1e, torque %.1e N m\n",
        th_star, eq, ew, ef);
    EXPECT_LT(eq, 1e-9);
    EXPECT_LT(ew, 1e-9);
    EXPECT_LT(ef, 1e-9);
  }
  {
    const double th0 = th_star - 0.3;
    const double th1 = std::acos(2 * g / (w * w * L) - std::cos(th0));
    const double Jh = Ib + m * L * L;
    auto U = [&](double th) {
      return -m * g * L * std::cos(th) - 0.5 * w * w * m * L * L * std::sin(th) * std::sin(th);
    };
    const double h0 = U(th0);
    const double tau_scale =
        w * m * L * L * 1.0 * std::sqrt(2 * (U(th0) - U(th_star)) / Jh);  // ~ largest torque
    Bodies b;
    Articulations art;
    make(b, art, th0);
    double eh = 0, ew = 0, ef = 0, lo = 10, hi = -10;
    for (int i = 1; i <= 3000; ++i) {  // 5 s at 1/600 s
      ASSERT_TRUE(art.step(1.0 / 600, Vec3(0, 0, -g), nullptr, b.state.data()));
      const double th = th0 + art.position(1), thd = art.speed(1);
      eh = std::max(eh, std::abs(0.5 * Jh * thd * thd + U(th) - h0) / (m * g * L));
      ew = std::max(ew, std::abs(art.speed(0) - w));
      ef = std::max(ef, std::abs(art.force(0) - w * m * L * L * std::sin(2 * th) * thd) / tau_scale);
      lo = std::min(lo, th);
      hi = std::max(hi, th);
    }
    std::printf(
        "Watt governor swinging: theta in [%.9f, %.9f] (closed form [%.9f, %.9f]); h %.1e m g L, spindle "
        "rate %.1e, torque %.1e\n",
        lo, hi, th0, th1, eh, ew, ef);
    EXPECT_LT(eh, 1e-9);
    EXPECT_LT(ew, 1e-9);
    EXPECT_LT(ef, 1e-7);
    EXPECT_GT(lo, th0 - 1e-9);
    EXPECT_LT(lo, th0 + 1e-4);
    EXPECT_LT(hi, th1 + 1e-9);
    EXPECT_GT(hi, th1 - 1e-4);
  }
}

}  // namespace
}  // namespace simreel
