// `place:` (app/scene/scene_place.cpp): bodies resting on a face where the file says, touching it,
// turned with it; a start state turned about a point; and the errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <string>

#include "app/runner/frame_loop.hpp"
#include "app/scene/scene.hpp"
#include "tests/app/scene/scene_error.hpp"

namespace simreel {
namespace {

constexpr double kPi = std::numbers::pi;

std::string error_of(const std::string& text) {
  return test::scene_error(text, "place.yaml");
}

// scenes/ramp_race.yaml: a 3 m x 1.3 m x 0.1 m ramp pitched 15 degrees about y, centred at
// (0, 0, 0.55); each racer 0.3 m below the face's upper edge. The face's normal is
// n = (sin 15, 0, cos 15), its centre 0.05 m along n from the ramp's, its downhill direction
// d = (cos 15, 0, -sin 15), its upper edge 1.5 m up from the centre.
TEST(Place, RacersRestOnTheRampWhereTheFileSays) {
  const Scene s = load_scene("scenes/ramp_race.yaml");
  const double th = 15 * kPi / 180;
  const Vec3 n(std::sin(th), 0, std::cos(th)), d(std::cos(th), 0, -std::sin(th));
  const Vec3 face = Vec3(0, 0, 0.55) + 0.05 * n;
  const Vec3 spot = face + (0.3 - 1.5) * d;  // on the face's centre line
  auto index = [&](const std::string& name) {
    for (size_t i = 0; i < s.bodies.size(); ++i)
      if (s.bodies[i].name == name) return (int)i;
    return -1;
  };
  // The ball: its centre one radius along n from the spot, moved -0.48 m across (y).
  const BodyDef& ball = s.bodies[index("ball")];
  EXPECT_NEAR((ball.p_WB - (spot + 0.08 * n + Vec3(0, -0.48, 0))).norm(), 0, 1e-12);
  // The box (0.16 m cube): its bottom face on the ramp's, turned with it (its z along n).
  const BodyDef& box = s.bodies[index("box")];
  EXPECT_NEAR((box.p_WB - (spot + 0.08 * n + Vec3(0, 0.48, 0))).norm(), 0, 1e-12);
  EXPECT_NEAR((box.q_WB * Vec3::UnitZ() - n).norm(), 0, 1e-12);
  EXPECT_NEAR((box.q_WB * Vec3::UnitX() - d).norm(), 0, 1e-12);
  // The cylinder lies with its axis across the slope, its rim on the face.
  const BodyDef& cyl = s.bodies[index("cylinder")];
  EXPECT_NEAR((cyl.p_WB - (spot + 0.08 * n + Vec3(0, -0.16, 0))).norm(), 0, 1e-12);
}

// Placed where the closed forms start (at rest, touching), the racers speed up at
// g sin(theta) / (1 + I / (m r^2)) rolling, and the box at g (sin - mu cos) sliding: at t = 1 s
// within 2e-4 (the contact's soft position correction settles the first steps; measured 5e-5).
TEST(Place, TheRampRaceFollowsTheClosedForms) {
  const Scene s = load_scene("scenes/ramp_race.yaml");
  FrameLoop loop(s, 1);
  std::vector<FrameTarget> t{{0, 0, std::lround(1.0 / s.timestep)}};
  loop.run(t, {}, false);
  const World& w = loop.world();
  const double g = 9.81, sn = std::sin(15 * kPi / 180), cs = std::cos(15 * kPi / 180);
  const struct {
    const char* name;
    double a;
  } racers[] = {{"ball", 5.0 / 7 * g * sn},
                {"cylinder", 2.0 / 3 * g * sn},
                {"hoop", 0.5 * g * sn},
                {"box", g * (sn - 0.2 * cs)}};
  for (const auto& r : racers) {
    int i = 0;
    while (i < w.body_count() && w.def(i).name != r.name) ++i;
    ASSERT_LT(i, w.body_count()) << r.name;
    EXPECT_NEAR(w.linear_velocity(i).norm() / (r.a * w.time()), 1.0, 2e-4) << r.name;
  }
}

// `about` turns the whole start state rigidly: a bob hanging 1 m under a pivot, turned 30 degrees
// about the pivot's y axis, sits at (sin 30, 0, -cos 30) from it, turned 30 degrees itself, and its
// velocity turns with it.
TEST(Place, AboutTurnsTheStartStateAboutAPoint) {
  const Scene s = load_scene_text(
      "bodies:\n"
      "  - { name: bob, position: [0, 0, 1], linear_velocity: [1, 0, 0],\n"
      "      place: { about: [0, 0, 2], axis: [0, 1, 0], angle: 30 },\n"
      "      colliders: [ { shape: sphere, radius: 0.1 } ] }\n",
      "about.yaml");
  const BodyDef& b = s.bodies[0];
  const double a = 30 * kPi / 180;
  EXPECT_NEAR((b.p_WB - Vec3(-std::sin(a), 0, 2 - std::cos(a))).norm(), 0, 1e-12)
      << "turning +30 about +y moves the bob towards -x";
  EXPECT_NEAR(b.q_WB.angularDistance(Quat(Eigen::AngleAxisd(a, Vec3::UnitY()))), 0, 1e-12);
  EXPECT_NEAR((b.v_W - Vec3(std::cos(a), 0, -std::sin(a))).norm(), 0, 1e-12);
}

TEST(Place, ErrorsNameTheProblem) {
  const std::string base =
      "bodies:\n"
      "  - { name: table, type: static, position: [0, 0, 0.5], colliders: [ { shape: box, size: [1, 1, 0.1] "
      "} ] }\n"
      "  - { name: ball, type: static, colliders: [ { shape: sphere, radius: 0.1 } ] }\n";
  auto with = [&](const std::string& place) {
    return error_of(base + "  - { name: cup, place: " + place +
                    ", colliders: [ { shape: sphere, radius: 0.05 } ] }\n");
  };
  EXPECT_NE(with("{ on: tabel }").find("no body is named 'tabel'; did you mean 'table'?"), std::string::npos);
  EXPECT_NE(with("{ on: ball }").find("has no box or plane collider to rest on"), std::string::npos);
  EXPECT_NE(with("{ on: table, at: 0.2 }").find("on a level face or a plane, 'at' is [along, across]"),
            std::string::npos);
  EXPECT_NE(with("{ on: cup }").find("cannot rest on itself"), std::string::npos);
  EXPECT_NE(with("{ about: [0, 0, 0], angle: 30 }").find("needs 'axis' and 'angle'"), std::string::npos);
  EXPECT_NE(with("{ on: table, height: 2 }").find("unknown key 'height'"), std::string::npos);
  EXPECT_NE(with("{ on: tabel }").find("place.yaml:4:"), std::string::npos) << with("{ on: tabel }");
  // On a level face, [along, across] from its centre: the cup's centre 0.05 m over the top.
  const Scene s = load_scene_text(base +
                                      "  - { name: cup, place: { on: table, at: [0.2, -0.1] }, "
                                      "colliders: [ { shape: sphere, radius: 0.05 } ] }\n",
                                  "level.yaml");
  const Vec3 p = s.bodies[2].p_WB;
  EXPECT_NEAR(p.z(), 0.55 + 0.05, 1e-12);
  EXPECT_NEAR(std::hypot(p.x(), p.y()), std::hypot(0.2, 0.1), 1e-12);
}

}  // namespace
}  // namespace simreel
