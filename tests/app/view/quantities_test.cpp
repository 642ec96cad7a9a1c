// HUD expressions and values measured over the physics steps (app/scene/hud_expr.cpp,
// app/view/quantities.cpp), each against a closed form of the motion it reads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "app/runner/frame_loop.hpp"
#include "app/view/quantities.hpp"
#include "tests/app/scene/scene_error.hpp"
#include "tests/app/view/overlay_fixtures.hpp"

namespace simreel {
namespace {

constexpr double kG = 9.81;

// Two balls in free space meeting head-on (scenes/momentum.yaml's numbers) with a HUD of expressions.
std::string collision_scene(const std::string& hud) {
  return "simulation: { duration: 2.4, timestep: 0.004166666666666667, gravity: [0, 0, 0] }\n"
         "bodies:\n"
         "  - { name: a, position: [-1.5, 0, 0], linear_velocity: [2, 0, 0],\n"
         "      colliders: [ { shape: sphere, radius: 0.2, mass: 1, friction: 0, restitution: 1 } ] }\n"
         "  - { name: b, position: [1.1, 0, 0], linear_velocity: [-0.5, 0, 0],\n"
         "      colliders: [ { shape: sphere, radius: 0.288, mass: 3, friction: 0, restitution: 1 } ] }\n"
         "overlays: { hud: [" +
         hud + "] }\n";
}

// A ball thrown straight up at 4.905 m/s from 2 m over a floor (it lands after the top).
std::string throw_scene(const std::string& hud) {
  return "simulation: { duration: 2.0, timestep: 0.004166666666666667, gravity: [0, 0, -9.81] }\n"
         "bodies:\n"
         "  - { name: floor, type: static, colliders: [ { shape: box, size: [6, 6, 0.2] } ],\n"
         "      position: [0, 0, -0.1] }\n"
         "  - { name: ball, position: [0, 0, 2], linear_velocity: [0, 0, 4.905],\n"
         "      colliders: [ { shape: sphere, radius: 0.1, mass: 1, restitution: 0 } ] }\n"
         "overlays: { hud: [" +
         hud + "] }\n";
}

// The HUD's fields of `scene` evaluated with meters recorded over every step up to time t.
struct Stepped {
  Scene scene;
  FrameLoop loop;
  StepMeters meters;
  bool recording = true;
  explicit Stepped(const std::string& text) : scene(load_scene_text(text, "q.yaml")), loop(scene, 1) {
    const World& w = loop.world();
    meters.set_reference(w.kinetic_energy() + w.potential_energy(), w.total_angular_momentum());
    for (const HudLine& l : scene.overlays.hud)
      for (const HudField& f : l.fields) meters.track(f, scene.timestep);
  }
  void to(double t) {
    FrameLoop::Hooks h;
    h.step = [&](const World& w) {
      if (recording) meters.record(w);
    };
    std::vector<FrameTarget> target{{0, 0, std::lround(t / scene.timestep)}};
    loop.run(target, h, false);
  }
  double value(int line, int field = 0) const {
    return quantity_value(scene.overlays.hud[line].fields[field], loop.world(), 0, 0, Vec3::Zero(), 0,
                          &meters);
  }
};

// {a.m * a.v.x + b.m * b.v.x} is the total momentum 1 x 2 + 3 x (-0.5) = 0.5 kg m/s before and
// after the elastic collision (to the contact solver's round-off); a's velocity after is the closed
// form -1.75 m/s; |a.v|, KE and arithmetic read as written.
TEST(HudExpressions, ArithmeticOverQuantities) {
  Stepped r(collision_scene(
      "'{a.m * a.v.x + b.m * b.v.x:.3f}', '{|a.v|}', '{a.KE + b.KE}', '{2^3^2 - -1}', '{(1 + 2) * 3 / 4}', "
      "'{deg(atan2(1, 1))}', '{sqrt(b.m) * a.v.x}'"));
  ASSERT_TRUE(r.scene.overlays.hud[0].fields[0].is_expr());
  std::string out;
  format_hud_line(r.scene.overlays.hud[0], r.loop.world(), 0, 0, Vec3::Zero(), out);
  EXPECT_EQ(out, "0.500");
  EXPECT_NEAR(r.value(1), 2.0, 1e-12);
  EXPECT_NEAR(r.value(2), 0.5 * 4 + 0.5 * 3 * 0.25, 1e-12) << "kinetic energies, 2.375 J";
  EXPECT_EQ(r.value(3), 513.0) << "^ is right-associative, binary minus of a negation";
  EXPECT_EQ(r.value(4), 2.25);
  EXPECT_NEAR(r.value(5), 45.0, 1e-12);
  EXPECT_NEAR(r.value(6), std::sqrt(3.0) * 2, 1e-12);
  r.to(2.4);
  EXPECT_NEAR(r.value(0), 0.5, 1e-9);
  EXPECT_NEAR(r.value(1), 1.75, 1e-9) << "|v_a'| = |(m_a - m_b) v_a + 2 m_b v_b| / (m_a + m_b)";
  EXPECT_NEAR(r.value(2), 2.375, 1e-9) << "elastic: the kinetic energy kept";
}

// Values measured over the steps, against the motion's closed form. The ball thrown up at
// v0 = 4.905 m/s from z0 = 2 m: v_z = v0 - g t is zero at t = v0 / g = 0.5 s (linear: linear
// interpolation is exact, up to the integrator's round-off); the time average of z since the throw,
// z0 + v0 t / 2 - g t^2 / 6, at t = 0.9 s (the trapezoid rule's error on a parabola, g h^2 / 12,
// is 1.4e-5 m); the average of v_z over the last 0.25 s, v0 - g (t - 0.125), exact for a linear
// v_z; first contact with the floor when z = r: z0 + v0 t - g t^2 / 2 = 0.1, t = 1.1612 s, read
// within a physics step.
TEST(HudExpressions, MeasuredValuesOfAThrow) {
  Stepped r(throw_scene(
      "'{last_zero(ball.v.z)}', '{mean(ball.position.z)}', '{mean(ball.v.z, 0.25)}', "
      "'{first_contact(ball)}', '{first_contact(ball, floor)}', '{first_contact}', '{mean(ball.v.z)}'"));
  const double v0 = 4.905, z0 = 2, h = r.scene.timestep;
  EXPECT_TRUE(std::isnan(r.value(0))) << "not known before v_z changes sign";
  r.to(0.3);
  EXPECT_TRUE(std::isnan(r.value(0)));
  EXPECT_NEAR(r.value(2), v0 - kG * (0.3 - 0.125), 1e-9);
  EXPECT_NEAR(r.value(6), v0 - kG * 0.3 / 2, 1e-9) << "mean since t = 0 of a linear v_z";
  r.to(0.9);
  EXPECT_NEAR(r.value(0), v0 / kG, 1e-9);
  EXPECT_NEAR(r.value(1), z0 + v0 * 0.9 / 2 - kG * 0.81 / 6, kG * h * h / 12 + 1e-9);
  EXPECT_NEAR(r.value(2), v0 - kG * (0.9 - 0.125), 1e-9);
  EXPECT_TRUE(std::isnan(r.value(3))) << "no contact yet";
  r.to(2.0);
  const double t_hit = (v0 + std::sqrt(v0 * v0 + 2 * kG * (z0 - 0.1))) / kG;
  for (int k : {3, 4, 5}) {
    EXPECT_NEAR(r.value(k), t_hit, h) << k;
  }
  EXPECT_GE(r.value(0), t_hit - 2 * h) << "the latest zero of v_z is now where the ball stopped on the floor";
}

// period(q) of a quantity that is not a joint coordinate (here the angle in degrees, measured as
// any expression is, from its samples): the compound pendulum's elliptic period T = 2.732730 s
// (tests/app/view/overlays_screen_test.cpp derives it); the parabola's vertex through three steps places each
// turn to O(h^2): within 2e-5 s here. period(joint.angle) is the joint's exact-rate measure.
TEST(HudExpressions, PeriodOfAnyQuantity) {
  std::string text = slurp("scenes/pendulum.yaml");
  const size_t at = text.find("    lines:\n");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 11,
              "      - \"{period(deg(pivot.angle))}\"\n      - \"{period(pivot.angle)}\"\n"
              "      - \"{mean(deg(pivot.angle), 2.7327)}\"\n");
  Stepped r(text);
  EXPECT_EQ(r.scene.overlays.hud[1].fields[0].name, "period") << "a joint's angle: the joint's own meter";
  r.to(1.5);
  EXPECT_TRUE(std::isnan(r.value(0)));
  r.to(9.0);
  EXPECT_NEAR(r.value(0), 2.732730, 2e-5);
  EXPECT_NEAR(r.value(1), 2.732730, 1e-6);
  EXPECT_NEAR(r.value(2), -120.0, 0.05) << "the swing from release, 0 to -240 deg: its mean over a period";
}

// A render that resumes mid-clip restores what the meters gathered: the values after equal a
// straight run's bit for bit.
TEST(HudExpressions, MetersResumeExactly) {
  const std::string text = throw_scene(
      "'{mean(ball.position.z)}', '{mean(ball.v.z, 0.25)}', "
      "'{last_zero(ball.v.z - 1)}', '{period(ball.position.z)}'");
  Stepped straight(text);
  straight.to(1.5);
  Stepped first(text);
  first.to(0.7);
  std::stringstream ss;
  first.meters.save(ss);
  Stepped second(text);
  second.recording = false;  // the steps before 0.7 s are not seen: their history comes from `first`
  second.to(0.7);
  second.meters.restore(ss);
  second.recording = true;
  second.to(1.5);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(second.value(k), straight.value(k)) << k;
}

// Bad expressions are refused at load with what is wrong.
TEST(HudExpressions, ErrorsSayWhatIsWrong) {
  auto message = [](const std::string& hud) { return test::scene_error(collision_scene(hud), "e.yaml"); };
  EXPECT_NE(message("'{a.v * 2}'").find("'a.v' is a vector: take a component (a.v.x) or its length |a.v|"),
            std::string::npos);
  EXPECT_NE(message("'{sqr(a.m)}'").find("unknown function 'sqr'; did you mean 'sqrt'?"), std::string::npos);
  EXPECT_NE(message("'{mean(mean(a.v.x))}'").find("already measured"), std::string::npos);
  EXPECT_NE(message("'{mean(a.v.x, -1)}'").find("a number of seconds > 0"), std::string::npos);
  EXPECT_NE(message("'{mean(frame)}'").find("no video frame"), std::string::npos);
  EXPECT_NE(message("'{(a.m + 1}'").find("a '(' without its ')'"), std::string::npos);
  EXPECT_NE(message("'{a.m +}'").find("ends where a value was expected"), std::string::npos);
  EXPECT_NE(message("'{first_contact(c)}'").find("no body is named 'c'"), std::string::npos);
  EXPECT_NE(message("'{a.mass * 2}'").find("unknown quantity 'mass'"), std::string::npos);
  EXPECT_NE(message("'{a.m:d}'").find("is not [+][width][.precision][f|e|g]"), std::string::npos);
  EXPECT_NE(message("'{sqrt}'").find("'sqrt' is a function: write sqrt(x)"), std::string::npos);
  EXPECT_NE(message("'{sqrt(1, 2)}'").find("sqrt(...) takes 1 argument, got 2"), std::string::npos);
  // Nesting is bounded (the parser recurses): a hostile line is an error, not a stack overflow.
  EXPECT_NE(message("'{" + std::string(100, '(') + "1" + std::string(100, ')') + "}'")
                .find("nested more than 64 deep"),
            std::string::npos);
  EXPECT_EQ(message("'{" + std::string(60, '(') + "1" + std::string(60, ')') + "}'"), "no error");
  // A line and column point at the HUD line.
  EXPECT_NE(message("'{a.v * 2}'").find("e.yaml:7:"), std::string::npos) << message("'{a.v * 2}'");
}

}  // namespace
}  // namespace simreel
