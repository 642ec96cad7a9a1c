// Teaching overlays drawn as `simreel render` and `check` draw them: arrows end at the
// projected point of their quantity, trails pass through the positions `simreel simulate --csv`
// reports, HUD text sits where the font puts it and is not blurred by FXAA, and frames with
// overlays are the same bytes across runs, thread counts and partial renders.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/runner/frame_loop.hpp"
#include "app/view/overlays.hpp"
#include "app/view/scene_view.hpp"
#include "render/camera.hpp"
#include "tests/app/view/overlay_fixtures.hpp"

namespace simreel {
namespace {

const char* kArrows =
    "simulation: { duration: 1, timestep: 0.005, gravity: [0, 0, 0] }\n"
    "video: { width: 320, height: 240, fps: 20 }\n"
    "render: { sky: flat, shadows: false, antialiasing: msaa4 }\n"
    "camera: { position: [0.4, -3, 0.6], look_at: [0, 0, 0.4], fov: 40 }\n"
    "bodies:\n"
    "  - name: box\n"
    "    angular_velocity: [0.6, 0, 2]\n"
    "    linear_velocity: [1, 0, 0.3]\n"
    "    color: [0.05, 0.05, 0.05]\n"
    "    colliders: [ { shape: box, size: [0.3, 0.2, 0.25], density: 1000 } ]\n"
    "    show:\n"
    "      - { angular_velocity: { color: [1, 0, 1], scale: 0.55, width: 2 } }\n"
    "      - { velocity: { color: [0, 1, 1], width: 2 } }\n";

TEST(Overlays, ArrowTipsLandOnTheProjectedPointWithinAPixel) {
  Drawn d(write_scene("arrows.yaml", kArrows), "msaa4");
  for (long k : {0L, 10L}) {
    d.draw_frame(k);
    g_sky = d.px(0, 0);
    const World& w = d.loop->world();
    const Vec3 c = w.centroid(0);
    expect_tip(d, magenta, c, c + 0.55 * w.angular_velocity(0), "omega");
    // The velocity arrow scales itself: the run's largest |v| (constant here) is kArrowReach body radii.
    const double R = 0.5 * Vec3(0.3, 0.2, 0.25).norm();
    const double scale = d.view->overlays->arrow_scale(0, ShowKind::velocity);
    EXPECT_NEAR(scale, kArrowReach * R / Vec3(1, 0, 0.3).norm(), 1e-7);  // R from the float render mesh
    expect_tip(d, cyan, c, c + scale * w.linear_velocity(0), "v");
  }
}

TEST(Overlays, AngularMomentumScaleComesFromThePrePass) {
  // A torque-free box tumbling about no principal axis: |omega| changes over the run, |L| does not.
  const std::string path =
      write_scene("prepass.yaml",
                  "simulation: { duration: 3, timestep: 0.002, gravity: [0, 0, 0] }\n"
                  "video: { width: 64, height: 48 }\n"
                  "bodies:\n"
                  "  - { name: b, angular_velocity: [3, 0.2, 1.5],\n"
                  "      colliders: [ { shape: box, size: [1, 0.5, 0.2], density: 10 } ],\n"
                  "      show: [ angular_momentum, angular_velocity ] }\n");
  Drawn d(path);
  const World& w = d.loop->world();
  const double R = 0.5 * Vec3(1, 0.5, 0.2).norm();
  EXPECT_NEAR(d.view->overlays->arrow_scale(0, ShowKind::angular_momentum),
              kArrowReach * R / w.angular_momentum(0).norm(),
              1e-6 * kArrowReach * R / w.angular_momentum(0).norm());
  // omega's largest magnitude is over every step of the run, not the initial one.
  const std::vector<Magnitudes> m = measure_magnitudes(d.scene, 1);
  EXPECT_GE(m[0].omega, w.angular_velocity(0).norm());
  EXPECT_NEAR(d.view->overlays->arrow_scale(0, ShowKind::angular_velocity), kArrowReach * R / m[0].omega,
              1e-6 * kArrowReach * R / m[0].omega);
}

const char* kTrail =
    "simulation: { duration: 2, timestep: 0.004166666666666667 }\n"
    "video: { width: 320, height: 240, fps: 30 }\n"
    "render: { sky: flat, shadows: false, antialiasing: none }\n"
    "camera: { position: [1, -9, 2], look_at: [1, 0, 1.5], fov: 45 }\n"
    "bodies:\n"
    "  - name: ball\n"
    "    position: [-1.5, 0, 0.5]\n"
    "    linear_velocity: [2.5, 0, 6]\n"
    "    angular_velocity: [0, 4, 1]\n"
    "    color: [0.9, 0.9, 0.9]\n"
    "    colliders: [ { shape: box, size: [0.2, 0.2, 0.2], density: 100 } ]\n"
    "    show:\n"
    "      - { trail: { point: [0.1, 0, 0.05], frame: body, length: 1.0, color: [0, 0, 0] } }\n";

// A trail as long as a 1e7-step run holds at most kMaxTrailPoints samples, spread over the whole
// length (was: 120 a second, 150 MB for a Poinsot trail); a short run keeps 120 samples a second.
TEST(Overlays, TrailMemoryIsBoundedOnLongRuns) {
  const auto trail_of = [&](const std::string& duration) {
    std::string text = kTrail;
    text.replace(text.find("length: 1.0"), 11, "length: 1e6");
    text = "simulation: { duration: " + duration + ", timestep: 0.001 }\n" + text.substr(text.find('\n') + 1);
    const std::string path = write_scene("long_trail.yaml", text);
    const Scene scene = load_scene(path);
    FrameLoop loop(scene, 1);
    SceneOverlays o(scene, loop.world(), std::vector<double>(1, 0.2), 320, 180, 1);
    return std::make_pair(o.trail_capacity(0), o.trail_every(0));
  };
  const auto [cap_long, every_long] = trail_of("10000");  // 1e7 steps
  EXPECT_LE(cap_long, (size_t)kMaxTrailPoints + 3);
  EXPECT_GE(cap_long, (size_t)(0.99 * kMaxTrailPoints)) << "the whole length is still sampled";
  EXPECT_EQ(every_long, (10000000 + kMaxTrailPoints - 1) / kMaxTrailPoints);
  const auto [cap_short, every_short] = trail_of("3");
  EXPECT_EQ(every_short, 8) << "120 samples a second at dt 1 ms";
  EXPECT_EQ(cap_short, (size_t)(3000 / 8 + 3));
}

TEST(Overlays, TrailPassesThroughThePositionsSimulateReports) {
  const std::string path = write_scene("trail.yaml", kTrail);
  const fs::path csv = test::scratch("trail.csv");
  ASSERT_EQ(run("simulate " + path + " --quiet --csv " + csv.string()), 0);
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  // t, and the traced body point from the CSV's body origin (px py pz) and orientation (qw .. qz).
  std::vector<std::pair<double, Vec3>> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[9];
    for (auto& x : f) std::getline(ss, x, ',');
    const Quat q(std::stod(f[5]), std::stod(f[6]), std::stod(f[7]), std::stod(f[8]));
    rows.push_back(
        {std::stod(f[0]), Vec3(std::stod(f[2]), std::stod(f[3]), std::stod(f[4])) + q * Vec3(0.1, 0, 0.05)});
  }
  Drawn d(path);
  const long k = 45;  // t = 1.5 s: the trail shows 0.5 .. 1.5 s
  d.draw_frame(k);
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(d.loop->world(), k, dl);
  const auto& v = dl.overlay.ribbons;
  ASSERT_GE(v.size(), 6u);
  std::vector<Vec3> centre;  // the ribbon's centre line: the traced points
  for (size_t q = 0; q < v.size(); q += 6) {
    centre.push_back(
        Vec3(v[q].pos[0] + v[q + 1].pos[0], v[q].pos[1] + v[q + 1].pos[1], v[q].pos[2] + v[q + 1].pos[2]) /
        2);
    if (q + 6 == v.size())
      centre.push_back(Vec3(v[q + 2].pos[0] + v[q + 5].pos[0], v[q + 2].pos[1] + v[q + 5].pos[1],
                            v[q + 2].pos[2] + v[q + 5].pos[2]) /
                       2);
  }
  int checked = 0, dark = 0;
  for (const auto& [t, p] : rows) {
    if (t < 0.5 - 1e-9 || t > 1.5 + 1e-9) {
      if (t < 0.45) {  // older than the trail's length: not in it
        double nearest = 1e9;
        for (const Vec3& c : centre) nearest = std::min(nearest, (c - p).norm());
        EXPECT_GT(nearest, 0.01) << "t = " << t << " is older than the trail";
      }
      continue;
    }
    double nearest = 1e9;
    for (const Vec3& c : centre) nearest = std::min(nearest, (c - p).norm());
    EXPECT_LT(nearest, 2e-5) << "t = " << t;  // float vertices
    ++checked;
    // And in the picture: the trail's pixel there is darker than the sky (older parts fade).
    if (t < 1.35) {
      const Eigen::Vector2d q = project_to_pixel(d.view->camera, d.w(), d.h(), p);
      const auto c = d.px((int)q.x(), (int)q.y());
      dark += c[0] + c[1] + c[2] < 3 * 190;
    }
  }
  EXPECT_EQ(checked, 31);  // 0.5 .. 1.5 s at 30 fps
  EXPECT_GE(dark, 22) << "of 26 points the trail should darken most (the oldest are faint)";
}

// Partial render == full render, --at == the frame, any --threads and LP_NUM_THREADS, run twice:
// with a trail (history from the physics steps), arrows and a HUD (post stage on the writer's
// thread for --frames-dir, in the renderer for --at).
TEST(Overlays, FramesAreTheSameBytesAcrossRunsThreadsAndPartialRenders) {
  const std::string path = write_scene(
      "det.yaml", std::string(kTrail) +
                      "      - angular_velocity\n      - axes\n"
                      "overlays: { title: Test, hud: [\"t = {t:.2f} s  ω = {|omega|:.3f}  {frame}\"],\n"
                      "  captions: [ { text: 'x_1 \\cdot \\vec{L}', from: 1.2, to: 1.8 } ], legend: true,\n"
                      "  labels: [ { body: ball, text: '\\omega_{ball}' } ],\n"
                      "  plots: [ { quantities: [omega_body.x, '|v|'], rect: [0.5, 0.6, 0.48, 0.38] } ] }\n");
  const fs::path full = test::scratch("det_full"), part = test::scratch("det_part"),
                 t4 = test::scratch("det_t4"), at = test::scratch("det_at.png");
  for (const fs::path& p : {full, part, t4}) fs::remove_all(p);
  ASSERT_EQ(run("render " + path + " --no-video --quiet --frames-dir " + full.string()), 0);
  ASSERT_EQ(run("render " + path + " --no-video --quiet --frames 40:42,50 --frames-dir " + part.string()), 0);
  ASSERT_EQ(
      run("render " + path + " --no-video --quiet --threads 3 --frames 40:42,50 --frames-dir " + t4.string(),
          "LP_NUM_THREADS=1"),
      0);
  ASSERT_EQ(run("render " + path + " --quiet --at 1.4 -o " + at.string(), "LP_NUM_THREADS=4"), 0);
  for (const char* n : {"frame_00040.png", "frame_00041.png", "frame_00042.png", "frame_00050.png"}) {
    const std::string f = slurp(full / n);
    ASSERT_FALSE(f.empty()) << n;
    EXPECT_TRUE(f == slurp(part / n)) << n << ": partial render";
    EXPECT_TRUE(f == slurp(t4 / n)) << n << ": --threads 3, LP_NUM_THREADS=1";
  }
  EXPECT_TRUE(slurp(at) == slurp(full / "frame_00042.png")) << "--at 1.4 is frame 42";
  // llvmpipe at a 128-bit vector width (a CI runner's CPU without AVX2 uses it): the arrows' instanced
  // draw aborted there ("double free or corruption" in Mesa 22.3.6) while a 1-float per-instance
  // attribute was part of it; now x-ray travels in the model matrix's spare element.
  const fs::path narrow = test::scratch("det_128.png");
  ASSERT_EQ(run("render " + path + " --quiet --at 1.4 -o " + narrow.string(), "LP_NATIVE_VECTOR_WIDTH=128"),
            0);
  EXPECT_FALSE(slurp(narrow).empty());
  EXPECT_FALSE(slurp(full / "frame_00040.png") == slurp(full / "frame_00041.png"));
  fs::remove_all(part);
  ASSERT_EQ(run("render " + path + " --no-video --quiet --frames 40:42,50 --frames-dir " + part.string()), 0);
  EXPECT_TRUE(slurp(full / "frame_00050.png") == slurp(part / "frame_00050.png")) << "a second run";
}

const char* kHud =
    "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
    "video: { width: 480, height: 270, fps: 10 }\n"
    "render: { sky: flat, shadows: false }\n"
    "camera: { position: [2, -6, 1.5], look_at: [0, 0, 0] }\n"
    "bodies:\n"
    "  - { name: b, angular_velocity: [0, 0, 1], colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
    "overlays:\n"
    "  hud: [\"Hello ω₃ = {omega.z:+.2f}\"]\n";

TEST(Overlays, HudGlyphsAppearWhereTheFontPutsThemAndStayCrispAfterFxaa) {
  const std::string path = write_scene("hud.yaml", kHud);
  Drawn with(path, "fxaa"), without(path, "none");
  with.draw_frame(0);
  without.draw_frame(0);
  // Where the glyphs go: the same layout made here from the font and the HUD's text.
  Font f(default_font_path(), 10);  // 3.2% of the height, at least 10 px
  ScreenLayer expect;
  const int pad = f.pixel_size() / 2, margin = pad;
  f.draw("Hello ω₃ = +1.00", margin + pad, margin + pad + f.ascent(), {255, 255, 255, 255}, &expect);
  ASSERT_EQ(expect.glyphs.size(), 13u);  // spaces have no bitmap
  int inked = 0, total = 0;
  for (const ScreenGlyph& g : expect.glyphs)
    for (int y = 0; y < g.bitmap->height; ++y)
      for (int x = 0; x < g.bitmap->width; ++x) {
        if (g.bitmap->coverage[(size_t)y * g.bitmap->width + x] < 255) continue;
        ++total;
        inked += with.px(g.x + x, g.y + y) == std::array<int, 3>{255, 255, 255};  // white ink, fully covered
      }
  EXPECT_EQ(inked, total) << "every fully covered glyph pixel is white";
  // Crisp: the HUD panel (over flat sky) is the same with and without FXAA. Were the text
  // anti-aliased, FXAA would blur its edges.
  const int x1 = margin + 2 * pad + f.width("Hello ω₃ = +1.00"), y1 = margin + 2 * pad + f.line_height();
  int differ = 0;
  for (int y = 0; y < y1; ++y)
    for (int x = 0; x < x1; ++x) differ += with.px(x, y) != without.px(x, y);
  EXPECT_EQ(differ, 0);
  // And the body's edges are anti-aliased (FXAA is on): the frames do differ elsewhere.
  EXPECT_NE(with.frame, without.frame);
}

// The body cone (about the symmetry axis) and the space cone (about L) touch along omega: omega's
// direction at the cones' slant lies on both base circles; the space cone stays put.
TEST(Overlays, BodyAndSpaceConesMeetAlongOmegaAndTheSpaceConeStandsStill) {
  const std::string path =
      write_scene("cones.yaml",
                  "simulation: { duration: 2, gravity: [0, 0, 0] }\n"
                  "video: { width: 64, height: 48 }\n"
                  "bodies:\n"
                  "  - { name: disc, orientation: [0.9659258262890683, 0.25881904510252074, 0, 0],\n"
                  "      angular_velocity: [0, 0, 4],\n"
                  "      colliders: [ { shape: cylinder, radius: 0.6, height: 0.08 } ],\n"
                  "      show: [ { cones: { scale: 0.8 } } ] }\n");
  Drawn d(path);
  Eigen::Matrix4f space0 = Eigen::Matrix4f::Zero();
  for (long k : {0L, 17L, 45L}) {
    d.draw_frame(k);
    DrawList dl;
    dl.camera = d.view->camera;
    d.view->overlays->build(d.loop->world(), k, dl);
    const auto& cones = dl.overlay.instances[(int)OverlayShape::cone];
    ASSERT_EQ(cones.size(), 2u);
    const World& w = d.loop->world();
    const Vec3 p = w.centroid(0) + 0.8 * w.angular_velocity(0).normalized();  // on the contact line
    for (const OverlayInstance& c : cones) {
      const Eigen::Vector4d q = c.model.cast<double>().inverse() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1);
      EXPECT_NEAR(q.z(), 0, 1e-5) << "frame " << k;                     // on the base's plane
      EXPECT_NEAR(std::hypot(q.x(), q.y()), 1, 1e-5) << "frame " << k;  // on its rim
    }
    if (k == 0) space0 = cones[1].model;
    EXPECT_LT((cones[1].model - space0).cwiseAbs().maxCoeff(), 1e-5) << "the space cone moved by frame " << k;
    if (k > 0) {
      EXPECT_GT((cones[0].model.col(2) - space0.col(2)).norm(), 1e-3) << "the body cone turns";
    }
  }
}

// Poinsot: omega (scaled) touches the energy ellipsoid and the invariable plane; the herpolhode
// stays in the plane and the polhode on the ellipsoid, over the whole run so far.
TEST(Overlays, PoinsotContactPointPolhodeAndHerpolhodeLieOnTheEllipsoidAndThePlane) {
  const std::string path =
      write_scene("poinsot.yaml",
                  "simulation: { duration: 3, gravity: [0, 0, 0] }\n"
                  "video: { width: 64, height: 48 }\n"
                  "bodies:\n"
                  "  - { name: brick, angular_velocity: [0.9, 0.7, 3.0],\n"
                  "      colliders: [ { shape: box, size: [0.8, 0.5, 0.25], density: 600 } ],\n"
                  "      show: [ poinsot ] }\n");
  Drawn d(path);
  d.draw_frame(80);
  DrawList dl;
  dl.camera = d.view->camera;
  const World& w = d.loop->world();
  d.view->overlays->build(w, 80, dl);
  const auto& spheres = dl.overlay.instances[(int)OverlayShape::sphere];
  ASSERT_EQ(spheres.size(), 2u);  // the ellipsoid and the contact point
  const Eigen::Matrix4d E = spheres[0].model.cast<double>(), Einv = E.inverse();
  const Vec3 c = w.centroid(0), L = w.angular_momentum(0), n = L.normalized();
  const Vec3 contact = spheres[1].model.cast<double>().block<3, 1>(0, 3);
  EXPECT_NEAR((Einv * contact.homogeneous()).head<3>().norm(), 1.0, 1e-5)
      << "the contact point is on the ellipsoid";
  const double k = d.view->overlays->arrow_scale(0, ShowKind::poinsot);
  EXPECT_LT((contact - (c + k * w.angular_velocity(0))).norm(), 1e-6) << "the contact point is k omega";
  // The plane: 2 triangles, its centre at 2T/|L| k along L.
  const auto& rib = dl.overlay.ribbons;
  const Vec3 q0(rib[0].pos[0], rib[0].pos[1], rib[0].pos[2]);
  const double plane = (q0 - c).dot(n);
  EXPECT_NEAR((contact - c).dot(n), plane, 1e-5) << "the contact point is on the plane";
  // The ribbons after the plane's 6 vertices: the polhode's, then the herpolhode's.
  ASSERT_GT(rib.size(), 6u + 12u);
  int on_plane = 0, on_ellipsoid = 0, total = 0;
  for (size_t q = 6; q < rib.size(); q += 6) {
    const Vec3 p = Vec3(rib[q].pos[0] + rib[q + 1].pos[0], rib[q].pos[1] + rib[q + 1].pos[1],
                        rib[q].pos[2] + rib[q + 1].pos[2]) /
                   2;
    ++total;
    on_plane += std::fabs((p - c).dot(n) - plane) < 2e-5;
    on_ellipsoid += std::fabs((Einv * p.homogeneous()).head<3>().norm() - 1.006) < 2e-5;  // drawn 0.6% out
    if (std::fabs((p - c).dot(n) - plane) >= 2e-5 &&
        std::fabs((Einv * p.homogeneous()).head<3>().norm() - 1.006) >= 2e-5)
      ADD_FAILURE() << "point " << q / 6 << " is on neither: " << (p - c).dot(n) - plane
                    << " from the plane, " << (Einv * p.homogeneous()).head<3>().norm() << " ellipsoid radii";
  }
  EXPECT_GT(on_plane, total / 3) << "the herpolhode";
  EXPECT_GT(on_ellipsoid, total / 3) << "the polhode";
  EXPECT_GE(on_plane + on_ellipsoid, total);  // near the contact point the polhode is on the plane too
}

// A double pendulum seen from the front and a little to the side; the lower bar shows its joint
// (the elbow) or not.
std::string jointed(const std::string& show) {
  return "simulation: { duration: 1 }\n"
         "video: { width: 320, height: 240, fps: 20 }\n"
         "render: { sky: flat, shadows: false, antialiasing: none }\n"
         "camera: { position: [1.4, -3, 2.6], look_at: [0.6, 0, 1.7], fov: 40 }\n"
         "bodies:\n"
         "  - { name: upper, position: [0.3, 0, 2], color: [0.1, 0.1, 0.1],\n"
         "      colliders: [ { shape: box, size: [0.6, 0.03, 0.03], density: 7850 } ] }\n"
         "  - { name: lower, position: [0.9, 0, 2], color: [0.1, 0.1, 0.1],\n"
         "      colliders: [ { shape: box, size: [0.6, 0.03, 0.03], density: 7850 } ]" +
         show +
         " }\n"
         "joints:\n"
         "  - { name: shoulder, type: revolute, bodies: [world, upper], anchor: [0, 0, 2], axis: [0, 1, 0] "
         "}\n"
         "  - { name: elbow, type: revolute, bodies: [upper, lower], anchor: [0.6, 0, 2], axis: [0, 1, 0] "
         "}\n";
}

// `joints`: a ball at the pivot, where the child carries the anchor (its point at t = 0, in the
// child's frame), and the hinge axis as an arrow through it along +axis, `scale` long. What the
// item adds to the frame (the pixels that differ from the frame without it) is the ball around
// the projected pivot and the arrow, whose far end lands on the projected tip.
TEST(Overlays, TheJointsItemDrawsThePivotWhereTheChildCarriesIt) {
  Drawn with(write_scene("joint_on.yaml",
                         jointed(",\n      show: [ { joints: { color: [1, 0, 1], scale: 0.4 } } ]"))),
      without(write_scene("joint_off.yaml", jointed("")));
  const long k = 12;  // 0.6 s: the elbow has fallen and turned
  with.draw_frame(k);
  without.draw_frame(k);
  const World& w = with.loop->world();
  const BodyDef& lower = w.def(1);
  const Vec3 anchor_W(0.6, 0, 2);
  const Vec3 pivot = w.local_to_world(1, lower.q_WB.conjugate() * (anchor_W - lower.p_WB));
  ASSERT_GT((pivot - anchor_W).norm(), 0.2) << "the elbow has moved";
  const Vec3 axis = w.local_to_world_vec(0, Vec3::UnitY());  // the hinge's axis, fixed in the parent
  const CameraView& cam = with.view->camera;
  const Eigen::Vector2d c = project_to_pixel(cam, with.w(), with.h(), pivot);
  const Eigen::Vector2d tip = project_to_pixel(cam, with.w(), with.h(), pivot + 0.2 * axis);
  const Eigen::Vector2d tail = project_to_pixel(cam, with.w(), with.h(), pivot - 0.2 * axis);
  const Eigen::Vector2d start = project_to_pixel(cam, with.w(), with.h(), anchor_W);
  // The ball: at least 3 px in radius (0.06 body radii here is less).
  const double ball_px = 3.0;
  const Eigen::Vector2d dir = (tip - c).normalized();
  int near_pivot = 0, in_disk = 0, stray = 0, near_start = 0;
  double far = -1e9;
  for (int y = 0; y < with.h(); ++y)
    for (int x = 0; x < with.w(); ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      const bool disk = (p - c).norm() <= ball_px - 0.5;
      in_disk += disk;
      if (with.px(x, y) == without.px(x, y)) continue;
      near_pivot += disk;
      near_start += (p - start).norm() < 2;
      // Every pixel drawn lies on the ball or along the arrow from tail to tip.
      const double along = (p - c).dot(dir),
                   side = std::fabs((p - c).dot(Eigen::Vector2d(-dir.y(), dir.x())));
      const bool on_arrow = along > -(tail - c).norm() - 2 && along < (tip - c).norm() + 2 && side < 4;
      if (!on_arrow && (p - c).norm() > ball_px + 1.5) ++stray;
      far = std::max(far, along);
    }
  EXPECT_EQ(near_pivot, in_disk) << "the ball covers the projected pivot";
  EXPECT_GT(in_disk, 15);
  EXPECT_EQ(stray, 0);
  EXPECT_EQ(near_start, 0) << "nothing where the elbow was at t = 0";
  EXPECT_NEAR(far, (tip - c).norm(), 1.5) << "the arrow ends at the projected tip";
  EXPECT_GT((tip - c).norm(), 8) << "the axis is seen from the side";
  // The parent's frame is untouched: the shoulder is not the lower bar's joint.
  const Eigen::Vector2d shoulder = project_to_pixel(cam, with.w(), with.h(), Vec3(0, 0, 2));
  EXPECT_EQ(with.px((int)shoulder.x(), (int)shoulder.y()), without.px((int)shoulder.x(), (int)shoulder.y()));
}

// Whether a pixel within `r` px of p differs between the frames drawn with and without an item.
int differ_near(const Drawn& with, const Drawn& without, const Eigen::Vector2d& p, int r) {
  int n = 0;
  for (int y = (int)p.y() - r; y <= (int)p.y() + r; ++y)
    for (int x = (int)p.x() - r; x <= (int)p.x() + r; ++x)
      if (x >= 0 && y >= 0 && x < with.w() && y < with.h()) n += with.px(x, y) != without.px(x, y);
  return n;
}

Vec3 at_angle(const Vec3& a, const Vec3& u, double t) {
  return std::cos(t) * u + std::sin(t) * a.cross(u);
}

// A bar hinged to the world at its left end, seen along the hinge axis (+y, away from the camera),
// released horizontal: it falls turning right-handed about +y (x towards -z), the angle growing.
std::string hinge_with_limits(const std::string& show) {
  return "simulation: { duration: 1 }\n"
         "video: { width: 320, height: 240, fps: 20 }\n"
         "render: { sky: flat, shadows: false, antialiasing: none }\n"
         "camera: { position: [0.1, -2.2, 1.9], look_at: [0.1, 0, 1.9], fov: 40 }\n"
         "bodies:\n"
         "  - { name: arm, position: [0.3, 0, 2], color: [0.1, 0.1, 0.1],\n"
         "      colliders: [ { shape: box, size: [0.6, 0.03, 0.03], density: 7850 } ]" +
         show +
         " }\n"
         "joints:\n"
         "  - { name: hinge, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0],\n"
         "      limits: [-0.5, 2.0] }\n";
}

// `joints` on a hinge with limits: the range as an arc about the axis at the pivot, fixed in the
// parent (here the world), from `lower` to `upper` measured from the child's start direction (the
// pivot to its centre of mass at t = 0: +x here), half the axis's length in radius, with a tick
// across each end, and the present angle as a needle to a dot on the arc. What the item adds to
// the frame is there along the range and not outside it.
TEST(Overlays, AHingesLimitsAreAnArcFromLowerToUpperWithTheAngleOnIt) {
  Drawn with(
      write_scene("limits_on.yaml",
                  hinge_with_limits(",\n      show: [ { joints: { color: [1, 0, 1], scale: 0.6 } } ]"))),
      without(write_scene("limits_off.yaml", hinge_with_limits("")));
  const long k = 4;  // 0.2 s: the bar has fallen part way
  with.draw_frame(k);
  without.draw_frame(k);
  const World& w = with.loop->world();
  const double q = w.joint_position(0);
  ASSERT_GT(q, 0.3) << "the bar has turned";
  ASSERT_LT(q, 1.5);
  const Vec3 pivot(0, 0, 2), a = Vec3::UnitY(), u = Vec3::UnitX();
  const double r = 0.3, lower = -0.5, upper = 2.0;  // r: half the axis's 0.6 m
  const CameraView& cam = with.view->camera;
  auto at = [&](double t, double radius) {
    return project_to_pixel(cam, with.w(), with.h(), pivot + radius * at_angle(a, u, t));
  };
  ASSERT_GT((at(0, r) - at(0, 0)).norm(), 25) << "the arc is large enough to sample";
  // Along the arc, every 0.1 rad from lower to upper: drawn.
  for (double t = lower; t <= upper + 1e-9; t += 0.1)
    EXPECT_GT(differ_near(with, without, at(t, r), 1), 0) << t;
  // Outside the range (between upper and lower + 2 pi): nothing, on the circle or off it.
  for (double t = upper + 0.35; t < lower + 2 * M_PI - 0.35; t += 0.1) {
    EXPECT_EQ(differ_near(with, without, at(t, r), 2), 0) << t;
    EXPECT_EQ(differ_near(with, without, at(t, 1.25 * r), 2), 0) << t;
  }
  // The end ticks cross the arc: drawn 1.2 r out at lower and upper, not halfway between them (away
  // from the bar).
  EXPECT_GT(differ_near(with, without, at(lower, 1.2 * r), 1), 0);
  EXPECT_GT(differ_near(with, without, at(upper, 1.2 * r), 1), 0);
  EXPECT_GT(differ_near(with, without, at(lower, 0.8 * r), 1), 0);
  EXPECT_EQ(differ_near(with, without, at(0.5 * (lower + upper), 1.2 * r), 2), 0);
  // The present angle: the needle halfway out (over the bar, drawn faded through it by xray) and
  // the dot on the arc, which lie along the bar: the pivot to the centre of mass.
  const Vec3 c = w.centroid(0) - pivot;
  EXPECT_NEAR(std::atan2(-c.z(), c.x()), q, 1e-9) << "the angle is the bar's turn from +x about +y";
  EXPECT_GT(differ_near(with, without, at(q, 0.5 * r), 0), 0);
  EXPECT_GT(differ_near(with, without, at(q, r), 0), 0);
}

// The range in the draw list: the arc's ends at lower and upper, measured from the child's start
// direction carried by the parent (the elbow's range turns with the upper bar), and the dot where
// the child points now; a universal joint's second range is about axis2 as the first angle has
// turned it.
TEST(Overlays, AJointsRangeTurnsWithTheParentAndItsDotWithTheChild) {
  const std::string scene =
      "simulation: { duration: 1 }\n"
      "video: { width: 160, height: 120, fps: 20 }\n"
      "render: { sky: flat, shadows: false }\n"
      "camera: { position: [1.4, -3, 2.6], look_at: [0.6, 0, 1.7], fov: 40 }\n"
      "bodies:\n"
      "  - { name: upper, position: [0.3, 0, 2], colliders: [ { shape: box, size: [0.6, 0.03, 0.03], "
      "density: "
      "7850 } ] }\n"
      "  - { name: lower, position: [0.9, 0, 2], show: [ { joints: { scale: 0.4 } } ],\n"
      "      colliders: [ { shape: box, size: [0.6, 0.03, 0.03], density: 7850 } ] }\n"
      "  - { name: bob, position: [3, 0.15, 1.7], angular_velocity: [0, 0, 1], linear_velocity: [-0.15, 0, "
      "0], show: [ { joints: { scale: 0.5 } "
      "} ],\n"
      "      colliders: [ { shape: capsule, radius: 0.035, height: 0.5, density: 2000 } ] }\n"
      "joints:\n"
      "  - { name: shoulder, type: revolute, bodies: [world, upper], anchor: [0, 0, 2], axis: [0, 1, 0] }\n"
      "  - { name: elbow, type: revolute, bodies: [upper, lower], anchor: [0.6, 0, 2], axis: [0, 1, 0],\n"
      "      limits: [-2.5, 1.0] }\n"
      "  - { name: cardan, type: universal, bodies: [world, bob], anchor: [3, 0, 2], axis: [0, 0, 1],\n"
      "      axis2: [1, 0, 0], limits: [-1.2, 0.9] }\n";
  Drawn d(write_scene("ranges.yaml", scene));
  const long k = 3;  // 0.15 s: before the bob, whose swing brings it close to its axis, spins up
  d.draw_frame(k);
  const World& w = d.loop->world();
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(w, k, dl);
  std::vector<Vec3> dots, ends, dirs;  // rods' ends, and each rod's direction
  for (const OverlayInstance& s : dl.overlay.instances[(int)OverlayShape::sphere])
    dots.push_back(s.model.block<3, 1>(0, 3).cast<double>());
  for (const OverlayInstance& c : dl.overlay.instances[(int)OverlayShape::cylinder]) {
    const Vec3 from = c.model.block<3, 1>(0, 3).cast<double>(),
               along = c.model.block<3, 1>(0, 2).cast<double>();
    for (const Vec3& x : {from, Vec3(from + along)}) ends.push_back(x), dirs.push_back(along.normalized());
  }
  auto has = [](const std::vector<Vec3>& v, const Vec3& p) {
    double best = 1e9;
    for (const Vec3& x : v) best = std::min(best, (x - p).norm());
    return best;
  };
  // Every end of an arc's segment (a rod across the radius, not along it as the axes, ticks and
  // needles) at radius r from the pivot in the plane perpendicular to `a` lies within [lower,
  // upper] from u.
  auto within = [&](const Vec3& p, const Vec3& a, const Vec3& u, double r, double lo, double hi) {
    int n = 0;
    for (size_t k = 0; k < ends.size(); ++k) {
      const Vec3 v = ends[k] - p;
      if (std::fabs(v.dot(a)) > 1e-5 || std::fabs(v.norm() - r) > 1e-5) continue;
      if (std::fabs(dirs[k].dot(v.normalized())) > 0.2) continue;
      const double t = std::atan2(v.dot(a.cross(u)), v.dot(u));
      EXPECT_GE(t, lo - 1e-5);
      EXPECT_LE(t, hi + 1e-5);
      ++n;
    }
    EXPECT_GE(n, (int)((hi - lo) / (M_PI / 36))) << "5 degrees a segment";
  };
  // The elbow: the pivot carried by the lower bar; its start direction +x, carried by the upper bar.
  {
    const Vec3 p = w.local_to_world(1, Vec3(-0.3, 0, 0));
    const Vec3 a = w.local_to_world_vec(0, Vec3::UnitY()), u = w.local_to_world_vec(0, Vec3::UnitX());
    ASSERT_GT(std::fabs(w.joint_position(0)), 0.1) << "the upper bar has turned";
    const double r = 0.2, q = w.joint_position(1);
    EXPECT_LT(has(ends, p + r * at_angle(a, u, -2.5)), 1e-5) << "the arc's lower end";
    EXPECT_LT(has(ends, p + r * at_angle(a, u, 1.0)), 1e-5) << "the arc's upper end";
    within(p, a, u, r, -2.5, 1.0);
    // The dot: where the lower bar points now (independently: its centre of mass from the pivot).
    const Vec3 c = w.centroid(1) - p;
    EXPECT_LT(has(dots, p + r * (c - c.dot(a) * a).normalized()), 1e-5);
    EXPECT_LT(has(dots, p + r * at_angle(a, u, q)), 1e-5);
  }
  // The universal joint: about z (in the world) from the bob's start direction (+y, its centre of
  // mass 0.15 off the anchor's vertical), and about axis2 where the first angle turned it.
  {
    const Vec3 p(3, 0, 2), a = Vec3::UnitZ(), u = Vec3::UnitY();
    const double r = 0.25, q0 = w.joint_position(2, 0), q1 = w.joint_position(2, 1);
    ASSERT_GT(std::fabs(q0), 0.1) << "the bob has turned about z";
    ASSERT_LT(q0, 0.8) << "short of the stop";
    ASSERT_GT(std::fabs(q1), 0.05) << "and swung about axis2";
    EXPECT_LT(has(ends, p + r * at_angle(a, u, -1.2)), 1e-5);
    EXPECT_LT(has(ends, p + r * at_angle(a, u, 0.9)), 1e-5);
    within(p, a, u, r, -1.2, 0.9);
    EXPECT_LT(has(dots, p + r * at_angle(a, u, q0)), 1e-5);
    // The second: axis2 as the bob carries it; from the start direction (the centre of mass at
    // t = 0 from the anchor, across x: (0, 0.15, -0.3) normalised) turned by q0 about z.
    const Vec3 a2 = w.local_to_world_vec(2, Vec3::UnitX());
    EXPECT_LT((a2 - at_angle(a, Vec3::UnitX(), q0)).norm(), 1e-9) << "axis2 turned by the first angle";
    const Vec3 u2 = Eigen::AngleAxisd(q0, a) * Vec3(0, 0.15, -0.3).normalized();
    EXPECT_LT(has(ends, p + r * at_angle(a2, u2, -1.2)), 1e-5);
    EXPECT_LT(has(ends, p + r * at_angle(a2, u2, 0.9)), 1e-5);
    within(p, a2, u2, r, -1.2, 0.9);
    // Its dot: where the bob points now, across axis2 (independently, from its centre of mass).
    const Vec3 c = w.centroid(2) - p;
    EXPECT_LT(has(dots, p + r * (c - c.dot(a2) * a2).normalized()), 1e-5);
  }
}

// A ball joint's stops: the cone as a ring at its rim (every segment end r from the pivot at the
// cone's angle from the parent's axis), the child's axis as a needle to a dot r from the pivot,
// and the twist's needle a dot 0.4 r from a point 0.6 r down the child's axis, in the plane across it.
TEST(Overlays, ABallJointsConeIsARingAboutItsAxisAndItsDotTheChildsAxis) {
  const std::string scene =
      "simulation: { duration: 1 }\n"
      "video: { width: 160, height: 120, fps: 20 }\n"
      "render: { sky: flat, shadows: false }\n"
      "camera: { position: [0.9, -1.0, 1.75], look_at: [0, 0, 1.3], fov: 45 }\n"
      "bodies:\n"
      "  - { name: limb, position: [0, 0, 1.25], angular_velocity: [2.5, 1.5, 2.0], linear_velocity: "
      "[-0.375, "
      "0.625, 0],\n"
      "      show: [ { joints: { scale: 0.35 } } ],\n"
      "      colliders: [ { shape: capsule, radius: 0.05, height: 0.5, density: 1000 } ] }\n"
      "joints:\n"
      "  - { name: shoulder, type: spherical, bodies: [world, limb], anchor: [0, 0, 1.5], axis: [0, 0, -1],\n"
      "      limits: { cone: 0.6, twist: [-0.5, 0.5], restitution: 1 } }\n";
  Drawn d(write_scene("ball.yaml", scene));
  const long k = 6;
  d.draw_frame(k);
  const World& w = d.loop->world();
  DrawList dl;
  dl.camera = d.view->camera;
  d.view->overlays->build(w, k, dl);
  std::vector<Vec3> dots, ends;
  for (const OverlayInstance& s : dl.overlay.instances[(int)OverlayShape::sphere])
    dots.push_back(s.model.block<3, 1>(0, 3).cast<double>());
  for (const OverlayInstance& c : dl.overlay.instances[(int)OverlayShape::cylinder]) {
    const Vec3 from = c.model.block<3, 1>(0, 3).cast<double>(),
               along = c.model.block<3, 1>(0, 2).cast<double>();
    ends.push_back(from);
    ends.push_back(from + along);
  }
  const Vec3 p(0, 0, 1.5), a(0, 0, -1);
  const double r = 0.35;
  int rim = 0;
  for (const Vec3& e : ends) {
    const Vec3 v = e - p;
    if (std::fabs(v.norm() - r) < 1e-5 && std::fabs(std::acos(v.normalized().dot(a)) - 0.6) < 1e-5) ++rim;
  }
  EXPECT_GE(rim, 48) << "the cone's ring";
  auto nearest = [](const std::vector<Vec3>& v, const Vec3& x) {
    double best = 1e9;
    for (const Vec3& y : v) best = std::min(best, (y - x).norm());
    return best;
  };
  // The child's axis now (independently: from the pivot to the limb's centre of mass).
  const Vec3 c = (w.centroid(0) - p).normalized();
  ASSERT_GT(std::acos(c.dot(a)), 0.05) << "the limb has swung";
  EXPECT_LT(nearest(dots, p + r * c), 1e-5);
  // The twist's dot: 0.4 r from 0.6 r down the axis, across it.
  const Vec3 centre = p + 0.6 * r * c;
  int twist_dots = 0;
  for (const Vec3& x : dots)
    if (std::fabs((x - centre).norm() - 0.4 * r) < 1e-5 && std::fabs((x - centre).dot(c)) < 1e-5)
      ++twist_dots;
  EXPECT_EQ(twist_dots, 1);
}

// A cart on an inclined slider with limits, seen from the front: the bar along the axis from
// lower to upper (from where the cart carried the anchor at t = 0), with a tick across each end.
std::string slider_with_limits(const std::string& show) {
  return "simulation: { duration: 1 }\n"
         "video: { width: 320, height: 240, fps: 20 }\n"
         "render: { sky: flat, shadows: false, antialiasing: none }\n"
         "camera: { position: [0.15, -2.2, 1.4], look_at: [0.15, 0, 1.4], fov: 40 }\n"
         "bodies:\n"
         "  - { name: cart, position: [0, 0, 1.5], color: [0.1, 0.1, 0.1],\n"
         "      colliders: [ { shape: box, size: [0.1, 0.1, 0.1], density: 500 } ]" +
         show +
         " }\n"
         "joints:\n"
         "  - { name: rail, type: prismatic, bodies: [world, cart], anchor: [0, 0, 1.5], axis: [0.8, 0, "
         "-0.6],\n"
         "      limits: [-0.4, 0.7] }\n";
}

TEST(Overlays, ASlidersLimitsAreABarAlongItsAxis) {
  Drawn with(write_scene(
      "slider_on.yaml", slider_with_limits(",\n      show: [ { joints: { color: [1, 0, 1], width: 2 } } ]"))),
      without(write_scene("slider_off.yaml", slider_with_limits("")));
  const long k = 6;  // 0.3 s: g 0.6 along the axis, q = 0.26 m
  with.draw_frame(k);
  without.draw_frame(k);
  const World& w = with.loop->world();
  const double q = w.joint_position(0);
  ASSERT_NEAR(q, 0.5 * 9.81 * 0.6 * 0.09, 1e-3);
  const Vec3 o(0, 0, 1.5), e = Vec3(0.8, 0, -0.6);
  const CameraView& cam = with.view->camera;
  auto at = [&](double s, double side) {  // side: m across the axis, in the image plane (x-z)
    return project_to_pixel(cam, with.w(), with.h(), o + s * e + side * Vec3(0.6, 0, 0.8));
  };
  // Along the bar, clear of the cart and of the axis arrow through it: drawn.
  for (double s : {-0.38, -0.3, -0.2, -0.1, 0.5, 0.6, 0.68})
    EXPECT_GT(differ_near(with, without, at(s, 0), 0), 0) << s;
  // Beyond its ends: nothing.
  for (double s : {-0.55, -0.5, 0.8, 0.85}) EXPECT_EQ(differ_near(with, without, at(s, 0), 2), 0) << s;
  // The ticks across each end reach past the bar's thickness; halfway along the bar, nothing there.
  const double off = 0.03;
  for (double sd : {-1.0, 1.0}) {
    EXPECT_GT(differ_near(with, without, at(-0.4, sd * off), 0), 0) << sd;
    EXPECT_GT(differ_near(with, without, at(0.7, sd * off), 0), 0) << sd;
    EXPECT_EQ(differ_near(with, without, at(-0.2, sd * off), 1), 0) << sd;
  }
}

TEST(Overlays, ScenesWithoutOverlaysHaveNone) {
  Drawn d(write_scene("none.yaml", "bodies: [ { name: a, colliders: [ { shape: sphere, radius: 1 } ] } ]\n"));
  EXPECT_EQ(d.view->overlays, nullptr);
  EXPECT_FALSE(d.view->step_hook());
}

// `joints` on a rope's end bodies: each straight run as a rod between its ends, which move with
// their bodies (each end's point fixed in its body from the start pose; the world's a world
// point), a pulley's fixed span between its two points when it has no wheel, and a dot at each
// end. A rope shown from both ends is drawn once; a rope is tan, a rigid rod grey. Render-free:
// the overlay list of a frame, built from the world at that frame.
TEST(Overlays, TheJointsItemDrawsARopeBetweenItsMovingEnds) {
  const std::string scene =
      "simulation: { duration: 1 }\n"
      "video: { width: 320, height: 240, fps: 20 }\n"
      "camera: { position: [1.5, -8, 2], look_at: [1.5, 0, 2], fov: 40 }\n"
      "bodies:\n"
      "  - { name: bob, position: [0, 0, 1.5], euler: [0, 0, 30], linear_velocity: [1.5, 0, 0],\n"
      "      colliders: [ { shape: box, size: [0.1, 0.1, 0.1], density: 1000 } ], show: [joints] }\n"
      "  - { name: heavy, position: [2, 0, 1.5], colliders: [ { shape: box, size: [0.1, 0.1, 0.1], "
      "density: 3000 } ],\n"
      "      show: [joints] }\n"
      "  - { name: light, position: [3, 0, 1.5], colliders: [ { shape: box, size: [0.1, 0.1, 0.1], "
      "density: 1000 } ],\n"
      "      show: [ { joints: { width: 2 } } ] }\n"
      "  - { name: arm, position: [5, 0, 1.5], angular_velocity: [0, 0, 2],\n"
      "      colliders: [ { shape: box, size: [0.1, 0.1, 0.1], density: 1000 } ], show: [joints] }\n"
      "joints:\n"
      "  - { name: tether, type: distance, bodies: [world, bob], anchors: [[0, 0, 3], [0.05, 0, 1.55]],\n"
      "      max_length: 1.6 }\n"
      "  - { name: rope, type: pulley, bodies: [heavy, light], anchors: [[2, 0, 1.55], [3, 0, 1.55]],\n"
      "      pulley_anchors: [[2, 0, 3], [3, 0, 3]] }\n"
      "  - { name: rod, type: distance, bodies: [world, arm], anchors: [[4, 0, 2.5], [5, 0.05, 1.55]] }\n";
  const Scene sc = load_scene(write_scene("ropes.yaml", scene));
  FrameLoop loop(sc, 1);
  SceneView view(sc, loop.world(), ViewOptions{});
  ASSERT_TRUE(view.overlays);
  loop.advance_to(120, {});  // 0.5 s
  const World& w = loop.world();
  // Each end's point now: carried by its body from where it was at t = 0.
  auto carried = [&](int b, const Vec3& p_W) {
    const BodyDef& d = sc.bodies[b];
    return w.local_to_world(b, d.q_WB.conjugate() * (p_W - d.p_WB));
  };
  const Vec3 tether[2] = {Vec3(0, 0, 3), carried(0, Vec3(0.05, 0, 1.55))};
  const Vec3 heavy = carried(1, Vec3(2, 0, 1.55)), light = carried(2, Vec3(3, 0, 1.55));
  const Vec3 top[2] = {Vec3(2, 0, 3), Vec3(3, 0, 3)};
  const Vec3 rod[2] = {Vec3(4, 0, 2.5), carried(3, Vec3(5, 0.05, 1.55))};
  ASSERT_GT((tether[1] - Vec3(0.05, 0, 1.55)).norm(), 0.3) << "the bob has swung";
  ASSERT_LT(heavy.z(), 1.55 - 0.1) << "the heavy side has gone down";
  ASSERT_GT(light.z(), 1.55 + 0.1) << "the light side up";
  ASSERT_GT((rod[1] - Vec3(5, 0.05, 1.55)).norm(), 0.1) << "the rod's end has moved";
  EXPECT_NEAR((tether[1] - tether[0]).norm(), w.joint_position(0, 0), 1e-6) << "the tether's length";
  EXPECT_NEAR((rod[1] - rod[0]).norm(), w.joint_position(2, 0), 1e-6) << "the rod's length";
  EXPECT_NEAR((heavy - top[0]).norm(), w.joint_position(1, 0), 1e-6) << "the pulley's run 0";
  EXPECT_NEAR((light - top[1]).norm(), w.joint_position(1, 1), 1e-6) << "the pulley's run 1";

  DrawList dl;
  dl.camera = view.camera;
  view.overlays->build(w, 10, dl);
  struct Seg {
    Vec3 a, b;
    double r;
    Rgba color;
  };
  std::vector<Seg> segs;
  for (const OverlayInstance& c : dl.overlay.instances[(int)OverlayShape::cylinder]) {
    const Vec3 from = c.model.block<3, 1>(0, 3).cast<double>(),
               along = c.model.block<3, 1>(0, 2).cast<double>();
    segs.push_back({from, from + along, c.model.block<3, 1>(0, 0).cast<double>().norm(), c.color});
  }
  // The tether, the pulley's two runs and its span, the rod: once each (heavy's and light's
  // items share the pulley), and nothing else.
  ASSERT_EQ(segs.size(), 5u);
  auto find = [&](const Vec3& a, const Vec3& b) -> const Seg* {
    for (const Seg& s : segs)
      if (((s.a - a).norm() < 1e-5 && (s.b - b).norm() < 1e-5) ||
          ((s.a - b).norm() < 1e-5 && (s.b - a).norm() < 1e-5))
        return &s;
    return nullptr;
  };
  const Seg* t = find(tether[0], tether[1]);
  const Seg* r0 = find(top[0], heavy);
  const Seg* r1 = find(top[1], light);
  const Seg* span = find(top[0], top[1]);
  const Seg* r = find(rod[0], rod[1]);
  ASSERT_TRUE(t) << "the tether from the world point to the bob's point";
  ASSERT_TRUE(r0) << "the pulley's run from pulley_anchors[0] to heavy's point";
  ASSERT_TRUE(r1) << "the pulley's run from pulley_anchors[1] to light's point";
  ASSERT_TRUE(span) << "the massless pulley's span";
  ASSERT_TRUE(r) << "the rod";
  // A rope tan (red over green over blue), a rod grey; the rod thicker than a rope at the same
  // distance from the camera (the tether's and the rod's midpoints are about as far).
  for (const Seg* s : {t, r0, r1, span}) {
    EXPECT_GT(s->color[0], s->color[1]);
    EXPECT_GT(s->color[1], s->color[2]);
  }
  EXPECT_NEAR(r->color[0], r->color[1], 0.01);
  EXPECT_GT(r->r, 1.3 * t->r);
  // Dots at the rope's ends and the pulley's fixed points: 2 + 4 + 2.
  const auto& dots = dl.overlay.instances[(int)OverlayShape::sphere];
  EXPECT_EQ(dots.size(), 8u);
  auto dotted = [&](const Vec3& p) {
    for (const OverlayInstance& d : dots)
      if ((d.model.block<3, 1>(0, 3).cast<double>() - p).norm() < 1e-5) return true;
    return false;
  };
  for (const Vec3& p : {tether[0], tether[1], heavy, light, top[0], top[1], rod[0], rod[1]})
    EXPECT_TRUE(dotted(p)) << p.transpose();
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// Overlay sizes come from what is drawn, about the centre of mass: a mesh whose file origin lies
// 2.5 m from its shape (as Blender's Suzanne once exported) gets the same axes as the same shape
// at its origin, 1.25 times the distance from its centre of mass to its farthest vertex.
TEST(Overlays, SizesAreAboutTheCentreOfMassNotTheFileOrigin) {
  const std::string tet = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  test::scratch_file("near.off", "OFF\n4 4 0\n0 0 0\n0.3 0 0\n0 0.3 0\n0 0 0.3\n" + tet);
  test::scratch_file("far.off", "OFF\n4 4 0\n2.5 0 0\n2.8 0 0\n2.5 0.3 0\n2.5 0 0.3\n" + tet);
  auto axes = [&](const std::string& file) {
    Drawn d(write_scene(file + ".yaml",
                        "simulation: { duration: 1, gravity: [0, 0, 0] }\n"
                        "video: { width: 160, height: 90, fps: 10 }\n"
                        "bodies:\n  - { name: t, show: [axes], colliders: [ { shape: mesh, file: " +
                            file + ".off } ] }\n"));
    return d.view->overlays->arrow_scale(0, ShowKind::axes);
  };
  const double near = axes("near"), far = axes("far");
  // The tetrahedron's centroid is at (0.075, 0.075, 0.075) from its right-angle corner; its
  // farthest vertex, (0.3, 0, 0), is sqrt(0.225^2 + 2 * 0.075^2) = 0.2598 m away.
  EXPECT_NEAR(near, 1.25 * std::sqrt(0.225 * 0.225 + 2 * 0.075 * 0.075), 1e-6);
  EXPECT_NEAR(far, near, 1e-6) << "sized by the file origin, 2.5 m away";
}

}  // namespace
}  // namespace simreel
