// Shared by the overlay tests: a scene drawn as the render and check commands draw it,
// stepped to any frame, and pixel helpers.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "app/runner/frame_loop.hpp"
#include "app/view/overlays.hpp"
#include "app/view/scene_view.hpp"
#include "render/camera.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

inline std::string write_scene(const std::string& name, const std::string& text) {
  return test::scratch_file(name, text);
}

inline int run(const std::string& args, const std::string& env = "") {
  const std::string cmd =
      (env.empty() ? "" : "env " + env + " ") + std::string(SIMREEL_BIN) + " " + args + " > /dev/null 2>&1";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// A scene drawn as the commands draw it, stepped to any moment with the step hook in place.
struct Drawn {
  Scene scene;
  std::unique_ptr<FrameLoop> loop;
  std::unique_ptr<SceneView> view;
  std::unique_ptr<Renderer> renderer;
  std::vector<uint8_t> frame;
  Drawn(const std::string& path, const std::string& aa = "none") : scene(load_scene(path)) {
    loop = std::make_unique<FrameLoop>(scene, 1);
    ViewOptions o;
    o.aa = aa;
    view = std::make_unique<SceneView>(scene, loop->world(), o);
    renderer = std::make_unique<Renderer>(view->settings, view->meshes);
  }
  int w() const { return view->settings.width; }
  int h() const { return view->settings.height; }
  // Frame k of the plan (k = -1: the present state), drawn.
  const std::vector<uint8_t>& draw_frame(long k) {
    FrameLoop::Hooks hooks;
    hooks.step = view->step_hook();
    hooks.frame = [&](const FrameTarget& t, const World& world) {
      const uint8_t* px = view->draw(*renderer, world, nullptr, t.index);
      frame.assign(px, px + (size_t)w() * h() * 4);
    };
    std::vector<FrameTarget> t;
    if (k >= 0)
      t.push_back(plan_target(loop->plan(), k, scene.video.fps));
    else
      t.push_back({0, 0, loop->world().steps()});
    loop->run(t, hooks, false);
    return frame;
  }
  std::array<int, 3> px(int x, int y) const {
    const uint8_t* p = &frame[((size_t)y * w() + x) * 4];
    return {p[0], p[1], p[2]};
  }
};

// Pixels touched by a magenta or a cyan arrow (one of the 4 MSAA samples is enough), over the sky
// (sky = the frame's corner): the arrow takes green (red) away from the sky's colour and leaves
// the other two; the dark grey body takes all three.
inline std::array<int, 3> g_sky;
inline bool magenta(const std::array<int, 3>& c) {
  return c[1] < g_sky[1] * 0.92 && c[0] > g_sky[0] * 0.75 && c[2] > g_sky[2] * 0.75;
}
inline bool cyan(const std::array<int, 3>& c) {
  return c[0] < g_sky[0] * 0.92 && c[1] > g_sky[1] * 0.75 && c[2] > g_sky[2] * 0.75;
}

// The farthest pixel of an arrow (by `is`) along its projected direction lands within a pixel of
// the projected tip, and no more than a pixel and a half to its side.
inline void expect_tip(Drawn& d, bool (*is)(const std::array<int, 3>&), const Vec3& from, const Vec3& tip,
                       const char* what) {
  const CameraView& cam = d.view->camera;
  const Eigen::Vector2d a = project_to_pixel(cam, d.w(), d.h(), from),
                        b = project_to_pixel(cam, d.w(), d.h(), tip);
  const Eigen::Vector2d dir = (b - a).normalized(), side(-dir.y(), dir.x());
  double best = -1e9, lateral = 0;
  int count = 0;
  for (int y = 0; y < d.h(); ++y)
    for (int x = 0; x < d.w(); ++x)
      if (is(d.px(x, y))) {
        ++count;
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        const double along = (p - a).dot(dir);
        if (along > best) best = along, lateral = (p - a).dot(side);
      }
  ASSERT_GT(count, 20) << what << ": the arrow is not in the frame";
  EXPECT_NEAR(best, (b - a).norm(), 1.0) << what << ": tip at " << b.transpose();
  EXPECT_LE(std::fabs(lateral), 1.5) << what;
}

}  // namespace
}  // namespace simreel
