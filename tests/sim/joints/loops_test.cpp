// Loops closed by prismatic, fixed and universal joints (sim/joints/loops.cpp, Mechanism::Loop)
// against closed forms: the slider-crank's kinematics x = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)),
// two bars hinged on one axis and welded together swinging as one compound pendulum at
// 4 K(sin(theta0/2)) sqrt(I_p / (m g d)), and a parallelogram closed by a Cardan joint whose cranks
// turn together. Revolute and spherical loops are in articulation_test.cpp (the four-bar).
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include <simreel/world.hpp>

#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

constexpr double g = 9.81;
using test::Bodies;

JointDef joint(JointType type, int parent, int child, const Vec3& anchor, const Vec3& axis) {
  JointDef j;
  j.name = "j" + std::to_string(parent) + "_" + std::to_string(child) + "_" + to_string(type);
  j.type = type;
  j.parent = parent;
  j.child = child;
  j.anchor_W = anchor;
  j.axis_W = axis;
  return j;
}

// A bar of mass m and length L (square section w) along its principal x axis: its moments.
Vec3 bar_x(double m, double L, double w = 0.04) {
  return Vec3(m * 2 * w * w / 12, m * (L * L + w * w) / 12, m * (L * L + w * w) / 12);
}

// A crank (r = 0.2 m) driven at 3 rad/s by a motor, a connecting rod (l = 0.6 m) and a slider on
// the x axis, the slider's prismatic joint closing the loop; no gravity. Whatever the crank's angle
// theta (a turn about +y, its end at (r cos theta, 0, -r sin theta)), the slider is at
// x = r cos theta + sqrt(l^2 - r^2 sin^2 theta).
TEST(Loops, SliderCrankClosedByASliderFollowsItsKinematics) {
  const double r = 0.2, l = 0.6;
  Bodies b;
  const int crank = b.add("crank", 1.0, bar_x(1.0, r), Vec3(r / 2, 0, 0));
  const int rod = b.add("rod", 0.5, bar_x(0.5, l), Vec3(r + l / 2, 0, 0));
  const int slider = b.add("slider", 2.0, Vec3(0.01, 0.01, 0.01), Vec3(r + l, 0, 0));
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, crank, Vec3::Zero(), Vec3::UnitY()));
  js.back().motor = JointMotor{JointMotor::Mode::speed, 3.0, 0, 0.1, 1e4};
  js.push_back(joint(JointType::revolute, crank, rod, Vec3(r, 0, 0), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, rod, slider, Vec3(r + l, 0, 0), Vec3::UnitY()));
  js.push_back(joint(JointType::prismatic, -1, slider, Vec3(r + l, 0, 0), Vec3::UnitX()));  // closes the loop
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  double worst = 0, worst_gap = 0;
  for (int f = 1; f <= 180; ++f) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
    const double th = art.position(0);
    const double x = r * std::cos(th) + std::sqrt(l * l - r * r * std::sin(th) * std::sin(th));
    worst = std::max(worst, std::abs(b.state[slider].x_W.x() - x));
    worst_gap = std::max(worst_gap, art.gap(b.state.data()));
    EXPECT_NEAR(b.state[slider].x_W.z(), 0, 1e-12);
  }
  EXPECT_GT(art.position(0), 8.0);  // the motor turned the crank over (3 rad/s for 3 s)
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_gap, 1e-12);
  EXPECT_NEAR(art.speed(0), 3.0, 1e-9);
  // The loop's read-out: the slide along x since the start.
  EXPECT_NEAR(art.position(3), b.state[slider].x_W.x() - (r + l), 1e-12);
}

// Two bars hinged to the world on the same axis (y through the origin), bar 1 hanging along -z,
// bar 2 horizontal below it, welded where they meet: one rigid L swinging about the pivot, released
// from rest with its centre of mass 18.4 degrees off the vertical. Its period is the compound
// pendulum's, and its centre of mass crosses the vertical at T/4 and 3T/4.
TEST(Loops, WeldedBarsSwingAsOneCompoundPendulum) {
  const double L = 0.6, m1 = 1, m2 = 1;
  Bodies b;
  // Bar 1 along z (principal x along z: turned about y), bar 2 along x.
  const Quat along_z(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const int b1 = b.add("bar1", m1, bar_x(m1, L), Vec3(0, 0, -L / 2), along_z);
  const int b2 = b.add("bar2", m2, bar_x(m2, L), Vec3(L / 2, 0, -L));
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, b1, Vec3::Zero(), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, -1, b2, Vec3::Zero(), Vec3::UnitY()));
  js.push_back(joint(JointType::fixed, b1, b2, Vec3(0, 0, -L), Vec3::UnitY()));  // closes the loop
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  const double m = m1 + m2;
  const Vec3 com0 = (m1 * b.state[b1].x_W + m2 * b.state[b2].x_W) / m;
  const double d = com0.norm(), th0 = std::atan2(com0.x(), -com0.z());
  const double Iy = bar_x(1, L).y();  // each bar's moment about its centre, across the swing
  const double Ip = m1 * (Iy + b.state[b1].x_W.squaredNorm()) + m2 * (Iy + b.state[b2].x_W.squaredNorm());
  const double T = ref::pendulum_period(th0, Ip, m, g, d);
  double now = 0;
  for (double at : {0.25, 0.75}) {
    while (now < at * T - 1e-15) {
      const double dt = std::min(1.0 / 60, at * T - now);
      ASSERT_TRUE(art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()));
      now += dt;
    }
    const Vec3 c = (m1 * b.state[b1].x_W + m2 * b.state[b2].x_W) / m;
    const Vec3 vc = (m1 * b.state[b1].v_W + m2 * b.state[b2].v_W) / m;
    EXPECT_LT(std::abs(c.x() / vc.x()), 1e-8 * T) << at << " T";
    EXPECT_NEAR(art.position(0), art.position(1), 1e-12);  // the two hinges turn together
  }
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
}

// A parallelogram: two 0.5 m cranks hinged to the world 1 m apart about y, a coupler hinged to the
// first crank's end and joined to the second's by a Cardan joint (axes y on the crank, x on the
// coupler): the cranks turn together and the coupler stays level, under gravity, released from
// 60 degrees; energy holds.
TEST(Loops, ParallelogramClosedByACardanJointKeepsItsCranksTogether) {
  const double c = 0.5;
  Bodies b;
  // Turned 60 degrees about +y from hanging: a crank's end at (-c sin phi, 0, -c cos phi).
  const double phi = std::numbers::pi / 3, sx = -c * std::sin(phi), sz = -c * std::cos(phi);
  const Quat turned = Quat(Eigen::AngleAxisd(phi, Vec3::UnitY())) *
                      Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const int k1 = b.add("crank1", 1.0, bar_x(1.0, c), Vec3(sx / 2, 0, sz / 2), turned);
  const int k2 = b.add("crank2", 1.0, bar_x(1.0, c), Vec3(1 + sx / 2, 0, sz / 2), turned);
  const int cp = b.add("coupler", 2.0, bar_x(2.0, 1.0), Vec3(0.5 + sx, 0, sz));
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, k1, Vec3::Zero(), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, -1, k2, Vec3(1, 0, 0), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, k1, cp, Vec3(sx, 0, sz), Vec3::UnitY()));
  JointDef u = joint(JointType::universal, k2, cp, Vec3(1 + sx, 0, sz), Vec3::UnitY());
  u.axis2_W = Vec3::UnitX();
  js.push_back(u);  // closes the loop
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  double now = 0, worst_q = 0, worst_level = 0;
  const double E0 = b.energy(g);
  double worst_E = 0;
  for (int f = 1; f <= 300; ++f) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    now += 1.0 / 60;
    worst_q = std::max(worst_q, std::abs(art.position(0) - art.position(1)));
    worst_level = std::max(worst_level, (b.state[cp].q_WP * Vec3::UnitX() - Vec3::UnitX()).norm());
    worst_E = std::max(worst_E, std::abs(b.energy(g) - E0));
  }
  EXPECT_LT(worst_q, 1e-10);
  EXPECT_LT(worst_level, 1e-10);
  EXPECT_LT(worst_E, 1e-8 * 4 * g * c);
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
  EXPECT_GT(std::abs(art.position(0)), 0.5);  // it swung
}

// A Cardan (Hooke's) joint between two shafts 30 degrees apart, closing the loop of two hinges on
// the world; no gravity, the input spun at 5 rad/s. The shafts' angles obey tan(theta_2) =
// tan(theta_1) cos(beta) (the input's yoke starts across the shafts' plane, so the output turns
// slower than the input at the start), and kinetic energy
// holds: the shafts trade speed twice a turn. A spatial loop: every velocity-product term of the
// Cardan row acts.
TEST(Loops, CardanShaftFollowsHookesLawAndKeepsItsEnergy) {
  const double beta = std::numbers::pi / 6;
  const Vec3 out_axis(std::cos(beta), std::sin(beta), 0);
  Bodies b;
  // Each shaft: a 1 kg rod 1 m long along its axis (principal x), its centre 0.5 m from the cross.
  const Vec3 I = bar_x(1.0, 1.0, 0.1);
  const int in = b.add("in", 1.0, I, Vec3(-0.5, 0, 0));
  const int out = b.add("out", 1.0, I, 0.5 * out_axis, Quat(Eigen::AngleAxisd(beta, Vec3::UnitZ())));
  b.state[in].w_P = Vec3(5, 0, 0);
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, in, Vec3::Zero(), Vec3::UnitX()));
  js.push_back(joint(JointType::revolute, -1, out, Vec3::Zero(), out_axis));
  JointDef u = joint(JointType::universal, in, out, Vec3::Zero(), Vec3::UnitZ());
  u.axis2_W = Vec3::UnitZ().cross(out_axis);
  js.push_back(u);  // closes the loop
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);  // the output's start rate is projected in
  const double E0 = b.energy(0);
  double worst_law = 0, worst_E = 0;
  for (int f = 1; f <= 300; ++f) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
    const double t1 = art.position(0), t2 = art.position(1);
    // In sin/cos form (no division by a vanishing cosine): sin t2 cos t1 = sin t1 cos t2 cos b.
    worst_law = std::max(
        worst_law, std::abs(std::sin(t2) * std::cos(t1) - std::sin(t1) * std::cos(t2) * std::cos(beta)));
    worst_E = std::max(worst_E, std::abs(b.energy(0) - E0));
  }
  EXPECT_GT(art.position(0), 12.0);  // two turns
  EXPECT_LT(worst_law, 1e-10);
  EXPECT_LT(worst_E, 1e-9 * E0);
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
}

// An oscillating-cylinder mechanism: a crank (0.3 m) hinged to the world at the origin, a rocker
// hinged 1 m away, and a block pinned to the crank's end that slides along the rocker, its slider
// closing the loop; no gravity, started turning. The rocker turns as the loop's slider runs along
// it, so every term of the slider's rows that carries the rocker's turning acts; kinetic energy
// holds, and the rocker points at the crank pin.
TEST(Loops, OscillatingCylinderKeepsItsEnergy) {
  const double r = 0.3;
  Bodies b;
  const int crank = b.add("crank", 1.0, bar_x(1.0, r), Vec3(r / 2, 0, 0));
  // The rocker from (1, 0, 0) towards the pin at (r, 0, 0): along -x, 1.2 m long.
  const int rocker = b.add("rocker", 2.0, bar_x(2.0, 1.2), Vec3(1 - 0.6, 0, 0));
  const int block = b.add("block", 0.5, Vec3(1e-3, 1e-3, 1e-3), Vec3(r, 0, 0));
  b.state[crank].w_P = Vec3(0, 4, 0);
  b.state[crank].v_W = Vec3(0, 0, -4 * r / 2);
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, crank, Vec3::Zero(), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, -1, rocker, Vec3(1, 0, 0), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, crank, block, Vec3(r, 0, 0), Vec3::UnitY()));
  js.push_back(joint(JointType::prismatic, rocker, block, Vec3(r, 0, 0), Vec3::UnitX()));  // closes
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  const double E0 = b.energy(0);
  double worst_E = 0, worst_aim = 0;
  for (int f = 1; f <= 300; ++f) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
    worst_E = std::max(worst_E, std::abs(b.energy(0) - E0));
    // The rocker's axis (its principal x) is along the line from its pivot to the pin.
    const Vec3 to_pin = (b.state[block].x_W - Vec3(1, 0, 0)).normalized();
    worst_aim = std::max(worst_aim, std::abs((b.state[rocker].q_WP * Vec3::UnitX()).cross(to_pin).norm()));
  }
  EXPECT_GT(std::abs(art.position(0)), 3.0);  // the crank swung through half a turn
  EXPECT_LT(worst_E, 1e-9 * E0);
  EXPECT_LT(worst_aim, 1e-12);
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
}

// m: the largest distance between two runs' sampled positions.
double farthest_apart(const std::vector<Vec3>& xa, const std::vector<Vec3>& xb) {
  double worst = 0;
  for (size_t i = 0; i < xa.size(); ++i) worst = std::max(worst, (xa[i] - xb[i]).norm());
  return worst;
}

// A mechanism with a stopped coordinate run for 3 s under gravity: the worst energy change (J),
// how far the coordinate went past [lo, hi] and how far from 0 it read at a frame's end, the
// mode changes, and the bodies' positions every 1/4 s (through the bouncing, not only at rest).
struct StopRun {
  std::vector<Vec3> x;
  double worst_E = 0, past = 0, travel = 0;
  int hits = 0;
};
StopRun run_stopped(Bodies& b, const std::vector<JointDef>& js, int stopped, double lo, double hi) {
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  const double E0 = b.energy(g);
  StopRun r;
  for (int f = 1; f <= 180; ++f) {
    EXPECT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    r.worst_E = std::max(r.worst_E, std::abs(b.energy(g) - E0));
    const double q = art.position(stopped);
    r.past = std::max({r.past, lo - q, q - hi});
    r.travel = std::max(r.travel, std::abs(q));
    if (f % 15 == 0)
      for (const MotionState& st : b.state) r.x.push_back(st.x_W);
  }
  for (const Mechanism& m : art.mechanisms()) r.hits += (int)m.events;
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
  return r;
}

// The four-bar of the tests below: crank, coupler and rocker (bodies 0, 1, 2 of `b`), the rocker
// hinged to the world 1.2 m from the crank (a non-Grashof linkage: no link turns fully, but the
// coupler turns more than half a turn from the rocker under gravity). The coupler-rocker hinge
// closes the loop (closing) or is in the tree with its axis reversed, so that its angle keeps its
// sign, the crank's pin then closing. Returns the joints and, in `hinge`, the coupler-rocker's.
std::vector<JointDef> make_four_bar(Bodies& b, bool closing, int& hinge) {
  const int crank = b.add("crank", 1.0, Vec3(0.02, 0.03, 0.025), Vec3(0.15, 0, 0.2));
  const int coupler = b.add("coupler", 1.5, Vec3(0.04, 0.06, 0.05), Vec3(0.65, 0, 0.5));
  const int rocker = b.add("rocker", 2.0, Vec3(0.05, 0.07, 0.06), Vec3(1.1, 0, 0.3));
  const Vec3 B(0.3, 0, 0.4), C(1.0, 0, 0.6);
  std::vector<JointDef> js;
  js.push_back(joint(JointType::revolute, -1, crank, Vec3::Zero(), Vec3::UnitY()));
  js.push_back(joint(JointType::revolute, -1, rocker, Vec3(1.2, 0, 0), Vec3::UnitY()));
  if (closing) {
    js.push_back(joint(JointType::revolute, crank, coupler, B, Vec3::UnitY()));
    js.push_back(joint(JointType::revolute, coupler, rocker, C, Vec3::UnitY()));  // closes
  } else {
    js.push_back(joint(JointType::revolute, rocker, coupler, C, -Vec3::UnitY()));
    js.push_back(joint(JointType::revolute, crank, coupler, B, Vec3::UnitY()));  // closes
  }
  hinge = closing ? 3 : 2;
  return js;
}

// A spring on a loop's closing joint is the same physics as the same spring on a tree joint. A
// four-bar under gravity whose coupler-rocker hinge carries a spring (5 N m/rad, rest 0.3 rad from
// the start), once with that hinge closing the loop and once with it in the tree (the crank's pin
// closing it instead; the axis reversed so that the angle keeps its sign); and two carts on rails
// joined by a sprung slider (40 N/m, rest 0.1 m), the slider closing the loop or in the tree. The runs take
// different coordinates, so they agree to the integrator's tolerance (1e-10 a step), not to the bit:
// positions within 1e-8 m over 3 s. Without damping the energy, the spring's included, holds to 1e-9 of what
// the swing exchanges; with damping the runs still agree. The four-bar's coupler turns past 180 degrees from
// the spring's rest.
struct SpringRun {
  std::vector<Vec3> x;
  double worst_E = 0, moved = 0;
};
SpringRun spring_run(bool four_bar, bool closing, double damping) {
  Bodies b;
  std::vector<JointDef> js;
  JointSpring spring{5.0, damping, 0.3};
  double grav = g;
  int watched = 0;
  if (four_bar) {
    int hinge = 0;
    js = make_four_bar(b, closing, hinge);
    js[hinge].spring = spring;
    watched = 0;  // the crank
  } else {
    // Two carts on rails along x (1 kg at the origin, 2 kg 1 m on), a slider between them along x
    // carrying the spring: the slider or the second cart's rail closes the loop (its other rows
    // are redundant with the rails). Only the spring acts along x, so the carts' separation is a
    // two-mass oscillator's: 1 + rest (1 - cos(w t)), w = sqrt(k (m1 + m2) / (m1 m2)).
    const int a = b.add("cart_a", 1.0, Vec3(0.01, 0.01, 0.01), Vec3::Zero());
    const int c = b.add("cart_b", 2.0, Vec3(0.02, 0.02, 0.02), Vec3(1, 0, 0));
    js.push_back(joint(JointType::prismatic, -1, a, Vec3::Zero(), Vec3::UnitX()));
    JointDef rail = joint(JointType::prismatic, -1, c, Vec3(1, 0, 0), Vec3::UnitX());
    JointDef slide = joint(JointType::prismatic, a, c, Vec3(1, 0, 0), Vec3::UnitX());
    slide.spring = JointSpring{40.0, damping, 0.1};
    js.push_back(closing ? rail : slide);
    js.push_back(closing ? slide : rail);  // the second closes the loop
    grav = 0;
    watched = c;
  }
  Articulations art;
  std::vector<std::string> warnings;
  art.build(js, {}, b.defs, b.model, b.state, warnings);
  SpringRun out;
  const Vec3 x0 = b.state[watched].x_W;
  const double E0 = b.energy(grav) + art.spring_energy();
  for (int f = 1; f <= 180; ++f) {
    EXPECT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -grav), nullptr, b.state.data()));
    out.worst_E = std::max(out.worst_E, std::abs(b.energy(grav) + art.spring_energy() - E0));
    out.moved = std::max(out.moved, (b.state[watched].x_W - x0).norm());
  }
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
  if (!four_bar && damping == 0) {
    const double w = std::sqrt(40.0 * 3.0 / 2.0), t = 180.0 / 60;
    EXPECT_NEAR(b.state[1].x_W.x() - b.state[0].x_W.x(), 1 + 0.1 * (1 - std::cos(w * t)), 1e-9);
  }
  for (const MotionState& st : b.state) out.x.push_back(st.x_W);
  return out;
}

TEST(Loops, SpringOnAClosingJointActsAsOnATreeJoint) {
  for (const bool four_bar : {true, false})
    for (const double damping : {0.0, 0.4}) {
      SCOPED_TRACE(std::string(four_bar ? "four-bar" : "carts") + " damping " + std::to_string(damping));
      const SpringRun a = spring_run(four_bar, true, damping), b = spring_run(four_bar, false, damping);
      double worst = 0;
      for (size_t i = 0; i < a.x.size(); ++i) worst = std::max(worst, (a.x[i] - b.x[i]).norm());
      EXPECT_GT(a.moved, 0.05);  // it moved
      EXPECT_LT(worst, 1e-8);
      if (damping == 0) {  // 1e-9 of the 30 J the four-bar's swing exchanges with the spring
        EXPECT_LT(a.worst_E, 3e-8);
        EXPECT_LT(b.worst_E, 3e-8);
      }
    }
}

// The sprung four-bar above through the World, its spring on the hinge closing the loop: the
// coupler turns more than 180 degrees from the rocker, so the spring's angle must be continuous
// there, not its principal value. A resume from a state saved past 180 degrees, and a second
// thread, give the straight run's bits; the energy holds.
TEST(Loops, SprungClosingHingePastHalfATurnResumes) {
  WorldConfig cfg;
  cfg.dt = 1.0 / 60;
  cfg.gravity = Vec3(0, 0, -g);
  cfg.contacts.sleep = false;
  Bodies bodies;
  int hinge = 0;
  cfg.joints = make_four_bar(bodies, true, hinge);
  cfg.joints[hinge].spring = JointSpring{5.0, 0, 0.3};
  std::vector<BodyDef> defs;
  for (size_t i = 0; i < bodies.defs.size(); ++i) {  // the same bodies, their mass stated
    defs.push_back(bodies.defs[i]);
    defs.back().mass_override =
        MassProperties{bodies.model[i].mass, Vec3::Zero(), bodies.model[i].I_P.asDiagonal()};
  }
  auto saved = [](const World& w) {
    std::ostringstream os;
    w.save_state(os);
    return os.str();
  };
  WorldConfig two = cfg;
  two.threads = 2;
  World a(cfg, defs), b(two, defs);
  const double E0 = a.kinetic_energy() + a.potential_energy();
  double drift = 0;
  std::string mid;
  int saved_at = -1;
  for (int k = 0; k < 240; ++k) {
    a.step();
    b.step();
    drift = std::max(drift, std::abs(a.kinetic_energy() + a.potential_energy() - E0));
    if (saved_at < 0 && std::abs(a.joint_position(hinge)) > std::numbers::pi) {
      mid = saved(a);
      saved_at = k;
    }
  }
  ASSERT_GE(saved_at, 0) << "the hinge never turned past half a turn";
  EXPECT_LT(drift, 1e-9 * E0);
  EXPECT_EQ(saved(a), saved(b));
  World c(cfg, defs);
  std::istringstream is(mid);
  c.restore_state(is);
  for (int k = saved_at + 1; k < 240; ++k) c.step();
  EXPECT_EQ(saved(c), saved(a));
}

// Stops on a hinge that closes a loop are the same physics as on a tree hinge: the sprung
// four-bar above without its spring, its coupler-rocker hinge stopped at [-1.2, 0.4] rad (it
// swings from -3.1 to 0.54 free), the hinge closing the loop or in the tree, positions sampled
// every 1/4 s. With restitution 1 the energy holds through every stop and the runs agree to
// 1e-8 m (each locates its impacts to the integrator's tolerance, through different
// coordinates); with 0.5 both bounce to rest in the same impacts; with 0 both come to rest on the
// stop alike. The angle stays within its stops.
TEST(Loops, StopsOnAClosingHingeActAsOnATreeHinge) {
  for (const double e : {1.0, 0.5, 0.0}) {
    SCOPED_TRACE(e);
    auto run = [&](bool closing) {
      Bodies b;
      int stopped = 0;
      std::vector<JointDef> js = make_four_bar(b, closing, stopped);
      js[stopped].limits = JointLimits{-1.2, 0.4, e};
      return run_stopped(b, js, stopped, -1.2, 0.4);
    };
    const StopRun a = run(true), t = run(false);
    const double worst = farthest_apart(a.x, t.x);
    const int ha = a.hits, hb = t.hits;
    const double pa = a.past, pb = t.past, Ea = a.worst_E, Eb = t.worst_E;
    EXPECT_GE(ha, e > 0 ? 4 : 1);  // it met its stops
    // With restitution 0.5 the bounces die out within a frame and the hinge rests, in as many
    // impacts either way (22; each return seen by its event function).
    EXPECT_NEAR(ha, hb, 2);
    EXPECT_LT(pa, 1e-9);
    EXPECT_LT(pb, 1e-9);
    EXPECT_LT(worst, 1e-8);
    if (e == 1.0) {
      EXPECT_LT(Ea, 1e-8);
      EXPECT_LT(Eb, 1e-8);
    }
  }
}

// What only a tree joint carries (a motor, friction, armature) on a joint written to close a loop:
// the tree takes that joint first and a plain joint of the loop closes it instead. The four-bar with
// its coupler-rocker hinge written last (so that, taken in file order, it would close the loop)
// against the same four-bar with that hinge in the tree by the order written: the trees differ (the
// rocker's pin or the crank's closes), so the runs agree to the integrator's tolerance over 3 s:
// within 1e-8 m, 1e-7 with armature (3e-8 at the default tolerance, falling tenfold with each decade
// of it: the two runs' integration error, not a difference in the physics). Each option acts: the
// motion differs from the plain four-bar's.
TEST(Loops, TreeOnlyOptionsOnAJointWrittenToCloseALoop) {
  const auto plain = [] {
    Bodies b;
    int h = 0;
    return run_stopped(b, make_four_bar(b, true, h), h, -1e9, 1e9);
  }();
  for (int option = 0; option < 3; ++option) {
    SCOPED_TRACE(option == 0 ? "motor" : option == 1 ? "friction" : "armature");
    auto run = [&](bool written_closing) {
      Bodies b;
      int hinge = 0;
      std::vector<JointDef> js = make_four_bar(b, written_closing, hinge);
      JointDef& d = js[hinge];
      if (option == 0) d.motor = JointMotor{JointMotor::Mode::speed, -0.5, 0, 0.1, 3.0};
      if (option == 1) d.friction = 0.8;
      if (option == 2) d.armature = 0.05;
      return run_stopped(b, js, hinge, -1e9, 1e9);
    };
    const StopRun a = run(true), t = run(false);
    EXPECT_LT(farthest_apart(a.x, t.x), option == 2 ? 1e-7 : 1e-8);
    EXPECT_GT(farthest_apart(a.x, plain.x), 1e-3);  // the option acted
  }
}

// Stops on a slider that closes a loop are the same physics as on a tree slider. An inverted
// slider-crank (an oscillating cylinder): a crank hinged to the world at O, a rocker hinged to the
// world at Q 0.6 m away, and a rod hinged to the crank's tip B and sliding through the rocker
// along B -> Q, its slide stopped at [-0.1, 0.1] m (free it runs -0.23..0.17 as the crank turns
// under gravity). The slider closes the loop, or sits in the tree with the crank-rod hinge closing
// it. The rocker turns, so the slide's axis does: the rows' terms in its turning rate are in play.
// With restitution 1 the energy holds through every stop and the runs agree to 1e-8 m; with 0.5
// both bounce to rest in as many impacts; with 0 both rest on the stop alike.
TEST(Loops, StopsOnAClosingSliderActAsOnATreeSlider) {
  const Vec3 O(0, 0, 0), Q(0.6, 0, 0), B(0, 0, 0.2), u = (Q - B).normalized();
  for (const double e : {1.0, 0.5, 0.0}) {
    SCOPED_TRACE(e);
    auto run = [&](bool closing) {
      Bodies b;
      const int crank = b.add("crank", 1.0, Vec3(0.004, 0.004, 0.0005), Vec3(0.02, 0, 0.1));
      const int rocker = b.add("rocker", 0.5, Vec3(0.002, 0.003, 0.002), Q);
      const int rod = b.add("rod", 0.8, Vec3(0.01, 0.012, 0.001), B + 0.3 * u);
      JointDef slide = joint(JointType::prismatic, rocker, rod, Q, u);
      slide.limits = JointLimits{-0.1, 0.1, e};
      const JointDef pin = joint(JointType::revolute, crank, rod, B, Vec3::UnitY());
      std::vector<JointDef> js{joint(JointType::revolute, -1, crank, O, Vec3::UnitY()),
                               joint(JointType::revolute, -1, rocker, Q, Vec3::UnitY())};
      js.push_back(closing ? pin : slide);
      js.push_back(closing ? slide : pin);   // the last closes the loop
      b.state[crank].w_P = Vec3(0, 1.0, 0);  // set going: the crank starts upright
      return run_stopped(b, js, closing ? 3 : 2, -0.1, 0.1);
    };
    const StopRun a = run(true), t = run(false);
    const double worst = farthest_apart(a.x, t.x);
    const int ha = a.hits, hb = t.hits;
    const double pa = a.past, pb = t.past, Ea = a.worst_E, Eb = t.worst_E, ta = a.travel, tb = t.travel;
    std::printf("slider stops, restitution %g: %d / %d impacts, runs %.1e m apart, energy %.1e / %.1e J\n", e,
                ha, hb, worst, Ea, Eb);
    EXPECT_GE(ha, e > 0 ? 4 : 1);  // it met its stops
    EXPECT_NEAR(ha, hb, 2);
    if (e < 1) {  // at rest on the stop by the end
      EXPECT_NEAR(ta, 0.1, 1e-12);
      EXPECT_NEAR(tb, 0.1, 1e-12);
    }
    EXPECT_LT(pa, 1e-9);
    EXPECT_LT(pb, 1e-9);
    // Each run locates its impacts to the integrator's tolerance through different coordinates,
    // and the crank's swing carries the difference on: 1.4e-8 m after five impacts with
    // restitution 1, 4e-11 with 0.5.
    EXPECT_LT(worst, 1e-7);
    if (e == 1.0) {
      EXPECT_LT(Ea, 1e-8);
      EXPECT_LT(Eb, 1e-8);
    }
  }
}

// A loop slider held on its stop while its axis turns: the held row carries the slide's
// centripetal terms. In the horizontal plane (hinges about z, gravity along -z does no work) an
// arm hinged to the world at O spins at 3 rad/s; a bead slides along it, joined back to the arm by
// two hinged links (two degrees of freedom: the spin and the slide), the slider closing the loop
// or in the tree (a hinge of the links closing it). The bead flies out onto its stop at 0.1 m
// (restitution 0) and the whole turns as one body on. Nothing acts about z: the angular momentum
// about O holds to 1e-10 throughout, the energy after the impact, and the runs agree to 1e-8 m.
TEST(Loops, ClosingSliderHeldOnItsStopWhileItsAxisTurns) {
  auto run = [&](bool closing, double& dL, double& dE, int& held) {
    Bodies b;
    const int arm = b.add("arm", 1.0, Vec3(0.001, 0.03, 0.03), Vec3(0.3, 0, 0));
    const int l1 = b.add("link1", 0.2, Vec3(0.0005, 0.002, 0.002), Vec3(0.4, 0.15, 0));
    const int l2 = b.add("link2", 0.2, Vec3(0.0005, 0.002, 0.002), Vec3(0.3, 0.075, 0));
    const int bead = b.add("bead", 0.5, Vec3(0.001, 0.001, 0.001), Vec3(0.2, 0, 0));
    const Vec3 z = Vec3::UnitZ();
    JointDef slide = joint(JointType::prismatic, arm, bead, Vec3(0.2, 0, 0), Vec3::UnitX());
    slide.limits = JointLimits{-0.05, 0.1, 0.0};
    const JointDef pin = joint(JointType::revolute, l2, bead, Vec3(0.2, 0, 0), z);
    std::vector<JointDef> js{joint(JointType::revolute, -1, arm, Vec3::Zero(), z),
                             joint(JointType::revolute, arm, l1, Vec3(0.5, 0.2, 0), z),
                             joint(JointType::revolute, l1, l2, Vec3(0.3, 0.1, 0), z)};
    js.push_back(closing ? pin : slide);
    js.push_back(closing ? slide : pin);  // the last closes the loop
    const int stopped = closing ? 4 : 3;
    for (int i : {arm, l1, l2, bead}) {  // spinning as one body about O at 3 rad/s
      b.state[i].w_P = Vec3(0, 0, 3);
      b.state[i].v_W = Vec3(0, 0, 3).cross(b.state[i].x_W);
    }
    Articulations art;
    std::vector<std::string> warnings;
    art.build(js, {}, b.defs, b.model, b.state, warnings);
    auto Lz = [&] {
      double L = 0;
      for (size_t i = 0; i < b.state.size(); ++i)
        L += b.model[i].mass * b.state[i].x_W.cross(b.state[i].v_W).z() +
             b.model[i].I_P.z() * b.state[i].w_P.z();
      return L;
    };
    const double L0 = Lz();
    double E_held = NAN;
    dL = dE = 0;
    held = 0;
    std::vector<Vec3> x;
    for (int f = 1; f <= 120; ++f) {
      EXPECT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
      dL = std::max(dL, std::abs(Lz() - L0) / std::abs(L0));
      const double q = art.position(stopped);
      if (std::abs(q - 0.1) < 1e-12) {
        if (std::isnan(E_held)) E_held = b.energy(g);
        dE = std::max(dE, std::abs(b.energy(g) - E_held) / E_held);
        held = std::max(held, 1);
      } else if (!std::isnan(E_held)) {
        held = 2;  // left the stop after resting on it
      }
      if (f % 15 == 0)
        for (const MotionState& st : b.state) x.push_back(st.x_W);
    }
    EXPECT_LT(art.gap(b.state.data()), 1e-12);
    return x;
  };
  double La, Lb, Ea, Eb;
  int ha, hb;
  const std::vector<Vec3> xa = run(true, La, Ea, ha), xb = run(false, Lb, Eb, hb);
  const double worst = farthest_apart(xa, xb);
  std::printf("held slider: L_z %.1e / %.1e, energy while held %.1e / %.1e, runs %.1e m apart\n", La, Lb, Ea,
              Eb, worst);
  EXPECT_EQ(ha, 1);  // reached the stop and stayed
  EXPECT_EQ(hb, 1);
  EXPECT_LT(La, 1e-10);
  EXPECT_LT(Lb, 1e-10);
  EXPECT_LT(Ea, 1e-10);
  EXPECT_LT(Eb, 1e-10);
  EXPECT_LT(worst, 1e-8);
}

// A ball joint with a spring may close a loop none of whose joints is plain. A body (principal
// moments 0.1, 0.2, 0.3 kg m^2) on a hinge about z through its centre of mass, the hinge carrying a
// rotor's armature (so the tree must take it), and a ball joint at the same point with a spring
// k = 3 N m/rad closing the loop. Started turning at w0 = 1 rad/s about z, no gravity: the spring's
// torque is -k q about z (phi stays on the axis), so q = (w0 / w) sin(w t) with
// w = sqrt(k / (I_z + armature)) exactly, and the energy, spring and rotor included, holds.
TEST(Loops, SprungBallJointClosesALoopAndTurnsAtItsClosedForm) {
  const double k = 3, Iz = 0.3, arm = 0.05, w0 = 1.0;
  for (bool ball_first : {false, true}) {
    SCOPED_TRACE(ball_first ? "ball written first" : "hinge written first");
    Bodies b;
    b.add("body", 2.0, Vec3(0.1, 0.2, Iz), Vec3(0.3, -0.2, 1.0));
    b.state[0].w_P = Vec3(0, 0, w0);
    JointDef h = joint(JointType::revolute, -1, 0, Vec3(0.3, -0.2, 1.0), Vec3::UnitZ());
    h.armature = arm;
    JointDef ball = joint(JointType::spherical, -1, 0, Vec3(0.3, -0.2, 1.0), Vec3::UnitZ());
    ball.spring = JointSpring{k, 0, 0};
    std::vector<JointDef> js = ball_first ? std::vector<JointDef>{ball, h} : std::vector<JointDef>{h, ball};
    Articulations art;
    std::vector<std::string> warnings;
    art.build(js, JointSettings{}, b.defs, b.model, b.state, warnings);
    const int hinge = ball_first ? 1 : 0;
    ASSERT_EQ(art.mechanisms()[0].loops.size(), 1u);
    const double w = std::sqrt(k / (Iz + arm));
    const double E0 = 0.5 * (Iz + arm) * w0 * w0;
    double worst = 0, worst_E = 0;
    for (int i = 1; i <= 180; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
      const double t = i / 60.0;
      worst = std::max(worst, std::abs(art.position(hinge) - w0 / w * std::sin(w * t)));
      const double E = 0.5 * b.state[0].w_P.dot(Vec3(0.1, 0.2, Iz).cwiseProduct(b.state[0].w_P)) +
                       art.spring_energy() + art.armature_energy();
      worst_E = std::max(worst_E, std::abs(E - E0) / E0);
    }
    EXPECT_LT(worst, 1e-8);    // rad: dopri5 at its default tolerance
    EXPECT_LT(worst_E, 1e-8);  // of E0
  }
}

// A gimbal about O: a ring (0.5 kg) on a hinge to the world about `outer_axis` with a rotor, and a
// body (2 kg) on a hinge about y in it with a rotor, both axes through the body's centre; the body
// starts turned off the world's axes (so b's start rotation relative to a's is not the identity,
// and R_a phi differs from R_b phi), both spinning. Its joints, then a ball joint at O from
// `ball_parent` (-1: the world; 0: the ring) to the body, which closes the loop.
struct Gimbal {
  Bodies b;
  std::vector<JointDef> joints;
  JointDef& ball() { return joints[2]; }
  Gimbal(const Vec3& outer_axis, int ball_parent) {
    const Vec3 O(0.1, 0.4, 0.8);
    b.add("ring", 0.5, Vec3(0.02, 0.01, 0.01), O);
    const Quat q0(Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()));
    b.add("body", 2.0, Vec3(0.1, 0.2, 0.3), O, q0);
    b.state[0].w_P = Vec3(1.5, 0, 0);
    b.state[1].w_P = q0.conjugate() * Vec3(1.5, -2.0, 0);
    joints.push_back(joint(JointType::revolute, -1, 0, O, outer_axis));
    joints.back().armature = 0.01;
    joints.push_back(joint(JointType::revolute, 0, 1, O, Vec3::UnitY()));
    joints.back().armature = 0.02;
    joints.push_back(joint(JointType::spherical, ball_parent, 1, O, Vec3::UnitZ()));
  }
  Articulations art;
  /// Builds the mechanism (after the ball joint's options are set): one loop.
  size_t build() {
    std::vector<std::string> warnings;
    art.build(joints, JointSettings{}, b.defs, b.model, b.state, warnings);
    return art.mechanisms()[0].loops.size();
  }
  /// J: the bodies' turning, the rotors' and the springs'.
  double energy() const {
    double E = art.spring_energy() + art.armature_energy();
    for (int i = 0; i < 2; ++i) E += 0.5 * b.state[i].w_P.dot(b.model[i].I_P.cwiseProduct(b.state[i].w_P));
    return E;
  }
};

// The same spring in three dimensions: a body in a gimbal (an outer ring on a hinge about x with
// armature, the body on a hinge about y in it with armature, both axes through the body's centre)
// held to the world at that centre by a sprung ball joint, which closes the loop. Spun about both
// hinges, the body wobbles against the spring; no gravity. The energy (body, ring, rotors, spring)
// holds, and a dashpot on the ball joint (c = 0.2 N m s/rad) dissipates exactly its power:
// E(t) = E0 - integral of c |w_b - w_a|^2.
TEST(Loops, SprungBallJointClosingAGimbalKeepsItsEnergy) {
  for (double c : {0.0, 0.2}) {
    SCOPED_TRACE(c == 0 ? "undamped" : "damped");
    Gimbal gim(Vec3::UnitX(), -1);
    Bodies& b = gim.b;
    gim.ball().spring = JointSpring{4.0, c, 0};
    ASSERT_EQ(gim.build(), 1u);
    Articulations& art = gim.art;
    auto energy = [&] { return gim.energy(); };
    const double E0 = energy();
    double dissipated = 0, worst = 0, turned = 0;
    Vec3 w_prev = b.state[1].q_WP * b.state[1].w_P;
    // The dashpot's work by the trapezoid rule on 1/480 s steps (its own error about 1e-6 of it).
    const int n = 8;
    for (int i = 1; i <= 240; ++i) {
      for (int s = 0; s < n; ++s) {
        ASSERT_TRUE(art.step(1.0 / (60 * n), Vec3::Zero(), nullptr, b.state.data()));
        const Vec3 w = b.state[1].q_WP * b.state[1].w_P;
        dissipated += c * 0.5 * (w_prev.squaredNorm() + w.squaredNorm()) / (60 * n);
        w_prev = w;
      }
      worst = std::max(worst, std::abs(energy() + dissipated - E0));
      turned = std::max(turned, art.mechanisms()[0].loop_angle(0));
    }
    EXPECT_GT(turned, 0.3);  // the spring wound (rad)
    if (c == 0)
      EXPECT_LT(worst, 1e-8 * E0);
    else
      EXPECT_LT(worst, 1e-4 * dissipated);
  }
}

// A ball joint's stops on a joint that closes a loop measure b's rotation relative to a's. A body
// turning at w0 = 2 rad/s on a hinge about z with a rotor (so the tree takes the hinge), closed to
// the world by a ball joint at its centre whose whole-rotation stop is 0.5 rad: no gravity, so it
// turns at constant speed between impacts, and each impact (at |q| = 0.5) reverses its rate times
// the restitution. With e = 1 the angle is a triangle wave of period 2 / w0 after the first
// quarter, 0.5 / w0; with e = 0.5 each crossing takes twice as long as the last.
TEST(Loops, StopsOnAClosingBallJointBounceAtTheirClosedForm) {
  const double w0 = 2.0, bound = 0.5;
  for (double e : {1.0, 0.5}) {
    SCOPED_TRACE(e == 1 ? "restitution 1" : "restitution 0.5");
    Bodies b;
    b.add("body", 2.0, Vec3(0.1, 0.2, 0.3), Vec3(0.3, -0.2, 1.0));
    b.state[0].w_P = Vec3(0, 0, w0);
    JointDef h = joint(JointType::revolute, -1, 0, Vec3(0.3, -0.2, 1.0), Vec3::UnitZ());
    h.armature = 0.05;
    JointDef ball = joint(JointType::spherical, -1, 0, Vec3(0.3, -0.2, 1.0), Vec3::UnitZ());
    ball.ball_limits = BallLimits{};
    ball.ball_limits->angle = bound;
    ball.ball_limits->restitution = e;
    Articulations art;
    std::vector<std::string> warnings;
    art.build({ball, h}, JointSettings{}, b.defs, b.model, b.state, warnings);
    ASSERT_EQ(art.mechanisms()[0].loops.size(), 1u);
    // The closed form: sweeps of 2 * bound (the first of bound), each at the speed left.
    auto angle = [&](double t) {
      double t0 = 0, q0 = 0, w = w0, span = bound;
      while (t > t0 + span / std::abs(w)) {
        t0 += span / std::abs(w);
        q0 += std::copysign(span, w);
        w = -e * w;
        span = 2 * bound;
      }
      return q0 + w * (t - t0);
    };
    double worst = 0, past = 0;
    for (int i = 1; i <= 150; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
      worst = std::max(worst, std::abs(art.position(1) - angle(i / 60.0)));
      past = std::max(past, std::abs(art.position(1)) - bound);
    }
    std::printf("ball stop e=%.1f: %ld mode changes, worst %.2e rad, past the stop %.2e rad\n", e,
                art.mechanisms()[0].events, worst, past);
    EXPECT_GE(art.mechanisms()[0].events, e == 1 ? 4 : 2);  // impacts in 2.5 s
    EXPECT_LT(worst, 1e-9);                                 // rad: impacts located to 1e-12 of a step
    EXPECT_LT(past, 1e-9);
  }
}

// The same stops between two moving bodies: the gimbal of SprungBallJointClosingAGimbalKeepsItsEnergy
// with a ball joint from the ring to the body (closing the loop the inner hinge opens) whose cone
// stop (0.4 rad about z) the body's turn about the inner hinge's y axis sweeps into, while the ring
// turns (about an axis askew to the inner one). The inner hinge's angle (the swing here) stays
// within the cone's 0.4 rad; with restitution 1 the energy holds through every impact, with 0 the
// body stays on the wall once there.
TEST(Loops, ConeStopOnAClosingBallJointKeepsTheBodyInside) {
  for (double e : {1.0, 0.0}) {
    SCOPED_TRACE(e == 1 ? "restitution 1" : "restitution 0");
    // The outer axis askew, so that the ring's turn has a part about the inner axis, which the
    // relative rate must take away.
    Gimbal gim(Vec3(1, 0.6, 0).normalized(), 0);
    Bodies& b = gim.b;
    gim.ball().ball_limits = BallLimits{};
    gim.ball().ball_limits->cone = 0.4;
    gim.ball().ball_limits->restitution = e;
    ASSERT_EQ(gim.build(), 1u);
    Articulations& art = gim.art;
    auto energy = [&] { return gim.energy(); };
    const double E0 = energy();
    double worst = 0, past = 0, reach = 0, held = 0, E_prev = E0, gained = 0;
    for (int i = 1; i <= 240; ++i) {
      ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
      const double E = energy();
      worst = std::max(worst, std::abs(E - E0));
      gained = std::max(gained, E - E_prev);
      E_prev = E;
      past = std::max(past, art.angular_gap(b.state.data()));
      reach = std::max(reach, std::abs(art.position(1)));
      if (i > 60) held = std::max(held, 0.4 - std::abs(art.position(1)));
    }
    const Mechanism& m = art.mechanisms()[0];
    std::printf(
        "cone e=%.0f: %ld mode changes, energy %.2e of E0 (largest gain in a frame %.1e), past the "
        "cone %.2e rad, off it after 1 s %.2e rad\n",
        e, m.events, worst / E0, gained / E0, past, held);
    EXPECT_GE(m.events, e == 1 ? 2 : 1);  // it struck the cone's wall
    EXPECT_LT(past, 1e-9);                // rad past the cone
    EXPECT_GT(reach, 0.35);               // at the frames; the impacts fall between them
    EXPECT_LT(reach, 0.4 + 1e-9);         // the inner hinge's angle is the swing here
    if (e == 1) {
      EXPECT_LT(worst, 1e-8 * E0);
    } else {
      // Plastic: the body comes to rest against the wall and stays there while the ring turns
      // (held by the stop's row at the acceleration level), losing energy only at its impact.
      EXPECT_LT(held, 1e-9);
      EXPECT_LT(gained, 1e-9 * E0);
    }
  }
}

}  // namespace
}  // namespace simreel
