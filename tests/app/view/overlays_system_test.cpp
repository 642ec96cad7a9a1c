// Quantities of several bodies and of a point (`system:`, `angular_momentum_about`), copies of a
// body as it was (`snapshot`), and colours that never repeat in a legend.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "app/view/panes.hpp"
#include "tests/app/view/overlay_fixtures.hpp"

namespace simreel {
namespace {

// Two balls in free space, elastic, frictionless, off-centre (b 0.3 m aside): internal central
// forces only, so the total momentum P and the angular momentum about the centre of mass are kept
// through the collision, and the centre of mass moves at P / M in a straight line.
const char* kPair =
    "simulation: { duration: 2.4, timestep: 0.004166666666666667, gravity: [0, 0, 0] }\n"
    "video: { width: 320, height: 180, fps: 30 }\n"
    "bodies:\n"
    "  - { name: a, position: [-1.5, 0, 0], linear_velocity: [2, 0, 0],\n"
    "      show: [ { momentum: { scale: 0.4 } }, { angular_momentum_about: { point: [0, -1, 0] } } ],\n"
    "      colliders: [ { shape: sphere, radius: 0.2, mass: 1, friction: 0, restitution: 1 } ] }\n"
    "  - { name: b, position: [1.1, 0.3, 0], linear_velocity: [-0.5, 0, 0],\n"
    "      show: [ { momentum: { scale: 0.4 } } ],\n"
    "      colliders: [ { shape: sphere, radius: 0.288, mass: 3, friction: 0, restitution: 1 } ] }\n"
    "overlays:\n"
    "  legend: true\n"
    "  system: { bodies: [a, b], show: [momentum, center_of_mass, angular_momentum, velocity] }\n";

// The system's momentum arrow is drawn with its members' scale, so the drawn P is the drawn
// p_a + p_b: 0.4 m per kg m/s x 0.5 kg m/s = 0.2 m along x, from the centre of mass
// C = (1 (-1.5, 0) + 3 (1.1, 0.3)) / 4 = (0.45, 0.225) at t = 0, moved by P / M t = 0.125 t after.
// The angular momentum about C is the world's total (spins included); the collision changes it by
// the contact solver's first-order error (its normal is fixed over a step while the centres move:
// 2.3% at 1/240 s, 0.7% at 1/1000 s, 0.19% at 1/4000 s for this off-centre hit), not conserved to
// round-off as the momentum is.
TEST(Systems, ArrowsAreTheMembersSumsFromTheCentreOfMass) {
  Drawn d(write_scene("system.yaml", kPair));
  const SceneOverlays& o = *d.view->overlays;
  Vec3 from, vec, L0;
  o.system_arrow(0, 0, d.loop->world(), from, vec);
  EXPECT_NEAR((from - Vec3(0.45, 0.225, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((vec - Vec3(0.2, 0, 0)).norm(), 0, 1e-12);
  // L about C: sum of (c_i - C) x m_i v_i = (-1.95, -0.225) x (2, 0) + 3 (0.65, 0.075) x (-0.5, 0).
  const double Lz = (-1.95 * 0 - (-0.225) * 2) + 3 * (0.65 * 0 - 0.075 * (-0.5));
  Vec3 Lfrom;
  o.system_arrow(0, 2, d.loop->world(), Lfrom, L0);
  ASSERT_GT(std::fabs(Lz), 0.5);
  const double scale_L = L0.z() / Lz;
  EXPECT_GT(scale_L, 0);
  EXPECT_NEAR(L0.x(), 0, 1e-12);
  d.draw_frame(72);  // 2.4 s: long after the collision
  const World& w = d.loop->world();
  EXPECT_LT(w.linear_velocity(0).x(), 0) << "a has bounced back";
  o.system_arrow(0, 0, w, from, vec);
  EXPECT_NEAR((from - Vec3(0.45 + 0.125 * w.time(), 0.225, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR((vec - Vec3(0.2, 0, 0)).norm(), 0, 1e-9);
  Vec3 L1;
  o.system_arrow(0, 2, w, Lfrom, L1);
  EXPECT_NEAR((L1 - scale_L * w.total_angular_momentum()).norm(), 0, 1e-12 * std::fabs(scale_L * Lz));
  EXPECT_NEAR((L1 - L0).norm() / std::fabs(L0.z()), 0, 0.03);
  // v of C: P / M = 0.125 m/s, drawn at its own automatic scale (no member shows velocity):
  // constant, so its largest is its value, drawn kArrowReach times the larger member's radius.
  o.system_arrow(0, 3, w, from, vec);
  EXPECT_NEAR(vec.norm(), kArrowReach * 0.288, 1e-6);
}

// The arrow of `angular_momentum_about` starts at O and draws L_O = L + (c - O) x m v: for a ball on
// a straight line at constant velocity (1 kg at 2 m/s along x, passing 1 m from O = (0, -1, 0) on its
// +y side, not spinning) the closed form (0, 0, -2) kg m^2/s, clockwise seen from above, the same at
// every moment before the collision.
TEST(Systems, AngularMomentumAboutAPointIsConstantOnAStraightLine) {
  Drawn d(write_scene("about.yaml", kPair));
  const SceneOverlays& o = *d.view->overlays;
  const double s = o.arrow_scale(0, ShowKind::angular_momentum_about);
  ASSERT_GT(s, 0);
  for (long k : {0L, 5L, 15L}) {  // 0, 0.17 and 0.5 s; the balls meet at 0.85 s
    d.draw_frame(k);
    Vec3 from, vec;
    ASSERT_TRUE(o.item_arrow(0, ShowKind::angular_momentum_about, d.loop->world(), from, vec));
    EXPECT_EQ(from, Vec3(0, -1, 0)) << "frame " << k;
    EXPECT_NEAR((vec / s - Vec3(0, 0, -2)).norm(), 0, 1e-12) << "frame " << k;
  }
  // The largest |L_O| over the run is 2 (after the impact a moves back at 1.75 m/s: 1.75), drawn
  // kArrowReach body radii long (0.4 m; the radius is the drawn mesh's farthest vertex, 0.2 m to 1e-7).
  EXPECT_NEAR(2 * s, kArrowReach * 0.2, 1e-6);
}

// A snapshot is the body's pose at the first step at or after its time, drawn from then on as a
// translucent copy; before its time nothing is drawn. The ball's centre at t = 0.5 s is on the
// closed-form parabola (x0 + vx t, z0 + vz t - g t^2 / 2) to the integrator's round-off; the copy's
// outline (its front faces' extent across the view) is centred on it.
TEST(Systems, ASnapshotKeepsTheBodyAsItWas) {
  const std::string path = write_scene("snapshot.yaml",
                                       "simulation: { duration: 1.5, timestep: 0.004166666666666667 }\n"
                                       "video: { width: 160, height: 120, fps: 30 }\n"
                                       "camera: { position: [0, -8, 1], look_at: [0, 0, 1] }\n"
                                       "bodies:\n"
                                       "  - { name: ball, position: [-1, 0, 1], linear_velocity: [1, 0, 3],\n"
                                       "      show: [ { snapshot: { at: [0.5, 1.0] } } ],\n"
                                       "      colliders: [ { shape: sphere, radius: 0.1, mass: 1 } ] }\n");
  Drawn d(path);
  auto copies_centre = [&](size_t& vertices) {
    // The overlay list of the frame just drawn: the copies are its only ribbons.
    const OverlayList& ol = d.view->overlay();
    vertices = ol.ribbons.size();
    Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
    for (const OverlayVertex& v : ol.ribbons) {
      lo = lo.cwiseMin(Vec3(v.pos[0], v.pos[1], v.pos[2]));
      hi = hi.cwiseMax(Vec3(v.pos[0], v.pos[1], v.pos[2]));
    }
    return Vec3(0.5 * (lo + hi));
  };
  size_t n0 = 0, n1 = 0, n2 = 0;
  d.draw_frame(12);  // 0.4 s
  copies_centre(n0);
  EXPECT_EQ(n0, 0u) << "no copy before its time";
  d.draw_frame(21);  // 0.7 s
  const Vec3 c1 = copies_centre(n1);
  EXPECT_GT(n1, 0u);
  const double t = 0.5;
  const Vec3 exact(-1 + t, 0, 1 + 3 * t - 0.5 * 9.81 * t * t);
  EXPECT_NEAR(c1.x(), exact.x(), 1e-3);
  EXPECT_NEAR(c1.z(), exact.z(), 1e-3);
  d.draw_frame(36);  // 1.2 s: both copies
  copies_centre(n2);
  EXPECT_GT(n2, n1);
}

// Axes take vermillion, green and blue for e1 e2 e3; L (blue by default) and v (green) shown with
// them take other colours, and the legend never shows one colour for two meanings.
TEST(Systems, LegendColoursDoNotRepeat) {
  Drawn d(write_scene("colours.yaml",
                      "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
                      "video: { width: 320, height: 180 }\n"
                      "bodies:\n"
                      "  - { name: top, angular_velocity: [0.3, 0, 5], linear_velocity: [0.1, 0, 0],\n"
                      "      show: [ axes, angular_momentum, velocity, angular_velocity, momentum ],\n"
                      "      colliders: [ { shape: box, size: [0.4, 0.3, 0.1], mass: 1 } ] }\n"
                      "overlays: { legend: true }\n"));
  const SceneOverlays& o = *d.view->overlays;
  const Legend& l = o.legend();
  ASSERT_GE(l.items.size(), 7u);
  std::set<std::array<float, 3>> seen;
  for (const LegendEntry& e : l.items)
    EXPECT_TRUE(seen.insert(e.color).second) << e.text << " repeats a colour";
  const Rgba blue = okabe_ito(5), green = okabe_ito(3);
  EXPECT_NE(o.color_of(0, ShowKind::angular_momentum), blue);
  EXPECT_NE(o.color_of(0, ShowKind::velocity), green);
  EXPECT_EQ(o.color_of(0, ShowKind::angular_velocity), okabe_ito(7)) << "no conflict: its own colour";
  // Without axes, L keeps its blue.
  Drawn e(write_scene("colours2.yaml",
                      "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
                      "video: { width: 320, height: 180 }\n"
                      "bodies:\n"
                      "  - { name: top, angular_velocity: [0.3, 0, 5], show: [ angular_momentum ],\n"
                      "      colliders: [ { shape: box, size: [0.4, 0.3, 0.1], mass: 1 } ] }\n"));
  EXPECT_EQ(e.view->overlays->color_of(0, ShowKind::angular_momentum), blue);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// Labels of neighbouring bodies are pushed apart: four balls 12 cm apart in a row, each labelled,
// seen from 6 m (their labels, each wider than the gap, would sit on top of each other); no two
// boxes overlap, and each stays within a box height of where its body puts it.
TEST(Systems, LabelsOfNeighboursDoNotOverlap) {
  std::string text =
      "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
      "video: { width: 640, height: 360 }\n"
      "camera: { position: [0, -6, 0], look_at: [0, 0, 0] }\n"
      "bodies:\n"
      "  - { name: ball, position: [-0.18, 0, 0], repeat: { count: 4, step: [0.12, 0, 0] },\n"
      "      colliders: [ { shape: sphere, radius: 0.05 } ] }\n"
      "overlays:\n"
      "  labels:\n";
  for (int k = 1; k <= 4; ++k)
    text += "    - { body: ball_" + std::to_string(k) + ", text: 'ball number " + std::to_string(k) + "' }\n";
  Drawn d(write_scene("labels.yaml", text));
  d.draw_frame(0);
  const auto& boxes = d.view->overlays->label_boxes();
  ASSERT_EQ(boxes.size(), 4u);
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      const bool apart = std::fabs(boxes[i].x - boxes[j].x) >= 0.5 * (boxes[i].w + boxes[j].w) ||
                         std::fabs(boxes[i].y - boxes[j].y) >= 0.5 * (boxes[i].h + boxes[j].h);
      EXPECT_TRUE(apart) << "labels " << i << " and " << j;
    }
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// scenes/chaos_overlay.yaml: three variants with `overlay:` make no panes (one view), take three
// different default colours, advance with the main world, and are drawn over it as translucent
// copies of their moving bodies; at t = 0 they sit within 3e-6 rad of the main pendulum, by the end
// (14 s) they have gone their own ways.
TEST(Systems, OverlaidVariantsAreDrawnInTheSameView) {
  const Scene scene = load_scene("scenes/chaos_overlay.yaml");
  ASSERT_EQ(scene.views.variants.size(), 3u);
  EXPECT_FALSE(scene.views.split()) << "overlaid variants make no panes";
  std::set<std::array<float, 3>> colours;
  for (size_t k = 0; k < scene.views.variants.size(); ++k) {
    EXPECT_TRUE(scene.views.variants[k].overlay);
    const Rgba c = variant_color(scene.views, k);
    colours.insert({c[0], c[1], c[2]});
  }
  EXPECT_EQ(colours.size(), 3u);
  FrameLoop loop(scene, 1);
  ViewOptions o;
  o.width = 320, o.height = 180, o.aa = "none";
  SceneFrames frames(scene, loop, o);
  FrameLoop::Hooks h;
  h.frame = [&](const FrameTarget& t, const World& w) { frames.draw(w, nullptr, t.index); };
  std::vector<FrameTarget> targets{plan_target(loop.video_plan(), 0, scene.video.fps)};
  loop.run(targets, h, false);
  std::vector<const World*> worlds = frames.worlds();
  ASSERT_EQ(worlds.size(), 4u);
  const double lower0 = worlds[0]->centroid(1).z();
  for (const World* w : worlds) {
    EXPECT_EQ(w->time(), worlds[0]->time());
    EXPECT_NEAR(w->centroid(1).z(), lower0, 1e-5);
  }
  targets = {plan_target(loop.video_plan(), loop.video_plan().frames - 1, scene.video.fps)};
  loop.run(targets, h, false);
  worlds = frames.worlds();
  for (size_t k = 1; k < worlds.size(); ++k) {
    EXPECT_EQ(worlds[k]->time(), worlds[0]->time());
    EXPECT_GT((worlds[k]->centroid(1) - worlds[0]->centroid(1)).norm(), 0.05) << "variant " << k;
  }
  // The copies are in the frame: the same moment drawn without the variants differs in many pixels.
  const uint8_t* px = frames.draw(loop.world());
  const std::vector<uint8_t> with(px, px + 320 * 180 * 4);
  Scene alone = scene;
  alone.views = {};
  FrameLoop loop2(alone, 1);
  SceneFrames frames2(alone, loop2, o);
  loop2.run(targets, {}, false);
  const uint8_t* q = frames2.draw(loop2.world());
  int differ = 0;
  for (size_t i = 0; i < with.size(); i += 4)
    differ +=
        std::abs(with[i] - q[i]) + std::abs(with[i + 1] - q[i + 1]) + std::abs(with[i + 2] - q[i + 2]) > 60;
  EXPECT_GT(differ, 200) << "pixels where the variants' copies show";
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// The HUD's corner by default (`auto`): where the moving bodies are least. A ball starting in the
// top left of the view pushes the HUD to the top right; one in the middle leaves it top left; a
// corner the scene names is kept. With a pre-pass that runs anyway (an auto-scaled arrow) the
// paths count: a ball flying through both top corners sends it to the bottom; without one the HUD
// costs no physics pass and the start counts.
TEST(Systems, TheHudKeepsOutOfTheBodiesWay) {
  auto corner = [](const std::string& ball, const std::string& hud) {
    Drawn d(write_scene("hud_corner.yaml",
                        "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
                        "video: { width: 320, height: 180 }\n"
                        "camera: { position: [0, -6, 0], look_at: [0, 0, 0] }\n"
                        "bodies:\n"
                        "  - { name: ball, " +
                            ball +
                            ", colliders: [ { shape: sphere, radius: 0.3 } ] }\n"
                            "overlays: { hud: " +
                            hud + " }\n"));
    return d.view->overlays->hud_corner();
  };
  const std::string hud = "['t = {t:.2f} s', 'v = {|ball.v|:.2f} m/s']";
  EXPECT_EQ(corner("position: [-3.2, 0, 1.6]", hud), "top_right");
  EXPECT_EQ(corner("position: [0, 0, 0]", hud), "top_left");
  EXPECT_EQ(corner("position: [-3.2, 0, 1.6]", "{ corner: top_left, lines: " + hud + " }"), "top_left");
  EXPECT_EQ(corner("position: [3.2, 0, 1.6], linear_velocity: [-6.4, 0, 0], show: [velocity]", hud),
            "bottom_left")
      << "top left and top right both crossed: the bottom";
  EXPECT_EQ(corner("position: [3.2, 0, 1.6], linear_velocity: [-6.4, 0, 0]", hud), "top_left")
      << "no pre-pass: where it starts (top right) counts";
}

}  // namespace
}  // namespace simreel
