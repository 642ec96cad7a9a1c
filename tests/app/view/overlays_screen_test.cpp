// The 2D layer of a scene's overlays: captions fade in and out over their time range,
// labels follow their body and stay in the frame, the legend fills itself from the show items, a
// title too wide for the frame is set smaller, inset plots carry the run's values, and all of it is
// composited after anti-aliasing (crisp whatever the AA mode).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "app/view/overlays.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/app/view/overlay_fixtures.hpp"

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

// Per-joint quantities read the World's joint coordinates: at any frame the HUD prints
// World::joint_position and joint_speed (a universal joint's second coordinate for angle2,
// speed2), and a plot's samples are those values at their steps.
TEST(OverlaysScreen, JointQuantitiesAreTheWorldsJointCoordinates) {
  Drawn d(write_scene(
      "joint_q.yaml",
      "simulation: { duration: 2 }\n"
      "video: { width: 160, height: 90, fps: 10 }\n"
      "render: { shadows: false }\n"
      "bodies:\n"
      "  - { name: upper, position: [0.3, 0, 2], colliders: [ { shape: box, size: [0.6, 0.05, 0.03] } ] }\n"
      "  - { name: lower, position: [0.9, 0, 2], colliders: [ { shape: box, size: [0.6, 0.05, 0.03] } ] }\n"
      "  - { name: bob, position: [3.3, 0.2, 1.6], angular_velocity: [0, 0, 1],\n"
      "      colliders: [ { shape: sphere, radius: 0.1 } ] }\n"
      "joints:\n"
      "  - { name: shoulder, type: revolute, bodies: [world, upper], anchor: [0, 0, 2], axis: [0, 1, 0] }\n"
      "  - { name: elbow, type: revolute, bodies: [upper, lower], anchor: [0.6, 0, 2], axis: [0, 1, 0] }\n"
      "  - { name: cardan, type: universal, bodies: [world, bob], anchor: [3, 0, 2], axis: [0, 0, 1],\n"
      "      axis2: [1, 0, 0] }\n"
      "overlays:\n"
      "  hud: ['{shoulder.angle:.17g} {elbow.speed:.17g} {cardan.angle:.17g} {cardan.angle2:.17g} "
      "{cardan.speed2:.17g}']\n"
      "  plots: [ { quantities: [elbow.angle, cardan.speed2] } ]\n"));
  const SceneOverlays& o = *d.view->overlays;
  for (long k : {0L, 7L, 15L}) {
    d.draw_frame(k);
    const World& w = d.loop->world();
    std::string line;
    format_hud_line(d.scene.overlays.hud[0], w, k, 0, Vec3::Zero(), line, 10, &o.meters());
    char want[512];
    std::snprintf(want, sizeof want, "%.17g %.17g %.17g %.17g %.17g", w.joint_position(0), w.joint_speed(1),
                  w.joint_position(2, 0), w.joint_position(2, 1), w.joint_speed(2, 1));
    EXPECT_EQ(line, want) << "frame " << k;
    if (k > 0) {
      EXPECT_GT(std::fabs(w.joint_position(1)), 1e-3) << "the elbow has turned";
    }
  }
  const std::vector<double>& t = o.plot_times(0);
  ASSERT_GT(t.size(), 50u);
  FrameLoop loop(d.scene, 1);
  size_t k = 0;
  FrameLoop::Hooks h;
  h.step = [&](const World& w) {
    if (k < t.size() && std::fabs(w.time() - t[k]) < 1e-12) {
      EXPECT_EQ(o.plot_values(0, 0)[k], (float)w.joint_position(1));
      EXPECT_EQ(o.plot_values(0, 1)[k], (float)w.joint_speed(2, 1));
      ++k;
    }
  };
  loop.run({}, h, true);
  EXPECT_EQ(k, t.size());
}

// The complete elliptic integral of the first kind, K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
double elliptic_K(double k) {
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 40 && std::fabs(a - b) > 1e-16 * a; ++i) {
    const double m = 0.5 * (a + b);
    b = std::sqrt(a * b), a = m;
  }
  return std::numbers::pi / (2 * a);
}

// {pivot.period} of the pendulum demo (scenes/pendulum.yaml): every period measured from the
// turns, maximum to maximum and minimum to minimum, is the exact period of a compound pendulum
// released from rest at 120 degrees, T = 4 sqrt(I_p / (m g d)) K(sin 60 deg), within the method's
// resolution w0^2 h^3 / 4 (StepMeters, app/view/quantities.hpp). The reference is the closed form
// from the scene's dimensions, not the World's mass properties.
TEST(OverlaysScreen, PendulumDemoPeriodIsTheEllipticPeriod) {
  const Scene scene = load_scene("scenes/pendulum.yaml");
  const double pi = std::numbers::pi, g = 9.81;
  const double r = 0.015, L = 1.0, R = 0.08, l_bob = 1.0;  // rod radius and length, bob radius and distance
  const double m_rod = 2700 * pi * r * r * L, m_bob = 7850 * 4.0 / 3.0 * pi * R * R * R, m = m_rod + m_bob;
  const double d = (m_rod * L / 2 + m_bob * l_bob) / m;
  const double I = m_rod * ((3 * r * r + L * L) / 12 + L * L / 4) + m_bob * (0.4 * R * R + l_bob * l_bob);
  const double w0sq = m * g * d / I, h = scene.timestep;
  const double T = 4 / std::sqrt(w0sq) * elliptic_K(std::sin(pi / 3));
  const double resolution = w0sq * h * h * h / 4;
  EXPECT_NEAR(T, 2.732730, 5e-7) << "the figure in the scene's comment";
  EXPECT_NEAR(2 * pi / std::sqrt(w0sq), 1.990508, 5e-7) << "the small-angle period in the scene's comment";
  EXPECT_LT(resolution, 2e-7);

  FrameLoop loop(scene, 1);
  ASSERT_NEAR(loop.world().mass(0), m, 1e-9 * m) << "the scene's pendulum is the one the reference describes";
  const HudField& f = scene.overlays.hud[2].fields[0];
  ASSERT_EQ(f.name, "period");
  StepMeters P;
  P.track(f, h);
  FrameLoop::Hooks hk;
  hk.step = [&](const World& w) { P.record(w); };
  loop.run({}, hk, true);
  const std::vector<double>&up = P.turns(0, 0, 1), &down = P.turns(0, 0, -1);
  // Released from rest at t = 0: a maximum of the coordinate there, then every T; minima between.
  ASSERT_EQ(up.size(), 5u);
  ASSERT_EQ(down.size(), 4u);
  EXPECT_EQ(up[0], 0.0);
  for (size_t k = 1; k < up.size(); ++k) EXPECT_NEAR(up[k] - up[k - 1], T, resolution) << "maxima " << k;
  for (size_t k = 1; k < down.size(); ++k)
    EXPECT_NEAR(down[k] - down[k - 1], T, resolution) << "minima " << k;
  EXPECT_NEAR(down[0], T / 2, resolution) << "the swing is symmetric";
  EXPECT_NEAR(P.period(0, 0), T, resolution);
  double lo = 1e9, hi = -1e9;
  for (const std::vector<double>* v : {&up, &down})
    for (size_t k = 1; k < v->size(); ++k)
      lo = std::min(lo, (*v)[k] - (*v)[k - 1]), hi = std::max(hi, (*v)[k] - (*v)[k - 1]);
  std::printf("pendulum period: measured %.10f to %.10f s (latest %.10f), exact %.10f s, resolution %.2e s\n",
              lo, hi, P.period(0, 0), T, resolution);
}

// The HUD's period is measured over the physics steps the frame loop runs, whichever frames are
// drawn: an em dash until two turns in one direction, then the period (the same figure at a frame
// drawn alone as in a full run).
TEST(OverlaysScreen, TheHudPeriodIsADashUntilMeasured) {
  Drawn d("scenes/pendulum.yaml");
  const HudLine& line = d.scene.overlays.hud[2];
  std::string out;
  d.draw_frame(30);  // 1 s: one maximum (the release) and one minimum seen
  format_hud_line(line, d.loop->world(), 30, 0, Vec3::Zero(), out, 30, &d.view->overlays->meters());
  EXPECT_EQ(out, "T measured \u2014 s");
  d.draw_frame(270);  // 9 s
  format_hud_line(line, d.loop->world(), 270, 0, Vec3::Zero(), out, 30, &d.view->overlays->meters());
  EXPECT_EQ(out, "T measured 2.73273 s");
  // Without the measured periods the value is not known.
  format_hud_line(line, d.loop->world(), 270, 0, Vec3::Zero(), out, 30);
  EXPECT_EQ(out, "T measured \u2014 s");
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// scenes/momentum.yaml: a 1 kg ball at 2 m/s meets a 3 kg ball at -0.5 m/s, elastic, in free space.
// The HUD's p and P are m v and the total; after the collision they are the closed form of a 1D
// elastic collision, p_a' = m_a ((m_a - m_b) v_a + 2 m_b v_b) / (m_a + m_b) = -1.75 kg m/s and
// p_b' = 2.25, and P = 0.5 kg m/s throughout (to the contact solver's 1e-9: it is an impulse
// exchange between the two, which conserves momentum to round-off). The momentum arrows' automatic
// scale is the velocity arrows' times 1/m: the largest |p| drawn 2 body radii long.
TEST(OverlaysScreen, MomentumOfAnElasticCollision) {
  Drawn d("scenes/momentum.yaml");
  const SceneOverlays& o = *d.view->overlays;
  const HudLine& pa = d.scene.overlays.hud[1];
  ASSERT_EQ(pa.fields[0].name, "p");
  const HudField P = d.scene.overlays.hud[3].fields[0];
  ASSERT_TRUE(P.is_expr()) << "a.m * a.v.x + b.m * b.v.x";
  HudField total;
  total.name = "P", total.component = 0;
  const HudField contact = d.scene.overlays.hud[5].fields[0];
  ASSERT_EQ(contact.name, "first_contact");
  for (long k : {0L, 10L, 40L, 72L}) {  // before (t = 0, 0.33 s) and after (1.33, 2.4 s) the impact
    d.draw_frame(k);
    const World& w = d.loop->world();
    EXPECT_NEAR(quantity_value(P, w, k, 0, Vec3::Zero()), 0.5, 1e-9) << "frame " << k;
    EXPECT_NEAR(quantity_value(total, w, k, 0, Vec3::Zero()), 0.5, 1e-9) << "frame " << k;
    // The gap 2.6 - 0.488 m closes at 2.5 m/s: contact at 0.8448 s, read within a step (0.8458).
    const double tc = quantity_value(contact, w, k, 0, Vec3::Zero(), 30, &d.view->overlays->meters());
    if (k <= 10)
      EXPECT_TRUE(std::isnan(tc)) << "frame " << k;
    else
      EXPECT_NEAR(tc, 2.112 / 2.5, d.scene.timestep) << "frame " << k;
    const double p_a = quantity_value(pa.fields[0], w, k, 0, Vec3::Zero());
    EXPECT_NEAR(p_a, k <= 10 ? 2.0 : -1.75, 1e-9) << "frame " << k;
    EXPECT_NEAR(quantity_value(d.scene.overlays.hud[2].fields[0], w, k, 0, Vec3::Zero()),
                k <= 10 ? -1.5 : 2.25, 1e-9);
  }
  // Given scale: 0.4 m per kg m/s, as the scene says.
  EXPECT_EQ(o.arrow_scale(0, ShowKind::momentum), 0.4);
  // The unknown-quantity message lists p and P; a body's P is refused.
  EXPECT_THROW(load_scene_text("bodies: [ { name: a, colliders: [ { shape: sphere, radius: 1 } ] } ]\n"
                               "overlays: { hud: ['{a.P.x}'] }\n",
                               "p.yaml"),
               InputError);
}

}  // namespace
}  // namespace simreel
