// The scene keys of split screens, variants, body-frame cameras and ghosts (app/scene/scene_views.hpp,
// app/scene/ghost.hpp): what they read into, and the clear errors for what cannot be drawn.
#include "app/scene/scene_views.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <simreel/error.hpp>
#include "app/runner/frame_loop.hpp"
#include "app/scene/scene.hpp"

namespace simreel {
namespace {

const char* kHead = "simulation: { duration: 2.0, gravity: [0, 0, 0] }\n";
const char* kHandle = R"(
  - name: handle
    angular_velocity: [0.02, 6.0, 0.02]
    colliders: [{ shape: box, size: [0.2, 0.6, 1.0] }]
)";

Scene load(const std::string& text) {
  return load_scene_text(kHead + text, "v.yaml");
}

std::string error_of(const std::string& text) {
  try {
    load(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneViews, PanesVariantsAndBodyFrameCameras) {
  const Scene s = load(std::string("bodies:") + kHandle + R"(
variants: [{ name: seed, integrator: seed }, { name: fine, timestep: 0.001 }]
panes:
  columns: 2
  views:
    - { title: "space", camera: { position: [3, 0, 0], look_at: [0, 0, 0] } }
    - { title: "body", camera: { frame: { body: handle }, position: [0, 0, 3], up: [0, 1, 0] } }
    - { title: "seed", variant: seed }
)");
  ASSERT_EQ(s.views.variants.size(), 2u);
  EXPECT_EQ(*s.views.variants[0].integrator, Integrator::seed);
  EXPECT_DOUBLE_EQ(*s.views.variants[1].timestep, 0.001);
  ASSERT_EQ(s.views.panes.size(), 3u);
  EXPECT_EQ(s.views.columns, 2);
  EXPECT_EQ(s.views.panes[0].title, "space");
  EXPECT_EQ(*s.views.panes[1].camera.frame_body, "handle");
  EXPECT_FALSE(s.views.panes[1].camera.look_at);  // the scene's, merged at drawing time
  EXPECT_EQ(s.views.panes[2].variant, "seed");
  // The variant's scene: every body on its integrator, the rest as given.
  Scene v = variant_scene(s, s.views.variants[0]);
  EXPECT_EQ(v.integrator, Integrator::seed);
  EXPECT_TRUE(v.views.panes.empty());
  EXPECT_DOUBLE_EQ(v.timestep, s.timestep);
}

TEST(SceneViews, APaneMayShowItsOwnItems) {
  const Scene s = load(std::string("bodies:") + kHandle + R"(
    show: [angular_momentum]
panes:
  - { title: "space" }
  - { title: "body", show: { handle: [axes, { trail: { point: [0, 0, 0.5], length: 1 } }] } }
  - { title: "bare", show: { handle: [] } }
)");
  ASSERT_EQ(s.views.panes.size(), 3u);
  EXPECT_TRUE(s.views.panes[0].show.empty()) << "the scene's items";
  ASSERT_EQ(s.views.panes[1].show.size(), 1u);
  EXPECT_EQ(s.views.panes[1].show[0].first, 0);
  ASSERT_EQ(s.views.panes[1].show[0].second.size(), 2u);
  EXPECT_EQ(s.views.panes[1].show[0].second[0].kind, ShowKind::axes);
  EXPECT_EQ(s.views.panes[1].show[0].second[1].kind, ShowKind::trail);
  EXPECT_DOUBLE_EQ(s.views.panes[1].show[0].second[1].length, 1.0);
  ASSERT_EQ(s.views.panes[2].show.size(), 1u);
  EXPECT_TRUE(s.views.panes[2].show[0].second.empty());
  ASSERT_EQ(s.overlays.show[0].size(), 1u);
  EXPECT_EQ(s.overlays.show[0][0].kind, ShowKind::angular_momentum);
}

TEST(SceneViews, VariantsAloneMakeOnePaneEach) {
  const Scene s = load(std::string("bodies:") + kHandle + "variants: [{ name: seed, integrator: seed }]\n");
  ASSERT_EQ(s.views.panes.size(), 2u);
  EXPECT_EQ(s.views.panes[0].variant, "");
  EXPECT_EQ(s.views.panes[1].variant, "seed");
  EXPECT_NE(s.views.panes[1].title.find("seed"), std::string::npos) << s.views.panes[1].title;
}

TEST(SceneViews, TheSceneCameraMayRideInABody) {
  const Scene s =
      load(std::string("camera: { frame: { body: handle }, position: [0, 0, 3], up: [0, 1, 0] }\nbodies:") +
           kHandle);
  EXPECT_EQ(s.camera.frame_body, "handle");
}

TEST(SceneViews, MistakesNameTheKey) {
  const std::string b = std::string("bodies:") + kHandle;
  struct Bad {
    std::string yaml, says;
  };
  for (const Bad& x : std::vector<Bad>{
           {b + "panes: [{ title: a, variant: sed }]\n", "panes[0].variant: no variant is named 'sed'"},
           {b + "variants: [{ name: s, integrator: seed }]\npanes: [{ variant: sed }]\n", "did you mean 's'"},
           {b + "variants: [{ name: s }]\n", "changes nothing"},
           {b + "variants: [{ name: s, integrator: sead }]\n", "did you mean 'seed'"},
           {b + "panes: [{ camera: { frame: { body: handel } } }]\n", "did you mean 'handle'"},
           {b + "panes: [{ camera: { frame: body } }]\n", "expected world or { body: NAME }"},
           {b + "panes: [{ camera: { frame: { body: handle }, follow: handle } }]\n", "give one"},
           {b + "panes: { columns: 3, views: [{ title: a }, { title: b }] }\n", "panes.columns"},
           {b + "panes: []\n", "expected a list of panes"},
           {b + "panes: [{ titel: a }]\n", "did you mean 'title'"},
           {"camera: { frame: { body: nobody } }\n" + b, "camera.frame.body"},
           {b + "panes: [{ show: { handel: [axes] } }]\n",
            "panes[0].show: no body is named 'handel'; did you mean 'handle'?"},
           {b + "panes: [{ show: [axes] }]\n", "panes[0].show: expected a mapping of body names"},
           {b + "panes: [{ show: { handle: [axis] } }]\n", "panes[0].show.handle[0]: unknown item 'axis'"},
           {b + "panes: [{ show: { handle: axes } }]\n", "panes[0].show.handle: expected a list of items"},
       }) {
    const std::string e = error_of(x.yaml);
    EXPECT_NE(e.find(x.says), std::string::npos) << "error: '" << e << "' for\n" << x.yaml;
    EXPECT_NE(e.find("v.yaml:"), std::string::npos) << e;
  }
}

// A variant's own start: a free body's pose and velocities, or a mechanism turned rigidly about its
// pivot. Checked against chaos.yaml's second pendulum, whose start was computed by hand (the same
// 1e-6 rad about the same pivot, 10 cm behind): the variant's elbow follows it to 1e-9 rad at 3 s,
// where both have left the unturned pendulum by 1.5e-5 rad.
TEST(SceneViews, VariantsChangeTheStart) {
  const Scene s = load_scene("scenes/chaos_variants.yaml");
  ASSERT_EQ(s.views.variants.size(), 1u);
  const Scene v = variant_scene(s, s.views.variants[0]);
  FrameLoop main(s, 1), nudged(v, 1);
  EXPECT_LT(nudged.world().joint_gap(), 1e-12) << "the turned mechanism is assembled";
  EXPECT_NEAR(nudged.world().centroid(1).z(), 2 - 0.9 * std::sin(1e-6), 1e-15);
  const Scene hand = load_scene("scenes/chaos.yaml");
  FrameLoop ref(hand, 1);
  const long steps = std::lround(3.0 / s.timestep);
  main.advance_to(steps, {});
  nudged.advance_to(steps, {});
  ref.advance_to(steps, {});
  const double a = main.world().joint_position(1), b = nudged.world().joint_position(1);
  const double r = ref.world().joint_position(3);  // elbow_b
  EXPECT_GT(std::fabs(a - b), 5e-6) << "the nudge has grown";
  EXPECT_NEAR(b, r, 1e-9) << "the variant is chaos.yaml's hand-made second pendulum";
  EXPECT_NEAR(a, ref.world().joint_position(1), 1e-9) << "and the main one its first";

  // A free body's start; a jointed one's is refused, as is a turn that would tear a joint.
  const Scene f =
      load(std::string("bodies:") + kHandle +
           "variants: [{ name: faster, bodies: { handle: { angular_velocity: [0.02, 7, 0.02] } } }]\n");
  EXPECT_EQ(variant_scene(f, f.views.variants[0]).bodies[0].w_W, Vec3(0.02, 7, 0.02));
  std::string bad =
      "simulation: { duration: 1 }\nbodies:\n"
      "  - { name: bar, position: [0.3, 0, 2], colliders: [ { shape: box, size: [0.6, 0.05, 0.03] } ] }\n"
      "joints: [ { name: pivot, type: revolute, bodies: [world, bar], anchor: [0, 0, 2], axis: [0, 1, 0] } "
      "]\n";
  auto err = [&](const std::string& variant) {
    try {
      load_scene_text(bad + "variants: [" + variant + "]\n", "t.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("{ name: n, bodies: { bar: { position: [0, 0, 1] } } }").find("is held by joint 'pivot'"),
            std::string::npos);
  EXPECT_NE(err("{ name: n, turn: { bodies: [bar], about: [0.1, 0, 2], axis: [0, 1, 0], angle: 1 } }")
                .find("would tear joint 'pivot'"),
            std::string::npos);
  EXPECT_NE(err("{ name: n, turn: { bodies: [bar], about: [0, 0, 2], axis: [0, 0, 1], angle: 1 } }")
                .find("turn about its axis"),
            std::string::npos);
  EXPECT_EQ(err("{ name: n, turn: { bodies: [bar], about: [0, 0, 2], axis: [0, 1, 0], angle: 1 } }"), "");
}

TEST(Ghost, OnlyWhereAClosedFormExists) {
  // A free body: yes, under gravity too.
  const Scene ok = load_scene_text(
      "bodies:\n  - { name: a, ghost: true, angular_velocity: [0, 1, 0.1], colliders: [{ shape: sphere, "
      "radius: 0.5 }] }\n",
      "g.yaml");
  EXPECT_TRUE(ok.looks[0].ghost.on);
  const Scene styled = load(
      "bodies:\n  - { name: a, ghost: { opacity: 0.5, offset: [1, 0, 0], color: [0, 0, 1] }, colliders: [{ "
      "shape: "
      "sphere, radius: 0.5 }] }\n");
  EXPECT_DOUBLE_EQ(styled.looks[0].ghost.opacity, 0.5);
  EXPECT_DOUBLE_EQ(styled.looks[0].ghost.offset.x(), 1.0);
  // Two bodies that never meet, said so: yes.
  EXPECT_NO_THROW(
      load_scene_text("simulation: { ignore_pairs: [[a, b]] }\n"
                      "bodies:\n  - { name: a, ghost: true, colliders: [{ shape: sphere, radius: 0.5 }] }\n"
                      "  - { name: b, position: [5, 0, 0], colliders: [{ shape: sphere, radius: 0.5 }] }\n",
                      "g.yaml"));
  struct Bad {
    std::string yaml, says;
  };
  for (const Bad& x : std::vector<Bad>{
           {"bodies:\n  - { name: a, ghost: true, colliders: [{ shape: sphere, radius: 0.5 }] }\n"
            "forces: [{ type: torque, body: a, vector: [0, 0, 1] }]\n",
            "forces[0] acts on it"},
           {"ground: true\nbodies:\n  - { name: a, ghost: true, position: [0, 0, 2], colliders: [{ shape: "
            "sphere, radius: 0.5 }] }\n",
            "contacts with body 'ground' could act on it"},
           {"bodies:\n  - { name: a, type: kinematic, ghost: true, colliders: [{ shape: sphere, radius: 0.5 "
            "}] }\n",
            "not dynamic"},
           {"bodies:\n  - { name: a, ghost: { opacity: 0 }, colliders: [{ shape: sphere, radius: 0.5 }] }\n",
            "above 0"},
           {"bodies:\n  - { name: a, ghost: maybe, colliders: [{ shape: sphere, radius: 0.5 }] }\n",
            "bodies[0].ghost"},
       }) {
    std::string e;
    try {
      load_scene_text(x.yaml, "g.yaml");
    } catch (const InputError& err) {
      e = err.what();
    }
    EXPECT_NE(e.find(x.says), std::string::npos) << "error: '" << e << "' for\n" << x.yaml;
    EXPECT_NE(e.find("g.yaml:"), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace simreel
