// camera.aim: the camera stays where it stands and turns to its bodies' centre of mass at every
// frame, so a ball flying across the view stays at the picture's centre; without aim it leaves it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <simreel/error.hpp>

#include "app/runner/frame_loop.hpp"
#include "app/view/scene_view.hpp"
#include "render/image.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

using test::scratch;
constexpr int kW = 160, kH = 120;

// The centre (px from the top left) of the red pixels of the frame drawn at time t.
Vec3 red_centre(const std::string& camera, double t) {
  const std::string yaml =
      "simulation: { duration: 2, gravity: [0, 0, 0] }\n"
      "video: { width: 160, height: 120, fps: 30 }\n"
      "camera: " +
      camera +
      "\n"
      "render: { shadows: false, antialiasing: none }\n"
      "bodies:\n"
      "  - { name: ball, color: [1, 0, 0], position: [0, 0, 1], linear_velocity: [2, 0, 0.5],\n"
      "      colliders: [ { shape: sphere, radius: 0.2 } ] }\n";
  const Scene sc = load_scene_text(yaml, scratch("aim.yaml"));
  FrameLoop loop(sc, 1);
  SceneView view(sc, loop.world(), ViewOptions{});
  Renderer r(view.settings, view.meshes);
  while (loop.world().time() < t - 1e-9) loop.world().step();
  const uint8_t* px = view.draw(r, loop.world());
  double sx = 0, sy = 0, n = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const uint8_t* p = px + ((size_t)y * kW + x) * 4;
      if (p[0] > 2 * p[1] + 20 && p[0] > 2 * p[2] + 20) sx += x + 0.5, sy += y + 0.5, n += 1;
    }
  return n > 0 ? Vec3(sx / n, sy / n, n) : Vec3(-1, -1, 0);
}

TEST(CameraAim, TurnsToTheBodyFromWhereItStands) {
  // At 1 s the ball is at (2, 0, 1.5): 2 m right of where the camera first looked, from 6 m.
  const std::string aimed = "{ position: [0, -6, 1], look_at: [0, 0, 1], fov: 30, aim: ball }";
  for (double t : {0.0, 1.0}) {
    const Vec3 c = red_centre(aimed, t);
    std::printf("aimed, t = %.0f s: ball at (%.2f, %.2f) px, %.0f px\n", t, c.x(), c.y(), c.z());
    ASSERT_GT(c.z(), 20);
    EXPECT_NEAR(c.x(), kW / 2.0, 0.5) << t;  // a symmetric disc's centroid sits on the image centre
    EXPECT_NEAR(c.y(), kH / 2.0, 0.5) << t;
  }
  // Without aim it leaves the centre: tan(atan(2 / 6)) / tan(15 deg) of the half-height, right.
  const Vec3 c = red_centre("{ position: [0, -6, 1], look_at: [0, 0, 1], fov: 30 }", 1.0);
  EXPECT_GT(c.x(), kW / 2.0 + 0.5 * kH / 2.0 * (2.0 / 6) / std::tan(15 * M_PI / 180));
}

TEST(CameraAim, KeysAndMistakes) {
  auto load = [](const std::string& camera) {
    return load_scene_text(
        "camera: " + camera +
            "\nbodies:\n  - { name: a, colliders: [ { shape: sphere, radius: 0.1 } ] }\n"
            "  - { name: b, position: [1, 0, 0], colliders: [ { shape: sphere, radius: 0.1 } ] }\n",
        scratch("aimkeys.yaml"));
  };
  EXPECT_EQ(load("{ aim: a }").camera.aim, std::vector<std::string>{"a"});
  EXPECT_EQ(load("{ aim: [a, b] }").camera.aim, (std::vector<std::string>{"a", "b"}));
  auto error = [&](const std::string& camera) {
    try {
      load(camera);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("{ aim: [a, c] }").find("camera.aim[1]: no body is named 'c'"), std::string::npos);
  EXPECT_NE(error("{ aim: a, follow: b }").find("camera.aim"), std::string::npos);
  EXPECT_NE(error("{ aim: a, orbit: { radius: 2, period: 5 } }").find("give one of orbit, aim"),
            std::string::npos);
  EXPECT_NE(error("{ aim: a, path: [ { t: 0, look_at: [0, 0, 1] } ] }").find("camera.path[0].look_at"),
            std::string::npos);
  EXPECT_NE(error("{ aim: {} }").find("expected a body name or a list of them"), std::string::npos);
}

}  // namespace
}  // namespace simreel
