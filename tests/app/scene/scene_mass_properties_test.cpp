// The scene key `mass_properties: { mass, center_of_mass, inertia }`: read into the body, reaching
// the World over the colliders' own mass, and every mistake refused naming file, line and key.
#include <gtest/gtest.h>

#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"
#include <simreel/error.hpp>
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

std::string body_with(const std::string& mp) {
  return "bodies:\n  - name: celt\n    colliders:\n      - { shape: ellipsoid, radii: [0.2, 0.03, 0.02] }\n"
         "    mass_properties: " +
         mp + "\n";
}

std::string error_of(const std::string& text) {
  const std::string path = test::scratch_file("bad.yaml", text);
  try {
    load_scene(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "scene was accepted:\n" << text;
  return "";
}

TEST(SceneMassProperties, OverrideReachesTheWorld) {
  const std::string path = test::scratch_file(
      "celt.yaml", body_with("{ mass: 1, center_of_mass: [0, 0, -0.01],\n"
                             "      inertia: [[2e-4, -2e-5, 0], [-2e-5, 1.6e-3, 0], [0, 0, 1.7e-3]] }"));
  const Scene s = load_scene(path);
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_TRUE(s.bodies[0].mass_override.has_value());
  EXPECT_EQ(s.bodies[0].mass_B().mass, 1.0);  // the ellipsoid alone at 1000 kg/m^3: 0.50 kg
  World w(world_config(s, 1), s.bodies);
  EXPECT_EQ(w.impl().model(0).mass, 1.0);
  EXPECT_EQ(w.local_centroid(0), Vec3(0, 0, -0.01));
  Mat3 I;
  I << 2e-4, -2e-5, 0, -2e-5, 1.6e-3, 0, 0, 0, 1.7e-3;
  EXPECT_LT((w.inertia_world(0) - I).norm(), 1e-18);
}

TEST(SceneMassProperties, DiagonalInertiaAsThreeMoments) {
  const Scene s = load_scene(test::scratch_file(
      "d.yaml", body_with("{ mass: 2, center_of_mass: [0, 0, 0], inertia: [1, 2, 2.5] }")));
  EXPECT_EQ(s.bodies[0].mass_B().inertia, Mat3(Vec3(1, 2, 2.5).asDiagonal()));
}

TEST(SceneMassProperties, EachMistakeNamesFileLineAndKey) {
  const std::string good_I = "inertia: [[1, 0, 0], [0, 2, 0], [0, 0, 2.5]]";
  struct Case {
    std::string mp, expect;
  };
  const Case cases[] = {
      {"{ mass: 0, center_of_mass: [0, 0, 0], " + good_I + " }",
       "bad.yaml:5:30: bodies[0].mass_properties.mass: must be positive"},
      {"{ mass: -1, center_of_mass: [0, 0, 0], " + good_I + " }", "bodies[0].mass_properties.mass"},
      {"{ center_of_mass: [0, 0, 0], " + good_I + " }", "bodies[0].mass_properties: needs 'mass'"},
      {"{ mass: 1, " + good_I + " }", "bodies[0].mass_properties: needs 'center_of_mass'"},
      {"{ mass: 1, center_of_mass: [0, 0] , " + good_I + " }",
       "bodies[0].mass_properties.center_of_mass: expected a list of 3 numbers"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], intertia: [1, 1, 1] }", "did you mean 'inertia'?"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 0.1, 0], [0, 2, 0], [0, 0, 2.5]] }",
       "bad.yaml:5:69: bodies[0].mass_properties.inertia: the inertia tensor must be symmetric"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 0, 0], [0, 2, 0], [0, 0, -2.5]] }",
       "bodies[0].mass_properties.inertia: principal moment -2.5 kg m^2 is not positive: the inertia "
       "tensor must be positive definite"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 2, 0], [2, 1, 0], [0, 0, 1]] }",
       "is not positive: the inertia tensor must be positive definite"},  // eigenvalues -1, 1, 3
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [1, 2, 3.5] }",
       "bodies[0].mass_properties.inertia: principal moments (1, 2, 3.5) violate the triangle inequality"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 0, 0], [0, 2, 0]] }",
       "bodies[0].mass_properties.inertia: expected a 3x3 tensor"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 0, 0], [0, 2], [0, 0, 2]] }",
       "bodies[0].mass_properties.inertia[1]: expected a list of 3 numbers"},
      {"{ mass: 1, center_of_mass: [0, 0, 0], inertia: [[1, 0, 0], [0, x, 0], [0, 0, 2]] }",
       "bodies[0].mass_properties.inertia[1][1]"},
      {"5", "bodies[0].mass_properties: expected a mapping"},
  };
  for (const Case& k : cases) {
    const std::string msg = error_of(body_with(k.mp));
    EXPECT_NE(msg.find(k.expect), std::string::npos) << "for " << k.mp << "\ngot: " << msg;
  }
}

}  // namespace
}  // namespace simreel
