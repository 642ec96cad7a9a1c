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

TEST(SceneJoints, LimitsNeedACoordinate) {
  EXPECT_JOINT_ERROR(kSpherical, "limits: [-1, 1]", 11,
                     "joints[0].limits: a spherical joint has no coordinate for limits");
  EXPECT_JOINT_ERROR(kFixed, "limits: { lower: -1, upper: 1 }", 11,
                     "joints[0].limits: a fixed joint has no coordinate for limits");
}

TEST(SceneJoints, MotorsDriveRevoluteAndPrismaticJointsOnly) {
  EXPECT_JOINT_ERROR(kSpherical, "motor: { speed: 1, max_torque: 1 }", 11,
                     "joints[0].motor: a spherical joint has no coordinate for a motor");
  EXPECT_JOINT_ERROR(kFixed, "motor: { speed: 1, max_torque: 1 }", 11,
                     "joints[0].motor: a fixed joint has no coordinate for a motor");
  EXPECT_JOINT_ERROR(kUniversal, "motor: { speed: 1, max_torque: 1 }", 11,
                     "joints[0].motor: a motor drives one coordinate: revolute and prismatic joints only");
}

TEST(SceneJoints, FrictionNeedsACoordinate) {
  EXPECT_JOINT_ERROR(kSpherical, "friction: 0.1", 11,
                     "joints[0].friction: a spherical joint has no coordinate for friction");
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

TEST(SceneJoints, DistanceJointsAreNotSupportedYet) {
  const std::string base = "name: j, type: distance, bodies: [world, arm], anchor: [0, 0, 2]";
  EXPECT_JOINT_ERROR(base.c_str(), "axis: [0, 1, 0]", 10,
                     "joints[0].type: joint type 'distance' is not supported yet");
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
