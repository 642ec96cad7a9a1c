// The 2D layer of a scene's overlays: captions fade in and out over their time range,
// labels follow their body and stay in the frame, the legend fills itself from the show items, a
// title too wide for the frame is set smaller, inset plots carry the run's values, and all of it is
// composited after anti-aliasing (crisp whatever the AA mode).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "app/view/overlays.hpp"
#include "tests/app/view/overlay_fixtures.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

// The screen layer of frame k.
ScreenLayer screen_at(Drawn& d, long k) {
  d.draw_frame(k);
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(d.loop->world(), k, dl);
  return dl.screen;
}

const char* kBody =
    "simulation: { duration: 2, gravity: [0, 0, 0] }\n"
    "video: { width: 480, height: 270, fps: 10 }\n"
    "render: { shadows: false }\n"
    "camera: { position: [0, -6, 0], look_at: [0, 0, 0] }\n"
    "bodies:\n"
    "  - { name: b, linear_velocity: [2.5, 0, 0], angular_velocity: [0, 0, 1],\n"
    "      colliders: [ { shape: box, size: [0.5, 0.5, 0.5] } ],\n"
    "      show: [ angular_velocity, { trail: { color: [0, 0, 0] } } ] }\n"
    "  - { name: c, position: [0, 0, 1], colliders: [ { shape: sphere, radius: 0.2 } ],\n"
    "      show: [ { trail: { color: [0, 0, 0] } }, { angular_momentum: { color: [1, 0, 0] } } ] }\n";

TEST(OverlaysScreen, CaptionsFadeInAndOutOverTheirRange) {
  Drawn d(
      write_scene("captions.yaml", std::string(kBody) +
                                       "overlays:\n"
                                       "  captions:\n"
                                       "    - { text: 'Watch \\omega', from: 0.5, to: 1.5, fade: 0.4 }\n"));
  auto alpha = [&](long k) {
    const ScreenLayer l = screen_at(d, k);
    int a = -1;
    for (const ScreenGlyph& g : l.glyphs) {
      if (a >= 0) {
        EXPECT_EQ(g.color[3], a) << "one alpha for the whole caption";
      }
      a = g.color[3];
    }
    return l.glyphs.empty() ? 0 : a;
  };
  EXPECT_EQ(alpha(4), 0) << "before 'from'";
  EXPECT_EQ(alpha(5), 0) << "at 'from': fully transparent, fading in";
  EXPECT_NEAR(alpha(7), 128, 1) << "0.2 s in: half";
  EXPECT_EQ(alpha(10), 255);
  EXPECT_NEAR(alpha(13), 128, 1) << "0.2 s before 'to'";
  EXPECT_EQ(alpha(15), 0) << "at 'to': gone";
}

TEST(OverlaysScreen, LabelsSitAboveTheirBodyAndStayInTheFrame) {
  Drawn d(write_scene("labels.yaml", std::string(kBody) +
                                         "overlays:\n"
                                         "  labels:\n"
                                         "    - { body: b, text: '\\vec{L} is fixed' }\n"
                                         "    - { body: c, text: 'c', offset: [40, 10] }\n"));
  for (long k : {0L, 10L, 19L}) {
    const ScreenLayer l = screen_at(d, k);
    ASSERT_EQ(l.rects.size(), 2u);
    const World& w = d.loop->world();
    const Eigen::Vector2d p = project_to_pixel(d.view->camera, d.w(), d.h(), w.centroid(0));
    const ScreenRect& r = l.rects[0];
    // Inside the frame, whole, whatever the body does (it leaves the frame on the right).
    EXPECT_GE(r.x0, 0);
    EXPECT_LE(r.x1, d.w());
    EXPECT_GE(r.y0, 0);
    const double radius_px = 0.5 * std::sqrt(0.75) / pixel_size_at(d.view->camera, d.h(), 6.0);
    EXPECT_LT(r.y1, p.y() - radius_px) << "above the body's outline";
    if (p.x() > 60 && p.x() < d.w() - 60) {
      EXPECT_NEAR(0.5 * (r.x0 + r.x1), p.x(), 1.0) << "centred over the body, frame " << k;
    } else {
      EXPECT_EQ(r.x1, d.w() - 5) << "pushed in: a margin (half the text size) from the edge";
    }
    // The second: its centre at the body's pixel plus the offset (px at 720 lines, y up).
    const Eigen::Vector2d q = project_to_pixel(d.view->camera, d.w(), d.h(), w.centroid(1));
    EXPECT_NEAR(0.5 * (l.rects[1].x0 + l.rects[1].x1), q.x() + 40 * 270.0 / 720, 1.0);
    EXPECT_NEAR(0.5 * (l.rects[1].y0 + l.rects[1].y1), q.y() - 10 * 270.0 / 720, 1.0);
  }
}

TEST(OverlaysScreen, LegendFillsItselfFromTheShowItems) {
  Drawn d(write_scene("legend.yaml", std::string(kBody) + "overlays: { legend: true }\n"));
  const ScreenLayer l = screen_at(d, 0);
  // angular velocity (b), trail (b and c: the same colour, one entry), angular momentum (c).
  // Each entry: its swatch on a light backing (2 rects), after the panel.
  EXPECT_EQ(l.rects.size(), 1u + 3u * 2u);
  // The swatches' colours in order: Okabe-Ito reddish purple, black, then red as given.
  EXPECT_EQ(l.rects[2].color, (Rgba8{0xCC, 0x79, 0xA7, 255}));
  EXPECT_EQ(l.rects[4].color, (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(l.rects[6].color, (Rgba8{255, 0, 0, 255}));
  // Given entries replace the automatic ones.
  Drawn g(write_scene("legend2.yaml",
                      std::string(kBody) +
                          "overlays: { legend: { corner: bottom_left, items: [ { text: 'x', color: "
                          "[0, 0, 1] } ] } }\n"));
  const ScreenLayer m = screen_at(g, 0);
  ASSERT_EQ(m.rects.size(), 3u);
  EXPECT_EQ(m.rects[2].color, (Rgba8{0, 0, 255, 255}));
  EXPECT_GT(m.rects[0].y0, g.h() / 2) << "bottom left";
}

TEST(OverlaysScreen, ATitleWiderThanTheFrameIsShrunkToFit) {
  const std::string title = "A title far too long for a frame only four hundred and eighty pixels wide";
  Drawn d(write_scene("title.yaml", std::string(kBody) + "overlays: { title: '" + title + "' }\n"));
  const int normal = (int)std::lround(10 * 1.4);  // 1.4 x the text size (3.2% of 270 lines, at least 10 px)
  EXPECT_LT(d.view->overlays->title_pixel_size(), normal);
  EXPECT_GE(d.view->overlays->title_pixel_size(), normal / 3);
  const ScreenLayer l = screen_at(d, 0);
  ASSERT_FALSE(l.glyphs.empty());
  int left = 1 << 20, right = 0;
  for (const ScreenGlyph& g : l.glyphs)
    left = std::min(left, g.x), right = std::max(right, g.x + g.bitmap->width);
  EXPECT_GE(left, 0);
  EXPECT_LE(right, d.w());
  EXPECT_GE(l.rects[0].x0, 0) << "its panel too";
  EXPECT_LE(l.rects[0].x1, d.w());
  // A title that fits keeps its size.
  Drawn s(write_scene("title2.yaml", std::string(kBody) + "overlays: { title: 'Short' }\n"));
  EXPECT_EQ(s.view->overlays->title_pixel_size(), normal);
}

TEST(OverlaysScreen, PlotsCarryTheRunsValues) {
  Drawn d(write_scene("plot.yaml", std::string(kBody) +
                                       "overlays:\n"
                                       "  plots:\n"
                                       "    - { quantities: [omega_body.z, '|c.L|', position.x], body: b,\n"
                                       "        rect: [0.5, 0.5, 0.45, 0.45] }\n"));
  const SceneOverlays& o = *d.view->overlays;
  const std::vector<double>& t = o.plot_times(0);
  ASSERT_GT(t.size(), 100u);
  // The samples are the run's own: step the same scene and compare at each sample's step.
  FrameLoop loop(d.scene, 1);
  size_t k = 0;
  FrameLoop::Hooks h;
  h.step = [&](const World& w) {
    if (k < t.size() && std::fabs(w.time() - t[k]) < 1e-12) {
      EXPECT_EQ(o.plot_values(0, 0)[k], (float)w.impl().state(0).w_P.z());
      EXPECT_EQ(o.plot_values(0, 1)[k], (float)w.angular_momentum(1).norm());
      EXPECT_EQ(o.plot_values(0, 2)[k], (float)w.centroid(0).x());
      ++k;
    }
  };
  loop.run({}, h, true);
  EXPECT_EQ(k, t.size());
  EXPECT_NEAR(t.back(), 2.0, 0.02) << "to the end of the run";
  // Auto range: the data fills the value axis but for a margin.
  const InsetPlot& p = o.plot(0);
  EXPECT_LT(p.layout().v0, 0.0);  // position.x from 0 ...
  EXPECT_GT(p.layout().v1, 5.0);  // ... to 5 m
  EXPECT_EQ(p.layout().labels, (std::vector<std::string>{"\\omega_3", "|L|", "x"}));
}

// `tilt`: a body's z axis from the world's +z, in degrees; a box turning about x at 1 rad/s has
// tilted by t rad. A number: a component or |...| of it is an error.
TEST(OverlaysScreen, TiltIsTheAngleOfTheBodyAxisFromTheVertical) {
  Drawn d(write_scene("tilt.yaml",
                      "simulation: { duration: 2, gravity: [0, 0, 0] }\n"
                      "video: { width: 480, height: 270, fps: 10 }\n"
                      "bodies:\n"
                      "  - { name: b, angular_velocity: [1, 0, 0],\n"
                      "      colliders: [ { shape: box, size: [0.5, 0.5, 0.5] } ] }\n"
                      "overlays:\n"
                      "  hud: ['{b.tilt:.4f}']\n"
                      "  plots: [ { quantities: [tilt] } ]\n"));
  const SceneOverlays& o = *d.view->overlays;
  const std::vector<double>& t = o.plot_times(0);
  ASSERT_GT(t.size(), 100u);
  for (size_t k = 0; k < t.size(); k += 10)
    EXPECT_NEAR(o.plot_values(0, 0)[k], t[k] * 180 / std::numbers::pi, 1e-3) << t[k];
  EXPECT_EQ(o.plot(0).layout().labels, (std::vector<std::string>{"\\theta"}));
  std::string line;
  d.draw_frame(10);
  format_hud_line(d.scene.overlays.hud[0], d.loop->world(), 10, 0, Vec3::Zero(), line, 10);
  EXPECT_EQ(line, "57.2958");  // 1 s: 1 rad
  try {
    load_scene(write_scene("tilt_bad.yaml",
                           "simulation: { duration: 2 }\nbodies:\n"
                           "  - { name: b, colliders: [ { shape: sphere, radius: 1 } ] }\n"
                           "overlays: { hud: ['{b.tilt.x}'] }\n"));
    ADD_FAILURE() << "tilt.x was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'tilt' is a number"), std::string::npos) << e.what();
  }
}

TEST(OverlaysScreen, TheWholeLayerIsCrispAfterFxaa) {
  // Caption, label, legend and plot over flat sky: the same pixels with FXAA and without it
  // everywhere the layer draws, away from the body.
  const std::string path = write_scene(
      "crisp.yaml", std::string(kBody) +
                        "overlays:\n"
                        "  captions: [ { text: 'x_1 \\cdot \\vec{L}', from: 0, to: 5, position: top } ]\n"
                        "  legend: { corner: bottom_left }\n"
                        "  plots: [ { quantities: ['|v|'], rect: [0.55, 0.55, 0.43, 0.43] } ]\n");
  Drawn with(path, "fxaa"), without(path, "none");
  with.draw_frame(0);
  without.draw_frame(0);
  const ScreenLayer l = screen_at(without, 0);
  int compared = 0, differ = 0;
  for (const ScreenRect& r : l.rects)
    for (int y = std::max(0, r.y0); y < std::min(r.y1, without.h()); ++y)
      for (int x = std::max(0, r.x0); x < std::min(r.x1, without.w()); ++x) {
        ++compared;
        differ += with.px(x, y) != without.px(x, y);
      }
  EXPECT_GT(compared, 10000);
  EXPECT_EQ(differ, 0);
}

// The per-body numbers tilt (deg, the body z axis from the vertical) and precession (rad/s, the
// axis's turn about the vertical): a body tilted 30 degrees about y and turning at 2 rad/s about
// the world's vertical: tilt 30, precession 2; turning about its own axis instead: precession 0.
TEST(OverlaysScreen, TiltAndPrecessionOfABodysAxis) {
  std::string hud = "{b.tilt:.6f} {b.precession:.6f}";
  const Scene s = load_scene_text(
      "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
      "bodies:\n"
      "  - { name: b, euler: [0, 30, 0], angular_velocity: [0, 0, 2],\n"
      "      colliders: [ { shape: box, size: [0.1, 0.2, 0.3] } ] }\n"
      "overlays: { hud: [\"" +
          hud + "\"] }\n",
      (test::scratch_dir() / "tilt.yaml").string());
  std::string line;
  {
    World w(WorldConfig{}, s.bodies);
    format_hud_line(s.overlays.hud[0], w, 0, 0, Vec3::Zero(), line, 30);
    EXPECT_EQ(line, "30.000000 2.000000");
  }
  std::vector<BodyDef> own = s.bodies;
  own[0].w_W = own[0].q_WB * Vec3(0, 0, 5);  // about its own z axis: the axis stays put
  World w(WorldConfig{}, own);
  format_hud_line(s.overlays.hud[0], w, 0, 0, Vec3::Zero(), line, 30);
  double tilt = 0, precession = 1;
  ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf", &tilt, &precession), 2) << line;
  EXPECT_NEAR(tilt, 30, 1e-6);
  EXPECT_NEAR(precession, 0, 1e-6);
}

}  // namespace
}  // namespace simreel
