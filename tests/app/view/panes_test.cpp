// Time and views drawn as `simreel render` and `check` draw them (app/view/panes.hpp,
// app/scene/scene_time.hpp, app/view/ghost_view.hpp): the frame at video time t shows simulated time f(t) (a
// moving ball where the hand-worked f puts it); a camera riding in a body sees it stand still; a variant's
// pane shows the run its settings give; a ghost is drawn where the closed form says and shows an integrator's
// drift; frames of all of these are the same bytes across runs and --threads.
#include "app/view/panes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "app/runner/camera_fit.hpp"
#include "render/camera.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/cli_run.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

// A scene loaded and drawn through SceneFrames and FrameLoop exactly as the commands do.
struct Frames {
  Scene scene;
  std::unique_ptr<FrameLoop> loop;
  std::unique_ptr<SceneFrames> frames;
  explicit Frames(const std::string& text, int threads = 1) {
    scene = load_scene_text(text, (test::scratch_dir() / "s.yaml").string());
    prepare_run(scene);
    loop = std::make_unique<FrameLoop>(scene, threads);
    ViewOptions o;
    o.aa = "none";
    o.threads = threads;
    frames = std::make_unique<SceneFrames>(scene, *loop, o);
  }
  // The video frames asked for, drawn: index -> RGBA.
  std::map<long, std::vector<uint8_t>> draw(const std::vector<long>& ks) {
    std::map<long, std::vector<uint8_t>> out;
    std::vector<FrameTarget> t;
    for (long k : ks) t.push_back(plan_target(loop->video_plan(), k, scene.video.fps));
    FrameLoop::Hooks h;
    h.step = frames->step_hook();
    h.frame = [&](const FrameTarget& f, const World& w) {
      const uint8_t* px = frames->draw(w, nullptr, f.index);
      out[f.index].assign(px, px + (size_t)frames->width() * frames->height() * 4);
    };
    loop->run(t, h, false);
    return out;
  }
};

// Pixels that differ from the top-left corner's colour (the sky) by more than a few levels.
std::vector<bool> mask_of(const std::vector<uint8_t>& img, int w, int h, int x0 = 0, int x1 = -1) {
  if (x1 < 0) x1 = w;
  std::vector<bool> m((size_t)w * h, false);
  const uint8_t* sky = &img[((size_t)2 * w + x0 + 2) * 4];
  for (int y = 0; y < h; ++y)
    for (int x = x0; x < x1; ++x) {
      const uint8_t* p = &img[((size_t)y * w + x) * 4];
      m[(size_t)y * w + x] = std::abs(p[0] - sky[0]) + std::abs(p[1] - sky[1]) + std::abs(p[2] - sky[2]) > 12;
    }
  return m;
}

Eigen::Vector2d centroid(const std::vector<bool>& m, int w) {
  double sx = 0, sy = 0, n = 0;
  for (size_t i = 0; i < m.size(); ++i)
    if (m[i]) sx += (double)(i % w) + 0.5, sy += (double)(i / w) + 0.5, ++n;
  return n ? Eigen::Vector2d(sx / n, sy / n) : Eigen::Vector2d(-1, -1);
}

TEST(Panes, LayoutSideBySideAndGrid) {
  std::vector<PaneRect> r = layout_panes(2, 0, 1280, 720, 0);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].x0, 0);
  EXPECT_EQ(r[0].width, 639);  // (1280 - a 2 px gutter) / 2
  EXPECT_EQ(r[1].x0, 641);
  EXPECT_EQ(r[1].height, 720);
  r = layout_panes(3, 2, 640, 480, 40);  // two columns, two rows under a 40 px band
  EXPECT_EQ(r[2].x0, r[0].x0);
  EXPECT_GT(r[2].y0, r[0].y0 + r[0].height);
  EXPECT_GE(r[0].y0, 40);
  EXPECT_LE(r[2].y0 + r[2].height, 480);
  EXPECT_THROW(layout_panes(16, 0, 160, 90, 0), std::invalid_argument);
}

// A ball crossing the view at 1 m/s: its pixel column tells the simulated time a frame shows.
const char* kBall = R"(
simulation: { duration: 3.0, timestep: 0.005, gravity: [0, 0, 0] }
video: { width: 320, height: 180, fps: 20 }
render: { sky: flat, shadows: false }
camera: { position: [0, -6, 0], look_at: [0, 0, 0], up: [0, 0, 1], fov: 60 }
time:
  segments: [{ until: 1.0, speed: 1 }, { until: 2.0, speed: 0.25 }]
  speed: 0.5
  hold: { at: 0.5, for: 1.0 }
bodies:
  - { name: ball, position: [-1.5, 0, 0], linear_velocity: [1, 0, 0], color: [0.1, 0.1, 0.1],
      colliders: [{ shape: sphere, radius: 0.12 }] }
)";

// f by hand: video 0-0.5 plays 0-0.5; 0.5-1.5 holds 0.5; 1.5-2.0 plays 0.5-1.0; 2.0-6.0 plays
// 1.0-2.0 at 0.25; 6.0-8.0 plays 2.0-3.0 at 0.5.
double f(double v) {
  if (v <= 0.5) return v;
  if (v <= 1.5) return 0.5;
  if (v <= 2.0) return v - 1.0;
  if (v <= 6.0) return 1.0 + 0.25 * (v - 2.0);
  return 2.0 + 0.5 * (v - 6.0);
}

TEST(TimeRemap, TheFrameAtVideoTimeTShowsSimulatedTimeFOfT) {
  Frames fr(kBall);
  EXPECT_DOUBLE_EQ(fr.loop->video_duration(), 8.0);
  const std::vector<long> ks = {0, 6, 10, 20, 29, 36, 50, 80, 100, 130, 160};
  const auto imgs = fr.draw(ks);
  CameraView cam;
  cam.eye = fr.scene.camera.position, cam.target = fr.scene.camera.look_at, cam.up = fr.scene.camera.up;
  cam.fov_deg = fr.scene.camera.fov;
  const int W = fr.frames->width(), H = fr.frames->height();
  for (long k : ks) {
    const double tv = k / 20.0, ts = f(tv);
    const Eigen::Vector2d want = project_to_pixel(cam, W, H, Vec3(-1.5 + ts, 0, 0));
    const Eigen::Vector2d got = centroid(mask_of(imgs.at(k), W, H), W);
    // The frame shows the nearest step: within half a step (2.5 ms, 0.1 px here) of f(t).
    EXPECT_NEAR(got.x(), want.x(), 0.75) << "video " << tv << " s, simulated " << ts << " s";
    EXPECT_NEAR(got.y(), want.y(), 0.75) << "video " << tv << " s";
    // And not where the unmapped video would have it (f(t) = t), when that differs by a pixel or more.
    const Eigen::Vector2d plain = project_to_pixel(cam, W, H, Vec3(-1.5 + std::min(tv, 3.0), 0, 0));
    if (std::fabs(plain.x() - want.x()) > 2) {
      EXPECT_GT(std::fabs(got.x() - plain.x()), 1.5) << tv;
    }
  }
}

TEST(TimeRemap, TheHudShowsSimulatedAndVideoTime) {
  Scene s =
      load_scene_text(std::string(kBall) + "overlays: { hud: [\"t = {t:.3f} s, video {video_t:.2f} s\"] }\n",
                      (test::scratch_dir() / "h.yaml").string());
  prepare_run(s);
  FrameLoop loop(s, 1);
  const long k = 100;  // video 5 s: simulated 1.75 s
  std::string line;
  FrameLoop::Hooks h;
  h.frame = [&](const FrameTarget& t, const World& w) {
    format_hud_line(s.overlays.hud[0], w, t.index, 0, Vec3::Zero(), line, s.video.fps);
  };
  loop.run({plan_target(loop.video_plan(), k, s.video.fps)}, h, false);
  EXPECT_EQ(line, "t = 1.750 s, video 5.00 s");
}

// A T-handle tumbling about its intermediate axis; pane 1 rides in its frame, pane 0 watches from
// the world.
const char* kHandle = R"(
simulation: { duration: 4.0, timestep: 0.004166666666666667, gravity: [0, 0, 0] }
video: { width: 400, height: 200, fps: 30 }
render: { sky: flat, shadows: false }
camera: { position: [2.4, -2.4, 1.4], look_at: [0, -0.1, 0], up: [0, 0, 1], fov: 40 }
bodies:
  - name: handle
    angular_velocity: [0.02, 6.0, 0.02]
    color: [0.1, 0.1, 0.1]
    colliders:
      - { shape: cylinder, radius: 0.07, height: 1.0, density: 7800, orientation: [0.7071067811865476, 0, 0.7071067811865476, 0] }
      - { shape: cylinder, radius: 0.05, height: 0.7, density: 7800, position: [0, -0.35, 0], orientation: [0.7071067811865476, -0.7071067811865476, 0, 0] }
)";

TEST(Panes, ACameraRidingInABodySeesItStandStill) {
  Frames fr(std::string(kHandle) + R"(
panes:
  - { title: "in space" }
  - { camera: { frame: { body: handle }, position: [2.4, -2.4, 1.4], look_at: [0, -0.1, 0], up: [0, 0, 1] } }
)");
  const auto imgs = fr.draw({0, 40, 80, 110});
  const int W = fr.frames->width(), H = fr.frames->height();
  const std::vector<PaneRect> r = layout_panes(2, 0, W, H, 0);
  auto changed = [&](int pane, long k) {  // silhouette pixels that differ from frame 0's, in a pane
    const auto a = mask_of(imgs.at(0), W, H, r[pane].x0, r[pane].x0 + r[pane].width);
    const auto b = mask_of(imgs.at(k), W, H, r[pane].x0, r[pane].x0 + r[pane].width);
    long n = 0, area = 0;
    for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i], area += a[i];
    return std::make_pair(n, area);
  };
  for (long k : {40L, 80L, 110L}) {
    const auto [ride, area] = changed(1, k);
    const auto [world, area0] = changed(0, k);
    EXPECT_GT(area, 500);
    EXPECT_LE(ride, area / 50) << "frame " << k << ": the riding pane's silhouette moved";
    EXPECT_GT(world, area0 / 5) << "frame " << k << ": the world pane should see it tumble";
  }
}

// A pane's own `show:`: the pane that hides the handle's arrows is, pixel for pixel, the pane of a
// scene without them; the pane that keeps them is not (and a pane that adds axes differs from both).
TEST(Panes, APaneShowsItsOwnItems) {
  const std::string arrows = "    show: [angular_momentum, angular_velocity]\n";
  const std::string panes = "panes:\n  - { title: a }\n  - { title: b, show: { handle: [] } }\n";
  Frames with(std::string(kHandle) + arrows + panes);
  Frames without(std::string(kHandle) + panes);
  Frames axes(std::string(kHandle) +
              "panes:\n  - { title: a }\n  - { title: b, show: { handle: [axes] } }\n");
  const long k = 40;
  const auto a = with.draw({k}).at(k), b = without.draw({k}).at(k), c = axes.draw({k}).at(k);
  const int W = with.frames->width(), H = with.frames->height();
  const std::vector<PaneRect> r = layout_panes(2, 0, W, H, 0);
  auto differing = [&](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y, int pane) {
    long n = 0;
    for (int yy = r[pane].y0; yy < r[pane].y0 + r[pane].height; ++yy)
      for (int xx = r[pane].x0; xx < r[pane].x0 + r[pane].width; ++xx)
        n += std::memcmp(&x[((size_t)yy * W + xx) * 4], &y[((size_t)yy * W + xx) * 4], 4) != 0;
    return n;
  };
  EXPECT_EQ(differing(a, b, 1), 0) << "the pane hiding the arrows";
  EXPECT_GT(differing(a, b, 0), 100) << "the pane keeping the scene's arrows";
  EXPECT_GT(differing(c, b, 1), 100) << "the pane adding axes";
  EXPECT_EQ(differing(c, b, 0), 0) << "the other pane is the scene's (no items)";
}

// A plot in a pane: its axes and curve are in the frame, inside the pane that holds it (they were
// dropped when the panes' screen layers were gathered: the plot's panel and labels came, its lines
// did not).
TEST(Panes, PlotsInPanesKeepTheirCurves) {
  Frames f(std::string(kHandle) +
           "panes:\n  - { title: a }\n  - { title: b }\n"
           "overlays: { plots: [ { quantities: [omega_body.y], rect: [0.5, 0.5, 0.45, 0.45] } ] }\n");
  f.draw({20});
  const ScreenLayer& layer = f.frames->screen();
  ASSERT_FALSE(layer.lines.empty()) << "the plots' axes and curves";
  const int W = f.frames->width(), H = f.frames->height();
  const std::vector<PaneRect> r = layout_panes(2, 0, W, H, 0);
  long left = 0, right = 0;
  for (const ScreenLine& l : layer.lines) {
    EXPECT_GE(std::min(l.x0, l.x1), 0.0f);
    EXPECT_LE(std::max(l.x0, l.x1), (float)W);
    (l.x0 < r[1].x0 ? left : right)++;
  }
  EXPECT_GT(left, 5);
  EXPECT_EQ(left, right) << "one plot in each pane, the same lines moved";
}

TEST(Panes, AVariantPaneShowsItsOwnRunAndGhostsShowTheDrift) {
  // The scene on the default integrator beside the `seed` variant, each with its ghost over it,
  // and the same without ghosts (the bodies' silhouettes).
  std::string text = kHandle;
  const std::string variants = "variants: [{ name: seed, integrator: seed }]\n";
  Frames plain(text + variants);
  text.replace(text.find("    color:"), 0, "    ghost: { color: [1, 0, 0], opacity: 0.6 }\n");
  Frames fr(text + variants);
  const long k = 75;  // 2.5 s: past the first flip
  const auto imgs = fr.draw({k});
  const auto bodies = plain.draw({k});
  const std::vector<const World*> worlds = fr.frames->worlds();
  ASSERT_EQ(worlds.size(), 2u);
  // The seed pane's world is the run the seed integrator gives, bit for bit.
  Scene seed = fr.scene;
  seed.integrator = Integrator::seed;
  World ref(world_config(seed, 1), seed.bodies);
  while (ref.steps() < worlds[1]->steps()) ref.step();
  EXPECT_EQ(worlds[1]->steps(), worlds[0]->steps());
  EXPECT_EQ(ref.impl().state(0).q_WP.coeffs(), worlds[1]->impl().state(0).q_WP.coeffs());
  EXPECT_EQ(ref.impl().state(0).w_P, worlds[1]->impl().state(0).w_P);
  // The ghost (red) shows where the closed form is: over the default body it hides in a thin
  // skin; beside the seed body, which never flips, it stands apart. Red pixels outside the
  // body's silhouette, per pane:
  const int W = fr.frames->width(), H = fr.frames->height();
  const std::vector<PaneRect> r = layout_panes(2, 0, W, H, 0);
  const std::vector<bool> body = mask_of(bodies.at(k), W, H);
  auto red = [&](int pane) {
    long n = 0;
    const auto& img = imgs.at(k);
    for (int y = r[pane].y0; y < r[pane].y0 + r[pane].height; ++y)
      for (int x = r[pane].x0; x < r[pane].x0 + r[pane].width; ++x) {
        const uint8_t* p = &img[((size_t)y * W + x) * 4];
        n += !body[(size_t)y * W + x] && p[0] > p[1] + 40 && p[0] > p[2] + 40;
      }
    return n;
  };
  std::printf("ghost pixels outside the body: default %ld, seed %ld\n", red(0), red(1));
  EXPECT_GT(red(1), 10 * red(0) + 200) << "default " << red(0) << " px, seed " << red(1) << " px";
}

TEST(Panes, FramesAreTheSameBytesAcrossRunsAndThreads) {
  const std::string dir = test::scratch_dir().string();
  std::string text = kHandle;
  text.replace(text.find("    color:"), 0, "    ghost: true\n");
  text += R"(
time: { segments: [{ until: 1.0, speed: 1 }, { until: 1.5, speed: 0.25 }], hold: { at: 2.0, for: 0.3 } }
variants: [{ name: seed, integrator: seed }, { name: fine, timestep: 0.001 }]
overlays: { title: "three runs", hud: ["t = {t:.2f} s  video {video_t:.2f} s"] }
panes:
  columns: 2
  views:
    - { title: default }
    - { title: seed, variant: seed }
    - { title: "fine, body frame", variant: fine, camera: { frame: { body: handle }, position: [2, -2, 1.2] } }
)";
  const std::string scene = test::scratch_file("views.yaml", text);
  const std::string frames = " --frames 0,30,44,60,70,95,140 --no-video --gl osmesa";
  for (const char* t : {"1", "2"}) {
    const test::Result r =
        test::run("render " + scene + " --threads " + t + " --frames-dir " + dir + "/t" + t + frames);
    ASSERT_EQ(r.code, 0) << r.out;
  }
  const test::Result again =
      test::run("render " + scene + " --threads 1 --frames-dir " + dir + "/again" + frames);
  ASSERT_EQ(again.code, 0) << again.out;
  int compared = 0;
  for (const auto& e : fs::directory_iterator(dir + "/t1")) {
    const std::string a = test::slurp(e.path());
    EXPECT_EQ(a, test::slurp(dir + "/t2/" + e.path().filename().string())) << e.path();
    EXPECT_EQ(a, test::slurp(dir + "/again/" + e.path().filename().string())) << e.path();
    ++compared;
  }
  EXPECT_EQ(compared, 7);
}

// simulate ignores playback (its CSV is every k / fps of simulated time); check compares simulated
// times and every run's bodies, and passes on a second run.
TEST(Panes, SimulateAndCheckWorkOnSplitScreensWithTimeMaps) {
  const std::string dir = test::scratch_dir().string();
  const std::string scene = test::scratch_file("views.yaml", std::string(kHandle) + R"(
time: { speed: 0.25, hold: { at: 1.0, for: 0.5 } }
variants: [{ name: seed, integrator: seed }]
test: { frames: "0%, 1s, 2.5s", width: 200, height: 100 }
)");
  const test::Result sim = test::run("simulate " + scene + " --csv " + dir + "/run.csv --quiet");
  ASSERT_EQ(sim.code, 0) << sim.out;
  const std::string csv = test::slurp(dir + "/run.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 121);  // header, 4 s at 30 fps: 121 frames
  const std::string check = "check " + scene + " --goldens " + dir + "/goldens --gl osmesa";
  const test::Result first = test::run(check + " --update missing");
  ASSERT_EQ(first.code, 0) << first.out;
  const test::Result second = test::run(check + " --update none");
  EXPECT_EQ(second.code, 0) << second.out;
  EXPECT_NE(second.out.find("PASS views t=2.5s"), std::string::npos) << second.out;
  const std::string manifest = test::slurp(dir + "/goldens/views/manifest.json");
  EXPECT_NE(manifest.find("seed/handle"), std::string::npos);  // the variant's physics is checked too
  // render's frame is check's: simulated 2.5 s is first shown at video 1 / 0.25 + 0.5 + 1.5 / 0.25 =
  // 10.5 s, frame 315.
  const test::Result r =
      test::run("render " + scene + " --width 200 --height 100 --frames 315 --frames-dir " + dir +
                "/f --no-video --gl osmesa");
  ASSERT_EQ(r.code, 0) << r.out;
  const test::Result d =
      test::run("diff " + dir + "/f/frame_00315.png " + dir + "/goldens/views/t2.5s.png --tolerance exact");
  EXPECT_EQ(d.code, 0) << d.out;
}

}  // namespace
}  // namespace simreel
