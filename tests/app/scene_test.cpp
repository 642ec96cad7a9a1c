// The scene parser: every mistake a user can make names the file, line, column and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/scene.hpp"
#include "sim/error.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

std::string write_scene(const std::string& name, const std::string& text) {
  const fs::path p = test::scratch(name);
  std::ofstream(p) << text;
  return p.string();
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
  EXPECT_NE(o.find("mode: shell"), std::string::npos) << o;
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
  ASSERT_TRUE(s.bodies[0].colliders[0].color.has_value());
  EXPECT_FLOAT_EQ((*s.bodies[0].colliders[0].color)[0], 0.9f);
  EXPECT_FALSE(s.bodies[0].colliders[1].color.has_value());              // a primitive has no file material
  EXPECT_FALSE(s.bodies[1].colliders[0].color.has_value());              // the scene's body colour wins
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

}  // namespace
}  // namespace simreel
