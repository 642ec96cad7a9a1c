// Applied forces (sim/dynamics/forces.hpp) against closed forms: each test names its closed form, its
// tolerance and why that tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <numbers>
#include <sstream>

#include <simreel/error.hpp>
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"
#include "tests/sim/dynamics/force_references.hpp"

namespace simreel {
namespace {

using contact_test::box;
using contact_test::ground;
using contact_test::sphere;

WorldConfig with_forces(std::vector<ForceDef> forces) {
  WorldConfig c;
  c.forces = std::move(forces);
  return c;
}

constexpr double kTau = 2 * std::numbers::pi;

// A box of full extents `size` and mass `mass`, origin at its centre.
BodyDef block(const std::string& name, const Vec3& size, double mass, const Vec3& at = Vec3::Zero()) {
  BodyDef b = box_body(name.c_str(), size, mass);
  b.p_WB = at;
  return b;
}

WorldConfig no_gravity(std::vector<ForceDef> forces, double dt = 1.0 / 240) {
  WorldConfig c;
  c.gravity = Vec3::Zero();
  c.dt = dt;
  c.forces = std::move(forces);
  return c;
}

ForceDef force(int body, const Vec3& F) {
  ForceDef f;
  f.kind = ForceKind::force;
  f.body = body;
  f.vector = F;
  return f;
}

ForceDef spring_to_anchor(int body, const Vec3& anchor, double k, double rest, double c = 0) {
  ForceDef f;
  f.kind = ForceKind::spring;
  f.body = body;
  f.anchor_W = anchor;
  f.stiffness = k;
  f.rest_length = rest;
  f.damping = c;
  return f;
}

// ---- Constant force: x(t) = x0 + v0 t + F t^2 / (2 m). RK4 is exact for a polynomial of degree
// <= 4 in t, so only rounding remains: 1e-13 relative to the distance travelled.
TEST(Forces, ConstantForceIsExactUnderTheDefaultIntegrator) {
  const double m = 3.0;
  BodyDef b = block("b", Vec3(0.3, 0.5, 0.9), m, Vec3(1, 2, 3));  // asymmetric: gyroscopic RK4 path
  b.v_W = Vec3(0.5, -1, 2);
  const Vec3 F(4, -2, 7);
  World w(no_gravity({force(0, F)}), {b});
  const Vec3 x0 = w.centroid(0), v0 = b.v_W;
  for (int k = 0; k < 480; ++k) w.step();
  const double t = w.time();
  const Vec3 want = x0 + v0 * t + F * (t * t / (2 * m));
  EXPECT_LT((w.centroid(0) - want).norm(), 1e-13 * (want - x0).norm()) << (w.centroid(0) - want).transpose();
  EXPECT_LT((w.linear_velocity(0) - (v0 + F * t / m)).norm(), 1e-13 * (F * t / m).norm());
  EXPECT_EQ(w.profile().runs[(int)Stage::forces], 480);
  EXPECT_EQ(w.profile().forced_bodies, 1);
}

// A window [from, to) whose edges fall inside steps: the step is split there, so the motion is
// the exact piecewise parabola (velocity change F (to - from) / m to rounding, 1e-13).
TEST(Forces, WindowEdgesInsideAStepAreExact) {
  const double m = 2.0, from = 0.1003, to = 0.7007;
  ForceDef f = force(0, Vec3(0, 0, 10));
  f.from = from;
  f.to = to;
  World w(no_gravity({f}), {block("b", Vec3(0.2, 0.3, 0.4), m)});
  for (int k = 0; k < 240; ++k) w.step();
  const double t = w.time(), a = 10 / m;
  const double z = 0.5 * a * (to - from) * (to - from) + a * (to - from) * (t - to);
  EXPECT_NEAR(w.linear_velocity(0).z(), a * (to - from), 1e-13 * a);
  EXPECT_NEAR(w.centroid(0).z(), z, 1e-13 * z);
}

// ---- Body-frame thrust at an offset point. Box with its principal axes on the body axes,
// force F along body x at (0, r, 0): torque r x F = -r F about z, constant in the body frame,
// about a principal axis, so w_z(t) = -r F t / I_zz exactly (Euler's equations: no gyroscopic
// term for a spin about a principal axis) and the angle is theta(t) = w_z t / 2. The centroid
// feels F turning with the body: v(t) = F/m int_0^t (cos theta, sin theta) ds (Fresnel integrals,
// here by Simpson's rule on 2e5 intervals, error < 1e-12). Tolerances: w to rounding (1e-13); v
// and theta to 1e-9, RK4's O(h^4) with forces evaluated at each stage (held constant over the
// step the velocity error would be O(h): 4e-3 m/s here, measured).
TEST(Forces, BodyFrameThrustAtAnOffsetSpinsUpAtTorqueOverInertia) {
  const double m = 2.0, F = 3.0, r = 0.4;
  const Vec3 size(0.6, 0.8, 1.0);
  ForceDef f = force(0, Vec3(F, 0, 0));
  f.frame = ForceFrame::body;
  f.at_centroid = false;
  f.at_B = Vec3(0, r, 0);
  World w(no_gravity({f}), {block("b", size, m)});
  const double Izz = m / 12 * (size.x() * size.x() + size.y() * size.y());
  const double alpha = -r * F / Izz;
  for (int k = 0; k < 240; ++k) w.step();
  const double t = w.time();
  EXPECT_NEAR(w.angular_velocity(0).z(), alpha * t, 1e-13 * std::fabs(alpha * t));
  EXPECT_LT(w.angular_velocity(0).head<2>().norm(), 1e-13);
  const Quat q = w.orientation(0);
  const double theta = 2 * std::atan2(q.z(), q.w());
  EXPECT_NEAR(theta, 0.5 * alpha * t * t, 1e-9);
  const Vec3 v_want = test::offset_thrust_velocity(F, m, alpha, t);
  EXPECT_LT((w.linear_velocity(0) - v_want).norm(), 1e-9)
      << w.linear_velocity(0).transpose() << " vs " << v_want.transpose();
}

// Crossing times of s(t) through zero upward, from samples (t, s, s') at each step by cubic
// Hermite interpolation (error O(h^4), far below the integrator's at these steps).
std::vector<double> upward_crossings(World& w, int body, const Vec3& axis, double rest, double duration) {
  std::vector<double> out;
  double t0 = w.time(), s0 = w.centroid(body).dot(axis) - rest, d0 = w.linear_velocity(body).dot(axis);
  while (w.time() < duration - 1e-12) {
    w.step();
    const double t1 = w.time(), s1 = w.centroid(body).dot(axis) - rest,
                 d1 = w.linear_velocity(body).dot(axis);
    if (s0 < 0 && s1 >= 0) {
      out.push_back(test::hermite_zero(t0, s0, d0, t1, s1, d1));
    }
    t0 = t1, s0 = s1, d0 = d1;
  }
  return out;
}

// ---- Undamped spring, body to anchor: period 2 pi sqrt(m / k). k = 100 N/m, m = 1 kg
// (omega = 10 rad/s, T = 0.628 s), dt = 1/240 s (omega dt = 0.042): the mean period over 100
// periods from upward zero crossings within 1e-6 relative (measured 2.5e-8: RK4's phase error
// (omega h)^4 / 120 per unit phase).
TEST(Forces, UndampedSpringOscillatesWithItsPeriod) {
  const double m = 1.0, k = 100.0, L0 = 1.0;
  BodyDef b = block("bob", Vec3(0.2, 0.2, 0.2), m, Vec3(0, 0, -L0 - 0.1));
  World w(no_gravity({spring_to_anchor(0, Vec3::Zero(), k, L0)}), {b});
  const double T = kTau * std::sqrt(m / k);
  const double E0 = w.kinetic_energy() + w.potential_energy();  // the spring's k s^2 / 2 included
  EXPECT_NEAR(E0, 0.5 * k * 0.1 * 0.1, 1e-15);
  // s = -(z + L0): the stretch, positive below the rest point.
  const std::vector<double> c = upward_crossings(w, 0, Vec3(0, 0, -1), L0, 101.5 * T);
  ASSERT_GE(c.size(), 101u);
  const double period = (c[100] - c[0]) / 100;
  EXPECT_NEAR(period / T - 1, 0, 1e-6) << "period " << period << " vs " << T;
  // Energy: RK4 shrinks the amplitude by (omega h)^6 / 144 a step, 1.1e-6 of the energy over
  // these 15,000 steps; within 2e-6.
  EXPECT_NEAR((w.kinetic_energy() + w.potential_energy()) / E0 - 1, 0, 2e-6);
  std::cout << "spring period relative error over 100 periods, dt 1/240: " << period / T - 1 << "\n";
}

// ---- Damped spring: x(t) = A e^(-g t) (cos wd t + g / wd sin wd t), g = c / 2m,
// wd = sqrt(k/m - g^2), from x(0) = A, v(0) = 0; its extrema fall at wd t = n pi with |x| =
// A e^(-c t / 2m) exactly. k = 100 N/m, m = 1 kg, c = 0.4 N s/m, dt = 1/240 s, 20 s. The path
// within 1e-6 A (RK4 phase error, (omega h)^4 / 120 per radian over 200 rad: measured 4.6e-7 A);
// each of the 63 extrema, found
// by cubic Hermite interpolation between steps (error ~1e-11 A), on the envelope within 1e-6
// relative (measured 3.2e-7: the peak's time carries the phase error, and e^(-g t) moves g dt).
TEST(Forces, DampedSpringDecaysAsExpMinusCtOver2m) {
  const double m = 1.0, k = 100.0, c = 0.4, L0 = 1.0, A = 0.1;
  BodyDef b = block("bob", Vec3(0.2, 0.2, 0.2), m, Vec3(0, 0, -L0 - A));
  World w(no_gravity({spring_to_anchor(0, Vec3::Zero(), k, L0, c)}), {b});
  const double g = c / (2 * m), wd = std::sqrt(k / m - g * g);
  double worst = 0, worst_env = 0;
  int extrema = 0;
  double t0 = 0, x0 = A, v0 = 0;
  while (w.time() < 20 - 1e-9) {
    w.step();
    const double t1 = w.time(), x1 = -w.centroid(0).z() - L0, v1 = -w.linear_velocity(0).z();
    const double want = A * std::exp(-g * t1) * (std::cos(wd * t1) + g / wd * std::sin(wd * t1));
    worst = std::max(worst, std::fabs(x1 - want));
    if ((v0 < 0 && v1 >= 0) || (v0 > 0 && v1 <= 0)) {
      const double h = t1 - t0;
      auto p = [&](double u) {  // cubic Hermite on [t0, t1]
        const double u2 = u * u, u3 = u2 * u;
        return (2 * u3 - 3 * u2 + 1) * x0 + (u3 - 2 * u2 + u) * h * v0 + (-2 * u3 + 3 * u2) * x1 +
               (u3 - u2) * h * v1;
      };
      auto dp = [&](double u) {
        const double u2 = u * u;
        return ((6 * u2 - 6 * u) * x0 + (3 * u2 - 4 * u + 1) * h * v0 + (-6 * u2 + 6 * u) * x1 +
                (3 * u2 - 2 * u) * h * v1) /
               h;
      };
      double lo = 0, hi = 1;
      const bool rising = v0 < 0;
      for (int it = 0; it < 100; ++it) {
        const double mid = 0.5 * (lo + hi);
        ((dp(mid) < 0) == rising ? lo : hi) = mid;
      }
      const double u = 0.5 * (lo + hi), tp = t0 + u * h;
      worst_env = std::max(worst_env, std::fabs(std::fabs(p(u)) / (A * std::exp(-g * tp)) - 1));
      ++extrema;
    }
    t0 = t1, x0 = x1, v0 = v1;
  }
  EXPECT_LT(worst, 1e-6 * A);
  EXPECT_GE(extrema, 60);
  EXPECT_LT(worst_env, 1e-6);
  std::cout << "damped spring: path error " << worst / A << " A, envelope " << worst_env << " relative over "
            << extrema << " extrema\n";
}

// ---- Quadratic drag on a falling ball: v(t) = v_t tanh(g t / v_t), v_t = sqrt(m g / c).
// Within 1e-6 relative of v_t after 20 s (the tanh is 1 - 2e-12 there), and of the tanh at every
// step within 1e-9 v_t (RK4 with the drag evaluated at each stage).
TEST(Forces, QuadraticDragReachesTerminalVelocity) {
  const double m = 1.0, c = 0.05, g = 9.81;
  ForceDef d;
  d.kind = ForceKind::drag;
  d.body = 0;
  d.quadratic = c;
  WorldConfig cfg;
  cfg.forces = {d};
  World w(cfg, {block("ball", Vec3(0.2, 0.2, 0.2), m, Vec3(0, 0, 1000))});
  const double vt = std::sqrt(m * g / c);
  double worst = 0;
  while (w.time() < 20 - 1e-9) {
    w.step();
    worst = std::max(worst, std::fabs(-w.linear_velocity(0).z() - vt * std::tanh(g * w.time() / vt)));
  }
  EXPECT_NEAR(-w.linear_velocity(0).z() / vt, 1.0, 1e-6);
  EXPECT_LT(worst, 1e-9 * vt);
}

// ---- Impulse: momentum changes by exactly J and angular momentum by r x J (to rounding: one
// multiply by 1/m and back, 1e-15 relative). Applied once, at the start of the first step whose
// start time reaches `time`.
TEST(Forces, ImpulseChangesMomentumByJAndAngularMomentumByRCrossJ) {
  const double m = 2.0;
  const Vec3 J(1.5, -0.5, 2.0), at(0.1, 0.05, -0.1);
  ForceDef f;
  f.kind = ForceKind::impulse;
  f.body = 0;
  f.vector = J;
  f.at_centroid = false;
  f.at_B = at;
  f.time = 0.501;  // between steps 120 (0.5 s) and 121 (0.50417 s): applied at the start of step 121
  BodyDef b = sphere(0.2, Vec3(0, 0, 1), 0.6, 0.0, m / (4.0 / 3 * std::numbers::pi * 0.008));
  b.v_W = Vec3(0.3, 0, 0);
  World w(no_gravity({f}), {b});
  for (int k = 0; k < 121; ++k) w.step();
  EXPECT_FALSE(w.impulse_applied(0));
  const Vec3 p0 = w.impl().model(0).mass * w.linear_velocity(0), L0 = w.angular_momentum(0);
  const Vec3 r = w.local_to_world(0, at) - w.centroid(0);
  w.step();
  EXPECT_TRUE(w.impulse_applied(0));
  const Vec3 dp = w.impl().model(0).mass * w.linear_velocity(0) - p0;
  EXPECT_LT((dp - J).norm(), 1e-15 * 4 * J.norm());
  const Vec3 dL = w.angular_momentum(0) - L0;
  EXPECT_LT((dL - r.cross(J)).norm(), 1e-14 * r.cross(J).norm()) << dL.transpose();
  const Vec3 v = w.linear_velocity(0);
  for (int k = 0; k < 100; ++k) w.step();  // once only
  EXPECT_EQ(w.linear_velocity(0), v);
}

TEST(Forces, AngularImpulseInTheBodyFrame) {
  ForceDef f;
  f.kind = ForceKind::angular_impulse;
  f.body = 0;
  f.vector = Vec3(0, 0, 0.3);
  f.frame = ForceFrame::body;
  BodyDef b = sphere(0.2, Vec3::Zero());
  b.q_WB = Quat(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitX()));  // body z = world -y
  World w(no_gravity({f}), {b});
  w.step();
  EXPECT_LT((w.angular_momentum(0) - Vec3(0, -0.3, 0)).norm(), 1e-15);
}

// ---- Two bodies joined by a damped spring, no gravity: internal forces F and -F, so the total
// momentum stays constant to rounding (1e-14 of its scale over 10 s: each stage adds h f/m_a
// and -h f/m_b, exactly opposite momenta up to one rounding each).
TEST(Forces, TwoBodySpringConservesTotalMomentum) {
  BodyDef a = block("a", Vec3(0.3, 0.2, 0.5), 2.0, Vec3(0, 0, 1));
  BodyDef b = block("b", Vec3(0.2, 0.4, 0.3), 1.0, Vec3(0.3, 0.1, -0.5));
  a.v_W = Vec3(0.5, 0, 0.1);
  b.v_W = Vec3(-0.2, 0.7, 0);
  a.w_W = Vec3(1, 2, 0.5);
  ForceDef f;
  f.kind = ForceKind::spring;
  f.body = 0;
  f.body_b = 1;
  f.at_centroid = f.at_b_centroid = false;
  f.at_B = Vec3(0, 0, -0.25);
  f.at_b_B = Vec3(0.1, 0, 0.15);
  f.stiffness = 50;
  f.rest_length = 1;
  f.damping = 0.5;
  World w(no_gravity({f}), {a, b});
  const Vec3 P0 = w.total_momentum();
  const Vec3 L0 = w.total_angular_momentum();
  double worst = 0, worstL = 0;
  for (int k = 0; k < 2400; ++k) {
    w.step();
    worst = std::max(worst, (w.total_momentum() - P0).norm());
    worstL = std::max(worstL, (w.total_angular_momentum() - L0).norm());
  }
  EXPECT_LT(worst, 1e-14 * 4);  // |P0| ~ 1 kg m/s
  // Angular momentum: the spring's pair of forces acts along one line, so L is conserved too; RK4
  // keeps it to its truncation error (measured 3e-10 of |L0|).
  EXPECT_LT(worstL, 1e-8 * L0.norm());
  std::cout << "two-body spring: momentum drift " << worst << ", angular momentum " << worstL / L0.norm()
            << " relative\n";
}

// ---- A box pushed along the floor: a = (F - mu m g) / m within 1% (the contact solver's
// Coulomb friction is exact when sliding; the 1% covers the start-up and the soft contact).
TEST(Forces, ForceReachesBodiesInContact) {
  const double mu = 0.5, m = 8.0, g = 9.81, F = 1.5 * mu * m * g;
  BodyDef b = box(Vec3(1, 1, 1), Vec3(0, 0, 0.5), mu, 0.0, m);
  World w(with_forces({force(0, Vec3(F, 0, 0))}), {b, ground(mu)});
  while (w.time() < 0.5 - 1e-9) w.step();
  const double t1 = w.time(), v1 = w.linear_velocity(0).x();
  while (w.time() < 1.5 - 1e-9) w.step();
  const double a = (w.linear_velocity(0).x() - v1) / (w.time() - t1);
  const double want = (F - mu * m * g) / m;
  EXPECT_NEAR(a / want, 1.0, 0.01) << a << " vs " << want;
  EXPECT_GT(w.profile().solver_bodies, 0);
  std::cout << "box pushed along the floor: a = " << a << " m/s^2 against " << want << "\n";
}

// A scene with several kinds of force, impulses before and after the save point, and contact.
std::vector<BodyDef> mixed_bodies() {
  std::vector<BodyDef> v;
  v.push_back(block("a", Vec3(0.3, 0.2, 0.5), 2.0, Vec3(0, 0, 2)));
  v.push_back(block("b", Vec3(0.2, 0.4, 0.3), 1.0, Vec3(0.3, 0.1, 1.2)));
  v.push_back(box(Vec3(0.5, 0.5, 0.5), Vec3(2, 0, 0.25)));
  v.push_back(block("c", Vec3(0.4, 0.4, 0.4), 1.5, Vec3(-1, 0, 3)));
  v[0].w_W = Vec3(1, 2, 0.5);
  v.push_back(ground());
  return v;
}
std::vector<ForceDef> mixed_forces() {
  std::vector<ForceDef> f;
  ForceDef s = spring_to_anchor(0, Vec3(0, 0, 3), 40, 0.8, 0.3);
  s.at_centroid = false;
  s.at_B = Vec3(0, 0, 0.25);
  f.push_back(s);
  ForceDef ab;
  ab.kind = ForceKind::spring;
  ab.body = 0;
  ab.body_b = 1;
  ab.stiffness = 30;
  ab.rest_length = 0.5;
  f.push_back(ab);
  ForceDef push = force(2, Vec3(60, 10, 0));
  push.from = 0.2;
  push.to = 0.61;
  f.push_back(push);
  ForceDef thrust = force(3, Vec3(0, 0, 20));
  thrust.frame = ForceFrame::body;
  thrust.at_centroid = false;
  thrust.at_B = Vec3(0.05, 0, -0.2);
  f.push_back(thrust);
  ForceDef tq;
  tq.kind = ForceKind::torque;
  tq.body = 3;
  tq.vector = Vec3(0, 0.2, 0.1);
  tq.frame = ForceFrame::body;
  f.push_back(tq);
  for (int i : {0, 1, 3}) {
    ForceDef d;
    d.kind = ForceKind::drag;
    d.body = i;
    d.linear = 0.1;
    d.quadratic = 0.05;
    f.push_back(d);
  }
  ForceDef imp;
  imp.kind = ForceKind::impulse;
  imp.body = 1;
  imp.vector = Vec3(0.5, 0, 1);
  imp.at_centroid = false;
  imp.at_B = Vec3(0.1, 0, 0);
  imp.time = 0.3;
  f.push_back(imp);
  imp.time = 0.9;
  imp.body = 2;
  f.push_back(imp);
  return f;
}

void expect_same_state(const World& a, const World& b) {
  for (int i = 0; i < a.body_count(); ++i) {
    const MotionState &x = a.impl().state(i), &y = b.impl().state(i);
    EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0) << "body " << i;
  }
}

TEST(Forces, SameResultsForAnyThreadCount) {
  WorldConfig c1 = with_forces(mixed_forces());
  WorldConfig c2 = c1;
  c2.threads = 2;
  World w1(c1, mixed_bodies()), w2(c2, mixed_bodies());
  for (int k = 0; k < 300; ++k) w1.step(), w2.step();
  expect_same_state(w1, w2);
}

// Resume equals a straight run, with one impulse applied before the save (its flag travels in the
// saved state: applied again it would change the result) and one after.
TEST(Forces, ResumeEqualsStraightRun) {
  const WorldConfig cfg = with_forces(mixed_forces());
  World straight(cfg, mixed_bodies());
  for (int k = 0; k < 360; ++k) straight.step();
  World first(cfg, mixed_bodies());
  for (int k = 0; k < 100; ++k) first.step();
  ASSERT_TRUE(first.impulse_applied(8));
  ASSERT_FALSE(first.impulse_applied(9));
  std::stringstream bytes;
  first.save_state(bytes);
  World resumed(cfg, mixed_bodies());
  resumed.restore_state(bytes);
  EXPECT_TRUE(resumed.impulse_applied(8));
  for (int k = 100; k < 360; ++k) resumed.step();
  EXPECT_TRUE(resumed.impulse_applied(9));
  expect_same_state(straight, resumed);
  // A state from the same bodies without the forces does not restore into this world.
  World plain(WorldConfig{}, mixed_bodies());
  std::stringstream other;
  plain.save_state(other);
  World again(cfg, mixed_bodies());
  EXPECT_THROW(again.restore_state(other), InputError);
}

TEST(Forces, NoForcesNoStage) {
  World w(WorldConfig{}, {block("b", Vec3(1, 1, 1), 1)});
  for (int k = 0; k < 10; ++k) w.step();
  EXPECT_EQ(w.profile().runs[(int)Stage::forces], 0);
  EXPECT_EQ(w.profile().skipped[(int)Stage::forces], 10);
  EXPECT_EQ(w.profile().forced_bodies, 0);
}

TEST(Forces, ValidationNamesTheEntry) {
  auto make = [](ForceDef f) { World w(no_gravity({f}), {block("b", Vec3(1, 1, 1), 1), ground()}); };
  ForceDef f = force(1, Vec3(1, 0, 0));
  EXPECT_THROW(make(f), InputError);  // the ground is static
  f.body = 5;
  EXPECT_THROW(make(f), InputError);
  ForceDef s = spring_to_anchor(0, Vec3::Zero(), -1, 1);
  EXPECT_THROW(make(s), InputError);
  ForceDef w = force(0, Vec3(1, 0, 0));
  w.from = 2;
  w.to = 1;
  try {
    make(w);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("force 0 (force)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace simreel
