// The moving camera (app/scene/camera_motion.hpp): a path through its keys exactly at their times,
// C1 and held outside them; an orbit's angle at known times; a damped follow against its closed
// form; and the scene keys' errors (app/scene/scene_camera.cpp), which name file, line and key.
#include "app/scene/camera_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"

namespace simreel {
namespace {

// Every channel of the camera at time t.
struct Cam {
  Vec3 eye = Vec3(8, -8, 5), target = Vec3::Zero(), up = Vec3::UnitZ();
  double fov = 40;
};
Cam at(const CameraPath& p, double t) {
  Cam c;
  p.apply(t, c.eye, c.target, c.up, c.fov);
  return c;
}

CameraPath three_keys() {
  CameraKey a, b, c;
  a.t = 0.5, a.position = Vec3(4, 0, 2), a.look_at = Vec3(0, 0, 0), a.fov = 30;
  b.t = 1.5, b.position = Vec3(0, 5, 3);  // no fov: interpolated between its neighbours' keys
  c.t = 4.0, c.position = Vec3(-6, 1, 1), c.look_at = Vec3(0, 0, 1), c.fov = 50;
  return CameraPath({a, b, c});
}

TEST(CameraPath, PassesThroughEachKeyExactlyAtItsTimeAndHoldsOutside) {
  const CameraPath p = three_keys();
  for (const CameraKey& k : p.keys()) {
    const Cam c = at(p, k.t);
    if (k.position) {
      EXPECT_EQ(c.eye, *k.position) << "t = " << k.t;  // bit for bit
    }
    if (k.look_at) {
      EXPECT_EQ(c.target, *k.look_at) << "t = " << k.t;
    }
    if (k.fov) {
      EXPECT_EQ(c.fov, *k.fov) << "t = " << k.t;
    }
  }
  // Before the first key and after the last: held.
  for (double t : {-3.0, 0.0, 0.49999}) {
    EXPECT_EQ(at(p, t).eye, Vec3(4, 0, 2)) << t;
    EXPECT_EQ(at(p, t).fov, 30) << t;
  }
  for (double t : {4.0, 4.00001, 100.0}) {
    EXPECT_EQ(at(p, t).eye, Vec3(-6, 1, 1)) << t;
    EXPECT_EQ(at(p, t).target, Vec3(0, 0, 1)) << t;
  }
  // No key gives `up`: the camera block's.
  EXPECT_EQ(at(p, 2.0).up, Vec3::UnitZ());
  // fov runs through the keys that give it only: the middle key does not pin it.
  EXPECT_GT(at(p, 1.5).fov, 30);
  EXPECT_LT(at(p, 1.5).fov, 50);
}

TEST(CameraPath, IsC1AtTheKeysAndEasesIntoTheHolds) {
  const CameraPath p = three_keys();
  const double h = 1e-6;
  auto velocity = [&](double t0, double t1) { return Vec3((at(p, t1).eye - at(p, t0).eye) / (t1 - t0)); };
  // At the inner key the velocity from either side is the same, and it is the parabola's through
  // the key's neighbours (not zero: the camera does not stop at a key).
  const Vec3 d0 = (Vec3(0, 5, 3) - Vec3(4, 0, 2)) / 1.0, d1 = (Vec3(-6, 1, 1) - Vec3(0, 5, 3)) / 2.5;
  const Vec3 expect = (2.5 * d0 + 1.0 * d1) / 3.5;
  const Vec3 left = velocity(1.5 - h, 1.5), right = velocity(1.5, 1.5 + h);
  EXPECT_LT((left - right).norm(), 1e-4) << left.transpose() << " | " << right.transpose();
  EXPECT_LT((right - expect).norm(), 1e-4) << right.transpose() << " vs " << expect.transpose();
  EXPECT_GT(expect.norm(), 1.0);
  // At the end keys the velocity is zero on both sides: the hold joins smoothly.
  EXPECT_LT(velocity(0.5, 0.5 + h).norm(), 1e-4);
  EXPECT_LT(velocity(4.0 - h, 4.0).norm(), 1e-4);
  // No jump anywhere: over a fine grid the steps stay small (continuity).
  double worst = 0;
  for (double t = 0.4; t < 4.1; t += 1e-3)
    worst = std::max(worst, (at(p, t + 1e-3).eye - at(p, t).eye).norm());
  EXPECT_LT(worst, 0.02);
}

TEST(CameraOrbit, AngleAtKnownTimes) {
  CameraOrbit o;
  o.radius = 3, o.height = 1.5, o.rate = 2 * M_PI / 8, o.start_angle = M_PI / 6;  // a turn in 8 s
  const Vec3 c(1, 2, 0.5);
  for (double t : {0.0, 1.0, 2.0, 5.5, 8.0}) {
    const Vec3 e = o.eye(t, c) - c;
    const double a = M_PI / 6 + 2 * M_PI * t / 8;
    EXPECT_NEAR(e.x(), 3 * std::cos(a), 1e-12) << t;
    EXPECT_NEAR(e.y(), 3 * std::sin(a), 1e-12) << t;
    EXPECT_EQ(e.z(), 1.5);
  }
  // A quarter turn after 2 s: from 30 degrees to 120.
  EXPECT_NEAR(std::atan2((o.eye(2, c) - c).y(), (o.eye(2, c) - c).x()) * 180 / M_PI, 120, 1e-10);
}

// A body at constant velocity u, followed from rest on it: x(t) = p0 + u t - 2 u tau
// + (2 u tau + u t) e^(-t / tau), since the step solves the filter exactly for a target linear
// between steps. After a few time constants the lag is 2 u tau: the rigid follow shifted back.
TEST(DampedFollow, MatchesTheClosedFormAndLagsAConstantVelocityBodyBy2UTau) {
  const double tau = 0.4, dt = 1.0 / 240;
  const Vec3 p0(1, -2, 0.5), u(3, 1, -0.5);
  DampedFollow f(tau);
  double worst = 0;
  for (long k = 0; k <= 2400; ++k) {
    const double t = k * dt;
    f.track(k, t, p0 + u * t);
    const Vec3 x = p0 + u * t - 2 * u * tau + (2 * u * tau + u * t) * std::exp(-t / tau);
    worst = std::max(worst, (f.position() - x).norm());
  }
  EXPECT_LT(worst, 1e-12);
  const double t = 2400 * dt;  // 25 time constants
  EXPECT_LT(((p0 + u * t) - f.position() - 2 * u * tau).norm(), 1e-8);
  EXPECT_LT((f.velocity() - u).norm(), 1e-8);
  // A step seen twice is taken once.
  const Vec3 before = f.position();
  f.track(2400, t, p0 + u * t + Vec3(100, 0, 0));
  EXPECT_EQ(f.position(), before);
}

// The same filter at other time steps: the state at a time does not depend on the step (exact
// for a linear target), so a body's damped camera is the same at 1/60 and 1/960 s.
TEST(DampedFollow, IndependentOfTheStepForALinearTarget) {
  auto run = [](double dt, double until) {
    DampedFollow f(0.25);
    const long n = std::lround(until / dt);
    for (long k = 0; k <= n; ++k) f.track(k, k * dt, Vec3(2 * k * dt, 0, 0));
    return f.position();
  };
  EXPECT_LT((run(1.0 / 60, 1.0) - run(1.0 / 960, 1.0)).norm(), 1e-12);
}

// ---- The scene keys.

const char* kBodies =
    "bodies:\n"
    "  - { name: ball, colliders: [ { shape: sphere, radius: 0.5 } ] }\n"
    "  - { name: box, position: [2, 0, 0], colliders: [ { shape: box, size: [1, 1, 1] } ] }\n";

Scene load(const std::string& camera, const std::string& render = "") {
  return load_scene_text("simulation: { duration: 5 }\n" + camera + render + kBodies, "cam.yaml");
}

std::string error_of(const std::string& camera, const std::string& render = "") {
  try {
    load(camera, render);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneCamera, PathOrbitFollowAndBlurKeys) {
  const Scene s = load(
      "camera:\n"
      "  position: [6, 0, 2]\n"
      "  path:\n"
      "    - { t: 0, position: [4, 0, 2], fov: 30 }\n"
      "    - { t: 2, look_at: [0, 0, 1] }\n",
      "render: { motion_blur: { samples: 6, shutter: 0.25 } }\n");
  ASSERT_EQ(s.camera.path.keys().size(), 2u);
  EXPECT_EQ(*s.camera.path.keys()[0].position, Vec3(4, 0, 2));
  EXPECT_FALSE(s.camera.path.keys()[1].position);
  EXPECT_EQ(s.motion_blur.samples, 6);
  EXPECT_EQ(s.motion_blur.shutter, 0.25);
  // An orbit starts where the camera block puts the camera, unless told otherwise.
  const Scene o = load("camera: { position: [0, 4, 3], look_at: [0, 0, 1], orbit: { period: 10 } }\n");
  ASSERT_TRUE(o.camera.orbit);
  EXPECT_DOUBLE_EQ(o.camera.orbit->radius, 4);
  EXPECT_DOUBLE_EQ(o.camera.orbit->height, 2);
  EXPECT_DOUBLE_EQ(o.camera.orbit->start_angle, M_PI / 2);
  EXPECT_DOUBLE_EQ(o.camera.orbit->rate, 2 * M_PI / 10);
  EXPECT_EQ(o.camera.orbit->center, Vec3(0, 0, 1));
  EXPECT_LT((o.camera.orbit->eye(0, o.camera.orbit->center) - Vec3(0, 4, 3)).norm(), 1e-12);
  const Scene b = load(
      "camera: { orbit: { body: box, radius: 5, height: 2, degrees_per_second: -30, start_angle: 90 } }\n");
  EXPECT_EQ(b.camera.orbit->body, "box");
  EXPECT_DOUBLE_EQ(b.camera.orbit->rate, -M_PI / 6);
  // follow: the plain name, or a mapping with a damping.
  const Scene f = load("camera: { follow: { body: ball, damping: 0.5 } }\n");
  EXPECT_EQ(f.camera.follow, "ball");
  EXPECT_EQ(f.camera.follow_damping, 0.5);
  EXPECT_EQ(load("camera: { follow: ball }\n").camera.follow_damping, 0);
}

TEST(SceneCamera, ErrorsNameFileLineAndKey) {
  struct Case {
    std::string camera, render, message;
  };
  const std::vector<Case> cases = {
      {"camera:\n  path:\n    - { t: 1, position: [1, 0, 0] }\n    - { t: 1, position: [2, 0, 0] }\n", "",
       "cam.yaml:5:12: camera.path[1].t: another key is already at t = 1 s"},
      {"camera:\n  path:\n    - { t: 2, position: [1, 0, 0] }\n    - { t: 1, position: [2, 0, 0] }\n", "",
       "cam.yaml:5:12: camera.path[1].t: t = 1 s is before the previous key's (2 s): keys go in time order"},
      {"camera:\n  path:\n    - { t: 0, positon: [1, 0, 0] }\n", "",
       "cam.yaml:4:15: camera.path[0].positon: unknown key 'positon'; did you mean 'position'?"},
      {"camera:\n  path:\n    - { position: [1, 0, 0] }\n", "", "cam.yaml:4:7: camera.path[0]: needs 't'"},
      {"camera:\n  path:\n    - { t: 0 }\n", "", "cam.yaml:4:7: camera.path[0]: gives none of position"},
      {"camera:\n  path:\n    - { t: 0, fov: 200 }\n", "",
       "cam.yaml:4:20: camera.path[0].fov: must be below 179 degrees"},
      {"camera:\n  path:\n    - { t: 0, position: [0, 0, 0] }\n", "",
       "cam.yaml:4:7: camera.path[0]: the camera's position reaches its look_at"},
      // The spline from +x to -x through the target's position: caught between the keys.
      {"camera:\n  look_at: [0, 0, 0]\n  path:\n    - { t: 0, position: [4, 0, 0] }\n"
       "    - { t: 2, position: [-4, 0, 0] }\n",
       "", "cam.yaml:5:7: camera.path[0]: between this key and the next, at t = 1 s"},
      {"camera:\n  follow: ball\n  path: [{ t: 0, position: [1, 0, 0] }]\n", "",
       "cam.yaml:3:11: camera.follow: a camera on a path does not also follow a body"},
      {"camera:\n  auto: true\n  orbit: { period: 4 }\n", "",
       "cam.yaml:3:9: camera.auto: camera.auto places a still camera; camera.orbit moves it: give one"},
      {"camera:\n  orbit: { period: 4 }\n  path: [{ t: 0, position: [1, 0, 0] }]\n", "",
       "cam.yaml:3:10: camera.orbit: a camera on a path does not also orbit"},
      {"camera:\n  orbit: { radius: 4 }\n", "",
       "cam.yaml:3:10: camera.orbit: needs period (s a turn) or degrees_per_second"},
      {"camera:\n  orbit: { body: bal, period: 3 }\n", "",
       "cam.yaml:3:18: camera.orbit.body: no body is named 'bal'; did you mean 'ball'?"},
      {"camera:\n  orbit: { body: ball, center: [0, 0, 0], period: 3 }\n", "",
       "cam.yaml:3:18: camera.orbit.body: an orbit circles a point (center) or a body: give one"},
      {"camera:\n  orbit: { period: 0 }\n", "", "cam.yaml:3:20: camera.orbit.period: must not be zero"},
      {"camera:\n  frame: { body: box }\n  orbit: { period: 3 }\n", "",
       "cam.yaml:3:10: camera.frame: an orbit circles a point or a body in the world"},
      {"camera:\n  follow: { damping: 1 }\n", "", "cam.yaml:3:11: camera.follow: needs 'body'"},
      {"camera:\n  follow: { body: ball, damping: -1 }\n", "",
       "cam.yaml:3:34: camera.follow.damping: must not be negative"},
      {"camera:\n  follow: { body: ball, dampnig: 1 }\n", "",
       "cam.yaml:3:25: camera.follow.dampnig: unknown key 'dampnig'; did you mean 'damping'?"},
      {"", "render: { motion_blur: { samples: 0 } }\n",
       "cam.yaml:2:35: render.motion_blur.samples: expected a whole number from 1 to 64"},
      {"", "render: { motion_blur: { samples: 4, shutter: 1.5 } }\n",
       "cam.yaml:2:47: render.motion_blur.shutter: must lie in (0, 1]"},
      {"", "render: { motion_blur: { sample: 4 } }\n",
       "cam.yaml:2:26: render.motion_blur.sample: unknown key 'sample'; did you mean 'samples'?"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.camera, c.render);
    EXPECT_EQ(e.rfind(c.message, 0), 0u) << "got:      " << e << "\nexpected: " << c.message;
  }
}

}  // namespace
}  // namespace simreel
