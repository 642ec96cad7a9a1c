// The scene's `forces:` list (app/scene/scene_forces.cpp): what it loads into, every mistake named by
// file, line, column and key, and the command line around it (profile, threads, resume).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"
#include <simreel/error.hpp>
#include <simreel/world.hpp>
#include "tests/cli_run.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

const char* kBodies =
    "simulation: { duration: 2, timestep: 0.01 }\n"
    "bodies:\n"
    "  - name: rocket\n    position: [0, 0, 1]\n"
    "    colliders: [ { shape: box, size: [0.2, 0.2, 1], mass: 2 } ]\n"
    "  - name: ball\n    position: [2, 0, 1]\n"
    "    colliders: [ { shape: sphere, radius: 0.1, mass: 1 } ]\n"
    "  - name: wall\n    static: true\n    position: [0, 5, 0]\n"
    "    colliders: [ { shape: box, size: [1, 1, 1] } ]\n";

std::string write_scene(const std::string& name, const std::string& text) {
  const fs::path p = test::scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

Scene load_forces_scene(const std::string& forces) {
  return load_scene(write_scene("f.yaml", std::string(kBodies) + "forces:\n" + forces));
}

// The message of a rejected `forces:` list (empty and a failure if it loaded).
std::string error_of(const std::string& forces) {
  try {
    load_forces_scene(forces);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "forces were accepted:\n" << forces;
  return "";
}

// Line 14 is the first entry of the list (kBodies has 12 lines, then "forces:").
#define EXPECT_ERROR(forces, text)                                            \
  do {                                                                        \
    const std::string m_ = error_of(forces);                                  \
    EXPECT_NE(m_.find(text), std::string::npos) << "message: " << m_;         \
    EXPECT_NE(m_.find("f.yaml:"), std::string::npos) << "no file in: " << m_; \
  } while (0)

TEST(SceneForces, TheContractFormLoads) {
  const Scene s = load_forces_scene(
      "  - { type: force, body: rocket, vector: [0, 0, 20], frame: body, at: [0, 0, -0.5], from: 0, to: 2 }\n"
      "  - { type: torque, body: rocket, vector: [0, 0, 1.5], frame: world }\n"
      "  - { type: impulse, body: ball, vector: [1, 0, 0], at: [0, 0, 0.1], time: 0.5 }\n"
      "  - { type: angular_impulse, body: ball, vector: [0, 0, 0.2], time: 1 }\n"
      "  - { type: spring, body: ball, point: [0, 0, 0], anchor: [2, 0, 2], stiffness: 100, rest_length: 1, "
      "damping: 0 }\n"
      "  - { type: spring, bodies: [rocket, ball], points: [[0, 0, 0.5], [0, 0, -0.1]], stiffness: 50, "
      "rest_length: 1 }\n"
      "  - { type: drag, bodies: [ball], linear: 0.1, quadratic: 0.05 }\n"
      "  - { type: drag, quadratic: 0.01 }\n"
      "  - { type: spring, bodies: [wall, ball], stiffness: 5 }\n");
  ASSERT_EQ(s.forces.size(), 10u);  // the last drag acts on both dynamic bodies: two records
  const ForceDef& f = s.forces[0];
  EXPECT_EQ(f.kind, ForceKind::force);
  EXPECT_EQ(f.body, 0);
  EXPECT_EQ(f.frame, ForceFrame::body);
  EXPECT_EQ(f.vector, Vec3(0, 0, 20));
  EXPECT_FALSE(f.at_centroid);
  EXPECT_EQ(f.at_B, Vec3(0, 0, -0.5));
  EXPECT_EQ(f.from, 0);
  EXPECT_EQ(f.to, 2);
  EXPECT_EQ(s.forces[1].frame, ForceFrame::world);
  EXPECT_TRUE(std::isinf(s.forces[1].from) && std::isinf(s.forces[1].to));
  EXPECT_EQ(s.forces[2].kind, ForceKind::impulse);
  EXPECT_EQ(s.forces[2].time, 0.5);
  EXPECT_EQ(s.forces[3].kind, ForceKind::angular_impulse);
  EXPECT_EQ(s.forces[4].body_b, -1);
  EXPECT_EQ(s.forces[4].anchor_W, Vec3(2, 0, 2));
  EXPECT_EQ(s.forces[4].stiffness, 100);
  EXPECT_EQ(s.forces[5].body, 0);
  EXPECT_EQ(s.forces[5].body_b, 1);
  EXPECT_EQ(s.forces[5].at_b_B, Vec3(0, 0, -0.1));
  EXPECT_EQ(s.forces[6].linear, 0.1);
  EXPECT_EQ(s.forces[6].quadratic, 0.05);
  EXPECT_EQ(s.forces[7].body, 0);
  EXPECT_EQ(s.forces[8].body, 1);
  // A spring to a static body: the dynamic end first; no rest_length: unstretched at the start
  // (centres (2, 0, 1) and (0, 5, 0)).
  EXPECT_EQ(s.forces[9].body, 1);
  EXPECT_EQ(s.forces[9].body_b, 2);
  EXPECT_NEAR(s.forces[9].rest_length, std::sqrt(4.0 + 25 + 1), 1e-12);
  // And the world takes them.
  World w(world_config(s, 1), s.bodies);
  w.step();
  EXPECT_EQ(w.profile().runs[(int)Stage::forces], 1);
}

TEST(SceneForces, UnknownBodySuggestsTheNearestName) {
  EXPECT_ERROR("  - { type: force, body: rockt, vector: [1, 0, 0] }\n",
               ":14:26: forces[0].body: no body is named 'rockt'; did you mean 'rocket'?");
  EXPECT_ERROR("  - { type: drag, bodies: [ball, bal], linear: 1 }\n",
               "forces[0].bodies[1]: no body is named 'bal'; did you mean 'ball'?");
}

TEST(SceneForces, WrongVectorLength) {
  EXPECT_ERROR("  - { type: force, body: rocket, vector: [1, 0] }\n",
               ":14:42: forces[0].vector: expected a list of 3 numbers, got a list of 2");
  EXPECT_ERROR("  - { type: force, body: rocket, vector: [1, 0, 0], at: 3 }\n",
               "forces[0].at: expected a list of 3 numbers, got '3'");
  EXPECT_ERROR("  - { type: spring, bodies: [rocket, ball], points: [[0, 0, 0]], stiffness: 1 }\n",
               "forces[0].points: expected two points");
}

TEST(SceneForces, NegativeStiffnessDampingOrDrag) {
  EXPECT_ERROR("  - { type: spring, body: ball, anchor: [0, 0, 0], stiffness: -1 }\n",
               "forces[0].stiffness: must not be negative, got '-1'");
  EXPECT_ERROR("  - { type: spring, body: ball, anchor: [0, 0, 0], stiffness: 1, damping: -0.5 }\n",
               "forces[0].damping: must not be negative");
  EXPECT_ERROR("  - { type: drag, linear: -0.1 }\n", "forces[0].linear: must not be negative");
  EXPECT_ERROR("  - { type: drag, quadratic: -2 }\n", "forces[0].quadratic: must not be negative");
  EXPECT_ERROR("  - { type: spring, body: ball, anchor: [0, 0, 0], stiffness: 1, rest_length: -1 }\n",
               "forces[0].rest_length: must not be negative");
}

TEST(SceneForces, FromAfterTo) {
  EXPECT_ERROR("  - { type: force, body: rocket, vector: [1, 0, 0], from: 3, to: 1 }\n",
               "forces[0].from: the window starts after it ends (from 3 s, to 1 s)");
}

TEST(SceneForces, BodyAndBodiesBothOrNeither) {
  EXPECT_ERROR("  - { type: force, body: rocket, bodies: [ball], vector: [1, 0, 0] }\n",
               "forces[0].bodies: give either 'body' (one name) or 'bodies' (a list), not both");
  EXPECT_ERROR("  - { type: torque, vector: [1, 0, 0] }\n",
               ":14:5: forces[0]: torque needs 'body' (a body's name) or 'bodies'");
  EXPECT_ERROR("  - { type: spring, anchor: [0, 0, 0], stiffness: 1 }\n",
               "forces[0]: spring needs 'body' with 'anchor'");
}

TEST(SceneForces, ImpulseWithoutTime) {
  EXPECT_ERROR("  - { type: impulse, body: ball, vector: [1, 0, 0] }\n",
               "forces[0]: impulse needs 'time' (s: when it is applied, once)");
  EXPECT_ERROR("  - { type: angular_impulse, body: ball, vector: [1, 0, 0], time: -1 }\n",
               "forces[0].time: must not be negative");
}

TEST(SceneForces, SpringWithNeitherAnchorNorSecondBodyOrBoth) {
  EXPECT_ERROR("  - { type: spring, body: ball, stiffness: 10 }\n",
               "forces[0]: spring on one body needs 'anchor' (a fixed world point [x, y, z], m)");
  EXPECT_ERROR("  - { type: spring, bodies: [rocket, ball], anchor: [0, 0, 0], stiffness: 10 }\n",
               "forces[0].anchor: a spring has one fixed anchor or a second body, not both");
  EXPECT_ERROR("  - { type: spring, bodies: [ball], stiffness: 10 }\n",
               "forces[0].bodies: a spring joins two bodies: expected [a, b], got a list of 1");
  EXPECT_ERROR("  - { type: spring, bodies: [ball, ball], stiffness: 10 }\n",
               "forces[0].bodies: a spring needs two different bodies");
  EXPECT_ERROR("  - { type: spring, body: ball, anchor: [0, 0, 0] }\n",
               "forces[0]: spring needs 'stiffness' (N/m)");
}

TEST(SceneForces, UnknownTypeKeyOrFrame) {
  EXPECT_ERROR("  - { type: forse, body: rocket, vector: [1, 0, 0] }\n",
               "forces[0].type: unknown force type 'forse'");
  EXPECT_ERROR("  - { type: forse, body: rocket, vector: [1, 0, 0] }\n", "did you mean 'force'?");
  EXPECT_ERROR("  - { body: rocket, vector: [1, 0, 0] }\n", "forces[0]: missing key 'type'");
  // A key another type has: `at` on a torque (a torque has no point of action).
  EXPECT_ERROR("  - { type: torque, body: rocket, vector: [1, 0, 0], at: [0, 0, 1] }\n",
               "forces[0].at: unknown key 'at' for type torque");
  EXPECT_ERROR("  - { type: force, body: rocket, vectr: [1, 0, 0] }\n", "did you mean 'vector'?");
  EXPECT_ERROR("  - { type: force, body: rocket, vector: [1, 0, 0], frame: local }\n",
               "forces[0].frame: unknown frame 'local' (world or body)");
  EXPECT_ERROR("  - { type: force, body: rocket }\n", "forces[0]: force needs 'vector' ([x, y, z] in N)");
  EXPECT_ERROR("  - { type: drag, body: ball }\n", "forces[0]: drag needs 'linear'");
}

TEST(SceneForces, ForcesActOnDynamicBodiesOnly) {
  EXPECT_ERROR("  - { type: force, body: wall, vector: [1, 0, 0] }\n",
               "forces[0].body: body 'wall' is static: forces act on dynamic bodies only");
  EXPECT_ERROR("  - { type: spring, bodies: [wall, ground], stiffness: 1 }\n", "no body is named 'ground'");
}

TEST(SceneForces, NotAListOrNotAMapping) {
  EXPECT_ERROR("  type: force\n", "forces: expected a list of forces");
  EXPECT_ERROR("  - force\n", "forces[0]: expected a mapping like { type: force");
  EXPECT_ERROR("  - { type: force, body: rocket, vector: [1, 0, x] }\n",
               "forces[0].vector[2]: expected a number, got 'x'");
}

TEST(SceneForces, ImpulseAfterTheEndIsANote) {
  const Scene s = load_forces_scene("  - { type: impulse, body: ball, vector: [1, 0, 0], time: 5 }\n");
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("f.yaml:14: forces[0].time: impulse at 5 s comes after the end of the run (2 s)"),
            std::string::npos)
      << s.notes[0];
}

TEST(SceneForces, TheTopLevelKeyIsKnown) {
  try {
    load_scene(write_scene("t.yaml", std::string(kBodies) + "forcse: []\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'forces'?"), std::string::npos) << e.what();
  }
}

// ---- The command line.

using test::Result;
using test::run;
using test::slurp;

const char* kForcesScene =
    "simulation: { duration: 2.0 }\n"
    "ground: { friction: 0.5 }\n"
    "bodies:\n"
    "  - name: bob\n    position: [0, 0, 1.5]\n    linear_velocity: [0.5, 0, 0]\n"
    "    colliders: [ { shape: sphere, radius: 0.1 } ]\n"
    "  - name: sled\n    position: [2, 0, 0.25]\n"
    "    colliders: [ { shape: box, size: [0.5, 0.5, 0.5] } ]\n"
    "  - name: top\n    position: [-2, 0, 2]\n    angular_velocity: [0, 0, 10]\n"
    "    colliders: [ { shape: cylinder, radius: 0.3, height: 0.1 } ]\n"
    "forces:\n"
    "  - { type: spring, body: bob, anchor: [0, 0, 2.5], stiffness: 200, damping: 0.5 }\n"
    "  - { type: force, body: sled, vector: [600, 0, 0], from: 0.3, to: 1.2 }\n"
    "  - { type: impulse, body: sled, vector: [0, 50, 0], time: 0.5 }\n"
    "  - { type: impulse, body: bob, vector: [0, 0.5, 0], time: 1.5 }\n"
    "  - { type: torque, body: top, vector: [0.5, 0, 0], frame: body }\n"
    "  - { type: drag, linear: 0.05, quadratic: 0.02 }\n";

TEST(SceneForces, ProfileShowsTheForcesStage) {
  const std::string sc = write_scene("forces.yaml", kForcesScene);
  const Result r = run("simulate " + sc + " --profile --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const size_t a = r.out.find('{'), b = r.out.rfind('}');
  ASSERT_NE(a, std::string::npos) << r.out;
  const nlohmann::json p = nlohmann::json::parse(r.out.substr(a, b - a + 1))["profile"];
  EXPECT_TRUE(p["forces"]["seconds"].is_number()) << r.out;
  EXPECT_EQ(p["forces"]["runs"], 480) << r.out;
  EXPECT_EQ(p["forces"]["skipped"], 0) << r.out;
  EXPECT_EQ(p["applied_forces"], nlohmann::json({{"records", 8}, {"rk4_bodies", 3}})) << r.out;
  const Result t = run("simulate " + sc + " --profile");
  EXPECT_NE(
      t.out.find("forces: 8 records (the drag is one per body), 3 bodies stepped by RK4 with the forces "
                 "evaluated at every stage"),
      std::string::npos)
      << t.out;
}

TEST(SceneForces, ThreadsAndResumeGiveTheStraightRun) {
  const std::string sc = write_scene("forces.yaml", kForcesScene);
  const fs::path dir = test::scratch_dir();
  ASSERT_EQ(run("simulate " + sc + " --quiet --csv " + (dir / "full.csv").string()).code, 0);
  ASSERT_EQ(run("simulate " + sc + " --quiet --threads 2 --csv " + (dir / "t2.csv").string()).code, 0);
  EXPECT_EQ(slurp(dir / "full.csv"), slurp(dir / "t2.csv"));
  // Saved at 1.0 s: the sled's impulse applied (its flag is in the file), the bob's still to come.
  ASSERT_EQ(run("simulate " + sc + " --quiet --duration 1.0 --save-state " + (dir / "s.bin").string()).code,
            0);
  const Result r = run("simulate " + sc + " --quiet --resume " + (dir / "s.bin").string() + " --csv " +
                       (dir / "part.csv").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string full = slurp(dir / "full.csv"), part = slurp(dir / "part.csv");
  const std::string tail = part.substr(part.find('\n') + 1);
  ASSERT_GE(full.size(), tail.size());
  EXPECT_EQ(full.substr(full.size() - tail.size()), tail);
}

}  // namespace
}  // namespace simreel
