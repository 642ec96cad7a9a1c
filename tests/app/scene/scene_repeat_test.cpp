// `repeat:` on bodies and joints (app/scene/scene_repeat.cpp): copies named NAME_1 .. NAME_N, each a
// step further, joints following their bodies' copies, errors pointing at the template's lines.
#include <gtest/gtest.h>

#include <string>

#include "app/scene/scene.hpp"
#include "tests/app/scene/scene_error.hpp"

namespace simreel {
namespace {

const char* kRow =
    "simulation: { duration: 1 }\n"                                                              // 1
    "bodies:\n"                                                                                  // 2
    "  - name: ball\n"                                                                           // 3
    "    position: [-0.2, 0, 0.35]\n"                                                            // 4
    "    repeat: { count: 5, step: [0.101, 0, 0] }\n"                                            // 5
    "    colliders: [ { shape: sphere, radius: 0.05, mass: 1 } ]\n"                              // 6
    "  - { name: other, position: [0, 2, 1], colliders: [ { shape: sphere, radius: 0.1 } ] }\n"  // 7
    "joints:\n"                                                                                  // 8
    "  - { name: string, type: revolute, bodies: [world, ball], anchor: [-0.2, 0, 0.75], axis: [0, 1, 0],\n"
    "      repeat: { count: 5, step: [0.101, 0, 0] } }\n";

std::string error_of(const std::string& text) {
  return test::scene_error(text, "row.yaml");
}

std::string replaced(std::string s, const std::string& a, const std::string& b) {
  const size_t at = s.find(a);
  EXPECT_NE(at, std::string::npos) << a;
  return s.replace(at, a.size(), b);
}

TEST(Repeat, BodiesAndJointsAreCopiedAStepApart) {
  const Scene s = load_scene_text(kRow, "row.yaml");
  ASSERT_EQ(s.bodies.size(), 6u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(s.bodies[k].name, "ball_" + std::to_string(k + 1));
    EXPECT_NEAR(s.bodies[k].p_WB.x(), -0.2 + 0.101 * k, 1e-15);
    EXPECT_EQ(s.bodies[k].p_WB.z(), 0.35);
    EXPECT_EQ(s.joints[k].name, "string_" + std::to_string(k + 1));
    EXPECT_EQ(s.joints[k].child, k) << "the k-th joint holds the k-th ball";
    EXPECT_NEAR(s.joints[k].anchor_W.x(), -0.2 + 0.101 * k, 1e-15);
  }
  EXPECT_EQ(s.bodies[5].name, "other");
}

TEST(Repeat, ErrorsPointAtTheTemplate) {
  // A bad key in the template: every copy would fail; the first names the template's line.
  EXPECT_NE(error_of(replaced(kRow, "radius: 0.05, mass: 1", "radius: 0.05, mas: 1")).find("row.yaml:6:"),
            std::string::npos)
      << error_of(replaced(kRow, "radius: 0.05, mass: 1", "radius: 0.05, mas: 1"));
  EXPECT_NE(
      error_of(replaced(kRow, "count: 5, step: [0.101, 0, 0] }\n    colliders", "count: 0 }\n    colliders"))
          .find("row.yaml:5:"),
      std::string::npos);
  EXPECT_NE(error_of(replaced(kRow, "count: 5, step: [0.101, 0, 0] }\n    colliders",
                              "count: 2.5 }\n    colliders"))
                .find("a whole number of copies"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(kRow, "repeat: { count: 5, step: [0.101, 0, 0] }\n    colliders",
                              "repeat: { count: 5, stride: 1 }\n    colliders"))
                .find("unknown key 'stride'"),
            std::string::npos);
  // A joint repeated another number of times than its body.
  const std::string e = error_of(replaced(kRow, "      repeat: { count: 5", "      repeat: { count: 4"));
  EXPECT_NE(e.find("body 'ball' is repeated 5 times"), std::string::npos) << e;
  EXPECT_NE(e.find("row.yaml:10:"), std::string::npos) << e;
  // A repeated joint must follow a repeated body.
  const std::string f =
      error_of(replaced(kRow, "bodies: [world, ball], anchor", "bodies: [world, other], anchor"));
  EXPECT_NE(f.find("neither of its bodies is"), std::string::npos) << f;
  // Copies are named: the template's name is not a body (the nearest copy suggested).
  const std::string g = error_of(std::string(kRow) + "overlays: { labels: [ { body: ball, text: x } ] }\n");
  EXPECT_NE(g.find("no body is named 'ball'; did you mean 'ball_1'?"), std::string::npos) << g;
}

}  // namespace
}  // namespace simreel
