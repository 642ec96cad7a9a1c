// The `forces`, `contacts` and `joint_forces` show items: contact forces from the solver's impulses
// add up to what statics says they must, arrows start and end where the forces put them, scales come
// from the pre-pass, springs run from end to end and torques turn the right way.
#include <gtest/gtest.h>

#include <cmath>

#include "app/view/overlays.hpp"
#include "tests/app/view/overlay_fixtures.hpp"

namespace simreel {
namespace {

// Two boxes stacked on the ground, at rest from the start (touching, not overlapping).
const char* kStack =
    "simulation: { duration: 2, timestep: 0.004166666666666667 }\n"
    "video: { width: 320, height: 240, fps: 10 }\n"
    "render: { shadows: false }\n"
    "camera: { position: [2, -3, 1.2], look_at: [0, 0, 0.3] }\n"
    "ground: { height: 0 }\n"
    "bodies:\n"
    "  - { name: low, position: [0, 0, 0.15], colliders: [ { shape: box, size: [0.6, 0.6, 0.3], density: 500 "
    "} ],\n"
    "      show: [ contacts ] }\n"
    "  - { name: top, position: [0, 0, 0.4], colliders: [ { shape: box, size: [0.3, 0.3, 0.2], density: 800 "
    "} ],\n"
    "      show: [ contacts ] }\n";

TEST(OverlaysForces, ContactForcesOfAStackAtRestAreItsWeights) {
  Drawn d(write_scene("stack.yaml", kStack));
  d.draw_frame(15);  // t = 1.5 s
  const World& w = d.loop->world();
  const double g = 9.81, m_low = 0.6 * 0.6 * 0.3 * 500, m_top = 0.3 * 0.3 * 0.2 * 800;
  // On the top box: the low box pushes up with its weight, spread over its corners.
  Vec3 top = Vec3::Zero();
  int points = 0;
  visit_contacts(w, 1, [&](const Vec3& p, const Vec3& n, const Vec3& F) {
    top += F;
    ++points;
    EXPECT_NEAR(n.z(), 1, 1e-9) << "the normal points into the top box";
    EXPECT_NEAR(p.z(), 0.3, 1e-3) << "on the low box's top face";
  });
  EXPECT_EQ(points, 4);
  EXPECT_NEAR(top.z(), m_top * g, 1e-6 * m_top * g);
  EXPECT_LT(top.head<2>().norm(), 1e-6 * m_top * g) << "no friction at rest";
  // On the low box: the ground's push carries both weights; the top box pushes down with its own.
  Vec3 up = Vec3::Zero(), down = Vec3::Zero();
  visit_contacts(w, 0, [&](const Vec3&, const Vec3& n, const Vec3& F) { (n.z() > 0 ? up : down) += F; });
  EXPECT_NEAR(up.z(), (m_low + m_top) * g, 1e-6 * (m_low + m_top) * g);
  EXPECT_NEAR(down.z(), -m_top * g, 1e-6 * m_top * g);
}

TEST(OverlaysForces, ContactArrowsRunFromEachPointAlongItsForceAtOneSharedScale) {
  Drawn d(write_scene("stack.yaml", kStack));
  d.draw_frame(15);
  const World& w = d.loop->world();
  // At rest every point of a manifold carries the same share: the contact forces of the run are
  // m_top g / 4 (8 points: the top box's and the low box's side of them) and (m_low + m_top) g / 4
  // (4 points); the 90th percentile of those samples is the larger.
  const double g = 9.81, m_low = 0.6 * 0.6 * 0.3 * 500, m_top = 0.3 * 0.3 * 0.2 * 800;
  const double R_low = 0.5 * Vec3(0.6, 0.6, 0.3).norm(), R_top = 0.5 * Vec3(0.3, 0.3, 0.2).norm();
  const double scale = d.view->overlays->arrow_scale(0, ShowKind::contacts);
  EXPECT_NEAR(scale, kContactReach * 0.5 * (R_low + R_top) / ((m_low + m_top) * g / 4), 1e-5 * scale);
  EXPECT_EQ(d.view->overlays->arrow_scale(1, ShowKind::contacts), scale) << "one scale for the pile";
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(w, 15, dl);
  // 12 arrows (4 ground points on the low box, 4 + 4 on the two sides of the stack's contact):
  // each a shaft and a head, the head's tip at p + scale F.
  const auto& cones = dl.overlay.instances[(int)OverlayShape::cone];
  ASSERT_EQ(cones.size(), 12u);
  std::vector<Vec3> tips;
  for (int b : {0, 1})
    visit_contacts(w, b, [&](const Vec3& p, const Vec3&, const Vec3& F) { tips.push_back(p + scale * F); });
  ASSERT_EQ(tips.size(), 12u);
  for (size_t k = 0; k < tips.size(); ++k) {
    const Vec3 tip = (cones[k].model.cast<double>() * Eigen::Vector4d(0, 0, 1, 1)).head<3>();
    EXPECT_LT((tip - tips[k]).norm(), 1e-5) << "arrow " << k;
  }
  // The points (dots) and normals (rods) are there too: 12 dots.
  EXPECT_EQ(dl.overlay.instances[(int)OverlayShape::sphere].size(), 12u);
}

const char* kPushed =
    "simulation: { duration: 1, timestep: 0.005, gravity: [0, 0, 0] }\n"
    "video: { width: 320, height: 240, fps: 20 }\n"
    "render: { shadows: false, antialiasing: msaa4 }\n"
    "camera: { position: [0.4, -3, 0.6], look_at: [0, 0, 0.4], fov: 40 }\n"
    "bodies:\n"
    "  - name: box\n"
    "    color: [0.05, 0.05, 0.05]\n"
    "    colliders: [ { shape: box, size: [0.3, 0.2, 0.25], density: 1000 } ]\n"
    "    show: [ { forces: { color: [1, 0, 1], scale: 0.08, xray: 0 } } ]\n"
    "forces:\n"
    "  - { type: force, body: box, vector: [3, 0, 6], at: [0.15, 0, 0.05] }\n";

TEST(OverlaysForces, ForceArrowStartsAtItsPointAndEndsWithinAPixelOfItsTip) {
  Drawn d(write_scene("pushed.yaml", kPushed), "msaa4");
  for (long k : {0L, 8L}) {
    d.draw_frame(k);
    g_sky = d.px(0, 0);
    const World& w = d.loop->world();
    const Vec3 at = w.local_to_world(0, Vec3(0.15, 0, 0.05));
    expect_tip(d, magenta, at, at + 0.08 * Vec3(3, 0, 6), "force");
  }
}

TEST(OverlaysForces, ForceAndTorqueScalesComeFromThePrePass) {
  // A force switched on at 0.5 s and a torque: their largest magnitudes over the run are drawn
  // kForceReach body radii long; with `gravity` the weight counts too.
  const std::string path = write_scene("scales.yaml",
                                       "simulation: { duration: 1, timestep: 0.005 }\n"
                                       "video: { width: 64, height: 48 }\n"
                                       "bodies:\n"
                                       "  - { name: a, colliders: [ { shape: box, size: [0.4, 0.2, 0.2], "
                                       "density: 100 } ], show: [ forces ] }\n"
                                       "  - { name: b, position: [2, 0, 0], colliders: [ { shape: box, size: "
                                       "[0.4, 0.2, 0.2], density: 100 } ],\n"
                                       "      show: [ { forces: { gravity: true } } ] }\n"
                                       "forces:\n"
                                       "  - { type: force, body: a, vector: [0, 30, 40], from: 0.5 }\n"
                                       "  - { type: torque, body: a, vector: [0, 0, 2] }\n"
                                       "  - { type: force, body: b, vector: [1, 0, 0] }\n");
  Drawn d(path);
  const double R = 0.5 * Vec3(0.4, 0.2, 0.2).norm(), m = 0.4 * 0.2 * 0.2 * 100;
  const SceneOverlays& o = *d.view->overlays;
  EXPECT_NEAR(o.arrow_scale(0, ShowKind::forces), kForceReach * R / 50, 1e-6 * R);
  EXPECT_NEAR(o.arrow_scale(0, ShowKind::forces, true), kForceReach * R / 2, 1e-6 * R);
  EXPECT_NEAR(o.arrow_scale(1, ShowKind::forces), kForceReach * R / (m * 9.81), 1e-6 * R);
  // Before 0.5 s the force is off: the torque alone is drawn (a double-headed arrow and an arc).
  d.draw_frame(2);
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(d.loop->world(), 2, dl);
  const auto& rods = dl.overlay.instances[(int)OverlayShape::cylinder];
  // body a: the torque's shaft and 18 arc rods; body b: its force's shaft and its weight's.
  ASSERT_EQ(rods.size(), 1u + 18u + 2u);
  // The arc turns right-handed about the torque (+z): each rod goes anticlockwise seen from +z.
  const Vec3 c = d.loop->world().centroid(0);
  const Vec3 mid = c + 0.45 * kForceReach * R * Vec3::UnitZ();
  for (int k = 1; k <= 18; ++k) {
    const Eigen::Matrix4d M = rods[k].model.cast<double>();
    const Vec3 from = M.block<3, 1>(0, 3), along = M.block<3, 1>(0, 2);
    EXPECT_GT((from - mid).cross(along).z(), 0) << "rod " << k;
    EXPECT_NEAR((from - mid).z(), 0, 1e-5);
  }
}

TEST(OverlaysForces, SpringsRunFromEndToEndAndAreDrawnOnce) {
  const std::string path =
      write_scene("springs.yaml",
                  "simulation: { duration: 1, timestep: 0.005, gravity: [0, 0, 0] }\n"
                  "video: { width: 64, height: 48 }\n"
                  "bodies:\n"
                  "  - { name: a, colliders: [ { shape: sphere, radius: 0.1 } ], show: [ forces ] }\n"
                  "  - { name: b, position: [1, 0, 0], colliders: [ { shape: sphere, radius: 0.1 } ], show: "
                  "[ forces ] }\n"
                  "forces:\n"
                  "  - { type: spring, bodies: [a, b], points: [[0, 0, 0.1], [0, 0, 0]], stiffness: 10, "
                  "rest_length: 0.5 }\n"
                  "  - { type: spring, body: b, anchor: [1, 0, 2], stiffness: 5 }\n");
  Drawn d(path);
  d.draw_frame(7);
  const World& w = d.loop->world();
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(w, 7, dl);
  const auto& v = dl.overlay.ribbons;
  // Two springs of 18 points each: 17 quads of 6 vertices.
  ASSERT_EQ(v.size(), 2u * 17u * 6u);
  auto centre = [&](size_t a, size_t b) {
    return Vec3((v[a].pos[0] + v[b].pos[0]) / 2, (v[a].pos[1] + v[b].pos[1]) / 2,
                (v[a].pos[2] + v[b].pos[2]) / 2);
  };
  const size_t last = 17 * 6 - 6;  // the first spring's last quad
  EXPECT_LT((centre(0, 1) - w.local_to_world(0, Vec3(0, 0, 0.1))).norm(), 1e-5);
  EXPECT_LT((centre(last + 2, last + 5) - w.centroid(1)).norm(), 1e-5);
  EXPECT_LT((centre(17 * 6, 17 * 6 + 1) - w.centroid(1)).norm(), 1e-5);
  EXPECT_LT((centre(2 * 17 * 6 - 4, 2 * 17 * 6 - 1) - Vec3(1, 0, 2)).norm(), 1e-5);
}

// `springs: line` draws each spring as one straight segment from end to end (strings).
TEST(OverlaysForces, SpringsAsLinesAreOneSegmentFromEndToEnd) {
  const std::string path =
      write_scene("spring_lines.yaml",
                  "simulation: { duration: 1, timestep: 0.005, gravity: [0, 0, 0] }\n"
                  "video: { width: 64, height: 48 }\n"
                  "bodies:\n"
                  "  - { name: b, position: [1, 0, 0], colliders: [ { shape: sphere, radius: 0.1 } ], show: "
                  "[ { forces: { springs: line, arrows: false } } ] }\n"
                  "forces:\n"
                  "  - { type: spring, body: b, anchor: [1, 0, 2], stiffness: 5 }\n");
  Drawn d(path);
  d.draw_frame(7);
  const World& w = d.loop->world();
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(w, 7, dl);
  const auto& v = dl.overlay.ribbons;
  ASSERT_EQ(v.size(), 6u);  // one quad
  auto centre = [&](size_t a, size_t b) {
    return Vec3((v[a].pos[0] + v[b].pos[0]) / 2, (v[a].pos[1] + v[b].pos[1]) / 2,
                (v[a].pos[2] + v[b].pos[2]) / 2);
  };
  EXPECT_LT((centre(0, 1) - w.centroid(0)).norm(), 1e-5);
  EXPECT_LT((centre(2, 5) - Vec3(1, 0, 2)).norm(), 1e-5);
}

// A bar hinged to the world at its end with a torsion spring, released horizontal, seen from the
// front (the hinge axis +y points away from the camera).
std::string sprung_hinge(const std::string& show) {
  return "simulation: { duration: 1.5 }\n"
         "video: { width: 320, height: 240, fps: 20 }\n"
         "render: { shadows: false, antialiasing: none }\n"
         "camera: { position: [0.2, -2.6, 1.8], look_at: [0.2, 0, 1.8], fov: 40 }\n"
         "bodies:\n"
         "  - { name: arm, position: [0.3, 0, 2], color: [0.1, 0.1, 0.1],\n"
         "      colliders: [ { shape: box, size: [0.6, 0.03, 0.03], density: 7850 } ]" +
         show +
         " }\n"
         "joints:\n"
         "  - { name: hinge, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0],\n"
         "      spring: { stiffness: 20 } }\n";
}

// `joint_forces`: World::joint_reaction's force as an arrow from the anchor (where the child carries
// it) and its torque as a double-headed arrow from there, each scaled so that the run's largest
// (from the pre-pass, every step) is kForceReach body radii long, round-off aside (kReactionFloor).
// Nothing is drawn where the reaction is zero: the test holds whatever the World reports.
TEST(OverlaysForces, JointForcesDrawTheReactionAtTheAnchorAtThePrePassScale) {
  Drawn with(write_scene("reaction_on.yaml",
                         sprung_hinge(",\n      show: [ { joint_forces: { color: [1, 0, 1] } } ]"))),
      without(write_scene("reaction_off.yaml", sprung_hinge("")));
  // The largest reaction, speed and rate of turn over the run, step by step.
  double bigF = 0, bigT = 0, v = 0, om = 0;
  {
    FrameLoop loop(with.scene, 1);
    FrameLoop::Hooks h;
    h.step = [&](const World& w) {
      Vec3 F, T;
      w.joint_reaction(0, F, T);
      bigF = std::max(bigF, F.norm());
      bigT = std::max(bigT, T.norm());
      v = std::max(v, w.linear_velocity(0).norm());
      om = std::max(om, w.angular_velocity(0).norm());
    };
    loop.run({}, h, true);
  }
  const double R = 0.5 * Vec3(0.6, 0.03, 0.03).norm(), m = 0.6 * 0.03 * 0.03 * 7850;
  const double fref = m * (9.81 + v * v / R + om * om * R), tref = std::max(fref, bigF) * R;
  const SceneOverlays& o = *with.view->overlays;
  const double s = o.arrow_scale(0, ShowKind::joint_forces),
               st = o.arrow_scale(0, ShowKind::joint_forces, true);
  if (bigF > kReactionFloor * fref) {
    EXPECT_NEAR(s, kForceReach * R / bigF, 1e-6 * s);
  } else {
    EXPECT_EQ(s, 0);
  }
  if (bigT > kReactionFloor * tref) {
    EXPECT_NEAR(st, kForceReach * R / bigT, 1e-6 * st);
  } else {
    EXPECT_EQ(st, 0);
  }
  const long k = 6;  // 0.3 s
  with.draw_frame(k);
  without.draw_frame(k);
  const World& w = with.loop->world();
  Vec3 F, T;
  w.joint_reaction(0, F, T);
  const Vec3 p = w.local_to_world(0, Vec3(-0.3, 0, 0));  // the anchor, carried by the bar
  EXPECT_LT((p - Vec3(0, 0, 2)).norm(), 1e-9);
  DrawList dl;
  dl.camera = with.view->camera;
  with.view->overlays->build(w, k, dl);
  std::vector<Vec3> tips;  // every cone's tip (arrow heads)
  for (const OverlayInstance& c : dl.overlay.instances[(int)OverlayShape::cone])
    tips.push_back((c.model.cast<double>() * Eigen::Vector4d(0, 0, 1, 1)).head<3>());
  auto nearest_tip = [&](const Vec3& x) {
    double best = 1e9;
    for (const Vec3& t : tips) best = std::min(best, (t - x).norm());
    return best;
  };
  const CameraView& cam = with.view->camera;
  int drawn = 0;
  for (int y = 0; y < with.h(); ++y)
    for (int x = 0; x < with.w(); ++x) drawn += with.px(x, y) != without.px(x, y);
  if (s > 0 && (s * F).norm() > 0.02) {
    EXPECT_LT(nearest_tip(p + s * F), 1e-5) << "the force's head ends at the anchor + scale F";
    const Eigen::Vector2d mid = project_to_pixel(cam, with.w(), with.h(), p + 0.5 * s * F);
    EXPECT_NE(with.px((int)mid.x(), (int)mid.y()), without.px((int)mid.x(), (int)mid.y())) << "its shaft";
  }
  if (st > 0 && (st * T).norm() > 0.02) {
    EXPECT_LT(nearest_tip(p + st * T), 1e-5) << "the torque's head";
  }
  if (!(s > 0) && !(st > 0)) {
    EXPECT_TRUE(dl.overlay.empty()) << "a zero reaction draws nothing";
    EXPECT_EQ(drawn, 0);
  } else {
    EXPECT_GT(drawn, 20);
  }
}

}  // namespace
}  // namespace simreel
