// The scene's `joints:` list (app/scene/scene_joints.cpp): limits, motors and friction load into
// JointDef as <simreel/joints.hpp> describes them, and every mistake with them is named by file,
// line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <simreel/error.hpp>
#include <simreel/joints.hpp>
#include "app/scene/scene.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

// Eight lines of bodies, then "joints:" on line 9: the first joint starts on line 10.
const char* kBodies =
    "simulation: { duration: 1 }\n"
    "bodies:\n"
    "  - { name: arm, position: [0.5, 0, 2], colliders: [ { shape: box, size: [1, 0.1, 0.1] } ] }\n"
    "  - { name: cart, position: [3, 0, 2], colliders: [ { shape: box, size: [0.2, 0.2, 0.2] } ] }\n"
    "  - { name: top, position: [6, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: gimbal, position: [9, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: welded, position: [12, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: arm2, position: [15.5, 0, 2], colliders: [ { shape: box, size: [1, 0.1, 0.1] } ] }\n"
    "joints:\n";

// One joint of each type, written as the start of a flow mapping: the keys under test follow on
// line 11 and after.
const char* kRevolute = "name: j, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0]";
const char* kPrismatic =
    "name: j, type: prismatic, bodies: [cart, world], anchor: [3, 0, 2], axis: [1, 0, 0]";
const char* kSpherical = "name: j, type: spherical, bodies: [world, top], anchor: [6, 0, 2.5]";
const char* kFixed = "name: j, type: fixed, bodies: [arm, welded], anchor: [12, 0, 2]";
const char* kUniversal =
    "name: j, type: universal, bodies: [world, gimbal], anchor: [9, 0, 2.5], axis: [0, 0, 1], axis2: [1, 0, "
    "0]";

std::string write_scene(const std::string& name, const std::string& text) {
  const fs::path p = test::scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

// The scene with one joint: `base` on line 10, then `extra` from line 11.
std::string one_joint(const char* base, const std::string& extra) {
  return std::string(kBodies) + "  - { " + base + ",\n      " + extra + " }\n";
}

// The message of a rejected joint (empty and a failure if it loaded).
std::string error_of(const char* base, const std::string& extra) {
  const std::string text = one_joint(base, extra);
  try {
    load_scene(write_scene("j.yaml", text));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the joint was accepted:\n" << text;
  return "";
}

// The message names the file and line, and holds `text` (which starts with the key path).
#define EXPECT_JOINT_ERROR(base, extra, line, text)                                                     \
  do {                                                                                                  \
    const std::string m_ = error_of(base, extra);                                                       \
    EXPECT_NE(m_.find("j.yaml:" + std::to_string(line) + ":"), std::string::npos) << "message: " << m_; \
    EXPECT_NE(m_.find(text), std::string::npos) << "message: " << m_;                                   \
  } while (0)

TEST(SceneJoints, LimitsMotorsAndFrictionLoad) {
  const Scene s = load_scene(write_scene(
      "joints_all.yaml",
      std::string(kBodies) +
          "  - { name: pivot, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0],\n"
          "      limits: [-1.0, 1.5], motor: { speed: -2.0, max_torque: 5.0 }, friction: 0.01 }\n"
          "  - { name: rail, type: prismatic, bodies: [cart, world], anchor: [3, 0, 2], axis: [1, 0, 0],\n"
          "      limits: { lower: -0.2, upper: 0.3, restitution: 0.5 }, friction: 2,\n"
          "      motor: { position: 0.1, max_force: 40, speed: 1.5, time_constant: 0.05 } }\n"
          "  - { name: ball, type: spherical, bodies: [world, top], anchor: [6, 0, 2.5] }\n"
          "  - { name: cardan, type: universal, bodies: [world, gimbal], anchor: [9, 0, 2.5], axis: [0, 0, "
          "1],\n"
          "      axis2: [1, 0, 0], limits: { lower: -0.5, upper: 0.5, restitution: 1 }, friction: 0.02 }\n"
          "  - { name: weld, type: fixed, bodies: [arm, welded], anchor: [12, 0, 2] }\n"
          "  - { name: elbow, type: revolute, bodies: [world, arm2], anchor: [15, 0, 2], axis: [0, 1, 0],\n"
          "      limits: { lower: 0, upper: 2 }, motor: { position: -0.25, max_torque: 1 } }\n"));
  ASSERT_EQ(s.joints.size(), 6u);
  const JointDef& pivot = s.joints[0];
  ASSERT_TRUE(pivot.limits);
  EXPECT_EQ(pivot.limits->lower, -1.0);
  EXPECT_EQ(pivot.limits->upper, 1.5);
  EXPECT_EQ(pivot.limits->restitution, 0.0);
  ASSERT_TRUE(pivot.motor);
  EXPECT_EQ(pivot.motor->mode, JointMotor::Mode::speed);
  EXPECT_EQ(pivot.motor->speed, -2.0);
  EXPECT_EQ(pivot.motor->max_force, 5.0);
  EXPECT_EQ(pivot.friction, 0.01);

  const JointDef& rail = s.joints[1];
  ASSERT_TRUE(rail.limits);
  EXPECT_EQ(rail.limits->lower, -0.2);
  EXPECT_EQ(rail.limits->upper, 0.3);
  EXPECT_EQ(rail.limits->restitution, 0.5);
  ASSERT_TRUE(rail.motor);
  EXPECT_EQ(rail.motor->mode, JointMotor::Mode::position);
  EXPECT_EQ(rail.motor->position, 0.1);
  EXPECT_EQ(rail.motor->speed, 1.5);
  EXPECT_EQ(rail.motor->time_constant, 0.05);
  EXPECT_EQ(rail.motor->max_force, 40.0);
  EXPECT_EQ(rail.friction, 2.0);

  // None of the three on a joint that gives none.
  for (int k : {2, 4}) {
    EXPECT_FALSE(s.joints[k].limits) << k;
    EXPECT_FALSE(s.joints[k].motor) << k;
    EXPECT_EQ(s.joints[k].friction, 0.0) << k;
  }

  // A universal joint's limits bound both of its angles; it takes no motor.
  const JointDef& cardan = s.joints[3];
  ASSERT_TRUE(cardan.limits);
  EXPECT_EQ(cardan.limits->lower, -0.5);
  EXPECT_EQ(cardan.limits->upper, 0.5);
  EXPECT_EQ(cardan.limits->restitution, 1.0);
  EXPECT_FALSE(cardan.motor);
  EXPECT_EQ(cardan.friction, 0.02);

  // A stop may sit at the start pose; a position motor's speed is unlimited and its time constant
  // 0.1 s unless given.
  const JointDef& elbow = s.joints[5];
  ASSERT_TRUE(elbow.limits);
  EXPECT_EQ(elbow.limits->lower, 0.0);
  EXPECT_EQ(elbow.limits->upper, 2.0);
  ASSERT_TRUE(elbow.motor);
  EXPECT_EQ(elbow.motor->mode, JointMotor::Mode::position);
  EXPECT_EQ(elbow.motor->position, -0.25);
  EXPECT_TRUE(std::isinf(elbow.motor->speed) && elbow.motor->speed > 0);
  EXPECT_EQ(elbow.motor->time_constant, 0.1);
  EXPECT_EQ(elbow.motor->max_force, 1.0);
  EXPECT_EQ(elbow.friction, 0.0);
}

TEST(SceneJoints, BallJointLimitsAndSpringLoad) {
  const Scene s = load_scene(write_scene(
      "ball.yaml", one_joint(kSpherical,
                             "axis: [0, 0, -2],\n      limits: { cone: 0.6, twist: [-0.3, 0.4], "
                             "restitution: 0.2 },\n      spring: { stiffness: 3, damping: 0.1 }")));
  const JointDef& j = s.joints.at(0);
  ASSERT_TRUE(j.ball_limits);
  EXPECT_EQ(j.ball_limits->cone, 0.6);
  EXPECT_EQ(j.ball_limits->twist_lower, -0.3);
  EXPECT_EQ(j.ball_limits->twist_upper, 0.4);
  EXPECT_EQ(j.ball_limits->restitution, 0.2);
  EXPECT_FALSE(j.limits);
  EXPECT_EQ(j.axis_W, Vec3(0, 0, -2));
  ASSERT_TRUE(j.spring);
  EXPECT_EQ(j.spring->stiffness, 3.0);
  EXPECT_EQ(j.spring->damping, 0.1);
  // The whole turn's angle needs no axis.
  const Scene a = load_scene(write_scene("angle.yaml", one_joint(kSpherical, "limits: { angle: 1.1 }")));
  EXPECT_EQ(a.joints.at(0).ball_limits->angle, 1.1);
  EXPECT_TRUE(std::isinf(a.joints.at(0).ball_limits->cone));
  // A cone alone: no twist stops.
  const Scene c =
      load_scene(write_scene("cone.yaml", one_joint(kSpherical, "axis: [1, 0, 0], limits: { cone: 1 }")));
  EXPECT_TRUE(std::isinf(c.joints.at(0).ball_limits->twist_upper));
}

TEST(SceneJoints, BallJointLimitsAreAConeAndATwistAboutAnAxis) {
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: [-1, 1]", 11,
                     "joints[0].limits: a spherical joint's limits are { cone: rad, twist: [lower, upper]");
  EXPECT_JOINT_ERROR(kSpherical, "limits: { cone: 0.5 }", 10,
                     "a spherical joint with a cone or twist needs 'axis'");
  EXPECT_JOINT_ERROR(kSpherical, "limits: { angle: 3.2 }", 11,
                     "joints[0].limits.angle: a rotation's angle is under pi rad");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { restitution: 1 }", 11,
                     "joints[0].limits: a spherical joint's limits need 'cone'");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { cone: 3.5 }", 11,
                     "joints[0].limits.cone: the cone's half angle must be under pi rad");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { cone: 0 }", 11, "joints[0].limits.cone:");
  EXPECT_JOINT_ERROR(
      kSpherical, "axis: [0, 0, 1], limits: { twist: [0.2, 0.5] }", 11,
      "joints[0].limits.twist: the twist is 0 in the start pose, so its limits must contain 0");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { twist: [0.5, -0.5] }", 11,
                     "joints[0].limits.twist: twist limits out of order");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { twist: [-4, 1] }", 11,
                     "joints[0].limits.twist: a twist is an angle in [-pi, pi]");
  EXPECT_JOINT_ERROR(kSpherical, "axis: [0, 0, 1], limits: { cone: 1, swing: 1 }", 11, "joints[0].limits");
  EXPECT_JOINT_ERROR(kSpherical, "spring: { stiffness: 1, rest: 0.2 }", 11,
                     "joints[0].spring.rest: a spherical joint's spring rests at the start pose");
  EXPECT_JOINT_ERROR(kFixed, "axis: [0, 0, 1]", 11, "joints[0].axis: a fixed joint has no axis");
}

// A joint that mimics another: named by the joint it follows (later in the list too), with a
// multiplier; every mistake named at its key.
TEST(SceneJoints, MimicFollowsANamedJoint) {
  auto scene = [](const std::string& mimic, const char* leader_type = "revolute") {
    return std::string(kBodies) +
           "  - { name: gear_b, type: revolute, bodies: [world, arm2], anchor: [15, 0, 2], "
           "axis: [0, 1, 0],\n      mimic: " +
           mimic + " }\n  - { name: gear_a, type: " + leader_type +
           ", bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0] }\n";
  };
  const Scene s = load_scene(write_scene("mimic.yaml", scene("{ joint: gear_a, multiplier: -0.5 }")));
  ASSERT_TRUE(s.joints.at(0).mimic);
  EXPECT_EQ(s.joints[0].mimic->leader, 1);
  EXPECT_EQ(s.joints[0].mimic->multiplier, -0.5);
  auto error = [&](const std::string& text) {
    try {
      load_scene(write_scene("m.yaml", text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  EXPECT_NE(error(scene("{ joint: gear_c }"))
                .find("m.yaml:11:23: joints[0].mimic.joint: no joint is named "
                      "'gear_c'; did you mean 'gear_a'?"),
            std::string::npos)
      << error(scene("{ joint: gear_c }"));
  EXPECT_NE(error(scene("{ joint: gear_b }")).find("joints[0].mimic.joint: a joint cannot mimic itself"),
            std::string::npos);
  EXPECT_NE(
      error(scene("{ joint: gear_a, multiplier: 0 }")).find("joints[0].mimic.multiplier: must not be 0"),
      std::string::npos);
  // With a range, the combination is only kept within it (0, the start pose, inside).
  const Scene r =
      load_scene(write_scene("mr.yaml", scene("{ joint: gear_a, multiplier: 1, range: [-0.6, 0.4] }")));
  ASSERT_TRUE(r.joints.at(0).mimic && r.joints[0].mimic->range);
  EXPECT_EQ(r.joints[0].mimic->range->first, -0.6);
  EXPECT_EQ(r.joints[0].mimic->range->second, 0.4);
  EXPECT_NE(error(scene("{ joint: gear_a, range: [0.1, 0.4] }"))
                .find("joints[0].mimic.range: expected lower < upper with 0 (the start pose) between them"),
            std::string::npos);
  // Further leaders: q_b - (-0.5) q_a - 0.25 q_c, a differential.
  const std::string three =
      std::string(kBodies) +
      "  - { name: gear_b, type: revolute, bodies: [world, arm2], anchor: [15, 0, 2], "
      "axis: [0, 1, 0],\n      mimic: { joint: gear_a, multiplier: -0.5, also: ALSO } }\n"
      "  - { name: gear_a, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0] }\n"
      "  - { name: gear_c, type: revolute, bodies: [world, welded], anchor: [12, 0, 2], axis: [0, 1, 0] }\n";
  auto with_also = [&](const std::string& also) {
    std::string t = three;
    t.replace(t.find("ALSO"), 4, also);
    return t;
  };
  const Scene d = load_scene(write_scene("md.yaml", with_also("{ gear_c: 0.25 }")));
  ASSERT_TRUE(d.joints.at(0).mimic);
  ASSERT_EQ(d.joints[0].mimic->also.size(), 1u);
  EXPECT_EQ(d.joints[0].mimic->also[0], (std::pair<int, double>{2, 0.25}));
  EXPECT_NE(
      error(with_also("{ gear_d: 0.25 }")).find("joints[0].mimic.also.gear_d: no joint is named 'gear_d'"),
      std::string::npos)
      << error(with_also("{ gear_d: 0.25 }"));
  EXPECT_NE(error(with_also("{ gear_a: 1 }")).find("is the mimic's joint already"), std::string::npos);
  EXPECT_NE(error(with_also("{ gear_c: 0 }")).find("joints[0].mimic.also.gear_c: must not be 0"),
            std::string::npos);
  // A hinge may follow a slider (a rack and pinion: the multiplier in rad/m).
  EXPECT_EQ(error(scene("{ joint: gear_a, multiplier: 10 }", "prismatic")), "loaded");
  EXPECT_NE(error(scene("{ multiplier: 2 }")).find("joints[0].mimic: missing key 'joint'"),
            std::string::npos);
  EXPECT_NE(
      error(scene("{ joint: gear_a }", "spherical"))
          .find("'gear_a' is a spherical joint: a mimic follows a revolute or prismatic joint's coordinate"),
      std::string::npos);
}

TEST(SceneJoints, ArmatureIsARotorOnACoordinate) {
  const Scene s = load_scene(write_scene("arm.yaml", one_joint(kRevolute, "armature: 0.25")));
  EXPECT_EQ(s.joints.at(0).armature, 0.25);
  EXPECT_JOINT_ERROR(kSpherical, "armature: 0.1", 11,
                     "joints[0].armature: a spherical joint has no armature");
  EXPECT_JOINT_ERROR(kRevolute, "armature: -1", 11, "joints[0].armature:");
}

TEST(SceneJoints, LimitsNeedACoordinate) {
  EXPECT_JOINT_ERROR(kFixed, "limits: { lower: -1, upper: 1 }", 11,
                     "joints[0].limits: a fixed joint has no coordinate for limits");
}

TEST(SceneJoints, MotorsNeedACoordinateToDrive) {
  EXPECT_JOINT_ERROR(kFixed, "motor: { speed: 1, max_torque: 1 }", 11,
                     "joints[0].motor: a fixed joint has no coordinate for a motor");
  EXPECT_JOINT_ERROR(kRevolute, "motor2: { speed: 1, max_torque: 1 }", 11,
                     "joints[0].motor2: only a universal joint has motor2");
}

TEST(SceneJoints, UniversalJointsTakeAMotorOnEachAngle) {
  const Scene s = load_scene(
      write_scene("u.yaml", one_joint(kUniversal,
                                      "motor: { speed: 1.5, max_torque: 2 },\n      motor2: { position: 0.4, "
                                      "max_torque: 3, time_constant: 0.2 }")));
  const JointDef& j = s.joints.at(0);
  ASSERT_TRUE(j.motor && j.motor2);
  EXPECT_EQ(j.motor->speed, 1.5);
  EXPECT_EQ(j.motor2->mode, JointMotor::Mode::position);
  EXPECT_EQ(j.motor2->position, 0.4);
  EXPECT_EQ(j.motor2->max_force, 3.0);
  EXPECT_JOINT_ERROR(kUniversal, "motor2: { speed: 1, max_force: 1 }", 11,
                     "joints[0].motor2.max_force: a universal joint's motor takes 'max_torque'");
}

// A ball joint's motor drives its angular velocity (a vector, the child's axes) or its rotation
// (a rotation vector); its friction acts about each axis.
TEST(SceneJoints, BallJointMotorsAndFrictionTakeVectors) {
  const Scene s = load_scene(write_scene(
      "bm.yaml", one_joint(kSpherical, "motor: { speed: [0, 1, 2], max_torque: 3 },\n      friction: 0.2")));
  const JointDef& j = s.joints.at(0);
  ASSERT_TRUE(j.motor);
  EXPECT_EQ(j.motor->mode, JointMotor::Mode::speed);
  EXPECT_EQ(j.motor->angular_velocity, Vec3(0, 1, 2));
  EXPECT_EQ(j.motor->max_force, 3.0);
  EXPECT_EQ(j.friction, 0.2);
  const Scene p = load_scene(
      write_scene("bp.yaml", one_joint(kSpherical,
                                       "motor: { position: [0.5, 0, 0], speed: 2, time_constant: 0.3, "
                                       "max_torque: 4 }")));
  const JointMotor& m = *p.joints.at(0).motor;
  EXPECT_EQ(m.mode, JointMotor::Mode::position);
  EXPECT_EQ(m.rotation, Vec3(0.5, 0, 0));
  EXPECT_EQ(m.speed, 2.0);
  EXPECT_EQ(m.time_constant, 0.3);
  EXPECT_JOINT_ERROR(
      kSpherical, "motor: { speed: 1, max_torque: 1 }", 11,
      "joints[0].motor.speed: a ball joint's target speed is an angular velocity [wx, wy, wz]");
  EXPECT_JOINT_ERROR(kSpherical, "motor: { position: 0.5, max_torque: 1 }", 11,
                     "joints[0].motor.position: a ball joint's target is a rotation vector [rx, ry, rz]");
  EXPECT_JOINT_ERROR(kSpherical, "motor: { position: [0, 3.2, 0], max_torque: 1 }", 11,
                     "joints[0].motor.position: a rotation vector's length is its angle, under pi rad");
  EXPECT_JOINT_ERROR(kSpherical, "motor: { speed: [1, 0, 0], max_force: 1 }", 11,
                     "joints[0].motor.max_force: a spherical joint's motor takes 'max_torque'");
  EXPECT_JOINT_ERROR(kSpherical, "motor: { speed: [1, 0, 0] }", 11,
                     "joints[0].motor: a motor needs 'max_torque'");
}

TEST(SceneJoints, FrictionNeedsACoordinate) {
  EXPECT_JOINT_ERROR(kFixed, "friction: 0.1", 11,
                     "joints[0].friction: a fixed joint has no coordinate for friction");
}

TEST(SceneJoints, LimitsOutOfOrder) {
  EXPECT_JOINT_ERROR(kRevolute, "limits: [1, -1]", 11, "joints[0].limits: limits out of order");
  EXPECT_JOINT_ERROR(kPrismatic, "limits: { lower: 0.5,\n                upper: -0.5 }", 11,
                     "joints[0].limits: limits out of order");
}

TEST(SceneJoints, LimitsThatMeetAreAFixedJoint) {
  EXPECT_JOINT_ERROR(kRevolute, "limits: [0, 0]", 11, "joints[0].limits: lower equals upper");
  EXPECT_NE(error_of(kRevolute, "limits: [0, 0]").find("type: fixed"), std::string::npos);
}

TEST(SceneJoints, LimitsMustContainTheStartPose) {
  const char* why = "joint coordinates are 0 in the start pose, so the limits must contain 0";
  EXPECT_JOINT_ERROR(kRevolute, "limits: [0.2, 1]", 11, why);
  EXPECT_JOINT_ERROR(kPrismatic, "limits: [-1, -0.1]", 11, why);
  EXPECT_JOINT_ERROR(kUniversal, "\n      limits: { lower: 0.1, upper: 0.5 }", 12, why);
}

TEST(SceneJoints, LimitsRestitutionLiesInTheUnitInterval) {
  EXPECT_JOINT_ERROR(kRevolute, "limits: { lower: -1, upper: 1,\n                restitution: 1.5 }", 12,
                     "joints[0].limits.restitution: must lie in [0, 1]");
  EXPECT_JOINT_ERROR(kRevolute, "limits: { lower: -1, upper: 1, restitution: -0.1 }", 11,
                     "joints[0].limits.restitution: must lie in [0, 1]");
}

TEST(SceneJoints, LimitsShapeAndKeys) {
  EXPECT_JOINT_ERROR(kRevolute, "limits: [1]", 11, "joints[0].limits: expected [lower, upper]");
  EXPECT_JOINT_ERROR(kRevolute, "limits: 1", 11, "joints[0].limits: expected [lower, upper]");
  EXPECT_JOINT_ERROR(kRevolute, "limits: { lower: -1 }", 11, "joints[0].limits: missing key 'upper'");
  EXPECT_JOINT_ERROR(kRevolute, "limits: [-1, x]", 11, "joints[0].limits[1]: expected a number");
  EXPECT_JOINT_ERROR(kRevolute, "limits: { lower: -1, upper: 1, restitutoin: 0.5 }", 11,
                     "joints[0].limits.restitutoin: unknown key 'restitutoin'; did you mean 'restitution'?");
  EXPECT_JOINT_ERROR(kRevolute, "limit: [-1, 1]", 11,
                     "joints[0].limit: unknown key 'limit'; did you mean 'limits'?");
}

TEST(SceneJoints, MotorNeedsAPositiveMaximum) {
  EXPECT_JOINT_ERROR(kRevolute, "motor: { speed: 1 }", 11,
                     "joints[0].motor: a motor needs 'max_torque' (N m, > 0)");
  EXPECT_JOINT_ERROR(kPrismatic, "motor: { speed: 1 }", 11,
                     "joints[0].motor: a motor needs 'max_force' (N, > 0)");
  EXPECT_JOINT_ERROR(kRevolute, "motor: { speed: 1, max_torque: 0 }", 11,
                     "joints[0].motor.max_torque: must be positive");
  EXPECT_JOINT_ERROR(kPrismatic, "motor: { speed: 1,\n               max_force: -3 }", 12,
                     "joints[0].motor.max_force: must be positive");
}

TEST(SceneJoints, MotorMaximumIsNamedInTheJointsUnits) {
  EXPECT_JOINT_ERROR(kRevolute, "motor: { speed: 1,\n               max_force: 3 }", 12,
                     "joints[0].motor.max_force: a revolute joint's motor takes 'max_torque' (N m), not "
                     "'max_force' (N)");
  EXPECT_JOINT_ERROR(kPrismatic, "motor: { speed: 1,\n               max_torque: 3 }", 12,
                     "joints[0].motor.max_torque: a prismatic joint's motor takes 'max_force' (N), not "
                     "'max_torque' (N m)");
  EXPECT_JOINT_ERROR(kRevolute, "motor: { speed: 1, max_torqe: 3 }", 11,
                     "joints[0].motor.max_torqe: unknown key 'max_torqe'; did you mean 'max_torque'?");
}

TEST(SceneJoints, MotorNeedsSpeedOrPosition) {
  EXPECT_JOINT_ERROR(
      kRevolute, "motor: { max_torque: 1 }", 11,
      "joints[0].motor: a motor needs 'speed' (a target rate, rad/s) or 'position' (a target, rad)");
  EXPECT_JOINT_ERROR(
      kPrismatic, "motor: { max_force: 1 }", 11,
      "joints[0].motor: a motor needs 'speed' (a target rate, m/s) or 'position' (a target, m)");
  EXPECT_JOINT_ERROR(kRevolute, "motor: 2", 11, "joints[0].motor: expected { speed: RATE, max_torque: MAX }");
  // With `position`, `speed` is the largest approach rate: positive.
  EXPECT_JOINT_ERROR(kRevolute, "motor: { position: 1, max_torque: 1,\n               speed: 0 }", 12,
                     "joints[0].motor.speed: must be positive");
  EXPECT_JOINT_ERROR(kRevolute, "motor: { position: 1, max_torque: 1, speed: -1 }", 11,
                     "joints[0].motor.speed: must be positive");
  EXPECT_JOINT_ERROR(kRevolute, "motor: { position: 1, max_torque: 1,\n               time_constant: 0 }", 12,
                     "joints[0].motor.time_constant: must be positive");
  // A speed motor has no time constant.
  EXPECT_JOINT_ERROR(kRevolute, "motor: { speed: 1, max_torque: 1, time_constant: 0.2 }", 11,
                     "joints[0].motor.time_constant: is for a position motor (with 'position')");
}

TEST(SceneJoints, FrictionIsAFiniteNonNegativeNumber) {
  EXPECT_JOINT_ERROR(kRevolute, "friction: -0.1", 11, "joints[0].friction: must not be negative");
  EXPECT_JOINT_ERROR(kPrismatic, "friction: .inf", 11, "joints[0].friction: must be a finite number");
  EXPECT_JOINT_ERROR(kUniversal, "\n      friction: .nan", 12, "joints[0].friction: must be a finite number");
}

// A distance joint between the world's point 1 m above arm's origin and that origin (start distance
// 1 m), and a pulley whose rope runs from arm up over two fixed points and down to cart.
const char* kDistance = "name: j, type: distance, bodies: [world, arm]";
const char* kRod = "name: j, type: distance, bodies: [world, arm], anchors: [[0.5, 0, 3], [0.5, 0, 2]]";
const char* kPulley = "name: j, type: pulley, bodies: [arm, cart], anchors: [[0.5, 0, 2], [3, 0, 2]]";
const char* kOverhead = "pulley_anchors: [[0.5, 0, 4], [3, 0, 4]]";

TEST(SceneJoints, DistanceRodsAndRopesLoad) {
  const Scene s = load_scene(write_scene(
      "joints_distance.yaml",
      std::string(kBodies) +
          "  - { name: rod, type: distance, bodies: [world, arm], anchors: [[0.5, 0, 3.5], [0.5, 0, 2]] }\n"
          "  - { name: rope, type: distance, bodies: [world, cart], anchors: [[3, 0, 4], [3, 0, 2]],\n"
          "      min_length: 0.5, max_length: 3, restitution: 0.4 }\n"
          "  - { name: taut, type: distance, bodies: [top, gimbal], anchors: [[6, 0, 2], [9, 0, 2]],\n"
          "      max_length: 2.9999999999 }\n"
          "  - { name: strut, type: distance, bodies: [welded, arm2], anchors: [[12, 0, 2], [15, 0, 2]],\n"
          "      min_length: 1 }\n"));
  ASSERT_EQ(s.joints.size(), 4u);
  // Neither bound: a rigid rod as long as the anchors are apart at t = 0.
  const JointDef& rod = s.joints[0];
  EXPECT_EQ(rod.type, JointType::distance);
  EXPECT_EQ(rod.parent, -1);
  EXPECT_EQ(rod.child, 0);
  EXPECT_EQ(rod.anchor_W, Vec3(0.5, 0, 3.5));
  EXPECT_EQ(rod.anchor2_W, Vec3(0.5, 0, 2));
  EXPECT_FALSE(rod.min_length);
  EXPECT_FALSE(rod.max_length);
  EXPECT_EQ(rod.restitution, 0.0);
  EXPECT_FALSE(rod.spring || rod.limits || rod.motor);
  // A rope slack between its bounds, rebounding from them.
  const JointDef& rope = s.joints[1];
  EXPECT_EQ(rope.type, JointType::distance);
  EXPECT_EQ(rope.child, 1);
  ASSERT_TRUE(rope.min_length && rope.max_length);
  EXPECT_EQ(*rope.min_length, 0.5);
  EXPECT_EQ(*rope.max_length, 3.0);
  EXPECT_EQ(rope.restitution, 0.4);
  // A max_length within 1e-9 m under the start distance is the start distance: the rope starts taut.
  const JointDef& taut = s.joints[2];
  EXPECT_EQ(taut.parent, 2);
  EXPECT_EQ(taut.child, 3);
  ASSERT_TRUE(taut.max_length);
  EXPECT_EQ(*taut.max_length, 3.0);
  EXPECT_FALSE(taut.min_length);
  // A min_length alone: a strut that only pushes, no upper bound.
  const JointDef& strut = s.joints[3];
  ASSERT_TRUE(strut.min_length);
  EXPECT_EQ(*strut.min_length, 1.0);
  EXPECT_FALSE(strut.max_length);
}

TEST(SceneJoints, DistanceSpringRestsAtTheStartLength) {
  const Scene s = load_scene(write_scene(
      "joints_distance_spring.yaml",
      std::string(kBodies) +
          "  - { name: bungee, type: distance, bodies: [world, arm], anchors: [[0.5, 0, 3.5], [0.5, 0, 2]],\n"
          "      max_length: 2, spring: { stiffness: 50, damping: 2 } }\n"
          "  - { name: coil, type: distance, bodies: [world, cart], anchors: [[3, 0, 4], [3, 0, 2]],\n"
          "      spring: { stiffness: 80, rest: 1.25 } }\n"));
  ASSERT_EQ(s.joints.size(), 2u);
  ASSERT_TRUE(s.joints[0].spring);
  EXPECT_EQ(s.joints[0].spring->stiffness, 50.0);
  EXPECT_EQ(s.joints[0].spring->damping, 2.0);
  EXPECT_EQ(s.joints[0].spring->rest, 1.5);  // the start distance, not 0
  ASSERT_TRUE(s.joints[1].spring);
  EXPECT_EQ(s.joints[1].spring->rest, 1.25);
  EXPECT_JOINT_ERROR(kRod, "spring: { stiffness: 1, rest: -0.5 }", 11,
                     "joints[0].spring.rest: must not be negative");
}

TEST(SceneJoints, DistanceJointsTakeTwoAnchors) {
  EXPECT_JOINT_ERROR(kDistance, "spring: { stiffness: 1 }", 10,
                     "joints[0]: a distance joint needs 'anchors: [[parent point], [child point]]'");
  EXPECT_JOINT_ERROR(kDistance, "anchor: [0.5, 0, 3]", 11,
                     "joints[0].anchor: a distance joint takes 'anchors: [[parent point], [child point]]'");
  EXPECT_JOINT_ERROR(kPulley, "anchor: [0.5, 0, 3]", 11,
                     "joints[0].anchor: a pulley joint takes 'anchors: [[a point], [b point]]'");
  EXPECT_JOINT_ERROR(kDistance, "anchors: [0.5, 0, 3]", 11,
                     "joints[0].anchors: expected [[x, y, z], [x, y, z]] (the parent's point, the child's "
                     "point), got a list of 3");
  EXPECT_JOINT_ERROR(kDistance, "anchors: [[0.5, 0, 3], [0.5, 2]]", 11,
                     "joints[0].anchors[1]: expected a list of 3 numbers");
  // ... and every other joint one.
  EXPECT_JOINT_ERROR(kRevolute, "anchors: [[0, 0, 2], [0.5, 0, 2]]", 11,
                     "joints[0].anchors: only a distance or pulley joint takes 'anchors'; a revolute joint "
                     "takes 'anchor: [x, y, z]'");
}

TEST(SceneJoints, DistanceAnchorsMustNotCoincide) {
  EXPECT_JOINT_ERROR(kDistance, "anchors: [[0.5, 0, 2], [0.5, 0, 2]]", 11,
                     "joints[0].anchors: the anchors coincide; a distance joint needs two distinct points "
                     "(use spherical for a ball joint)");
}

TEST(SceneJoints, RopeBoundsHoldTheStartDistance) {
  EXPECT_JOINT_ERROR(
      kRod, "max_length: 0.9", 11,
      "joints[0].max_length: max_length 0.9 m is shorter than the anchors' start distance 1 m");
  EXPECT_JOINT_ERROR(kRod, "\n      min_length: 1.2", 12,
                     "joints[0].min_length: min_length 1.2 m is longer than the anchors' start distance 1 m");
  EXPECT_JOINT_ERROR(kRod, "max_length: 1,\n      min_length: 2", 12,
                     "joints[0].min_length: min_length must be below max_length, got 2 m and 1 m");
  EXPECT_JOINT_ERROR(kRod, "min_length: 1, max_length: 1", 11,
                     "(equal bounds are a rigid rod: leave both out)");
  EXPECT_JOINT_ERROR(kRod, "min_length: -0.1", 11, "joints[0].min_length: must not be negative");
  EXPECT_JOINT_ERROR(kRod, "max_length: 0", 11, "joints[0].max_length: must be positive");
}

TEST(SceneJoints, RestitutionBelongsToRopesAndPulleys) {
  EXPECT_JOINT_ERROR(kRod, "restitution: 0.5", 11,
                     "joints[0].restitution: a rigid rod (no min_length or max_length) never goes slack");
  EXPECT_JOINT_ERROR(kRod, "max_length: 2,\n      restitution: 1.5", 12,
                     "joints[0].restitution: must lie in [0, 1]");
  EXPECT_JOINT_ERROR(
      kRevolute, "restitution: 0.5", 11,
      "joints[0].restitution: only a rope (a distance joint with min_length or max_length) or a "
      "pulley has restitution");
  EXPECT_JOINT_ERROR(kPrismatic, "max_length: 2", 11,
                     "joints[0].max_length: only a distance joint has max_length");
}

TEST(SceneJoints, DistanceJointsRefuseAxesLimitsMotorsAndFriction) {
  EXPECT_JOINT_ERROR(kRod, "limits: [-0.1, 0.1]", 11,
                     "joints[0].limits: a distance joint's limits are min_length/max_length");
  EXPECT_JOINT_ERROR(kRod, "motor: { speed: 1, max_force: 1 }", 11,
                     "joints[0].motor: a distance joint takes no motor");
  EXPECT_JOINT_ERROR(kRod, "friction: 1", 11, "joints[0].friction: a distance joint has no friction");
  EXPECT_JOINT_ERROR(kRod, "axis: [0, 0, 1]", 11, "joints[0].axis: a distance joint has no axis");
  EXPECT_JOINT_ERROR(kRod, "\n      axis2: [0, 0, 1]", 12,
                     "joints[0].axis2: only a universal or wheel joint has axis2");
  EXPECT_JOINT_ERROR(kRod, "pulley_anchors: [[0, 0, 4], [1, 0, 4]]", 11,
                     "joints[0].pulley_anchors: only a pulley joint has pulley_anchors");
}

TEST(SceneJoints, PulleysLoad) {
  const Scene s = load_scene(write_scene(
      "joints_pulley.yaml",
      std::string(kBodies) +
          "  - { name: axle, type: revolute, bodies: [world, top], anchor: [6, 0, 2], axis: [0, 1, 0] }\n"
          "  - { name: rope, type: pulley, bodies: [arm, cart], anchors: [[0.5, 0, 2], [3, 0, 2]],\n"
          "      pulley_anchors: [[0.5, 0, 4], [3, 0, 4]], wheel: top, restitution: 0.2 }\n"
          "  - { name: tackle, type: pulley, bodies: [world, gimbal], anchors: [[7, 0, 0], [9, 0, 2]],\n"
          "      pulley_anchors: [[7, 0, 5], [9, 0, 5]], ratio: 2 }\n"));
  ASSERT_EQ(s.joints.size(), 3u);
  const JointDef& rope = s.joints[1];
  EXPECT_EQ(rope.type, JointType::pulley);
  EXPECT_EQ(rope.parent, 0);
  EXPECT_EQ(rope.child, 1);
  EXPECT_EQ(rope.anchor_W, Vec3(0.5, 0, 2));
  EXPECT_EQ(rope.anchor2_W, Vec3(3, 0, 2));
  EXPECT_EQ(rope.pulley_anchor_W[0], Vec3(0.5, 0, 4));
  EXPECT_EQ(rope.pulley_anchor_W[1], Vec3(3, 0, 4));
  EXPECT_EQ(rope.ratio, 1.0);
  EXPECT_EQ(rope.wheel, 2);
  EXPECT_EQ(rope.restitution, 0.2);
  // One end on the world: the other side moves. No wheel: a massless pulley.
  const JointDef& tackle = s.joints[2];
  EXPECT_EQ(tackle.parent, -1);
  EXPECT_EQ(tackle.child, 3);
  EXPECT_EQ(tackle.ratio, 2.0);
  EXPECT_EQ(tackle.wheel, -1);
  EXPECT_EQ(tackle.restitution, 0.0);
}

TEST(SceneJoints, PulleyNeedsItsPulleyAnchors) {
  EXPECT_JOINT_ERROR(kPulley, "ratio: 2", 10,
                     "joints[0]: a pulley joint needs 'pulley_anchors: [[x, y, z], [x, y, z]]'");
  EXPECT_JOINT_ERROR(kPulley, "pulley_anchors: [[0.5, 0, 2], [3, 0, 4]]", 11,
                     "joints[0].pulley_anchors[0]: the rope's parent side starts with no length");
  EXPECT_JOINT_ERROR(kPulley, "pulley_anchors: [[0.5, 0, 4]]", 11,
                     "joints[0].pulley_anchors: expected [[x, y, z], [x, y, z]]");
  EXPECT_JOINT_ERROR(kPulley, std::string(kOverhead) + ",\n      ratio: 0", 12,
                     "joints[0].ratio: must be positive");
  // Both ends on things that cannot move: nothing to pull.
  const char* fixed_ends = "name: j, type: pulley, bodies: [world, world], anchors: [[0, 0, 2], [3, 0, 2]]";
  EXPECT_JOINT_ERROR(fixed_ends, kOverhead, 10, "joints[0].bodies: joins the world to itself");
}

TEST(SceneJoints, PulleyWheelIsAThirdBodyOnAHinge) {
  EXPECT_JOINT_ERROR(kPulley, std::string(kOverhead) + ",\n      wheel: tpo", 12,
                     "joints[0].wheel: no body is named 'tpo'; did you mean 'top'?");
  EXPECT_JOINT_ERROR(kPulley, std::string(kOverhead) + ",\n      wheel: cart", 12,
                     "joints[0].wheel: the wheel 'cart' is one of the rope's bodies");
  EXPECT_JOINT_ERROR(
      kPulley, std::string(kOverhead) + ",\n      wheel: world", 12,
      "joints[0].wheel: the wheel must be a body that turns on a revolute joint, not the world");
  EXPECT_JOINT_ERROR(kPulley, std::string(kOverhead) + ", wheel: top,\n      ratio: 2", 12,
                     "joints[0].ratio: a rope over a wheel has ratio 1");
  // The scene holds no revolute joint for it.
  EXPECT_JOINT_ERROR(kPulley, std::string(kOverhead) + ",\n      wheel: top", 12,
                     "joints[0].wheel: the wheel 'top' turns on no revolute joint");
  // A static wheel cannot turn.
  const std::string text =
      "simulation: { duration: 1 }\n"
      "bodies:\n"
      "  - { name: a, position: [0, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
      "  - { name: b, position: [2, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
      "  - { name: drum, type: static, position: [1, 0, 4], colliders: [ { shape: sphere, radius: 1 } ] }\n"
      "joints:\n"
      "  - { type: pulley, bodies: [a, b], anchors: [[0, 0, 2], [2, 0, 2]], pulley_anchors: [[0, 0, 4], [2, "
      "0, 4]],\n"
      "      wheel: drum }\n";
  try {
    load_scene(write_scene("j.yaml", text));
    ADD_FAILURE() << "a static wheel was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("j.yaml:8:"), std::string::npos) << m;
    EXPECT_NE(m.find("joints[0].wheel: the wheel 'drum' is static: it must be a dynamic body"),
              std::string::npos)
        << m;
  }
}

TEST(SceneJoints, PulleysRefuseSpringsLimitsMotorsAndLengths) {
  const std::string over = std::string(kOverhead) + ",\n      ";
  EXPECT_JOINT_ERROR(kPulley, over + "spring: { stiffness: 1 }", 12,
                     "joints[0].spring: a pulley joint takes no spring");
  EXPECT_JOINT_ERROR(kPulley, over + "limits: [-1, 1]", 12, "joints[0].limits: a pulley joint has no limits");
  EXPECT_JOINT_ERROR(kPulley, over + "motor: { speed: 1, max_force: 1 }", 12,
                     "joints[0].motor: a pulley joint takes no motor");
  EXPECT_JOINT_ERROR(kPulley, over + "friction: 1", 12, "joints[0].friction: a pulley joint has no friction");
  EXPECT_JOINT_ERROR(
      kPulley, over + "max_length: 5", 12,
      "joints[0].max_length: a pulley's rope keeps its start length: max_length is for a distance "
      "joint");
  EXPECT_JOINT_ERROR(kPulley, over + "axis: [0, 1, 0]", 12, "joints[0].axis: a pulley joint has no axis");
  EXPECT_JOINT_ERROR(kPulley, over + "steering: { position: 0, max_torque: 1 }", 12,
                     "joints[0].steering: only a wheel joint steers");
  EXPECT_JOINT_ERROR(kRevolute, "wheel: top", 11, "joints[0].wheel: only a pulley joint has wheel");
  EXPECT_JOINT_ERROR(kSpherical, "ratio: 2", 11, "joints[0].ratio: only a pulley joint has ratio");
}

TEST(SceneJoints, UnknownTypesNameTheNewTypes) {
  EXPECT_JOINT_ERROR("name: j, type: pully, bodies: [world, arm]", "anchor: [0, 0, 2]", 10,
                     "joints[0].type: unknown joint type 'pully' (revolute, prismatic, spherical, fixed, "
                     "universal, wheel, distance, pulley); did you mean 'pulley'?");
  EXPECT_JOINT_ERROR("name: j, type: distanse, bodies: [world, arm]", "anchor: [0, 0, 2]", 10,
                     "did you mean 'distance'?");
  EXPECT_JOINT_ERROR(
      "name: j, bodies: [world, arm]", "anchor: [0, 0, 2]", 10,
      "joints[0]: missing key 'type' (revolute, prismatic, spherical, fixed, universal, wheel, "
      "distance, pulley)");
}

// A wheel: suspension along axis (spring, stops), steering to an angle, the axle's motor and
// friction; its errors name the key.
TEST(SceneJoints, WheelJointsLoadWithSuspensionSteeringAndDrive) {
  const Scene s = load_scene(write_scene(
      "joints_wheel.yaml",
      std::string(kBodies) +
          "  - { name: corner, type: wheel, bodies: [world, top], anchor: [6, 0, 2], axis: [0, 0, 1], axis2: "
          "[0, 1, 0],\n"
          "      spring: { stiffness: 20000, damping: 1000 }, limits: [-0.1, 0.1], friction: 0.5,\n"
          "      motor: { speed: 30, max_torque: 200 }, steering: { position: 0.3, max_torque: 100 } }\n"));
  ASSERT_EQ(s.joints.size(), 1u);
  const JointDef& w = s.joints[0];
  EXPECT_EQ(w.type, JointType::wheel);
  EXPECT_EQ(w.axis2_W, Vec3(0, 1, 0));
  ASSERT_TRUE(w.spring && w.limits && w.motor && w.steering);
  EXPECT_EQ(w.spring->stiffness, 20000);
  EXPECT_EQ(w.limits->upper, 0.1);
  EXPECT_EQ(w.motor->speed, 30);
  EXPECT_EQ(w.motor->max_force, 200);
  EXPECT_EQ(w.steering->mode, JointMotor::Mode::position);
  EXPECT_EQ(w.steering->position, 0.3);
  EXPECT_EQ(w.friction, 0.5);
  const char* wheel = "name: j, type: wheel, bodies: [world, top], anchor: [6, 0, 2], axis: [0, 0, 1]";
  EXPECT_JOINT_ERROR(wheel, "friction: 0", 10, "a wheel joint needs 'axis2'");
  EXPECT_JOINT_ERROR(kRevolute, "steering: { position: 0.3, max_torque: 1 }", 11,
                     "only a wheel joint steers");
  const std::string with_axle = std::string(wheel) + ", axis2: [0, 1, 0]";
  EXPECT_JOINT_ERROR(with_axle.c_str(), "steering: { speed: 1, max_torque: 1 }", 11,
                     "steering turns the wheel to an angle");
}

}  // namespace
}  // namespace simreel
