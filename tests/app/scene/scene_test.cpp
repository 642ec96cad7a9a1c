// The scene parser: every mistake a user can make names the file, line, column and key.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <simreel/error.hpp>
#include <simreel/world.hpp>
#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"
#include "sim/geometry/polyhedron.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

std::string write_scene(const std::string& name, const std::string& text) {
  return test::scratch_file(name, text);
}

// Loads a scene expected to be rejected; returns the message.
std::string error_of(const std::string& text) {
  const std::string path = write_scene("bad.yaml", text);
  try {
    load_scene(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "scene was accepted:\n" << text;
  return "";
}

const char* kBox = "    colliders:\n      - { shape: box, size: [1, 2, 3], density: 10 }\n";

TEST(Scene, ValidSceneLoadsWithDefaultsAndUnits) {
  const std::string path =
      write_scene("ok.yaml", std::string("simulation:\n  duration: 2\n  timestep: 0.01\n"
                                         "bodies:\n  - name: a\n    position: [1, 2, 3]\n") +
                                 kBox);
  const Scene s = load_scene(path);
  EXPECT_EQ(s.name, "ok");
  EXPECT_EQ(s.duration, 2.0);
  EXPECT_EQ(s.integrator, Integrator::automatic);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_NEAR(s.bodies[0].mass_B().mass, 60.0, 1e-12);  // 1 x 2 x 3 m at 10 kg/m^3
  EXPECT_EQ(s.bodies[0].p_WB, Vec3(1, 2, 3));
}

TEST(Scene, UnknownKeySuggestsTheNearestAndNamesLineAndColumn) {
  const std::string msg = error_of("simulation:\n  duraton: 2\nbodies:\n  - name: a\n" + std::string(kBox));
  EXPECT_NE(msg.find("bad.yaml:2:3: simulation.duraton: unknown key 'duraton'; did you mean 'duration'?"),
            std::string::npos)
      << msg;
}

TEST(Scene, WrongTypesAndLengthsNameTheKey) {
  EXPECT_NE(error_of("simulation:\n  timestep: fast\nbodies: []\n")
                .find(":2:13: simulation.timestep: expected a number"),
            std::string::npos);
  const std::string m = error_of("bodies:\n  - name: a\n    position: [1, 2]\n" + std::string(kBox));
  EXPECT_NE(m.find(":3:15: bodies[0].position: expected a list of 3 numbers, got a list of 2"),
            std::string::npos)
      << m;
}

TEST(Scene, NonFiniteAndNonPositiveValuesAreRejected) {
  EXPECT_NE(error_of("simulation:\n  duration: .nan\nbodies: []\n")
                .find("simulation.duration: must be a finite number"),
            std::string::npos);
  EXPECT_NE(
      error_of("simulation:\n  timestep: -0.1\nbodies: []\n").find("simulation.timestep: must be positive"),
      std::string::npos);
  const std::string m = error_of("bodies:\n  - colliders:\n      - { shape: sphere, radius: 0 }\n");
  EXPECT_NE(m.find(":3:34: bodies[0].colliders[0].radius: must be positive"), std::string::npos) << m;
  const std::string n =
      error_of("bodies:\n  - colliders:\n      - { shape: box, size: [1, 1, 1], density: -3 }\n");
  EXPECT_NE(n.find("bodies[0].colliders[0].density: must be positive"), std::string::npos) << n;
  const std::string inf = error_of("bodies:\n  - position: [0, .inf, 0]\n" + std::string(kBox));
  EXPECT_NE(inf.find("bodies[0].position[1]: must be a finite number"), std::string::npos) << inf;
}

TEST(Scene, MassAndDensityTogetherIsAnError) {
  const std::string m =
      error_of("bodies:\n  - colliders:\n      - { shape: box, size: [1, 1, 1], density: 3, mass: 2 }\n");
  EXPECT_NE(m.find("bodies[0].colliders[0].mass: give either 'density' or 'mass', not both"),
            std::string::npos)
      << m;
}

TEST(Scene, UnknownShapeAndIntegratorSuggestNames) {
  const std::string s = error_of("bodies:\n  - colliders:\n      - { shape: sphre, radius: 1 }\n");
  EXPECT_NE(s.find("unknown shape 'sphre'"), std::string::npos) << s;
  EXPECT_NE(s.find("did you mean 'sphere'?"), std::string::npos) << s;
  const std::string i = error_of("simulation:\n  integrator: rk5\nbodies: []\n");
  EXPECT_NE(i.find("simulation.integrator: unknown integrator 'rk5'"), std::string::npos) << i;
  EXPECT_NE(i.find("did you mean 'rk4'?"), std::string::npos) << i;
}

TEST(Scene, AntiAliasingModes) {
  const std::string bodies = std::string("bodies:\n  - name: a\n") + kBox;
  EXPECT_EQ(load_scene(write_scene("aa.yaml", bodies)).render.antialiasing, AntiAliasing::fxaa);  // default
  EXPECT_EQ(
      load_scene(write_scene("aa4.yaml", "render: { antialiasing: msaa4 }\n" + bodies)).render.antialiasing,
      AntiAliasing::msaa4);
  const std::string e = error_of("render:\n  antialiasing: msaa3\n" + bodies);
  EXPECT_NE(e.find(":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("render.antialiasing: unknown anti-aliasing 'msaa3' (fxaa, msaa2, msaa4, none)"),
            std::string::npos)
      << e;
}

TEST(Scene, YamlSyntaxErrorNamesTheLine) {
  const std::string m = error_of("simulation:\n  duration: [1, 2\nbodies: []\n");
  EXPECT_NE(m.find("bad.yaml:3:"), std::string::npos) << m;
  EXPECT_NE(m.find("YAML syntax error"), std::string::npos) << m;
}

TEST(Scene, MissingMeshFileAndOpenMeshAreExplained) {
  const std::string m = error_of("bodies:\n  - colliders:\n      - { shape: mesh, file: nowhere.obj }\n");
  EXPECT_NE(m.find("bodies[0].colliders[0].file: mesh file 'nowhere.obj' not found"), std::string::npos) << m;
  // Relative paths resolve against the scene's folder, then assets/ (the working directory is the
  // project root when ctest runs).
  const std::string o = error_of("bodies:\n  - colliders:\n      - { shape: mesh, file: open_box.obj }\n");
  EXPECT_NE(o.find("mesh is open"), std::string::npos) << o;
  EXPECT_NE(o.find("(shell mode)"), std::string::npos) << o;
}

TEST(Scene, MeshModesAndMassScaling) {
  const std::string path = write_scene(
      "mesh.yaml",
      "bodies:\n  - colliders:\n      - { shape: mesh, file: open_box.obj, mode: hull, mass: 5 }\n");
  const Scene s = load_scene(path);
  EXPECT_NEAR(s.bodies[0].mass_B().mass, 5.0, 1e-12);
  // The unit cube's hull: I = m / 6 about each axis.
  // Integer corners read in double precision and a hull of 12 triangles: rounding only.
  EXPECT_NEAR(s.bodies[0].mass_B().inertia(0, 0), 5.0 / 6.0, 1e-12);
}

TEST(Scene, MaterialColourFromTheFileUnlessTheBodySetsOne) {
  write_scene("tet.mtl", "newmtl red\nKd 0.9 0.1 0.1\n");
  write_scene("tet.obj",
              "mtllib tet.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
              "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const std::string col = "    colliders: [ { shape: mesh, file: tet.obj }, { shape: sphere, radius: 1 } ]\n";
  const Scene s = load_scene(
      write_scene("tet.yaml", "bodies:\n  - name: a\n" + col + "  - name: b\n    color: [0, 0, 1]\n" + col));
  ASSERT_EQ(s.looks.size(), 2u);
  ASSERT_TRUE(s.looks[0].colliders[0].color.has_value());
  EXPECT_FLOAT_EQ((*s.looks[0].colliders[0].color)[0], 0.9f);
  EXPECT_FALSE(s.looks[0].colliders[1].color.has_value());  // a primitive has no file material
  EXPECT_FALSE(s.looks[1].colliders[0].color.has_value());  // the scene's body colour wins
  EXPECT_FLOAT_EQ(s.looks[1].collider_color(0)[2], 1.0f);
  EXPECT_FLOAT_EQ(s.looks[0].collider_color(1)[0], 0.8f);  // the default body colour
  // A collider's own colour wins over both.
  const Scene o = load_scene(write_scene(
      "tet2.yaml",
      "bodies:\n  - color: [0, 0, 1]\n    colliders: [ { shape: mesh, file: tet.obj, color: [0, 1, 0] },"
      " { shape: sphere, radius: 1, color: [1, 1, 0] }, { shape: sphere, radius: 1 } ]\n"));
  EXPECT_EQ(o.looks[0].collider_color(0), (Rgb{0, 1, 0}));
  EXPECT_EQ(o.looks[0].collider_color(1), (Rgb{1, 1, 0}));
  EXPECT_EQ(o.looks[0].collider_color(2), (Rgb{0, 0, 1}));
  EXPECT_NE(error_of("bodies:\n  - colliders: [ { shape: sphere, radius: 1, color: [2, 0, 0] } ]\n")
                .find("bodies[0].colliders[0].color[0]: colour components must lie in [0, 1]"),
            std::string::npos);
  EXPECT_NEAR(s.bodies[0].colliders[0].props_C.mass, 1000.0 / 6, 1e-9);  // V = 1/6 at 1000 kg/m^3
}

TEST(Scene, DuplicateNamesAndBadFollowAreErrors) {
  const std::string m = error_of("bodies:\n  - name: a\n" + std::string(kBox) + "  - name: a\n" + kBox);
  EXPECT_NE(m.find("bodies[1].name: another body is already named 'a'"), std::string::npos) << m;
  const std::string f = error_of("camera: { follow: b }\nbodies:\n  - name: a\n" + std::string(kBox));
  EXPECT_NE(f.find("camera.follow: no body is named 'b'"), std::string::npos) << f;
}

TEST(Scene, QuaternionMustBeUnit) {
  const std::string m = error_of("bodies:\n  - orientation: [1, 1, 0, 0]\n" + std::string(kBox));
  EXPECT_NE(m.find("bodies[0].orientation: must be a unit quaternion"), std::string::npos) << m;
}

// `msg` holds `part` (the message is printed on failure).
#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << (msg)

// ---- Contacts: ground, body types, contact keys on colliders, planes, ellipsoids.

TEST(Scene, GroundIsAStaticPlaneBodyAndTheDrawnGround) {
  const Scene s =
      load_scene(write_scene("ground.yaml",
                             "ground: { height: 0.5, friction: 0.3, restitution: 0.2, size: 30, tile: 2 }\n"
                             "bodies:\n  - name: a\n" +
                                 std::string(kBox)));
  ASSERT_EQ(s.bodies.size(), 2u);  // the ground comes after the scene's bodies
  ASSERT_EQ(s.looks.size(), 2u);
  const BodyDef& g = s.bodies[1];
  EXPECT_EQ(g.name, "ground");
  EXPECT_EQ(g.type, BodyType::static_body);
  ASSERT_EQ(g.colliders.size(), 1u);
  const Collider& p = g.colliders[0];
  EXPECT_EQ(p.shape, ShapeKind::plane);
  EXPECT_EQ(p.p_BC, Vec3(0, 0, 0.5));
  EXPECT_TRUE(p.q_BC.isApprox(Quat::Identity()));  // normal +z
  EXPECT_EQ(p.friction, 0.3);
  EXPECT_EQ(p.restitution, 0.2);
  ASSERT_TRUE(s.ground.has_value());
  EXPECT_TRUE(s.render.ground);  // drawn by the renderer's checkered ground ...
  EXPECT_EQ(s.render.ground_height, 0.5);
  EXPECT_EQ(s.render.ground_size, 30);
  EXPECT_EQ(s.render.ground_tile, 2);
  EXPECT_FALSE(s.looks[1].drawn);  // ... not again as a collider
  EXPECT_TRUE(s.looks[0].drawn);
  World w(world_config(s, 1), s.bodies);  // the world takes it and steps
  EXPECT_EQ(w.dynamic_count(), 1);
  w.step();

  const Scene d =
      load_scene(write_scene("ground2.yaml", "ground: true\nbodies:\n  - name: a\n" + std::string(kBox)));
  ASSERT_EQ(d.bodies.size(), 2u);
  EXPECT_EQ(d.bodies[1].colliders[0].friction, 0.6);
  EXPECT_EQ(d.bodies[1].colliders[0].p_BC, Vec3::Zero());
  EXPECT_EQ(d.render.ground_size, 20);
  const Scene off =
      load_scene(write_scene("ground3.yaml", "ground: false\nbodies:\n  - name: a\n" + std::string(kBox)));
  EXPECT_EQ(off.bodies.size(), 1u);
  EXPECT_FALSE(off.render.ground);
  // render.ground alone draws and does not collide.
  const Scene r = load_scene(
      write_scene("ground4.yaml", "render: { ground: true }\nbodies:\n  - name: a\n" + std::string(kBox)));
  EXPECT_EQ(r.bodies.size(), 1u);
  EXPECT_TRUE(r.render.ground);
}

TEST(Scene, GroundErrors) {
  const std::string both = error_of(
      "ground: { height: 0 }\nrender:\n  ground: { size: 5 }\nbodies:\n  - name: a\n" + std::string(kBox));
  EXPECT_HAS(both, "bad.yaml:3:11: render.ground: the top-level 'ground' already draws the ground");
  const std::string clash = error_of("ground: {}\nbodies:\n  - name: ground\n" + std::string(kBox));
  EXPECT_HAS(clash,
             "bad.yaml:3:11: bodies[0].name: the top-level 'ground' makes a static body named 'ground'");
  EXPECT_HAS(error_of("ground: { friction: -1 }\nbodies:\n  - name: a\n" + std::string(kBox)),
             "bad.yaml:1:21: ground.friction: must not be negative");
  EXPECT_HAS(error_of("ground: { restitution: 2 }\nbodies:\n  - name: a\n" + std::string(kBox)),
             "ground.restitution: must lie in [0, 1]");
  EXPECT_HAS(error_of("ground: { size: 0 }\nbodies:\n  - name: a\n" + std::string(kBox)),
             "ground.size: must be positive");
  EXPECT_HAS(error_of("ground: { frction: 1 }\nbodies:\n  - name: a\n" + std::string(kBox)),
             "ground.frction: unknown key 'frction'; did you mean 'friction'?");
}

TEST(Scene, BodyTypes) {
  const Scene s = load_scene(write_scene(
      "types.yaml",
      "bodies:\n"
      "  - { name: d, colliders: [ { shape: sphere, radius: 1 } ] }\n"
      "  - { name: k, type: kinematic, linear_velocity: [1, 0, 0], angular_velocity: [0, 0, 2],\n"
      "      colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
      "  - { name: s, type: static, colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
      "  - { name: t, static: true, colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
      "  - { name: u, static: true, type: static, colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
      "  - { name: v, static: false, type: kinematic, colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"));
  EXPECT_EQ(s.bodies[0].type, BodyType::dynamic);
  EXPECT_EQ(s.bodies[1].type, BodyType::kinematic);
  EXPECT_EQ(s.bodies[1].v_W, Vec3(1, 0, 0));  // a kinematic body keeps its velocity
  EXPECT_EQ(s.bodies[1].w_W, Vec3(0, 0, 2));
  EXPECT_EQ(s.bodies[2].type, BodyType::static_body);
  EXPECT_EQ(s.bodies[3].type, BodyType::static_body);
  EXPECT_EQ(s.bodies[4].type, BodyType::static_body);
  EXPECT_EQ(s.bodies[5].type, BodyType::kinematic);
  EXPECT_TRUE(s.notes.empty());

  const std::string c = error_of("bodies:\n  - type: dynamic\n    static: true\n" + std::string(kBox));
  EXPECT_HAS(c, "bad.yaml:3:13: bodies[0].static: static: true contradicts type: dynamic");
  const std::string f = error_of("bodies:\n  - type: static\n    static: false\n" + std::string(kBox));
  EXPECT_HAS(f, "bodies[0].static: static: false contradicts type: static");
  const std::string u = error_of("bodies:\n  - type: kinematik\n" + std::string(kBox));
  EXPECT_HAS(u,
             "bad.yaml:2:11: bodies[0].type: unknown body type 'kinematik' (dynamic, static or kinematic); "
             "did you mean 'kinematic'?");
}

TEST(Scene, StaticBodyVelocityIsIgnoredWithANote) {
  const Scene s = load_scene(write_scene("sv.yaml",
                                         "bodies:\n  - name: wall\n    type: static\n"
                                         "    linear_velocity: [1, 0, 0]\n"
                                         "    angular_velocity: [0, 0, 0]\n" +
                                             std::string(kBox)));
  EXPECT_EQ(s.bodies[0].v_W, Vec3::Zero());
  ASSERT_EQ(s.notes.size(), 1u);  // a zero velocity is no news
  EXPECT_HAS(s.notes[0],
             "sv.yaml:4: bodies[0].linear_velocity: body 'wall' is static: its velocity is ignored");
}

TEST(Scene, ColliderContactKeys) {
  const Scene s = load_scene(write_scene(
      "contact.yaml",
      "bodies:\n  - colliders:\n"
      "      - { shape: box, size: [1, 1, 1], friction: 0.2, restitution: 0.9, group: [0, 3], mask: 0xF0 }\n"
      "      - { shape: sphere, radius: 0.1, position: [0, 0, 1], collide: false, group: 4294967295, mask: "
      "[] }\n"
      "      - { shape: sphere, radius: 0.1, position: [0, 0, -1] }\n"));
  const auto& c = s.bodies[0].colliders;
  EXPECT_EQ(c[0].friction, 0.2);
  EXPECT_EQ(c[0].restitution, 0.9);
  EXPECT_TRUE(c[0].collide);
  EXPECT_EQ(c[0].group, 9u);  // bits 0 and 3
  EXPECT_EQ(c[0].mask, 0xF0u);
  EXPECT_FALSE(c[1].collide);
  EXPECT_EQ(c[1].group, 0xFFFFFFFFu);
  EXPECT_EQ(c[1].mask, 0u);
  EXPECT_EQ(c[2].friction, 0.6);  // defaults
  EXPECT_EQ(c[2].restitution, 0.0);
  EXPECT_EQ(c[2].group, 1u);
  EXPECT_EQ(c[2].mask, 0xFFFFFFFFu);

  const std::string col = "bodies:\n  - colliders:\n      - { shape: sphere, radius: 1, ";
  EXPECT_HAS(error_of(col + "friction: -0.1 }\n"),
             "bad.yaml:3:47: bodies[0].colliders[0].friction: must not be negative");
  EXPECT_HAS(error_of(col + "restitution: 1.5 }\n"),
             "bad.yaml:3:50: bodies[0].colliders[0].restitution: must lie in [0, 1], got '1.5'");
  EXPECT_HAS(error_of(col + "restitution: -0.5 }\n"),
             "bodies[0].colliders[0].restitution: must lie in [0, 1]");
  EXPECT_HAS(error_of(col + "collide: maybe }\n"), "bodies[0].colliders[0].collide: expected true or false");
  EXPECT_HAS(error_of(col + "group: 4294967296 }\n"),
             "bad.yaml:3:44: bodies[0].colliders[0].group: expected a whole number from 0 to 4294967295");
  EXPECT_HAS(error_of(col + "mask: -1 }\n"), "bodies[0].colliders[0].mask: expected a whole number");
  EXPECT_HAS(error_of(col + "mask: 1.5 }\n"), "bodies[0].colliders[0].mask: expected a whole number");
  EXPECT_HAS(error_of(col + "mask: [1, 32] }\n"),
             "bodies[0].colliders[0].mask[1]: expected a bit number from 0 to 31, got '32'");
  EXPECT_HAS(error_of(col + "frictoin: 1 }\n"), "unknown key 'frictoin'; did you mean 'friction'?");
}

TEST(Scene, PlanesOnStaticBodiesOnly) {
  const Scene s = load_scene(write_scene(
      "plane.yaml",
      "bodies:\n  - name: slope\n    type: static\n"
      "    colliders:\n      - { shape: plane, size: 6, friction: 0.4, orientation: [0.9659258262890683, "
      "0.25881904510252074, 0, 0] }\n"
      "  - name: ball\n    colliders: [ { shape: sphere, radius: 1 } ]\n"));
  const Collider& p = s.bodies[0].colliders[0];
  EXPECT_EQ(p.shape, ShapeKind::plane);
  EXPECT_EQ(p.friction, 0.4);
  EXPECT_EQ(s.looks[0].colliders[0].plane_size, 6);
  EXPECT_TRUE(s.looks[0].drawn);          // a plane of the scene's own is drawn (a finite square)
  World w(world_config(s, 1), s.bodies);  // a plane-only static body steps
  EXPECT_EQ(w.dynamic_count(), 1);

  const std::string d = error_of("bodies:\n  - name: b\n    colliders:\n      - { shape: plane }\n");
  EXPECT_HAS(d,
             "bad.yaml:4:18: bodies[0].colliders[0].shape: a plane may only be a collider of a static body "
             "(body 'b' is dynamic; give it 'type: static')");
  EXPECT_HAS(error_of("bodies:\n  - type: kinematic\n    colliders:\n      - { shape: plane }\n"),
             "body 'body0' is kinematic");
  EXPECT_HAS(error_of("bodies:\n  - static: true\n    colliders:\n      - { shape: plane, mass: 3 }\n"),
             "bad.yaml:4:31: bodies[0].colliders[0].mass: a plane has no mass");
  EXPECT_HAS(error_of("bodies:\n  - static: true\n    colliders:\n      - { shape: plane, size: -1 }\n"),
             "bodies[0].colliders[0].size: must be positive");
  EXPECT_HAS(error_of("bodies:\n  - static: true\n    colliders:\n      - { shape: plane, radius: 1 }\n"),
             "bodies[0].colliders[0].radius: does not apply to a plane");
}

TEST(Scene, EllipsoidExactMassAndPositiveRadii) {
  const Scene s = load_scene(write_scene(
      "ell.yaml",
      "bodies:\n  - colliders: [ { shape: ellipsoid, radii: [0.3, 0.2, 0.1], density: 500 } ]\n"));
  const Collider& e = s.bodies[0].colliders[0];
  EXPECT_EQ(e.shape, ShapeKind::ellipsoid);
  EXPECT_EQ(e.radii, Vec3(0.3, 0.2, 0.1));
  const double m = 500 * 4.0 / 3.0 * M_PI * 0.3 * 0.2 * 0.1;
  EXPECT_NEAR(e.props_C.mass, m, 1e-12);
  EXPECT_NEAR(e.props_C.inertia(0, 0), m / 5 * (0.04 + 0.01), 1e-15);
  EXPECT_NEAR(e.props_C.inertia(2, 2), m / 5 * (0.09 + 0.04), 1e-15);
  const Scene k = load_scene(write_scene(
      "ell2.yaml", "bodies:\n  - colliders: [ { shape: ellipsoid, radii: [1, 2, 3], mass: 7 } ]\n"));
  EXPECT_NEAR(k.bodies[0].mass_B().mass, 7, 1e-12);

  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: ellipsoid, radii: [1, 0, 1] }\n"),
             "bad.yaml:3:40: bodies[0].colliders[0].radii[1]: must be positive");
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: ellipsoid, radii: [1, 1] }\n"),
             "bodies[0].colliders[0].radii: expected a list of 3 numbers, got a list of 2");
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: ellipsoid }\n"),
             "a ellipsoid needs 'radii'");
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: ellipsoid, radii: [1, 1, 1], radius: 1 }\n"),
             "bodies[0].colliders[0].radius: does not apply to a ellipsoid");
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: elipsoid, radii: [1, 1, 1] }\n"),
             "did you mean 'ellipsoid'?");
}

TEST(Scene, NonPositiveSizesOfEveryShapeNameTheKey) {
  const std::string pre = "bodies:\n  - colliders:\n      - { shape: ";
  EXPECT_HAS(error_of(pre + "box, size: [1, -1, 1] }\n"),
             "bad.yaml:3:33: bodies[0].colliders[0].size[1]: must be positive");
  EXPECT_HAS(error_of(pre + "box, size: [0, 1, 1] }\n"), "bodies[0].colliders[0].size[0]: must be positive");
  EXPECT_HAS(error_of(pre + "sphere, radius: -2 }\n"), "bodies[0].colliders[0].radius: must be positive");
  EXPECT_HAS(error_of(pre + "cylinder, radius: 1, height: 0 }\n"),
             "bad.yaml:3:47: bodies[0].colliders[0].height: must be positive");
  EXPECT_HAS(error_of(pre + "capsule, radius: 0, height: 1 }\n"),
             "bodies[0].colliders[0].radius: must be positive");
}

TEST(Scene, ContactSettings) {
  const Scene s = load_scene(write_scene(
      "cs.yaml",
      "simulation:\n  contacts: { substeps: 8, iterations: 2, passes: 3, contact_hertz: 60, damping_ratio: "
      "5,\n"
      "    max_push_out: 1, restitution_threshold: 0.5, speculative_distance: 0.01, linear_slop: 0.001,\n"
      "    rolling_resistance: 0.02, slip_speed: 0.01, compound_shapes: 3, rolling: false,\n"
      "    rolling_tolerance: 1e-8 }\nbodies:\n  - name: a\n" +
          std::string(kBox)));
  EXPECT_EQ(s.contacts.substeps, 8);
  EXPECT_EQ(s.contacts.iterations, 2);
  EXPECT_EQ(s.contacts.passes, 3);
  EXPECT_EQ(s.contacts.contact_hertz, 60);
  EXPECT_EQ(s.contacts.damping_ratio, 5);
  EXPECT_EQ(s.contacts.max_push_out, 1);
  EXPECT_EQ(s.contacts.restitution_threshold, 0.5);
  EXPECT_EQ(s.contacts.speculative_distance, 0.01);
  EXPECT_EQ(s.contacts.linear_slop, 0.001);
  EXPECT_EQ(s.contacts.rolling_resistance, 0.02);
  const WorldConfig wc = world_config(s, 1);
  EXPECT_EQ(wc.contacts.substeps, 8);
  EXPECT_EQ(wc.contacts.passes, 3);
  EXPECT_EQ(wc.contacts.rolling_resistance, 0.02);
  EXPECT_EQ(wc.contacts.slip_speed, 0.01);
  EXPECT_EQ(wc.contacts.compound_shapes, 3);
  EXPECT_FALSE(wc.contacts.rolling);
  EXPECT_EQ(wc.contacts.rolling_tolerance, 1e-8);
  const Scene d = load_scene(write_scene("cs2.yaml", "bodies:\n  - name: a\n" + std::string(kBox)));
  EXPECT_EQ(d.contacts.substeps, ContactSettings{}.substeps);  // defaults untouched

  const std::string b = "bodies:\n  - name: a\n" + std::string(kBox);
  EXPECT_HAS(error_of("simulation:\n  contacts: { substeps: -1 }\n" + b),
             "bad.yaml:2:25: simulation.contacts.substeps: expected a whole number from 0 to 1000, got '-1'");
  EXPECT_HAS(error_of("simulation:\n  contacts: { iterations: 1.5 }\n" + b),
             "simulation.contacts.iterations: expected a whole number");
  EXPECT_HAS(error_of("simulation:\n  contacts: { passes: 0 }\n" + b),
             "simulation.contacts.passes: expected a whole number from 1 to 32, got '0'");
  EXPECT_HAS(error_of("simulation:\n  contacts: { contact_hertz: 0 }\n" + b),
             "simulation.contacts.contact_hertz: must be positive");
  EXPECT_HAS(error_of("simulation:\n  contacts: { damping_ratio: -1 }\n" + b),
             "simulation.contacts.damping_ratio: must not be negative");
  EXPECT_HAS(error_of("simulation:\n  contacts: { speculative_distance: -0.1 }\n" + b),
             "simulation.contacts.speculative_distance: must not be negative");
  EXPECT_HAS(error_of("simulation:\n  contacts: { slip_speed: -0.01 }\n" + b),
             "simulation.contacts.slip_speed: must not be negative");
  EXPECT_HAS(error_of("simulation:\n  contacts: { rolling_tolerance: 0.5 }\n" + b),
             "bad.yaml:2:34: simulation.contacts.rolling_tolerance: must be below 0.01");
  EXPECT_HAS(error_of("simulation:\n  contacts: { rolling: maybe }\n" + b), "simulation.contacts.rolling:");
  EXPECT_HAS(error_of("simulation:\n  contacts: { compound_shapes: -2 }\n" + b),
             "simulation.contacts.compound_shapes: expected a whole number from 0");
  EXPECT_HAS(error_of("simulation:\n  contacts: { substep: 4 }\n" + b),
             "simulation.contacts.substep: unknown key 'substep'; did you mean 'substeps'?");
}

TEST(Scene, JointIntegratorSettings) {
  const std::string b = "bodies:\n  - name: a\n" + std::string(kBox);
  const Scene v =
      load_scene(write_scene("ji.yaml", "simulation:\n  joints: { integrator: verlet, substeps: 3 }\n" + b));
  EXPECT_EQ(v.joint_settings.integrator, JointIntegrator::verlet);
  EXPECT_EQ(v.joint_settings.substeps, 3);
  const Scene d = load_scene(write_scene("ji2.yaml", b));
  EXPECT_EQ(d.joint_settings.integrator, JointIntegrator::dopri5);
  EXPECT_EQ(d.joint_settings.substeps, 0);  // chosen from the fastest mode
  EXPECT_HAS(error_of("simulation:\n  joints: { integrator: rk4 }\n" + b),
             "bad.yaml:2:25: simulation.joints.integrator: expected dopri5 or verlet, got 'rk4'");
  EXPECT_HAS(error_of("simulation:\n  joints: { integrator: verlet, substeps: 1.5 }\n" + b),
             "simulation.joints.substeps: must be a whole number");
  EXPECT_HAS(error_of("simulation:\n  joints: { substeps: 2 }\n" + b),
             "simulation.joints.substeps: is verlet's (dopri5 chooses its steps by the tolerance)");
}

TEST(Scene, IgnorePairsByName) {
  const std::string bodies =
      "ground: {}\nbodies:\n  - name: left\n" + std::string(kBox) + "  - name: right\n" + kBox;
  const Scene s = load_scene(
      write_scene("ip.yaml", "simulation:\n  ignore_pairs: [[right, left], [ground, right]]\n" + bodies));
  ASSERT_EQ(s.ignore_pairs.size(), 2u);
  EXPECT_EQ(s.ignore_pairs[0], std::make_pair(0, 1));  // body indices, smaller first
  EXPECT_EQ(s.ignore_pairs[1], std::make_pair(1, 2));  // the ground is the last body
  EXPECT_EQ(world_config(s, 1).ignore_pairs, s.ignore_pairs);

  EXPECT_HAS(error_of("simulation:\n  ignore_pairs: [[left, rihgt]]\n" + bodies),
             "bad.yaml:2:25: simulation.ignore_pairs[0][1]: no body is named 'rihgt'; did you mean 'right'?");
  EXPECT_HAS(error_of("simulation:\n  ignore_pairs: [[left, left]]\n" + bodies),
             "simulation.ignore_pairs[0]: names the same body twice");
  EXPECT_HAS(error_of("simulation:\n  ignore_pairs: [[left, right, ground]]\n" + bodies),
             "simulation.ignore_pairs[0]: expected a pair of body names [a, b], got a list of 3");
  EXPECT_HAS(error_of("simulation:\n  ignore_pairs: left\n" + bodies),
             "simulation.ignore_pairs: expected a list of body name pairs");
}

// Two unit cubes 3 m apart in one OBJ file (two connected parts), written next to the scene.
void write_two_cubes(const std::string& name) {
  std::ofstream f(test::scratch(name));
  for (int part = 0; part < 2; ++part) {
    const double x0 = 3.0 * part;
    for (int i = 0; i < 8; ++i)
      f << "v " << x0 + (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
  }
  // Faces of cube 0 (vertices 1..8), counter-clockwise from outside; cube 1 is offset by 8.
  const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                           {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int part = 0; part < 2; ++part)
    for (const auto& q : faces)
      f << "f " << q[0] + 8 * part << " " << q[1] + 8 * part << " " << q[2] + 8 * part << " "
        << q[3] + 8 * part << "\n";
}

// A mesh collider collides as its convex hull; `mode: parts` as one hull per connected part. Mass
// properties stay the exact mesh's either way.
TEST(Scene, MeshCollisionHullsAndParts) {
  write_two_cubes("two_cubes.obj");
  const Scene whole = load_scene(write_scene(
      "hull.yaml", "bodies:\n  - colliders:\n      - { shape: mesh, file: two_cubes.obj, density: 1 }\n"));
  const Collider& c = whole.bodies[0].colliders[0];
  ASSERT_EQ(c.hulls.size(), 1u);
  EXPECT_EQ(c.hulls[0]->faces.size(), 6u);  // one box 4 x 1 x 1 around both cubes
  EXPECT_NEAR(polyhedron_volume(*c.hulls[0]), 4.0, 1e-12);
  EXPECT_NEAR(c.props_C.mass, 2.0, 1e-12);  // the two cubes, not the hull
  bool noted = false;
  for (const std::string& n : whole.notes) noted = noted || n.find("not convex") != std::string::npos;
  EXPECT_TRUE(noted) << "no note that the mesh collides as a larger hull";

  const Scene parts = load_scene(write_scene(
      "parts.yaml", "bodies:\n  - colliders:\n      - { shape: mesh, file: two_cubes.obj, mode: parts }\n"));
  const Collider& p = parts.bodies[0].colliders[0];
  ASSERT_EQ(p.hulls.size(), 2u);
  for (const auto& h : p.hulls) {
    EXPECT_EQ(polyhedron_problem(*h), "");
    EXPECT_NEAR(polyhedron_volume(*h), 1.0, 1e-12);
  }
  EXPECT_NEAR(p.hulls[1]->centroid.x(), 3.5, 1e-12);
  for (const std::string& n : parts.notes) EXPECT_EQ(n.find("not convex"), std::string::npos) << n;
  // A convex mesh gets no note; `collide: false` builds no hull.
  const Scene off = load_scene(write_scene(
      "off.yaml", "bodies:\n  - colliders:\n      - { shape: mesh, file: two_cubes.obj, collide: false }\n"));
  EXPECT_TRUE(off.bodies[0].colliders[0].hulls.empty());
  EXPECT_NE(error_of("bodies:\n  - colliders:\n      - { shape: mesh, file: two_cubes.obj, mode: part }\n")
                .find("did you mean 'parts'"),
            std::string::npos);
}

// `hull_vertices: N` simplifies a mesh collider's hull to at most N of its vertices and says by
// how much the volume shrank; the mass properties stay the mesh's.
TEST(Scene, HullVerticesCapsTheCollisionHull) {
  {
    std::ofstream f(test::scratch("ball.obj"));  // a UV sphere: 18 x 9 bands, 164 vertices
    const int nu = 18, nv = 10;
    f << "v 0 0 -1\n";
    for (int j = 1; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const double t = M_PI * j / nv - M_PI / 2, a = 2 * M_PI * i / nu;
        f << "v " << std::cos(t) * std::cos(a) << " " << std::cos(t) * std::sin(a) << " " << std::sin(t)
          << "\n";
      }
    f << "v 0 0 1\n";
    auto id = [&](int j, int i) { return 2 + (j - 1) * nu + (i % nu); };
    for (int i = 0; i < nu; ++i) f << "f 1 " << id(1, i + 1) << " " << id(1, i) << "\n";
    for (int j = 1; j + 1 < nv; ++j)
      for (int i = 0; i < nu; ++i)
        f << "f " << id(j, i) << " " << id(j, i + 1) << " " << id(j + 1, i + 1) << " " << id(j + 1, i)
          << "\n";
    const int top = 2 + (nv - 1) * nu;
    for (int i = 0; i < nu; ++i) f << "f " << top << " " << id(nv - 1, i) << " " << id(nv - 1, i + 1) << "\n";
  }
  const Scene full = load_scene(write_scene(
      "ball.yaml", "bodies:\n  - colliders:\n      - { shape: mesh, file: ball.obj, density: 1 }\n"));
  const Scene capped = load_scene(write_scene(
      "ball32.yaml",
      "bodies:\n  - colliders:\n      - { shape: mesh, file: ball.obj, density: 1, hull_vertices: 32 }\n"));
  const Collider& a = full.bodies[0].colliders[0];
  const Collider& b = capped.bodies[0].colliders[0];
  ASSERT_EQ(a.hulls[0]->vertices.size(), 164u);
  EXPECT_LE(b.hulls[0]->vertices.size(), 32u);
  // (A stopped hull of a symmetric point set may keep two coplanar neighbours apart, which the
  // hull builder accepts: convex_hull.cpp.)
  const std::string problem = polyhedron_problem(*b.hulls[0]);
  EXPECT_TRUE(problem.empty() || problem.find("joins two coplanar faces") != std::string::npos) << problem;
  EXPECT_EQ(b.props_C.mass, a.props_C.mass);
  const double lost = 1 - polyhedron_volume(*b.hulls[0]) / polyhedron_volume(*a.hulls[0]);
  EXPECT_GT(lost, 0.0);
  bool noted = false;
  for (const std::string& n : capped.notes)
    noted = noted || (n.find("simplified from 164 to") != std::string::npos &&
                      n.find("% less volume") != std::string::npos);
  EXPECT_TRUE(noted) << "no note of the simplification";
  for (const std::string& n : full.notes) EXPECT_EQ(n.find("simplified"), std::string::npos) << n;
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: sphere, radius: 1, hull_vertices: 8 }\n"),
             "hull_vertices: applies to mesh colliders only");
  EXPECT_HAS(error_of("bodies:\n  - colliders:\n      - { shape: mesh, file: ball.obj, hull_vertices: 3 }\n"),
             "hull_vertices: expected a whole number from 4");
}

// Copies of one mesh file share what the loader makes of it: the imported surface (and through it
// one render mesh), the analysis and the collision hulls; a part mode has its own hulls, and
// scales that six decimals would not tell apart are other meshes (their masses scale as s^3).
TEST(Scene, CopiesOfOneMeshShareTheirHullsAndScalesAreExact) {
  write_two_cubes("two_cubes.obj");
  const Scene s = load_scene(write_scene(
      "copies.yaml",
      "bodies:\n"
      "  - { colliders: [ { shape: mesh, file: two_cubes.obj } ] }\n"
      "  - { position: [0, 5, 0], colliders: [ { shape: mesh, file: two_cubes.obj } ] }\n"
      "  - { position: [0, 9, 0], colliders: [ { shape: mesh, file: two_cubes.obj, mode: parts } ] }\n"
      "  - { position: [0, 0, 9], colliders: [ { shape: mesh, file: two_cubes.obj, scale: 1e-7 } ] }\n"
      "  - { position: [0, 0, 19], colliders: [ { shape: mesh, file: two_cubes.obj, scale: 2e-7 } ] }\n"));
  const Collider &a = s.bodies[0].colliders[0], &b = s.bodies[1].colliders[0], &p = s.bodies[2].colliders[0];
  EXPECT_EQ(a.mesh.get(), b.mesh.get());
  EXPECT_EQ(a.mesh.get(), p.mesh.get());
  ASSERT_EQ(a.hulls.size(), 1u);
  EXPECT_EQ(a.hulls, b.hulls);
  ASSERT_EQ(p.hulls.size(), 2u);
  EXPECT_NE(p.hulls[0].get(), a.hulls[0].get());
  const Collider &small = s.bodies[3].colliders[0], &twice = s.bodies[4].colliders[0];
  EXPECT_NE(small.mesh.get(), twice.mesh.get());
  EXPECT_NEAR(twice.props_C.mass / small.props_C.mass, 8.0, 1e-9);
}

// ---- YAML that yaml-cpp would read silently, and values that make no body ---------------------

// The message from the file's name on (the scratch folder differs per run).
std::string rel(const std::string& m) {
  const size_t i = m.find("bad.yaml");
  return i == std::string::npos ? m : m.substr(i);
}

// Item 13: each a clear error naming file, line and key.
TEST(Scene, YamlItReadsSilentlyOtherwiseIsAnError) {
  const std::string body = "bodies:\n  - name: a\n" + std::string(kBox);
  // A duplicate key: the first one won silently.
  EXPECT_EQ(rel(error_of("simulation: { duration: 1, duration: 2 }\n" + body)),
            "bad.yaml:1:28: simulation.duration: duplicate key 'duration' (first on line 1); YAML would keep "
            "only one of them");
  // A second `bodies:`.
  EXPECT_NE(error_of(body + "bodies:\n  - name: b\n" + kBox)
                .find("bad.yaml:5:1: bodies: duplicate key 'bodies' (first on line 1)"),
            std::string::npos);
  // Several documents.
  EXPECT_NE(error_of(body + "---\n" + body)
                .find("bad.yaml:5:1: scene: a scene file holds one YAML document; a second one starts here"),
            std::string::npos);
  // `!!str 5` and a quoted number are text.
  EXPECT_EQ(rel(error_of("simulation: { duration: !!str 5 }\n" + body)),
            "bad.yaml:1:25: simulation.duration: expected a number, got '5', a value tagged !!str");
  EXPECT_EQ(rel(error_of("simulation: { duration: \"5\" }\n" + body)),
            "bad.yaml:1:25: simulation.duration: expected a number, got '5', text (it is quoted)");
  EXPECT_EQ(rel(error_of("ground: !!str yes\n" + body)),
            "bad.yaml:1:9: ground: expected true or false, got 'yes', a value tagged !!str");
  // Hexadecimal outside collision bits (where it is documented).
  EXPECT_EQ(rel(error_of("video: { fps: 0x10 }\n" + body)),
            "bad.yaml:1:15: video.fps: expected a decimal number, got '0x10' (hexadecimal and octal are for "
            "collision bits only)");
  // A list as a key: was "bad conversion", exit 1.
  EXPECT_EQ(rel(error_of("? [a, b]\n: 1\n" + body)),
            "bad.yaml:1:3: scene: a key must be a plain name, not a list");
  EXPECT_EQ(rel(error_of("simulation:\n  ? { a: 1 }\n  : 2\n" + body)),
            "bad.yaml:2:5: simulation: a key must be a plain name, not a mapping");
  // Explicit numeric tags and plain numbers still work; so does hex in collision bits.
  const std::string ok = write_scene("ok.yaml",
                                     "simulation: { duration: !!float 2, timestep: +0.01 }\n"
                                     "bodies:\n  - colliders:\n"
                                     "      - { shape: box, size: [1, 1, 1], mask: 0x0F }\n");
  const Scene sc = load_scene(ok);
  EXPECT_EQ(sc.duration, 2.0);
  EXPECT_EQ(sc.bodies[0].colliders[0].mask, 0x0Fu);
}

// Aliases that expand past any scene (a few hundred bytes standing for billions of nodes).
TEST(Scene, AliasBombsAreRefusedBeforeTheyExpand) {
  std::string y = "a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int i = 1; i < 10; ++i)
    y += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [" + [&] {
      std::string r;
      for (int k = 0; k < 10; ++k) r += (k ? ", *a" : "*a") + std::to_string(i - 1);
      return r;
    }() + "]\n";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string m = error_of(y + "bodies: []\n");
  EXPECT_NE(m.find("the scene expands to more than 2000000 YAML nodes (through aliases)"), std::string::npos)
      << m;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
}

// Item 14: errors the world would raise without file, line or key are found here, with them.
TEST(Scene, MassesThatMakeNoBodyNameFileLineAndKey) {
  // mass: 1e308 on a tiny box: an infinite density, not "mass must be positive".
  EXPECT_EQ(
      rel(error_of("bodies:\n  - name: a\n    colliders:\n"
                   "      - { shape: box, size: [1e-3, 1e-3, 1e-3], mass: 1e308 }\n")),
      "bad.yaml:4:55: bodies[0].colliders[0].mass: over a volume of 1e-09 m^3 is a density of inf kg/m^3: "
      "out of the range of double precision");
  // A volume that overflows.
  EXPECT_NE(
      error_of("bodies:\n  - colliders:\n      - { shape: box, size: [1e200, 1e200, 1e200] }\n")
          .find("bad.yaml:3:29: bodies[0].colliders[0].size: gives a volume of inf m^3, out of the range"),
      std::string::npos);
  // Density and size in range, inertia not.
  EXPECT_NE(error_of("bodies:\n  - colliders:\n      - { shape: sphere, radius: 1e100, density: 1e100 }\n")
                .find("bodies[0].colliders[0].density: gives a mass of"),
            std::string::npos);
  // Each collider fine, the body not: the parallel-axis terms overflow.
  EXPECT_NE(error_of("bodies:\n  - name: far\n    colliders:\n"
                     "      - { shape: sphere, radius: 1, position: [1e160, 0, 0] }\n"
                     "      - { shape: sphere, radius: 1, position: [-1e160, 0, 0] }\n")
                .find("bad.yaml:4:7: bodies[0].colliders: body 'far': the body's mass"),
            std::string::npos);
  // A timestep that makes the step count uncountable (4.9e-324 ran zero steps).
  const std::string sphere = "bodies:\n  - colliders: [{ shape: sphere, radius: 1 }]\n";
  EXPECT_NE(error_of("simulation: { timestep: 4.9e-324 }\n" + sphere).find("simulation.timestep: "),
            std::string::npos);
  EXPECT_NE(error_of("simulation: { duration: 1e300, timestep: 1e-10 }\n" + sphere)
                .find("simulation.timestep: makes duration / timestep = inf steps"),
            std::string::npos);
  // A number beyond double precision is out of range, not "not a number".
  EXPECT_NE(
      error_of("simulation: { duration: 1e999 }\nbodies:\n  - colliders: [{ shape: sphere, radius: 1 }]\n")
          .find("simulation.duration: is out of the range of double precision"),
      std::string::npos);
}

// Item 16: a directory or FIFO is not a missing file.
TEST(Scene, DirectoriesAndFifosAreNotMissingFiles) {
  const std::string dir = test::scratch("d.yaml");
  fs::create_directory(dir);
  try {
    load_scene(dir);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory, not a scene file"), std::string::npos) << e.what();
  }
  fs::create_directory(test::scratch("m.obj"));
  EXPECT_NE(error_of("bodies:\n  - colliders: [{ shape: mesh, file: " + test::scratch("m.obj") + " }]\n")
                .find("m.obj' is a directory"),
            std::string::npos);
}

// Item 1 through a scene: a malformed PLY file (which crashed assimp) is an error naming the key.
TEST(Scene, MalformedPlyThroughASceneIsAnError) {
  const std::string m =
      error_of("bodies:\n  - colliders: [{ shape: mesh, file: " +
               fs::absolute("tests/data/hostile/ply_duplicate_property.ply").string() + " }]\n");
  EXPECT_NE(m.find("bodies[0].colliders[0].file: "), std::string::npos) << m;
  EXPECT_NE(m.find("element 'vertex' has a second property named 'x'"), std::string::npos) << m;
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

Quat body_orientation(const std::string& keys) {
  const Scene s = load_scene(write_scene("orient.yaml", "bodies:\n  - name: a\n    " + keys + "\n" + kBox));
  return s.bodies[0].q_WB;
}

// Orientation as a quaternion, as Euler angles (degrees; intrinsic z-y-x, aerospace: q = qz(yaw)
// qy(pitch) qx(roll)) or as an axis and an angle: the same rotation whichever form, to rounding.
TEST(Scene, OrientationAsQuaternionEulerOrAxisAngle) {
  const double h = std::sqrt(0.5);
  const Quat yaw90 =
      body_orientation("orientation: [" + std::to_string(h) + ", 0, 0, " + std::to_string(h) + "]");
  EXPECT_LT(yaw90.angularDistance(body_orientation("euler: [0, 0, 90]")), 1e-6);
  EXPECT_LT(yaw90.angularDistance(body_orientation("axis_angle: { axis: [0, 0, 2], angle: 90 }")), 1e-12);
  // Order: roll first about the body's x, then yaw: body y -> world z, body x -> world y.
  const Quat q = body_orientation("euler: [90, 0, 90]");
  EXPECT_LT((q * Vec3::UnitY() - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_LT((q * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-12);
  // A positive rotation about y turns x toward -z (right-handed).
  EXPECT_LT((body_orientation("euler: [0, 90, 0]") * Vec3::UnitX() - Vec3(0, 0, -1)).norm(), 1e-12);
  EXPECT_NE(error_of("bodies:\n  - name: a\n    euler: [0, 0, 90]\n    orientation: [1, 0, 0, 0]\n" +
                     std::string(kBox))
                .find("give one orientation"),
            std::string::npos);
  EXPECT_NE(
      error_of("bodies:\n  - name: a\n    axis_angle: { axis: [0, 0, 0], angle: 10 }\n" + std::string(kBox))
          .find("axis_angle.axis: must not be zero"),
      std::string::npos);
  EXPECT_NE(error_of("bodies:\n  - name: a\n    axis_angle: { axis: [0, 0, 1] }\n" + std::string(kBox))
                .find("needs both 'axis' and 'angle'"),
            std::string::npos);
}

// The angular velocity may be given in the body frame: w_W = R_WB w_B.
TEST(Scene, AngularVelocityInTheBodyFrame) {
  const Scene s = load_scene(write_scene(
      "wb.yaml", "bodies:\n  - name: top\n    euler: [90, 0, 0]\n    angular_velocity_body: [0, 2, 0]\n" +
                     std::string(kBox)));
  EXPECT_LT((s.bodies[0].w_W - Vec3(0, 0, 2)).norm(), 1e-12);
  EXPECT_NE(
      error_of(
          "bodies:\n  - name: a\n    angular_velocity: [0, 0, 1]\n    angular_velocity_body: [0, 0, 1]\n" +
          std::string(kBox))
          .find("give the angular velocity once"),
      std::string::npos);
}

// A y-up mesh stands up: up_axis: y turns mesh +y into the body's +z.
TEST(Scene, UpAxisYTurnsAMeshUpright) {
  const Scene s = load_scene(
      write_scene("up.yaml", "bodies:\n  - name: m\n    colliders:\n      - { shape: mesh, file: " +
                                 fs::absolute("assets/tetra.off").string() + ", up_axis: y }\n"));
  EXPECT_LT((s.bodies[0].colliders[0].q_BC * Vec3::UnitY() - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NE(error_of("bodies:\n  - name: a\n    colliders:\n      - { shape: box, up_axis: y }\n")
                .find("applies to mesh colliders only"),
            std::string::npos);
  EXPECT_NE(error_of("bodies:\n  - name: a\n    colliders:\n      - { shape: mesh, file: " +
                     fs::absolute("assets/tetra.off").string() + ", up_axis: x }\n")
                .find("expected y or z"),
            std::string::npos);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// Composition is linear in the colliders (each addition used to re-sum all earlier ones: 16,000
// colliders took 20 s), and a scene's body and collider counts have limits named in the message.
TEST(Scene, ManyCollidersComposeInLinearTimeAndLimitsAreNamed) {
  auto scene_of = [](int n) {
    std::string text = "bodies:\n  - name: many\n    colliders:\n";
    for (int i = 0; i < n; ++i)
      text += "      - { shape: sphere, radius: 0.1, position: [" + std::to_string(i % 100) + ", " +
              std::to_string(i / 100) + ", 0] }\n";
    return text;
  };
  auto seconds_to_load = [&](int n, Scene* out) {
    const std::string path = write_scene("many" + std::to_string(n) + ".yaml", scene_of(n));
    const auto t0 = std::chrono::steady_clock::now();
    *out = load_scene(path);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  Scene small, s;
  const double t4 = seconds_to_load(4000, &small), t16 = seconds_to_load(16000, &s);
  // Linear: 4x the colliders take about 4x the time (quadratic took 16x); 8x leaves room for noise
  // and holds in any build type (sanitizers slow both alike).
  EXPECT_LT(t16, 8 * t4 + 0.05) << "4000 colliders " << t4 << " s, 16000 colliders " << t16 << " s";
  const double m1 = 1000 * 4.0 / 3.0 * M_PI * 0.001;  // one sphere, kg
  EXPECT_NEAR(s.bodies[0].mass_B().mass, 16000 * m1, 1e-9 * 16000 * m1);
  EXPECT_NEAR(s.bodies[0].mass_B().com.x(), 49.5, 1e-9);
  EXPECT_NEAR(s.bodies[0].mass_B().com.y(), 79.5, 1e-9);
  std::string big = "bodies: [";
  for (int i = 0; i <= 100000; ++i) big += std::string(i ? ", " : "") + "{}";
  EXPECT_NE(error_of(big + "]\n").find("a scene holds at most 100000"), std::string::npos);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// A static body's mesh collides as its triangles (sim/geometry/trimesh.hpp): an open mesh (which no
// dynamic body may weigh) loads, weighs nothing, and becomes one triangle-mesh shape; mass keys
// on it are errors naming file, line and key.
TEST(Scene, StaticMeshCollidesAsItsTriangles) {
  const Scene s = load_scene(write_scene(
      "tray.yaml",
      "bodies:\n  - name: tray\n    type: static\n    colliders:\n      - { shape: mesh, file: open_box.obj "
      "}\n"
      "  - name: ball\n    position: [0.5, 0.5, 0.5]\n    colliders: [ { shape: sphere, radius: 0.1 } ]\n"));
  EXPECT_EQ(s.bodies[0].colliders[0].props_C.mass, 0);
  World w(world_config(s, 1), s.bodies);
  ASSERT_EQ(w.impl().shapes().size(), 2);
  EXPECT_EQ(w.impl().shapes()[0].geom.kind, CollideKind::mesh);
  EXPECT_HAS(
      error_of("bodies:\n  - static: true\n    colliders:\n      - { shape: mesh, file: open_box.obj, "
               "density: 3 }\n"),
      "bodies[0].colliders[0].density: a static body's mesh collides as its triangles and has no mass");
  // On a dynamic body the same open mesh is still refused (it has no volume to weigh).
  EXPECT_NE(error_of("bodies:\n  - colliders:\n      - { shape: mesh, file: open_box.obj }\n"), "");
}

// The look's keys: each error names the file, line, column and key.
TEST(Scene, LookKeysAreCheckedWithFileLineAndKey) {
  const std::string body = "bodies:\n  - name: a\n" + std::string(kBox);
  const std::pair<std::string, std::string> cases[] = {
      {"render: { quality: ultra }\n",
       "bad.yaml:1:20: render.quality: unknown quality 'ultra' (standard, high)"},
      {"render: { sky: stars }\n", "bad.yaml:1:16: render.sky: unknown sky 'stars' (gradient, flat)"},
      {"render: { horizon: [1, 2, 0] }\n", "render.horizon[1]: colour components must lie in [0, 1]"},
      {"ground: { colors: [[1, 1, 1]] }\n", "bad.yaml:1:19: ground.colors: expected two colours"},
      {"ground: { texture: nowhere.png }\n", "bad.yaml:1:20: ground.texture: image 'nowhere.png' not found"},
      {"ground: { texture_size: 2 }\n", "ground.texture_size: applies with 'texture' only"},
  };
  for (const auto& [head, want] : cases) {
    const std::string e = error_of(head + body);
    EXPECT_NE(e.find(want), std::string::npos) << e;
  }
  const std::string e = error_of(
      "bodies:\n  - name: a\n    colliders:\n      - { shape: box, size: [1, 1, 1], "
      "texture: x.png }\n");
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("texture: applies to mesh colliders only"), std::string::npos) << e;
}

}  // namespace
}  // namespace simreel
