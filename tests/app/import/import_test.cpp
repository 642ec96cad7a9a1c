// Robots and rigs from URDF files (app/import/): what a file says becomes the same bodies and
// joints a scene would write, its mass properties are checked against its own geometry, its
// mistakes are named by file and line, and the mechanisms move as physics says they must.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <simreel/error.hpp>
#include <simreel/world.hpp>
#include "app/import/urdf.hpp"
#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"
#include "app/scene/scene_imports.hpp"
#include "render/material.hpp"
#include "sim/geometry/point_triangle.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;
const std::string kData = "tests/data/import/";

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = test::scratch(name);
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::string& path) {
  try {
    load_scene(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " loaded";
  return "";
}

bool has(const std::vector<std::string>& v, const std::string& part) {
  for (const std::string& s : v)
    if (s.find(part) != std::string::npos) return true;
  return false;
}

int body(const Scene& s, const std::string& name) {
  for (size_t i = 0; i < s.bodies.size(); ++i)
    if (s.bodies[i].name == name) return (int)i;
  ADD_FAILURE() << "no body " << name;
  return -1;
}

// The same double pendulum written as scene YAML and as URDF (link frames at the joints, a
// `world` link) moves the same to the last bit: the importer makes the very bodies and joints the
// scene format makes.
// Two scenes stepped side by side for 2 s: every body's pose and spin equal to the bit. Returns
// the second world's bodies' origins.
std::vector<Vec3> expect_same_motion(const std::string& yaml_a, const std::string& yaml_b) {
  const Scene a = load_scene(kData + yaml_a);
  const Scene b = load_scene(kData + yaml_b);
  EXPECT_EQ(a.bodies.size(), b.bodies.size());
  EXPECT_EQ(b.joints.size(), 2u);
  World wa(world_config(a, 1), a.bodies), wb(world_config(b, 1), b.bodies);
  for (int step = 0; step < 480; ++step) {
    wa.step();
    wb.step();
  }
  std::vector<Vec3> out;
  for (int i = 0; i < wa.body_count() && i < wb.body_count(); ++i) {
    EXPECT_EQ(wa.origin_position(i), wb.origin_position(i)) << i;
    EXPECT_EQ(wa.orientation(i).coeffs(), wb.orientation(i).coeffs()) << i;
    EXPECT_EQ(wa.angular_velocity(i), wb.angular_velocity(i)) << i;
    out.push_back(wb.origin_position(i));
  }
  return out;
}

TEST(Import, UrdfMechanismEqualsTheSameSceneBitForBit) {
  const std::vector<Vec3> p = expect_same_motion("double_pendulum.yaml", "double_pendulum_import.yaml");
  // And it moved: released horizontal, the elbow is far below after 2 s.
  ASSERT_EQ(p.size(), 2u);
  EXPECT_LT(p[1].z(), 1.5);
}

// A cart on a rail with a bar hanging from it (the rail has no mass: fixed to the world). Small
// swings: omega^2 = m g l (M + m) / ((M + m)(I + m l^2) - (m l)^2), with I the bar's moment about
// the hinge axis through its centre of mass, which the file states about the bar's own axes,
// turned a quarter about z: dropping that rotation (I = 0.24 instead of 0.25) moves the period by
// 0.7%. The horizontal centre of mass stays put (no horizontal force on the system).
TEST(Import, CartPendulumSwingsAtItsClosedFormFrequency) {
  const std::string scene = write("cart.yaml",
                                  "simulation: { duration: 10, timestep: 0.001 }\n"
                                  "imports:\n"
                                  "  - { file: " +
                                      fs::absolute(kData + "cart_pendulum.urdf").string() +
                                      ", joint_positions: { hinge: 0.002 } }\n");
  const Scene s = load_scene(scene);
  ASSERT_EQ(s.bodies.size(), 3u);  // rail (static), cart, bar
  EXPECT_EQ(s.bodies[body(s, "rail")].type, BodyType::static_body);
  EXPECT_TRUE(has(s.notes, "the root link has no mass: fixed to the world"));
  ASSERT_EQ(s.joints.size(), 2u);
  const int bar = body(s, "bar"), cart = body(s, "cart");
  EXPECT_NEAR(s.bodies[bar].mass_override->inertia(1, 1), 0.25, 1e-15);  // the rpy applied
  World w(world_config(s, 1), s.bodies);
  const double M = 3, m = 2, l = 0.6, I = 0.25, g = 9.81;
  const double omega = std::sqrt(m * g * l * (M + m) / ((M + m) * (I + m * l * l) - m * l * m * l));
  auto x_cm = [&] { return (M * w.centroid(cart).x() + m * w.centroid(bar).x()) / (M + m); };
  const double x0 = x_cm();
  // simreel's coordinate is zero at the start pose: the file's angle is it plus 0.002.
  double prev = w.joint_position(1) + 0.002, t_prev = 0;
  std::vector<double> crossings;
  double worst_x = 0;
  while (w.time() < 10) {
    w.step();
    const double q = w.joint_position(1) + 0.002;
    if ((prev > 0) != (q > 0)) crossings.push_back(t_prev + (w.time() - t_prev) * prev / (prev - q));
    prev = q;
    t_prev = w.time();
    worst_x = std::max(worst_x, std::fabs(x_cm() - x0));
  }
  ASSERT_GE(crossings.size(), 11u);
  const double period = (crossings[10] - crossings[0]) / 5;
  // Amplitude 0.002 rad: the nonlinear correction is about theta^2/16 = 2.5e-7 of the period.
  EXPECT_NEAR(period, 2 * M_PI / omega, 2e-6 * period);
  EXPECT_LT(worst_x, 1e-12);
}

// <inertial><origin rpy> turns the stated tensor into the link frame (the rotation several
// loaders drop).
TEST(Import, InertialOriginRotationIsApplied) {
  const Model m = read_urdf(kData + "cart_pendulum.urdf");
  ASSERT_EQ(m.links.size(), 3u);
  const Mat3& I = m.links[2].inertial->inertia;
  EXPECT_NEAR(I(0, 0), 0.24, 1e-15);
  EXPECT_NEAR(I(1, 1), 0.25, 1e-15);
  EXPECT_NEAR(I(2, 2), 0.012, 1e-15);
  EXPECT_NEAR(I(0, 1), 0, 1e-15);
}

// The inertia policies: `check` keeps the file's values and warns with both; `geometry` uses the
// collision geometry's at the file's mass; `file` is silent.
TEST(Import, PlaceholderInertiaIsCheckedAgainstGeometry) {
  const std::string urdf = write("cube.urdf", R"(<?xml version="1.0"?>
<robot name="cube">
  <link name="box">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><box size="1 1 1"/></geometry></collision>
  </link>
</robot>
)");
  auto scene = [&](const char* policy) {
    return load_scene(write(std::string("s_") + policy + ".yaml",
                            "imports: [ { file: " + urdf + ", inertia: " + policy + " } ]\n"));
  };
  const Scene check = scene("check");
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_NE(check.warnings[0].find("cube.urdf:4: link 'box', inertial: the stated inertia disagrees"),
            std::string::npos)
      << check.warnings[0];
  EXPECT_NE(check.warnings[0].find("(1, 1, 1) kg m^2 stated, (0.167, 0.167, 0.167) from the geometry"),
            std::string::npos)
      << check.warnings[0];
  EXPECT_DOUBLE_EQ(check.bodies[0].mass_override->inertia(0, 0), 1.0);
  const Scene geometry = scene("geometry");
  EXPECT_TRUE(geometry.warnings.empty());
  EXPECT_NEAR(geometry.bodies[0].mass_override->inertia(0, 0), 1.0 / 6, 1e-15);
  EXPECT_DOUBLE_EQ(geometry.bodies[0].mass_override->mass, 1.0);
  EXPECT_TRUE(scene("file").warnings.empty());
}

// Fixed joints weld links into one body; a `world` root fixes the base; visual shapes draw
// without weighing or colliding, collision shapes collide without drawing (unless shown).
TEST(Import, FixedLinksJoinTheirParentAndVisualsOnlyDraw) {
  const std::string urdf = write("arm.urdf", R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="world"/>
  <link name="base"><visual><geometry><cylinder radius="0.2" length="0.1"/></geometry></visual>
    <collision><geometry><cylinder radius="0.2" length="0.1"/></geometry></collision></link>
  <link name="upper">
    <inertial><origin xyz="0 0 0.25"/><mass value="1"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.001"/></inertial>
    <visual><origin xyz="0 0 0.25"/><geometry><box size="0.05 0.05 0.5"/></geometry></visual>
    <collision><origin xyz="0 0 0.25"/><geometry><box size="0.05 0.05 0.5"/></geometry></collision>
  </link>
  <link name="tool">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
    <visual><geometry><sphere radius="0.05"/></geometry></visual>
  </link>
  <joint name="mount" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 0.05"/></joint>
  <joint name="lift" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.05"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="20" velocity="2"/><dynamics damping="0.1" friction="0.05"/></joint>
  <joint name="flange" type="fixed"><parent link="upper"/><child link="tool"/><origin xyz="0 0 0.5"/></joint>
</robot>
)");
  const Scene s = load_scene(write("s.yaml", "imports: [ { file: " + urdf + ", name: a1, hold: true } ]\n"));
  ASSERT_EQ(s.bodies.size(), 2u);  // base (static), upper with the tool welded on
  EXPECT_EQ(s.bodies[0].name, "a1/base");
  EXPECT_EQ(s.bodies[0].type, BodyType::static_body);
  EXPECT_EQ(s.bodies[1].name, "a1/upper");
  const MassProperties& mp = *s.bodies[1].mass_override;
  EXPECT_DOUBLE_EQ(mp.mass, 1.5);
  EXPECT_NEAR(mp.com.z(), (1 * 0.25 + 0.5 * 0.5) / 1.5, 1e-15);  // in the upper link's frame
  ASSERT_EQ(s.joints.size(), 1u);
  const JointDef& j = s.joints[0];
  EXPECT_EQ(j.name, "a1/lift");
  EXPECT_EQ(j.parent, 0);
  EXPECT_EQ(j.child, 1);
  EXPECT_EQ(j.anchor_W, Vec3(0, 0, 0.1));
  EXPECT_EQ(j.axis_W, Vec3(1, 0, 0));
  ASSERT_TRUE(j.limits && j.spring && j.motor);
  EXPECT_EQ(j.limits->lower, -1);
  EXPECT_EQ(j.spring->damping, 0.1);
  EXPECT_EQ(j.friction, 0.05);
  EXPECT_EQ(j.motor->max_force, 20);
  // upper: visual box (drawn, no collision), collision box (collides, not drawn); tool: visual sphere.
  const std::vector<Collider>& c = s.bodies[1].colliders;
  ASSERT_EQ(c.size(), 3u);
  EXPECT_FALSE(c[0].collide);
  EXPECT_TRUE(s.looks[1].colliders[0].drawn);
  EXPECT_TRUE(c[1].collide);
  EXPECT_FALSE(s.looks[1].colliders[1].drawn);
  EXPECT_EQ(c[2].shape, ShapeKind::sphere);
  EXPECT_EQ(c[2].p_BC, Vec3(0, 0, 0.5));
  // show: [colliders] draws exactly the other set.
  const Scene shown = load_scene(write("t.yaml", "imports: [ { file: " + urdf + ", show: [colliders] } ]\n"));
  EXPECT_FALSE(shown.looks[1].colliders[0].drawn);
  EXPECT_TRUE(shown.looks[1].colliders[1].drawn);
  // Held by its motor, the arm stays put against gravity (it starts level with its centre of
  // mass over the hinge, then is tipped by nothing: 2 s of holding).
  World w(world_config(s, 1), s.bodies);
  for (int i = 0; i < 480; ++i) w.step();
  EXPECT_NEAR(w.joint_position(0), 0, 1e-9);
}

// A planar joint becomes two sliders and a hinge through helper links: a puck held in the plane
// z = 1 under gravity tilted 1 m/s^2 along x slides x = t^2 / 2 with z kept exactly (closed form:
// the helpers' 2e-9 of the mass changes it by 2e-9).
TEST(Import, PlanarJointIsTwoSlidersAndAHinge) {
  const std::string urdf = write("puck.urdf", R"(<?xml version="1.0"?>
<robot name="puck">
  <link name="world"/>
  <link name="puck">
    <inertial><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.016"/></inertial>
    <collision><geometry><cylinder radius="0.125" length="0.05"/></geometry></collision>
  </link>
  <joint name="slide" type="planar"><parent link="world"/><child link="puck"/><origin xyz="0 0 1"/><axis xyz="0 0 1"/></joint>
</robot>
)");
  const Scene s = load_scene(
      write("p.yaml", "simulation: { gravity: [1, 0, -9.81], duration: 1 }\nimports: [ { file: " + urdf +
                          ", inertia: file } ]\n"));
  ASSERT_EQ(s.joints.size(), 3u);
  EXPECT_TRUE(has(s.notes, "planar: two prismatic joints (slide/x, slide/y) and a hinge"));
  const int puck = body(s, "puck");
  World w(world_config(s, 1), s.bodies);
  for (int i = 0; i < 240; ++i) w.step();
  EXPECT_NEAR(w.centroid(puck).x(), 0.5, 1e-8);
  EXPECT_NEAR(w.centroid(puck).z(), 1.0, 1e-14);
  EXPECT_NEAR(w.centroid(puck).y(), 0.0, 1e-14);
}

// package:// through the file's own package, or `package_paths`; a Windows path from another
// machine by its file name beside the URDF, with a note; capsules; ignored elements noted.
// URDF's mimic: a follower joint's coordinate is multiplier times its leader's plus offset. Two
// hinged bars, the second mimicking the first with multiplier -1 and offset 0.3 rad: it starts
// turned by 0.3 rad, moves as minus the first (in simreel's coordinates, zero at the start), and
// `hold` puts no motor on it.
TEST(Import, UrdfMimicCouplesTheFollowerToItsLeader) {
  const std::string bar =
      "<inertial><mass value=\"1\"/><origin xyz=\"0 0 -0.5\"/><inertia ixx=\"0.08\" iyy=\"0.08\" "
      "izz=\"0.001\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
  const std::string urdf =
      write("mimic.urdf",
            "<robot name=\"pair\">\n<link name=\"world\"/>\n<link name=\"a\">" + bar +
                "</link>\n<link name=\"b\">" + bar +
                "</link>\n"
                "<joint name=\"left\" type=\"continuous\"><parent link=\"world\"/><child link=\"a\"/>"
                "<origin xyz=\"0 0 1\" rpy=\"0 0.8 0\"/><axis xyz=\"0 1 0\"/>"
                "<limit effort=\"100\" velocity=\"5\"/></joint>\n"
                "<joint name=\"right\" type=\"continuous\"><parent link=\"world\"/><child link=\"b\"/>"
                "<origin xyz=\"2 0 1\"/><axis xyz=\"0 1 0\"/>"
                "<mimic joint=\"left\" multiplier=\"-1\" offset=\"0.3\"/></joint>\n</robot>\n");
  const Scene s = load_scene(urdf);
  ASSERT_EQ(s.joints.size(), 2u);
  ASSERT_TRUE(s.joints[1].mimic);
  EXPECT_EQ(s.joints[1].mimic->leader, 0);
  EXPECT_EQ(s.joints[1].mimic->multiplier, -1.0);
  const int b = body(s, "b");
  // Turned by the offset about +y at the start: its centre of mass 0.5 m down the turned bar.
  World w(world_config(s, 1), s.bodies);
  const Vec3 c0 = w.centroid(b) - Vec3(2, 0, 1);
  EXPECT_NEAR(c0.x(), -0.5 * std::sin(0.3), 1e-12);
  EXPECT_NEAR(c0.z(), -0.5 * std::cos(0.3), 1e-12);
  double worst = 0;
  for (int i = 0; i < 240; ++i) {
    w.step();
    worst = std::max(worst, std::abs(w.joint_position(1) + w.joint_position(0)));
  }
  EXPECT_GT(std::abs(w.joint_position(0)), 0.1);
  EXPECT_LT(worst, 1e-12);
  const Scene held = load_scene(write("held.yaml", "imports: [ { file: " + urdf + ", hold: true } ]\n"));
  EXPECT_TRUE(held.joints[0].motor);
  EXPECT_FALSE(held.joints[1].motor);
}

// MJCF's <equality><joint joint1 joint2 polycoef="c0 c1 ...">: joint1 = c0 + c1 joint2, simreel's
// mimic. Two fingers on slides, the second coupled to the first with c1 = -1 (a parallel gripper):
// pushed apart by gravity along a tilted rail, they keep q2 = -q1 to 1e-12 m. A quadratic term and
// a joint locked alone are notes.
TEST(ImportMjcf, JointEqualityCouplesTwoCoordinates) {
  const std::string xml = write("grip.xml", R"(<mujoco>
  <worldbody>
    <body name="f1" pos="0 0 1"><joint name="s1" type="slide" axis="1 0 1"/><geom size="0.05"/></body>
    <body name="f2" pos="1 0 1"><joint name="s2" type="slide" axis="1 0 0"/><geom size="0.05" mass="3"/></body>
    <body name="f3" pos="2 0 1"><joint name="s3" type="slide" axis="0 0 1"/><geom size="0.05"/></body>
  </worldbody>
  <equality>
    <joint joint1="s2" joint2="s1" polycoef="0 -1 0 0 0"/>
    <joint joint1="s3" joint2="s1" polycoef="0 2 0.5 0 0"/>
  </equality>
</mujoco>
)");
  const Scene s =
      load_scene(write("grip.yaml", "imports: [ { file: " + xml + ", self_collision: false } ]\n"));
  ASSERT_EQ(s.joints.size(), 3u);
  ASSERT_TRUE(s.joints[1].mimic);
  EXPECT_EQ(s.joints[1].mimic->leader, 0);
  EXPECT_EQ(s.joints[1].mimic->multiplier, -1.0);
  ASSERT_TRUE(s.joints[2].mimic);
  EXPECT_EQ(s.joints[2].mimic->multiplier, 2.0);  // the linear part
  EXPECT_TRUE(has(s.notes, "only the polynomial's linear part is held"));
  World w(world_config(s, 1), s.bodies);
  double worst = 0;
  for (int i = 0; i < 120; ++i) {
    w.step();
    worst = std::max(worst, std::abs(w.joint_position(1) + w.joint_position(0)));
  }
  EXPECT_GT(std::abs(w.joint_position(0)), 0.1);  // it moved (down its tilted rail)
  EXPECT_LT(worst, 1e-12);
  const Scene locked =
      load_scene(write("lock.xml",
                       "<mujoco><worldbody><body><joint name=\"h\"/><geom size=\"0.1\"/></body></worldbody>"
                       "<equality><joint joint1=\"h\"/></equality></mujoco>\n"));
  EXPECT_TRUE(has(locked.notes, "a joint locked alone (no joint2) is not simulated"));
}

// An inline MJCF mesh with faces is the mesh they make: an L-shaped prism (3 unit squares by
// 0.5 m, 1.5 m^3) weighs 1500 kg at 1000 kg/m^3, not its convex hull's 1750; without faces, the
// vertices' hull. A face naming no vertex is an error at its line.
TEST(ImportMjcf, InlineMeshFacesAreTheSolid) {
  const std::string v = "0 0 0 2 0 0 2 0 1 1 0 1 1 0 2 0 0 2 0 0.5 0 2 0.5 0 2 0.5 1 1 0.5 1 1 0.5 2 0 0.5 2";
  const std::string f =
      "3 4 5 9 11 10 3 5 0 9 6 11 3 0 1 9 7 6 3 1 2 9 8 7 0 7 1 0 6 7 1 8 2 1 7 8 2 9 3 2 8 9 3 10 4 3 9 10 "
      "4 "
      "11 5 4 10 11 5 6 0 5 11 6";
  auto mass = [&](const std::string& mesh) {
    const Scene s =
        load_scene(write("l.xml", "<mujoco><asset>" + mesh +
                                      "</asset><worldbody><body name=\"b\" pos=\"0 0 3\"><freejoint/>"
                                      "<geom type=\"mesh\" mesh=\"L\" density=\"1000\"/></body>"
                                      "</worldbody></mujoco>\n"));
    World w(world_config(s, 1), s.bodies);
    return w.mass(body(s, "b"));
  };
  EXPECT_NEAR(mass("<mesh name=\"L\" vertex=\"" + v + "\" face=\"" + f + "\"/>"), 1500.0, 1e-9);
  EXPECT_NEAR(mass("<mesh name=\"L\" vertex=\"" + v + "\"/>"), 1750.0, 1e-9);
  const std::string e = error_of(write("bad.xml", "<mujoco><asset><mesh name=\"L\" vertex=\"" + v +
                                                      "\" face=\"0 1 12\"/></asset><worldbody/></mujoco>\n"));
  EXPECT_NE(e.find("bad.xml:1: mesh 'L': face index 12 is not a vertex (0 to 11)"), std::string::npos) << e;
}

TEST(Import, PathsPackagesAndTolerance) {
  const Scene in_pkg = load_scene(kData + "pkg/my_robot/urdf/box_robot.urdf");
  EXPECT_EQ(in_pkg.bodies.size(), 2u);  // the robot and the ground
  const std::string scene =
      write("s.yaml", "imports: [ { file: " + fs::absolute(kData + "elsewhere.urdf").string() +
                          ", package_paths: [" + fs::absolute(kData + "pkg").string() + "] } ]\n");
  const Scene s = load_scene(scene);
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_EQ(s.bodies[0].colliders.size(), 3u);
  EXPECT_EQ(s.bodies[0].colliders[2].shape, ShapeKind::capsule);
  EXPECT_DOUBLE_EQ(s.bodies[0].colliders[2].height, 0.4);  // URDF length between the caps' centres
  EXPECT_TRUE(
      has(s.notes,
          "elsewhere.urdf:5: link 'base', visual 0: mesh 'E:\\develop\\robots\\block.obj' is a path on "
          "another machine; using"))
      << s.notes[0];
  EXPECT_TRUE(has(s.notes, "elsewhere.urdf:9: <gazebo> is not used by simreel"));
  // Without the package path the error says where it looked and what to set.
  const std::string e = error_of(
      write("u.yaml", "imports: [ { file: " + fs::absolute(kData + "elsewhere.urdf").string() + " } ]\n"));
  EXPECT_NE(
      e.find(
          "elsewhere.urdf:6: link 'base', collision 0: mesh 'package://my_robot/meshes/block.obj': package "
          "'my_robot' not found; give its folder in the import's `package_paths`"),
      std::string::npos)
      << e;
}

// What cannot be a robot is an error naming file, line and the link or joint.
TEST(Import, MistakesAreNamedByFileAndLine) {
  auto err = [&](const std::string& name, const std::string& text) { return error_of(write(name, text)); };
  EXPECT_NE(
      err("r.xacro", "<robot xmlns:xacro=\"http://ros.org/wiki/xacro\"><xacro:macro name=\"m\"/></robot>\n")
          .find("a xacro file (macros, not a robot): expand it first with xacro"),
      std::string::npos);
  const std::string head = "<?xml version=\"0.0\"?>\n<robot name=\"r\">\n  <link name=\"base\"/>\n";
  EXPECT_NE(
      err("j.urdf", head +
                        "  <link name=\"arm\"/>\n  <joint name=\"j\" type=\"revolute\">\n"
                        "    <parent link=\"bse\"/><child link=\"arm\"/><limit lower=\"-1\" upper=\"1\"/>\n"
                        "  </joint>\n</robot>\n")
          .find(
              "j.urdf:6: joint 'j': <parent> names link 'bse', which the file does not define; did you mean "
              "'base'?"),
      std::string::npos);
  EXPECT_NE(err("n.urdf",
                head + "  <link name=\"arm\"><inertial><mass value=\"1.5kg\"/></inertial></link>\n</robot>\n")
                .find("n.urdf:4: link 'arm': <mass value=\"1.5kg\">: expected numbers"),
            std::string::npos);
  EXPECT_NE(err("t.urdf",
                head + "  <link name=\"arm\"/>\n  <joint name=\"j\" type=\"hinge\">\n</joint>\n</robot>\n")
                .find("t.urdf:5: joint 'j': unknown joint type 'hinge'"),
            std::string::npos);
  EXPECT_NE(err("x.urdf", head + "  <link name=\"arm\">\n</robot>\n").find("x.urdf:"), std::string::npos);
  EXPECT_NE(err("two.urdf", head + "  <link name=\"arm\"/>\n</robot>\n").find("2 links have no parent joint"),
            std::string::npos);
  // A moving link with nothing to weigh.
  EXPECT_NE(err("w.urdf",
                "<robot name=\"r\">\n  <link name=\"base\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" "
                "iyy=\"1\" izz=\"1\"/></inertial></link>\n  <link name=\"arm\"/>\n  <joint name=\"j\" "
                "type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/></joint>\n</robot>\n")
                .find("w.urdf:3: link 'arm': has no mass (no <inertial>) and no collision geometry to weigh, "
                      "yet moves"),
            std::string::npos);
  // joint_positions name a joint of the file, within its limits.
  const std::string dp = fs::absolute(kData + "double_pendulum.urdf").string();
  EXPECT_NE(err("p.yaml", "imports: [ { file: " + dp + ", joint_positions: { elbw: 1 } } ]\n")
                .find("has no joint named 'elbw'; did you mean 'elbow'?"),
            std::string::npos);
}

// The same double pendulum in MJCF (nested bodies, inertials, a joint without a type is a hinge)
// moves as the scene and the URDF do, to the bit.
TEST(ImportMjcf, MechanismEqualsTheSameSceneBitForBit) {
  expect_same_motion("double_pendulum.yaml", "double_pendulum_mjcf.yaml");
}

// A linkage loaded from a file, swung by gravity for 3 s: its joints and loops stay closed to
// 1e-9 m, its energy is kept to 1e-8 (no damping) and its first joint moved.
void expect_swings_closed(const Scene& s) {
  World w(world_config(s, 1), s.bodies);
  Drift drift(w);
  for (int i = 0; i < 3 * 240; ++i) {
    w.step();
    if (i % 8 == 0) drift.sample(w);
  }
  EXPECT_LT(drift.joint_gap(), 1e-9);
  EXPECT_LT(drift.energy_rel(), 1e-8);
  EXPECT_GT(std::fabs(w.joint_position(0)), 0.1);  // it moved
}

// Default classes cascade (childclass, class, nested defaults, from an included file), capsules
// from `fromto` weigh at their density, and an equality connect closes a loop that stays closed
// while the linkage swings with its energy kept. Unknown elements and attributes are notes with
// file and line.
TEST(ImportMjcf, FourBarWithClassesIncludeAndLoop) {
  const Scene s = load_scene(write("s.yaml", "simulation: { duration: 3 }\nimports: [ { file: " +
                                                 fs::absolute(kData + "four_bar.xml").string() + " } ]\n"));
  ASSERT_EQ(s.bodies.size(), 3u);
  ASSERT_EQ(s.joints.size(), 4u);  // three hinges and the loop
  EXPECT_EQ(s.joints[3].type, JointType::spherical);
  const int coupler = body(s, "coupler"), crank = body(s, "crank");
  ASSERT_EQ(s.bodies[coupler].colliders.size(), 1u);
  EXPECT_EQ(s.bodies[coupler].colliders[0].radius, 0.01);  // class thin, inside bar
  EXPECT_EQ(s.bodies[crank].colliders[0].radius, 0.02);
  EXPECT_EQ(s.bodies[coupler].colliders[0].shape, ShapeKind::capsule);
  const double r = 0.01, L = std::sqrt(0.7 * 0.7 + 0.4 * 0.4);
  EXPECT_NEAR(s.bodies[coupler].mass_override->mass, 2700 * (M_PI * r * r * L + 4.0 / 3 * M_PI * r * r * r),
              1e-12);
  EXPECT_TRUE(has(s.notes, "four_bar.xml:16: <joint> has no attribute 'wobble' that simreel knows; ignored"));
  EXPECT_TRUE(has(s.notes, "four_bar.xml:23: <flywheel> is not an MJCF element simreel knows; ignored"));
  expect_swings_closed(s);
}

// An MJCF model's links collide by MuJoCo's rule (its default, and self_collision: true): every
// pair of the model's bodies may touch but a body and its parent (through helper bodies) and the
// pairs <contact><exclude> names; self_collision: false turns them all off.
TEST(ImportMjcf, SelfCollisionSkipsParentsAndExcludedPairs) {
  const std::string xml = write("m.xml", R"(<mujoco>
  <worldbody>
    <body name="a" pos="0 0 1"><freejoint/><geom size="0.1"/>
      <body name="b" pos="0 0 -0.3"><joint axis="1 0 0"/><joint axis="0 1 0"/><geom size="0.1"/>
        <body name="c" pos="0 0 -0.3"><joint axis="1 0 0"/><geom size="0.1"/></body>
      </body>
      <body name="d" pos="0.3 0 0"><joint axis="1 0 0"/><geom size="0.1"/></body>
    </body>
  </worldbody>
  <contact><exclude body1="c" body2="d"/></contact>
</mujoco>
)");
  const Scene off =
      load_scene(write("off.yaml", "imports: [ { file: " + xml + ", self_collision: false } ]\n"));
  const Scene on = load_scene(write("on.yaml", "imports: [ { file: " + xml + " } ]\n"));
  auto ignored = [&](const Scene& s, const char* x, const char* y) {
    const int i = body(s, x), j = body(s, y);
    const std::pair<int, int> p(std::min(i, j), std::max(i, j));
    return std::find(s.ignore_pairs.begin(), s.ignore_pairs.end(), p) != s.ignore_pairs.end();
  };
  EXPECT_TRUE(ignored(off, "a", "c"));
  EXPECT_TRUE(ignored(on, "a", "b"));   // parent, through the helper b#1
  EXPECT_TRUE(ignored(on, "c", "d"));   // excluded by the file
  EXPECT_FALSE(ignored(on, "a", "c"));  // grandparent: may touch
  EXPECT_FALSE(ignored(on, "b", "d"));
}

// A ball joint's range bounds its rotation's angle (the second number; degrees by default), its
// stiffness and damping are a spring on the rotation vector and its frictionloss a friction about
// each axis, as in MuJoCo.
TEST(ImportMjcf, BallJointRangeAndSpringLoad) {
  const Scene s = load_scene(write("ball.xml",
                                   "<mujoco><worldbody><body name=\"limb\" pos=\"0 0 1\">\n"
                                   "<joint name=\"shoulder\" type=\"ball\" range=\"0 60\" stiffness=\"2\" "
                                   "damping=\"0.1\" frictionloss=\"0.3\"/>\n"
                                   "<geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.4\" size=\"0.05\"/>\n"
                                   "</body></worldbody></mujoco>\n"));
  ASSERT_EQ(s.joints.size(), 1u);
  const JointDef& j = s.joints[0];
  EXPECT_EQ(j.type, JointType::spherical);
  ASSERT_TRUE(j.ball_limits);
  EXPECT_NEAR(j.ball_limits->angle, std::numbers::pi / 3, 1e-15);
  EXPECT_TRUE(std::isinf(j.ball_limits->cone));
  EXPECT_EQ(j.armature, 0.0);
  ASSERT_TRUE(j.spring);
  EXPECT_EQ(j.spring->stiffness, 2.0);
  EXPECT_EQ(j.spring->damping, 0.1);
  EXPECT_EQ(j.spring->rest, 0.0);
  EXPECT_EQ(j.friction, 0.3);  // about each of the child's axes, as MuJoCo's per-dof rows
  EXPECT_FALSE(has(s.notes, "frictionloss"));
  const Scene wide = load_scene(write("wide.xml",
                                      "<mujoco><worldbody><body name=\"limb\" pos=\"0 0 1\">\n"
                                      "<joint type=\"ball\" range=\"0 200\"/>\n"
                                      "<geom type=\"sphere\" size=\"0.05\"/>\n"
                                      "</body></worldbody></mujoco>\n"));
  EXPECT_FALSE(wide.joints.at(0).ball_limits);
  EXPECT_TRUE(has(wide.notes, "a ball joint's range of pi or more leaves it free"));
}

// MJCF actuators bound the force of the motor `hold: true` puts on their joint, by MuJoCo's rules:
// |gear| times the forcerange, or a motor's ctrlrange (through a default class); several on one
// joint add up, capped by the joint's actuatorfrcrange. A position servo without forcerange and an
// actuator on a tendon give none (notes).
TEST(ImportMjcf, ActuatorsBoundTheHeldJointsMotors) {
  const std::string xml = write("act.xml", R"(<mujoco>
  <default><motor ctrlrange="-1 1" ctrllimited="true"/></default>
  <worldbody><body name="a" pos="0 0 1"><joint name="j1" axis="0 1 0"/><geom size="0.1"/>
    <body name="b" pos="0 0 -0.3"><joint name="j2" axis="0 1 0" actuatorfrcrange="-5 5"/><geom size="0.1"/>
      <body name="c" pos="0 0 -0.3"><joint name="j3" axis="0 1 0"/><geom size="0.1"/></body>
    </body></body></worldbody>
  <tendon><fixed name="t"><joint joint="j1" coef="1"/></fixed></tendon>
  <actuator>
    <motor joint="j1" gear="50"/>
    <position joint="j2" kp="10" gear="2" forcerange="-3 3"/>
    <motor joint="j2" gear="1" ctrlrange="-0.5 0.5"/>
    <position joint="j3" kp="10"/>
    <motor tendon="t" gear="1"/>
  </actuator>
</mujoco>
)");
  const Scene s = load_scene(write("act.yaml", "imports: [ { file: " + xml + ", hold: true } ]\n"));
  auto motor_of = [&](const char* name) -> std::optional<JointMotor> {
    for (const JointDef& j : s.joints)
      if (j.name == name) return j.motor;
    ADD_FAILURE() << "no joint " << name;
    return std::nullopt;
  };
  ASSERT_TRUE(motor_of("j1"));
  EXPECT_EQ(motor_of("j1")->max_force, 50.0);  // gear 50 x ctrlrange 1 (the default class's)
  ASSERT_TRUE(motor_of("j2"));
  EXPECT_EQ(motor_of("j2")->max_force, 5.0);  // 2 x 3 + 1 x 0.5, capped by actuatorfrcrange
  EXPECT_FALSE(motor_of("j3"));               // a servo with no forcerange: no bound
  EXPECT_TRUE(has(s.notes, "no force bound (forcerange or ctrlrange)"));
  EXPECT_TRUE(has(s.notes, "actuators on tendons, sites and bodies are not used"));
  EXPECT_TRUE(has(s.notes, "joint 'j3': no effort limit: no motor holds it"));
}

// A hinge's armature is its rotor inertia; a ball joint's is a note.
TEST(ImportMjcf, ArmatureIsTheCoordinatesRotorInertia) {
  const Scene s = load_scene(write("arm.xml",
                                   "<mujoco><worldbody><body name=\"a\" pos=\"0 0 1\">\n"
                                   "<joint name=\"h\" axis=\"0 1 0\" armature=\"0.02\"/>\n"
                                   "<geom type=\"sphere\" size=\"0.05\"/>\n"
                                   "<body name=\"b\" pos=\"0 0 -0.5\"><joint name=\"k\" type=\"ball\" "
                                   "armature=\"0.01\"/>\n"
                                   "<geom type=\"sphere\" size=\"0.05\"/></body>\n"
                                   "</body></worldbody></mujoco>\n"));
  ASSERT_EQ(s.joints.size(), 2u);
  EXPECT_EQ(s.joints[0].armature, 0.02);
  EXPECT_EQ(s.joints[1].armature, 0.0);
  EXPECT_TRUE(has(s.notes, "arm.xml:4: joint 'k': a ball joint's armature is not simulated"));
}

// An equality connect between two sites (MuJoCo 3's form) closes the loop where the sites meet: a
// crank and coupler hinged in a chain and a rocker hinged to the world, the coupler's tip site
// joined to the rocker's, swing as a four-bar with the loop closed to 1e-9 m and the energy kept
// to 1e-8. Sites apart at the
// start are held apart (a note); an unknown site is an error with the nearest name.
TEST(ImportMjcf, SiteConnectClosesALoopWhereTheSitesMeet) {
  const std::string four = R"(<mujoco>
  <worldbody>
    <body name="crank" pos="0 0 1"><joint axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02"/>
      <body name="coupler" pos="0.2 0 0"><joint axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.6 0 -0.3" size="0.02"/>
        <site name="tip" pos="0.6 0 -0.3"/>
      </body>
    </body>
    <body name="rocker" pos="1 0 0.2"><joint axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 -0.2 0 0.5" size="0.02"/>
      <site name="rocker_tip" pos="-0.2 0 0.5"/>
    </body>
  </worldbody>
  <equality><connect site1="tip" site2="rocker_tip"/></equality>
</mujoco>
)";
  const Scene s = load_scene(write("sc.yaml", "imports: [ { file: " + write("sc.xml", four) + " } ]\n"));
  ASSERT_EQ(s.joints.size(), 4u);  // three hinges and the loop
  EXPECT_EQ(s.joints[3].type, JointType::spherical);
  EXPECT_FALSE(has(s.notes, "apart"));
  expect_swings_closed(s);
  std::string apart = four;
  apart.replace(apart.find("-0.2 0 0.5\"/>"), 10, "-0.2 0 0.6");
  const Scene a = load_scene(write("sa.yaml", "imports: [ { file: " + write("sa.xml", apart) + " } ]\n"));
  EXPECT_TRUE(has(a.notes, "its sites are apart at the start (0.100000 m): held as they are"));
  std::string typo = four;
  typo.replace(typo.find("site1=\"tip\""), 11, "site1=\"tpi\"");
  const std::string e = error_of(write("st.yaml", "imports: [ { file: " + write("st.xml", typo) + " } ]\n"));
  EXPECT_NE(e.find("site1 names site 'tpi', which the file does not define; did you mean 'tip'?"),
            std::string::npos)
      << e;
}

// MuJoCo 3's <frame> and <replicate>: copies placed step by step (each step taken in the previous
// copy's frame), names suffixed as MuJoCo does (sep, then the index with as many digits as
// count - 1, an inner replicate's first), and what names a copied thing outside the replicate (a
// tendon, an equality) copied with it. A spatial tendon between two sites with a limited length
// is a rope: a ball hung 0.1 m slack below its top falls, is caught (restitution 0) and hangs at
// the rope's length to round-off.
TEST(ImportMjcf, ReplicateFrameAndTendonRopes) {
  const std::string xml = R"(<mujoco>
  <default><tendon limited="true" range="0 0.8"/></default>
  <worldbody>
    <frame pos="0 0 2" euler="0 0 90">
      <replicate count="3" offset="0.5 0 0" sep="-">
        <site name="top" pos="0 0 0.5"/>
        <body name="b" pos="0 0 -0.2">
          <freejoint/>
          <geom size="0.05" solref="0.02 0.5"/>
          <site name="s" pos="0 0 0"/>
        </body>
      </replicate>
    </frame>
    <replicate count="2" offset="0 5 0" euler="0 0 90">
      <replicate count="12" sep="_" offset="0 0 1">
        <body name="c" pos="10 0 1"><freejoint/><geom size="0.05" solref="-1e8 -0"/></body>
      </replicate>
    </replicate>
  </worldbody>
  <tendon><spatial name="rope"><site site="top"/><site site="s"/></spatial></tendon>
  <equality><connect name="pin" body1="c" anchor="0 0 0"/></equality>
</mujoco>
)";
  const Scene s = load_scene(write("rep.yaml",
                                   "simulation: { sleep: false }\n"
                                   "imports: [ { file: " +
                                       write("rep.xml", xml) + " } ]\n"));
  // The frame turns the row 90 degrees about z: copy i at (0, 0.5 i, 2 - 0.2).
  for (int i = 0; i < 3; ++i) {
    const BodyDef& b = s.bodies[body(s, "b-" + std::to_string(i))];
    EXPECT_LT((b.p_WB - Vec3(0, 0.5 * i, 1.8)).norm(), 1e-12) << i;
  }
  // Outer copy 1 is 5 m along y and turned 90 degrees; its inner copies stack 1 m apart in its frame.
  const BodyDef& c = s.bodies[body(s, "c_051")];
  EXPECT_LT((c.p_WB - Vec3(0, 5 + 10, 1 + 5)).norm(), 1e-12) << c.p_WB.transpose();
  body(s, "c_110");
  int ropes = 0, pins = 0;
  for (const JointDef& j : s.joints) {
    if (j.type == JointType::distance) {
      ++ropes;
      EXPECT_EQ(*j.max_length, 0.8);
      EXPECT_FALSE(j.min_length);
      EXPECT_NEAR((j.anchor2_W - j.anchor_W).norm(), 0.7, 1e-12);
    }
    pins += j.name.rfind("pin_", 0) == 0;
  }
  EXPECT_EQ(ropes, 3);
  EXPECT_EQ(pins, 24);  // the connect copied with every c
  // solref (0.02 s, damping ratio 0.5): a spring-damper's exp(-pi z / sqrt(1 - z^2)); (-k, -0): 1.
  EXPECT_NEAR(s.bodies[body(s, "b-0")].colliders[0].restitution, std::exp(-M_PI * 0.5 / std::sqrt(0.75)),
              1e-15);
  EXPECT_EQ(s.bodies[body(s, "c_000")].colliders[0].restitution, 1.0);
  EXPECT_TRUE(has(s.notes, "restitution_threshold set to 0.05 m/s"));
  World w(world_config(s, 1), s.bodies);
  const int b0 = body(s, "b-1");
  for (int i = 0; i < 3 * 240; ++i) w.step();
  EXPECT_NEAR((w.centroid(b0) - Vec3(0, 0.5, 2.5)).norm(), 0.8, 1e-9);
  EXPECT_LT(w.linear_velocity(b0).norm(), 1e-9);
  // A tendon through three sites, and one without a limit, are notes.
  std::string three = xml;
  three.replace(three.find("<site site=\"s\"/>"), 16, "<site site=\"s\"/><site site=\"top\"/>");
  EXPECT_TRUE(
      has(load_scene(write("r3.yaml", "imports: [ { file: " + write("r3.xml", three) + " } ]\n")).notes,
          "a tendon through 3 sites is not simulated"));
  std::string free = xml;
  free.replace(free.find("limited=\"true\""), 14, "limited=\"false\"");
  EXPECT_TRUE(
      has(load_scene(write("r4.yaml", "imports: [ { file: " + write("r4.xml", free) + " } ]\n")).notes,
          "a tendon without a limited length or a spring pulls nothing here"));
}

// A spatial tendon's spring: -stiffness (L - springlength) - damping L'. Without a range it is a
// spring alone (a bungee): a 1 kg ball hung from a site on one of 100 N/m, rest 0.5 m, bobs at
// sqrt(k / m) (the mean of seven periods from the crossings of its rest height, each found by
// linear interpolation between 1/240 s frames: within 1e-5), and with damping settles at
// 0.5 + m g / k to 1e-7 m. With a range it is the rope's spring, resting at the length in the
// file's pose when springlength is not given. A dead band (two springlength values) is a note.
TEST(ImportMjcf, TendonSpringsPullAlongTheTendon) {
  auto xml = [](const std::string& spring) {
    return R"(<mujoco>
  <worldbody>
    <site name="hook" pos="0 0 3"/>
    <body name="ball" pos="0 0 2"><freejoint/>
      <geom type="sphere" size="0.1" mass="1"/><site name="top" pos="0 0 0.1"/>
    </body>
    <site name="hook2" pos="1 0 3"/>
    <body name="ball2" pos="1 0 2.2"><freejoint/>
      <geom type="sphere" size="0.1" mass="1"/><site name="top2" pos="0 0 0.1"/>
    </body>
  </worldbody>
  <tendon>
    <spatial name="cord" )" +
           spring + R"(><site site="hook"/><site site="top"/></spatial>
    <spatial name="rope" range="0 0.95" stiffness="50"><site site="hook2"/><site site="top2"/></spatial>
  </tendon>
</mujoco>
)";
  };
  const double k = 100, m = 1, L_eq = 0.5 + m * 9.81 / k;
  auto load = [&](const std::string& name, const std::string& spring) {
    return load_scene(write(name + ".yaml", "simulation: { sleep: false }\nimports: [ { file: " +
                                                write(name + ".xml", xml(spring)) + " } ]\n"));
  };
  const Scene s = load("ts", "stiffness=\"100\" springlength=\"0.5\"");
  ASSERT_EQ(s.forces.size(), 1u);
  EXPECT_EQ(s.forces[0].kind, ForceKind::spring);
  EXPECT_EQ(s.forces[0].stiffness, 100);
  EXPECT_EQ(s.forces[0].rest_length, 0.5);
  const JointDef* rope = nullptr;
  for (const JointDef& j : s.joints)
    if (j.type == JointType::distance) rope = &j;
  ASSERT_TRUE(rope && rope->spring);
  EXPECT_EQ(rope->spring->stiffness, 50);
  EXPECT_NEAR(rope->spring->rest, 0.7, 1e-12);  // the length in the file's pose
  EXPECT_EQ(*rope->max_length, 0.95);
  {
    World w(world_config(s, 1), s.bodies);
    const int b = body(s, "ball");
    const double z_eq = 3 - L_eq - 0.1, dt = w.config().dt;
    std::vector<double> up;
    double prev = w.centroid(b).z() - z_eq;
    for (int i = 1; i <= 5 * 240 && up.size() < 8; ++i) {
      w.step();
      const double x = w.centroid(b).z() - z_eq;
      if (prev < 0 && x >= 0) up.push_back((i - 1) * dt + dt * prev / (prev - x));
      prev = x;
    }
    ASSERT_EQ(up.size(), 8u);
    const double T = (up.back() - up.front()) / 7, T_ref = 2 * M_PI / std::sqrt(k / m);
    EXPECT_NEAR(T / T_ref, 1, 1e-5) << T << " " << T_ref;
  }
  {
    const Scene d = load("td", "stiffness=\"100\" damping=\"2\" springlength=\"0.5\"");
    World w(world_config(d, 1), d.bodies);
    for (int i = 0; i < 25 * 240; ++i) w.step();
    EXPECT_NEAR(3 - (w.centroid(body(d, "ball")).z() + 0.1), L_eq, 1e-7);
  }
  EXPECT_TRUE(has(load("tb", "stiffness=\"100\" springlength=\"0.2 0.5\"").notes,
                  "a dead-band spring (two springlength values) is not simulated"));
}

// A limited fixed tendon over two joints (a hamstring: 0.5 hip - 0.5 knee within [-0.3, 0.2]) is
// a stop on that combination: a two-bar leg released horizontal swings down, and the combination
// reaches its bound and never passes it (1e-9), where without the tendon it runs past. The same
// over three joints (the first following the other two); a joint named twice is a note.
TEST(ImportMjcf, LimitedFixedTendonStopsItsJointsCombination) {
  auto xml = [](const std::string& tendon) {
    return R"(<mujoco><worldbody>
  <body name="thigh" pos="0 0 2"><joint name="hip" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03"/>
    <body name="shank" pos="0.4 0 0"><joint name="knee" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03"/>
      <body name="foot" pos="0.4 0 0"><joint name="ankle" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.02"/></body>
    </body>
  </body></worldbody>
  <tendon>)" +
           tendon +
           R"(</tendon></mujoco>
)";
  };
  const std::string ham =
      R"(<fixed name="ham" limited="true" range="-0.3 0.2"><joint joint="hip" coef="0.5"/>)"
      R"(<joint joint="knee" coef="-0.5"/></fixed>)";
  // The leg released horizontal for 2 s: the extremes of c_hip q_hip + c_knee q_knee + c_ankle q_ankle.
  auto swing = [&](const std::string& name, const std::string& tendon, double& lo, double& hi,
                   std::array<double, 3> c = {0.5, -0.5, 0}) {
    const Scene s = load_scene(write(name + ".yaml", "simulation: { sleep: false }\nimports: [ { file: " +
                                                         write(name + ".xml", xml(tendon)) + " } ]\n"));
    World w(world_config(s, 1), s.bodies);
    const int hip = w.find_joint("hip"), knee = w.find_joint("knee"), ankle = w.find_joint("ankle");
    lo = hi = 0;
    for (int i = 0; i < 2 * 240; ++i) {
      w.step();
      const double x =
          c[0] * w.joint_position(hip) + c[1] * w.joint_position(knee) + c[2] * w.joint_position(ankle);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    return s;
  };
  double lo, hi, flo, fhi;
  const Scene s = swing("ft", ham, lo, hi);
  const JointDef& j = s.joints[0];  // the hip follows the knee within the range
  ASSERT_TRUE(j.mimic && j.mimic->range);
  EXPECT_EQ(j.mimic->multiplier, 1);
  EXPECT_NEAR(j.mimic->range->first, -0.6, 1e-15);
  EXPECT_NEAR(j.mimic->range->second, 0.4, 1e-15);
  swing("ff", "", flo, fhi);
  EXPECT_TRUE(flo < -0.3 - 1e-3 || fhi > 0.2 + 1e-3) << flo << " " << fhi;  // free, it runs past
  EXPECT_GE(lo, -0.3 - 1e-9);
  EXPECT_LE(hi, 0.2 + 1e-9);
  EXPECT_TRUE(lo < -0.3 + 1e-9 || hi > 0.2 - 1e-9) << lo << " " << hi;  // it met its bound
  // Over three joints: 0.5 hip - 0.5 knee + 0.4 ankle within [-0.3, 0.2], the hip following the
  // other two (multipliers 1 and -0.8, range [-0.6, 0.4]); free, the combination runs past.
  const std::string three =
      R"(<fixed limited="true" range="-0.3 0.2"><joint joint="hip" coef="0.5"/><joint joint="knee" coef="-0.5"/>)"
      R"(<joint joint="ankle" coef="0.4"/></fixed>)";
  const Scene s3 = swing("f3", three, lo, hi, {0.5, -0.5, 0.4});
  ASSERT_TRUE(s3.joints[0].mimic && s3.joints[0].mimic->range);
  ASSERT_EQ(s3.joints[0].mimic->also.size(), 1u);
  EXPECT_NEAR(s3.joints[0].mimic->also[0].second, -0.8, 1e-15);
  swing("f3free", "", flo, fhi, {0.5, -0.5, 0.4});
  EXPECT_TRUE(flo < -0.3 - 1e-3 || fhi > 0.2 + 1e-3) << flo << " " << fhi;
  EXPECT_GE(lo, -0.3 - 1e-9);
  EXPECT_LE(hi, 0.2 + 1e-9);
  EXPECT_TRUE(lo < -0.3 + 1e-9 || hi > 0.2 - 1e-9) << lo << " " << hi;
  const std::string twice =
      R"(<fixed limited="true" range="-1 1"><joint joint="hip" coef="1"/><joint joint="hip" coef="1"/></fixed>)";
  double a, b;
  EXPECT_TRUE(has(swing("f2", twice, a, b).notes, "over two or more distinct joints"));
}

// MJCF's built-in textures that set a scene's look: a checker on the floor plane becomes the
// ground's two colours and its square (the 2x2 image repeated texrepeat times a metre with
// texuniform, else across the plane's width), a gradient skybox the sky (its top colour straight
// up, half way to its bottom colour at the horizon). Colours are the file's display values, the
// scene's linear ones. A scene that sets its own sky or ground look keeps it.
TEST(ImportMjcf, BuiltInCheckerFloorAndGradientSkyAreTheScenesLook) {
  auto xml = [](const std::string& material) {
    return R"(<mujoco>
  <asset>
    <texture type="skybox" builtin="gradient" rgb1=".3 .5 .7" rgb2="0 0 0" width="32" height="512"/>
    <texture name="grid" type="2d" builtin="checker" width="512" height="512" rgb1=".1 .2 .3" rgb2=".2 .3 .4" mark="edge"/>
    <material name="grid" texture="grid" )" +
           material + R"(/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="4 4 .1" material="grid"/>
    <body name="ball" pos="0 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
  </worldbody>
</mujoco>
)";
  };
  auto lin = [](float c) { return srgb_to_linear(c); };
  const std::string per_metre = write("look/per_metre.xml", xml(R"(texrepeat="2 2" texuniform="true")"));
  const Scene s = load_scene(write("look/per_metre.yaml", scene_for_model_file(per_metre)));
  EXPECT_FLOAT_EQ(s.render.ground_color[1], lin(0.2f));
  EXPECT_FLOAT_EQ(s.render.ground_color2[2], lin(0.4f));
  EXPECT_DOUBLE_EQ(s.render.ground_tile, 0.25);  // 2 images of 2 squares a metre
  EXPECT_FLOAT_EQ(s.render.background[0], lin(0.3f));
  EXPECT_FLOAT_EQ(s.render.horizon[2], lin(0.35f));
  EXPECT_TRUE(s.render.sky_gradient);
  EXPECT_TRUE(has(s.notes, "mark lines are not drawn"));
  // Across the plane: 8 m wide, 4 images of 2 squares.
  const std::string across = write("look/across.xml", xml(R"(texrepeat="4 4")"));
  EXPECT_DOUBLE_EQ(load_scene(write("look/across.yaml", scene_for_model_file(across))).render.ground_tile,
                   1.0);
  // The scene's own sky and ground colours win.
  const Scene own =
      load_scene(write("look/own.yaml",
                       "ground: { colors: [[0.5, 0.5, 0.5], [0.2, 0.2, 0.2]] }\nrender: { sky: flat }\n"
                       "imports: [ { file: " +
                           per_metre + " } ]\n"));
  EXPECT_FLOAT_EQ(own.render.ground_color[0], 0.5f);
  EXPECT_DOUBLE_EQ(own.render.ground_tile, RenderLook{}.ground_tile);
  EXPECT_FALSE(own.render.sky_gradient);
  EXPECT_FLOAT_EQ(own.render.background[0], RenderLook{}.background[0]);
}

// <option gravity> is the model's: a file simulated directly falls by it; a scene that gives
// its own gravity keeps it, with a note. The option's steps and integrator are notes.
TEST(ImportMjcf, OptionGravityActsUnlessTheSceneGivesItsOwn) {
  const std::string xml = write("gravity/moon.xml", R"(<mujoco>
  <option gravity="0 0 -1.62" timestep="0.002"/>
  <worldbody><body name="ball" pos="0 0 3"><freejoint/><geom type="sphere" size="0.1"/></body></worldbody>
</mujoco>
)");
  const Scene direct = load_scene(write("gravity/direct.yaml", scene_for_model_file(xml)));
  EXPECT_EQ(direct.gravity, Vec3(0, 0, -1.62));
  EXPECT_TRUE(has(direct.notes, "<option timestep> is not used"));
  // Released from rest in free fall (no ground under it for 1 s): z drops by g t^2 / 2.
  const Scene fall =
      load_scene(write("gravity/fall.yaml",
                       "simulation: { duration: 1, sleep: false }\nimports: [ { file: " + xml + " } ]\n"));
  World w(world_config(fall, 1), fall.bodies);
  const double z0 = w.centroid(0).z();
  const int n = (int)std::lround(1.0 / fall.timestep);
  for (int i = 0; i < n; ++i) w.step();
  EXPECT_NEAR(z0 - w.centroid(0).z(), 0.5 * 1.62 * 1.0, 1e-9);
  const Scene own = load_scene(write(
      "gravity/own.yaml", "simulation: { gravity: [0, 0, -9.81] }\nimports: [ { file: " + xml + " } ]\n"));
  EXPECT_EQ(own.gravity, Vec3(0, 0, -9.81));
  EXPECT_TRUE(has(own.notes, "is not the scene's"));
}

// A named pose of the file (imports: keyframe): the key's qpos in MuJoCo's order (a free body's
// position and quaternion, then each joint as the file writes it) places the free body and starts
// each hinge and slide at the key's value less its ref (the range, in qpos too, shifts by ref);
// key numbers are radians whatever the compiler's angle. joint_positions given beside it win; a key the file
// lacks or one of the wrong length is an error naming the import.
TEST(ImportMjcf, KeyframePlacesFreeBodiesAndStartsJoints) {
  const std::string xml = write("key/arm.xml", R"(<mujoco>
  <compiler angle="degree"/>
  <worldbody>
    <body name="base" pos="0 0 1"><freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <body name="arm" pos="0.3 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0" ref="10" range="-30 90"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="tip" pos="0.3 0 0">
          <joint name="ext" type="slide" axis="1 0 0"/>
          <geom type="sphere" size="0.04"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="bent" qpos="0.1 0.2 1.5  0.9 0 0.3 0  0.6  0.05" qvel="0 0 0 0 0 0 0 0"/>
    <key name="short" qpos="0 0 1"/>
  </keyframe>
</mujoco>
)");
  auto load = [&](const std::string& name, const std::string& extra) {
    return load_scene(write("key/" + name + ".yaml", "imports: [ { file: " + xml + extra + " } ]\n"));
  };
  const Scene s = load("bent", ", keyframe: bent");
  const BodyDef &base = s.bodies[body(s, "base")], &arm = s.bodies[body(s, "arm")],
                &tip = s.bodies[body(s, "tip")];
  EXPECT_LT((base.p_WB - Vec3(0.1, 0.2, 1.5)).norm(), 1e-15);
  const Quat qb = Quat(0.9, 0, 0.3, 0).normalized();
  EXPECT_LT(base.q_WB.angularDistance(qb), 1e-15);
  // The elbow turned by 0.6 rad less its ref of 10 degrees about y (the file's pose is at ref).
  const double turn = 0.6 - 10 * std::numbers::pi / 180;
  EXPECT_LT((base.q_WB.conjugate() * arm.q_WB).angularDistance(Quat(Eigen::AngleAxisd(turn, Vec3::UnitY()))),
            1e-12);
  // The tip slid 0.05 m out along the arm.
  EXPECT_NEAR((arm.q_WB.conjugate() * (tip.p_WB - arm.p_WB)).x(), 0.35, 1e-12);
  EXPECT_TRUE(has(s.notes, "a key's qvel is not used"));
  // The range is in qpos too: from the file's pose (at ref) the elbow turns -40 to 80 degrees.
  const Scene plain = load("plain", "");
  for (const JointDef& j : plain.joints)
    if (j.name == "elbow") {
      ASSERT_TRUE(j.limits);
      EXPECT_NEAR(j.limits->lower, -40 * std::numbers::pi / 180, 1e-12);
      EXPECT_NEAR(j.limits->upper, 80 * std::numbers::pi / 180, 1e-12);
    }
  // joint_positions beside the key win.
  const Scene w = load("wins", ", keyframe: bent, joint_positions: { ext: 0.1 }");
  const BodyDef &arm2 = w.bodies[body(w, "arm")], &tip2 = w.bodies[body(w, "tip")];
  EXPECT_NEAR((arm2.q_WB.conjugate() * (tip2.p_WB - arm2.p_WB)).x(), 0.4, 1e-12);
  EXPECT_NE(error_of(write("key/missing.yaml", "imports: [ { file: " + xml + ", keyframe: bnet } ]\n"))
                .find("has no key named 'bnet'; did you mean 'bent'?"),
            std::string::npos);
  EXPECT_NE(error_of(write("key/short.yaml", "imports: [ { file: " + xml + ", keyframe: short } ]\n"))
                .find("key 'short' has 3 qpos numbers; the file's joints take 9"),
            std::string::npos);
}

// A ball joint in a key: its child turned by the key's quaternion about the joint's anchor, in the
// child's own axes (MuJoCo's xquat = parent's * body quat * qpos), so the anchor stays where the
// file puts it; the range is then measured from there (a note); a zero quaternion is an error.
TEST(ImportMjcf, KeyframeTurnsBallJoints) {
  const std::string xml = write("key/ball.xml", R"(<mujoco>
  <worldbody>
    <body name="post" pos="0 0 1" euler="0 0 90">
      <geom type="box" size="0.05 0.05 0.05"/>
      <body name="bob" pos="0 0 -0.5">
        <joint name="neck" type="ball" pos="0 0 0.5" range="0 60" limited="true"/>
        <geom type="sphere" size="0.1"/>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="tilt" qpos="0.8660254037844387 0.5 0 0"/>
    <key name="zero" qpos="0 0 0 0"/>
  </keyframe>
</mujoco>
)");
  const Scene s = load_scene(
      write("key/ball.yaml", "imports: [ { file: " + xml + ", keyframe: tilt, fixed_base: true } ]\n"));
  const Scene plain =
      load_scene(write("key/ball_plain.yaml", "imports: [ { file: " + xml + ", fixed_base: true } ]\n"));
  const BodyDef &bob = s.bodies[body(s, "bob")], &bob0 = plain.bodies[body(plain, "bob")];
  // 60 degrees about the bob's own x axis (world y, the post turned 90 degrees about z).
  const Quat key(Eigen::AngleAxisd(std::numbers::pi / 3, Vec3::UnitX()));
  EXPECT_LT(bob.q_WB.angularDistance(bob0.q_WB * key), 1e-12);
  // The anchor, 0.5 m above the bob's origin in its frame, is where the file puts it: (0, 0, 1).
  EXPECT_LT((bob.p_WB + bob.q_WB * Vec3(0, 0, 0.5) - Vec3(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((bob0.p_WB - Vec3(0, 0, 0.5)).norm(), 1e-12);
  EXPECT_TRUE(has(s.notes, "ball joint 'neck' starts turned by the key; its range is measured from there"));
  EXPECT_NE(error_of(write("key/ball_zero.yaml", "imports: [ { file: " + xml + ", keyframe: zero } ]\n"))
                .find("ball joint 'neck' has a zero quaternion"),
            std::string::npos);
}

// A file's camera named by the import becomes the scene's: it looks along its -z with +y up at
// its fovy. In the world it stays put; fixed on a moving body it rides in the body's frame; a
// tracking one follows its body; a targeting one turns to its target. Unnamed, the file's
// cameras are listed in a note; a name the file lacks, or a scene camera beside it, is an error.
TEST(ImportMjcf, FileCamerasBecomeTheScenesCamera) {
  const std::string xml = write("cam/cams.xml", R"(<mujoco>
  <worldbody>
    <camera name="side" pos="0 -3 1" xyaxes="1 0 0 0 0 1" fovy="30"/>
    <camera name="aim" pos="2 0 1" mode="targetbody" target="ball"/>
    <body name="ball" pos="0 0 1" euler="0 0 90"><freejoint/>
      <geom type="sphere" size="0.1"/>
      <camera name="eye" pos="0.5 0 0" zaxis="1 0 0"/>
      <camera name="chase" pos="0 -2 0" mode="trackcom" xyaxes="1 0 0 0 0 1"/>
    </body>
  </worldbody>
</mujoco>
)");
  auto scene = [&](const std::string& name, const std::string& cam) {
    return load_scene(
        write("cam/" + name + ".yaml", "imports: [ { file: " + xml + ", camera: " + cam + " } ]\n"));
  };
  const Scene side = scene("side", "side");
  // xyaxes x = (1 0 0), y = (0 0 1): -z looks along +y (toward the origin), up is +z.
  EXPECT_LT((side.camera.position - Vec3(0, -3, 1)).norm(), 1e-12);
  EXPECT_LT(((side.camera.look_at - side.camera.position).normalized() - Vec3(0, 1, 0)).norm(), 1e-12);
  EXPECT_LT((side.camera.up - Vec3(0, 0, 1)).norm(), 1e-12);
  EXPECT_EQ(side.camera.fov, 30);
  EXPECT_TRUE(side.camera.frame_body.empty());
  EXPECT_TRUE(side.camera.follow.empty());
  // On the ball (turned 90 deg about z): in the ball's frame, 0.5 m along its x, its z axis along
  // +x, so it looks back along -x at the ball.
  const Scene eye = scene("eye", "eye");
  EXPECT_EQ(eye.camera.frame_body, "ball");
  EXPECT_EQ(eye.camera.fov, 45);  // MuJoCo's default
  EXPECT_LT((eye.camera.position - Vec3(0.5, 0, 0)).norm(), 1e-12);
  EXPECT_LT(((eye.camera.look_at - eye.camera.position) - Vec3(-1, 0, 0)).norm(), 1e-12);
  const Scene chase = scene("chase", "chase");
  EXPECT_EQ(chase.camera.follow, "ball");
  EXPECT_LT((chase.camera.position - Vec3(2, 0, 1)).norm(), 1e-12);  // (0, -2, 0) turned 90 deg about z
  EXPECT_TRUE(has(chase.notes, "trackcom follows the body aimed at it"));
  const Scene aim = scene("aim", "aim");
  EXPECT_LT((aim.camera.look_at - Vec3(0, 0, 1)).norm(), 1e-12);
  EXPECT_EQ(aim.camera.aim, std::vector<std::string>{"ball"});  // turned to it at every frame
  EXPECT_TRUE(aim.camera.frame_body.empty());                   // from the world, where it stands
  EXPECT_LT((aim.camera.position - Vec3(2, 0, 1)).norm(), 1e-12);
  EXPECT_TRUE(has(aim.notes, "turns to 'ball''s centre of mass (camera.aim"));
  // Unnamed: listed.
  const Scene plain = load_scene(write("cam/plain.yaml", "imports: [ { file: " + xml + " } ]\n"));
  EXPECT_TRUE(has(plain.notes, "its cameras 'side', 'aim', 'eye', 'chase'"));
  EXPECT_NE(error_of(write("cam/typo.yaml", "imports: [ { file: " + xml + ", camera: sied } ]\n"))
                .find("has no camera named 'sied'; did you mean 'side'?"),
            std::string::npos);
  EXPECT_NE(error_of(write("cam/both.yaml", "camera: { position: [1, 2, 3] }\nimports: [ { file: " + xml +
                                                ", camera: side } ]\n"))
                .find("imports[0].camera: the scene gives its own camera"),
            std::string::npos);
}

// An MJCF heightfield becomes a closed solid on its static body. Its grid is MuJoCo's: inline
// `elevation` row 0 at -y; a PNG's top row at +y, grey levels normalised to [0, 1] (MuJoCo 2.2.2
// measured by mj_ray on this 3 x 2 image: 0.6 at (-1, -2), 1.0 at (1, -2), 0 at (-1, 2)). A V
// valley (|x| under 45 degree slopes) holds 4 m^3 above its 0.8 m^3 base, and a ball dropped into
// it settles on both slopes, its centre r sqrt(2) above the valley's floor line.
TEST(ImportMjcf, HeightfieldIsTheSolidABallRestsIn) {
  const std::string xml = write("hf/valley.xml", R"(<mujoco>
  <asset><hfield name="v" nrow="2" ncol="3" elevation="7 5 7  7 5 7" size="1 2 1 0.1"/></asset>
  <worldbody>
    <geom type="hfield" hfield="v"/>
    <body name="ball" pos="0.3 0 1"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body>
  </worldbody>
</mujoco>
)");
  const Scene s = load_scene(write("hf/valley.yaml", "imports: [ { file: " + xml + " } ]\n"));
  const Collider* hf = nullptr;
  for (const BodyDef& b : s.bodies)
    for (const Collider& c : b.colliders)
      if (c.mesh && b.type == BodyType::static_body) hf = &c;
  ASSERT_NE(hf, nullptr);
  MeshMassOptions opt;
  const MeshReport rep = analyze_mesh(*hf->mesh, opt);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.consistently_oriented);
  EXPECT_NEAR(rep.volume, 4.8, 1e-12);  // normalised: |x| from 0 to 1
  World w(world_config(s, 1), s.bodies);
  const int ball = body(s, "ball");
  while (w.time() < 6) w.step();
  const Vec3 x = w.centroid(ball);
  std::printf("ball at rest: x %.2e, z %.6f (r sqrt 2 = %.6f)\n", x.x(), x.z(), 0.1 * std::sqrt(2.0));
  EXPECT_NEAR(x.x(), 0, 1e-3);
  EXPECT_NEAR(x.z(), 0.1 * std::sqrt(2.0), 1e-3);

  // The PNG: written here (grey, 8 bits), its top row 0 51 102, its bottom 153 204 255.
  const std::string png = (fs::path(xml).parent_path() / "steps.png").string();
  const uint8_t px[6] = {0, 51, 102, 153, 204, 255};
  png_image im{};
  im.version = PNG_IMAGE_VERSION;
  im.width = 3;
  im.height = 2;
  im.format = PNG_FORMAT_GRAY;
  ASSERT_TRUE(png_image_write_to_file(&im, png.c_str(), 0, px, 0, nullptr));
  const std::string xml2 = write("hf/steps.xml", R"(<mujoco>
  <asset><hfield name="s" file="steps.png" size="1 2 1 0.1"/></asset>
  <worldbody><geom type="hfield" hfield="s"/></worldbody>
</mujoco>
)");
  auto mesh_of = [](const Scene& sc) {  // the terrain's collider
    const Collider* out = nullptr;
    for (const BodyDef& b : sc.bodies)
      for (const Collider& c : b.colliders)
        if (c.mesh) out = &c;
    return out;
  };
  const Scene s2 = load_scene(write("hf/steps.yaml", "imports: [ { file: " + xml2 + " } ]\n"));
  const Collider* c2 = mesh_of(s2);
  ASSERT_NE(c2, nullptr);
  auto height_at = [&](double xx, double yy) {
    for (const Vec3& v : c2->mesh->vertices)
      if (std::abs(v.x() - xx) < 1e-12 && std::abs(v.y() - yy) < 1e-12 && v.z() > -0.05) return v.z();
    return -1.0;
  };
  EXPECT_NEAR(height_at(-1, -2), 0.6, 1e-12);
  EXPECT_NEAR(height_at(1, -2), 1.0, 1e-12);
  EXPECT_NEAR(height_at(-1, 2), 0.0, 1e-12);
  EXPECT_NEAR(height_at(0, 2), 0.2, 1e-12);

  // MuJoCo's binary file (any other extension): int32 nrow, ncol, then float32 rows from -y.
  // MuJoCo 2.2.2's mj_ray on this file (3 rows of 2: 2 3 / 6 4 / 12 5, size 1 2 1 0.1) found
  // z = 0, 0.1 at y = -2; 0.4, 0.2 at y = 0; 1, 0.3 at y = 2 (normalised from [2, 12]).
  const auto binary = [&](const std::string& name, int nrow, int ncol, std::vector<float> z) {
    std::ofstream f((fs::path(xml).parent_path() / name).string(), std::ios::binary);
    const int32_t head[2] = {nrow, ncol};
    f.write(reinterpret_cast<const char*>(head), sizeof head);
    f.write(reinterpret_cast<const char*>(z.data()), (std::streamsize)(4 * z.size()));
  };
  binary("terrain.bin", 3, 2, {2, 3, 6, 4, 12, 5});
  const std::string xml3 = write("hf/bin.xml", R"(<mujoco>
  <asset><hfield name="t" file="terrain.bin" size="1 2 1 0.1"/></asset>
  <worldbody><geom type="hfield" hfield="t"/></worldbody>
</mujoco>
)");
  const Scene s3 = load_scene(write("hf/bin.yaml", "imports: [ { file: " + xml3 + " } ]\n"));
  c2 = mesh_of(s3);
  ASSERT_NE(c2, nullptr);
  const double mujoco[3][2] = {{0, 0.1}, {0.4, 0.2}, {1, 0.3}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 2; ++c) EXPECT_NEAR(height_at(c ? 1 : -1, -2 + 2 * r), mujoco[r][c], 1e-7) << r << c;
  binary("short.bin", 3, 2, {2, 3, 6, 4, 12});  // a value short
  EXPECT_NE(error_of(write("hf/short.xml", R"(<mujoco>
  <asset><hfield name="t" file="short.bin" size="1 2 1 0.1"/></asset>
</mujoco>
)"))
                .find("short.xml:2: hfield 't': " + (fs::path(xml).parent_path() / "short.bin").string() +
                      ": 3 x 2 float32 elevations need 32 bytes; the file has 28"),
            std::string::npos);

  // A heightfield on a moving body is an error naming file and line.
  EXPECT_NE(error_of(write("hf/moving.xml", R"(<mujoco>
  <asset><hfield name="v" nrow="2" ncol="2" elevation="0 1 0 1" size="1 1 1 0.1"/></asset>
  <worldbody><body name="b"><freejoint/><geom type="hfield" hfield="v"/></body></worldbody>
</mujoco>
)"))
                .find("moving.xml:3: geom of body 'b': an hfield geom must be on a static body"),
            std::string::npos);
}

// An undefined class, a joint type MuJoCo does not have, a connect to a missing body.
TEST(ImportMjcf, MistakesAreNamedByFileAndLine) {
  auto err = [&](const std::string& xml) { return error_of(write("m.xml", xml)); };
  EXPECT_NE(err("<mujoco>\n<default><default class=\"bar\"/></default>\n<worldbody>\n"
                "<body><freejoint/><geom size=\"0.1\" class=\"baz\"/></body>\n</worldbody></mujoco>\n")
                .find("m.xml:4: body 'body0', geom: class 'baz' is not defined; did you mean 'bar'?"),
            std::string::npos);
  EXPECT_NE(err("<mujoco><worldbody>\n<body name=\"b\"><joint type=\"twist\"/><geom size=\"0.1\"/></body>\n"
                "</worldbody></mujoco>\n")
                .find("m.xml:2: joint 'b/joint': unknown joint type 'twist' (hinge, slide, ball, free)"),
            std::string::npos);
  EXPECT_NE(err("<mujoco><worldbody><body name=\"b\"><joint/><geom size=\"0.1\"/></body></worldbody>\n"
                "<equality><connect body1=\"bb\" body2=\"b\" anchor=\"0 0 0\"/></equality></mujoco>\n")
                .find("m.xml:2: equality connect 'connect1': body1 names body 'bb', which the file does "
                      "not define; "
                      "did you mean 'b'?"),
            std::string::npos);
  EXPECT_NE(err("<robot/>\n").find("expected a <mujoco> element"), std::string::npos);
}

// Downloaded meshes as users meet them: every mesh that cannot be weighed is reported in one run,
// each with its fix; a millimetre file and a y-up file get a note with the key that fixes them.
TEST(DownloadedAssets, EveryMeshProblemAtOnceAndAuthoringHints) {
  const std::string open = fs::absolute("assets/open_box.obj").string();
  const std::string e = error_of(write("open.yaml",
                                       "bodies:\n"
                                       "  - { name: a, colliders: [ { shape: mesh, file: " +
                                           open +
                                           " } ] }\n"
                                           "  - { name: b, colliders: [ { shape: box, size: [1, 1, 1] } ] }\n"
                                           "  - { name: c, colliders: [ { shape: mesh, file: " +
                                           open + " } ] }\n"));
  EXPECT_NE(e.find("2 meshes cannot be weighed as they are:"), std::string::npos) << e;
  EXPECT_NE(e.find("open.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("open.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("(on this collider: `mode: shell`, or `mode: hull`)"), std::string::npos) << e;
  const Scene s = load_scene(write("hints.yaml",
                                   "bodies:\n"
                                   "  - { name: a, colliders: [ { shape: mesh, file: " +
                                       fs::absolute(kData + "y_up_pyramid.obj").string() +
                                       " } ] }\n"
                                       "  - { name: b, colliders: [ { shape: mesh, file: " +
                                       fs::absolute(kData + "block_mm.obj").string() + " } ] }\n"));
  EXPECT_TRUE(has(s.notes, "probably authored y-up and will lie on its side; `up_axis: y` stands it up"));
  EXPECT_TRUE(
      has(s.notes,
          "block_mm.obj is 200 m across: if the file is in millimetres, give the collider `scale: 0.001`"));
  // Given the fixes, no hints.
  const Scene fixed = load_scene(write("fixed.yaml",
                                       "bodies:\n"
                                       "  - { name: a, colliders: [ { shape: mesh, up_axis: y, file: " +
                                           fs::absolute(kData + "y_up_pyramid.obj").string() +
                                           " } ] }\n"
                                           "  - { name: b, colliders: [ { shape: mesh, scale: 0.001, file: " +
                                           fs::absolute(kData + "block_mm.obj").string() + " } ] }\n"));
  EXPECT_FALSE(has(fixed.notes, "authored y-up"));
  EXPECT_FALSE(has(fixed.notes, "millimetres"));
  // center: com puts the pyramid's centre of mass (a quarter of its height up) at the position.
  const Scene centred =
      load_scene(write("c.yaml",
                       "bodies:\n  - { name: a, position: [1, 2, 3], colliders: [ { shape: mesh, "
                       "center: com, file: " +
                           fs::absolute(kData + "y_up_pyramid.obj").string() + " } ] }\n"));
  World w(world_config(centred, 1), centred.bodies);
  EXPECT_NEAR((w.centroid(0) - Vec3(1, 2, 3)).norm(), 0, 1e-15);
  EXPECT_NEAR(centred.bodies[0].colliders[0].p_BC.y(), -0.25, 1e-15);
}

// `mode: decompose`: a concave mesh collides as itself. A ball dropped over the inside corner of
// the L-bracket falls past it to the ground (its convex hull, 64% larger, would hold it 0.1 m up),
// and a second load reads the decomposition from the cache, moving the same to the bit.
TEST(DownloadedAssets, ConcaveMeshCollidesAsItselfWhenDecomposed) {
  const std::string cache = test::scratch("cache");
  setenv("SIMREEL_CACHE_DIR", cache.c_str(), 1);
  auto scene = [&](const char* mode) {
    return load_scene(write(std::string(mode) + ".yaml",
                            "simulation: { duration: 2 }\nground: true\nbodies:\n"
                            "  - { name: bracket, colliders: [ { shape: mesh, mode: " +
                                std::string(mode) +
                                ", file: " + fs::absolute("assets/l_bracket.stl").string() +
                                " } ] }\n"
                                "  - { name: ball, position: [0.2, 0.2, 0.3], colliders: [ { shape: sphere, "
                                "radius: 0.04 } ] }\n"));
  };
  auto rest_height = [](const Scene& s) {
    World w(world_config(s, 1), s.bodies);
    for (int i = 0; i < 2 * 240; ++i) w.step();
    return w.centroid(1);
  };
  const Scene d = scene("decompose");
  EXPECT_TRUE(has(d.notes, "decomposed into 2 convex parts"));
  EXPECT_EQ(d.bodies[0].colliders[0].hulls.size(), 2u);
  EXPECT_TRUE(fs::exists(fs::path(cache) / "decompose"));
  const Vec3 down = rest_height(d);
  EXPECT_NEAR(down.z(), 0.04, 5e-4);  // on the ground, between the legs (contacts settle within 0.3 mm)
  EXPECT_NEAR(rest_height(scene("solid")).z(), 0.14, 5e-4);  // on the hull's top
  const Vec3 cached = rest_height(scene("decompose"));
  EXPECT_EQ(cached, down);
  unsetenv("SIMREEL_CACHE_DIR");
}

// An import's `collision: decompose`: a moving link's concave collision mesh collides as its parts.
TEST(DownloadedAssets, ImportedConcaveMeshesDecompose) {
  setenv("SIMREEL_CACHE_DIR", test::scratch("cache").c_str(), 1);
  const std::string urdf = fs::absolute(kData + "bracket.urdf").string();
  const Scene hull = load_scene(write("h.yaml", "imports: [ { file: " + urdf + ", inertia: file } ]\n"));
  const Scene parts = load_scene(
      write("d.yaml", "imports: [ { file: " + urdf + ", inertia: file, collision: decompose } ]\n"));
  ASSERT_EQ(parts.bodies.size(), 1u);
  EXPECT_EQ(hull.bodies[0].colliders[1].hulls.size(), 0u);  // built by the World: the convex hull
  EXPECT_EQ(parts.bodies[0].colliders[1].hulls.size(), 2u);
  EXPECT_TRUE(
      has(parts.notes, "bracket.urdf:8: link 'bracket', collision 0: decomposed into 2 convex parts"));
  unsetenv("SIMREEL_CACHE_DIR");
}

// The corpus: real files nobody here wrote (../shared/corpus; skipped when absent).
const fs::path kCorpus = "../shared/corpus/bullet3/data";

TEST(ImportCorpus, BulletUrdfsLoadWithTheirLinksJointsAndMasses) {
  if (!fs::exists(kCorpus)) GTEST_SKIP() << "no " << kCorpus << " (the shared corpus)";
  struct Case {
    const char* file;
    size_t bodies;  // after fixed links join their parents, with the ground
    size_t joints;
    double mass;  // kg, every moving body
  };
  // Masses: every <mass> of the file on moving bodies (the kuka's and hinge's massless bases are
  // fixed, as Bullet reads them; cartpole's slide bar likewise).
  for (const Case& c : {Case{"cube.urdf", 2, 0, 1.0}, Case{"r2d2.urdf", 10, 8, 65.25},
                        Case{"cartpole.urdf", 4, 2, 11.0}, Case{"hinge.urdf", 4, 2, 2.0},
                        Case{"racecar/racecar.urdf", 8, 6, 5.89223}, Case{"kuka_iiwa/model.urdf", 9, 7, 17.5},
                        Case{"sphere2.urdf", 2, 0, 10.0}, Case{"plane.urdf", 2, 0, 0}}) {
    SCOPED_TRACE(c.file);
    const Scene s = load_scene((kCorpus / c.file).string());
    EXPECT_EQ(s.bodies.size(), c.bodies);
    EXPECT_EQ(s.joints.size(), c.joints);
    double mass = 0;
    for (const BodyDef& b : s.bodies)
      if (b.type == BodyType::dynamic) mass += b.mass_override->mass;
    EXPECT_NEAR(mass, c.mass, 1e-12 * c.mass);
    World w(world_config(s, 1), s.bodies);  // every one builds
  }
  // r2d2's file defines its colours inside visuals and names them in others: all are found.
  const Scene r2 = load_scene((kCorpus / "r2d2.urdf").string());
  EXPECT_FALSE(has(r2.notes, "is not defined"));
  // cube.urdf states I = 1, 1, 1 for a 1 kg cube of 1 m (0.167 from its geometry).
  const Scene cube = load_scene((kCorpus / "cube.urdf").string());
  EXPECT_TRUE(has(cube.warnings, "(1, 1, 1) kg m^2 stated, (0.167, 0.167, 0.167) from the geometry"));
  // concave_box.urdf names a Bullet .cdf file: that shape is left out with a note, the rest loads.
  const Scene box = load_scene((kCorpus / "toys/concave_box.urdf").string());
  EXPECT_TRUE(has(box.notes, "unknown geometry <cdf>"));
}

// Bullet's cartpole.urdf turned upside down (the pole hanging from the cart on its rail) and let go
// 0.001 rad from hanging: its small swings keep omega^2 = m g l (M + m) / ((M + m)(I + m l^2) -
// (m l)^2) with the file's M = 1 kg, m = 10 kg, l = 0.5 m and I = 1 kg m^2 (its stated, placeholder
// inertia; the check warns about it and uses it): a period of 0.99387 s. The swing's own
// nonlinearity lengthens it by about 5e-7 s at this amplitude (2.1e-6 s at 0.002 rad: fourfold,
// as amplitude squared), inside the 2e-6 s asked.
TEST(ImportCorpus, CartpoleSwingsAtItsClosedFormFrequency) {
  if (!fs::exists(kCorpus)) GTEST_SKIP() << "no " << kCorpus << " (the shared corpus)";
  const Scene s = load_scene(
      write("cp.yaml", "simulation: { duration: 6, timestep: 0.001 }\nimports: [ { file: " +
                           fs::absolute(kCorpus / "cartpole.urdf").string() +
                           ", euler: [180, 0, 0], joint_positions: { cart_to_pole: 0.001 } } ]\n"));
  ASSERT_EQ(s.joints.size(), 2u);
  World w(world_config(s, 1), s.bodies);
  double prev = w.joint_position(1) + 0.001, t_prev = 0;
  std::vector<double> crossings;
  while (w.time() < 6) {
    w.step();
    const double q = w.joint_position(1) + 0.001;
    if ((prev > 0) != (q > 0)) crossings.push_back(t_prev + (w.time() - t_prev) * prev / (prev - q));
    prev = q;
    t_prev = w.time();
  }
  ASSERT_GE(crossings.size(), 11u);
  const double M = 1, m = 10, l = 0.5, I = 1, g = 9.81;
  const double omega = std::sqrt(m * g * l * (M + m) / ((M + m) * (I + m * l * l) - m * l * m * l));
  EXPECT_NEAR((crossings[10] - crossings[0]) / 5, 2 * M_PI / omega, 2e-6);
}

// r2d2 and the racecar, dropped on the ground, settle on their wheels.
TEST(ImportCorpus, R2d2AndRacecarRestOnTheirWheels) {
  if (!fs::exists(kCorpus)) GTEST_SKIP() << "no " << kCorpus << " (the shared corpus)";
  for (const char* f : {"r2d2.urdf", "racecar/racecar.urdf"}) {
    SCOPED_TRACE(f);
    Scene s = load_scene((kCorpus / f).string());
    for (BodyDef& b : s.bodies) b.p_WB.z() += 0.05;  // dropped from 5 cm
    World w(world_config(s, 1), s.bodies);
    const int ground = (int)s.bodies.size() - 1;
    for (int i = 0; i < 3 * 240; ++i) w.step();
    double speed = 0;
    for (int i = 0; i < w.body_count(); ++i) speed = std::max(speed, w.linear_velocity(i).norm());
    EXPECT_LT(speed, 1e-3);
    // Only wheels touch the ground.
    bool touching = false;
    std::vector<ContactData> contacts;
    w.contacts(contacts);
    for (const ContactData& c : contacts) {
      const int other = c.body_a == ground ? c.body_b : c.body_b == ground ? c.body_a : -1;
      if (other < 0) continue;
      EXPECT_NE(w.def(other).name.find("wheel"), std::string::npos) << w.def(other).name;
      touching = true;
    }
    EXPECT_TRUE(touching);
  }
}

const fs::path kMujoco = "../shared/corpus/mujoco";

// MuJoCo's own models: each loads; the humanoid (capsules, classes, bodies with two and three
// hinges) falls as a ragdoll with its joints closed to 1e-6 m, and never gains energy to speak of:
// its joints are damped, its stops plastic, its contacts inelastic (the largest gain in a frame
// measured 0.015 J; 0.1 J allowed). A contact solved with a stale inverse inertia, one that did
// not hold a coordinate its stop had just caught, pushed that coordinate through the stop and
// gained 51 J in one frame.
TEST(ImportCorpus, MujocoModelsLoadAndTheHumanoidFallsAsARagdoll) {
  if (!fs::exists(kMujoco)) GTEST_SKIP() << "no " << kMujoco << " (the shared corpus)";
  for (const char* f : {"model/humanoid/humanoid.xml", "model/slider_crank/slider_crank.xml",
                        "model/mug/mug.xml", "python/mujoco/testdata/model.xml", "model/sleep/dominos.xml",
                        "model/replicate/newton_cradle.xml", "model/replicate/stonehenge.xml"}) {
    SCOPED_TRACE(f);
    const Scene s = load_scene((kMujoco / f).string());
    World w(world_config(s, 1), s.bodies);
  }
  const Scene s = load_scene((kMujoco / "model/humanoid/humanoid.xml").string());
  EXPECT_EQ(s.joints.size(), 21u);  // 22 in the file, the free joint being no joint here
  int helpers = 0;
  for (const BodyDef& b : s.bodies) helpers += b.name.find('#') != std::string::npos;
  EXPECT_EQ(helpers, 9);  // abdomen 1, hips 2 + 2, ankles 1 + 1, shoulders 1 + 1
  // 16 bodies less the head and hands (no joints: welded to their parents), the world's and the ground.
  EXPECT_EQ((int)s.bodies.size() - helpers, 13 + 2);
  World w(world_config(s, 1), s.bodies);
  Drift drift(w);
  const double z0 = w.centroid(body(s, "torso")).z();
  const double E0 = w.kinetic_energy() + w.potential_energy();
  double E = E0, gain = 0;
  for (int i = 0; i < 3 * 240; ++i) {
    w.step();
    if (i % 8 == 0) drift.sample(w);
    const double e = w.kinetic_energy() + w.potential_energy();
    gain = std::max(gain, e - E);
    E = e;
  }
  EXPECT_LT(gain, 0.1);
  EXPECT_LT(E, E0);
  EXPECT_LT(drift.joint_gap(), 1e-6);
  EXPECT_LT(w.centroid(body(s, "torso")).z(), z0 - 0.5);  // it fell
  // Its "squat" key: the torso turned as the key says, the right knee bent by -2.65 rad about its
  // axis, the file's -y (the shin's turn from the thigh: +2.65 rad about y).
  const std::string yaml = write(
      "humanoid_squat.yaml",
      "ground: true\nimports: [ { file: " + (fs::absolute(kMujoco) / "model/humanoid/humanoid.xml").string() +
          ", keyframe: squat, on_ground: true } ]\n");
  const Scene sq = load_scene(yaml);
  const BodyDef &torso = sq.bodies[body(sq, "torso")], &thigh = sq.bodies[body(sq, "thigh_right")],
                &shin = sq.bodies[body(sq, "shin_right")];
  EXPECT_LT(torso.q_WB.angularDistance(Quat(0.988015, 0, 0.154359, 0).normalized()), 1e-12);
  const Eigen::AngleAxisd knee(thigh.q_WB.conjugate() * shin.q_WB);
  EXPECT_NEAR(knee.angle() * knee.axis().y(), 2.65, 1e-9);
}

// A pile of Stanford bunnies (a scan with holes: decomposed as the solid it nearly bounds). Where
// two bunnies' collision shapes touch (sampled every 1/8 s from 0.5 s to 3 s, as the pile falls
// and settles; a contact within the speculative distance is not touching), the gap a viewer sees
// is the distance between the meshes themselves there: the closest approach of one mesh's
// vertices to the other's surface within 3 cm of the contact. As convex hulls, bunnies rest on
// each other's hulls across ears and backs, millimetres apart (7.6 measured); decomposed, they
// touch (0.17 mm).
TEST(ImportCorpus, DecomposedBunnyPileRestsWithoutHullSizedGaps) {
  const fs::path bunny = "../shared/meshes/real/tm_bunny.ply";
  if (!fs::exists(bunny)) GTEST_SKIP() << "no " << bunny << " (the shared real meshes)";
  setenv("SIMREEL_CACHE_DIR", test::scratch("cache").c_str(), 1);
  auto gap = [&](const char* mode) {
    std::string yaml = "simulation: { duration: 3 }\nground: true\nbodies:\n";
    for (int i = 0; i < 5; ++i) {
      char b[400];
      std::snprintf(
          b, sizeof b,
          "  - { name: b%d, position: [%g, %g, %g], euler: [90, 0, %d], colliders: [ { shape: mesh, "
          "file: %s, mode: %s, density: 500, friction: 0.8 } ] }\n",
          i, 0.03 * (i % 2), 0.02 * (i % 3), 0.05 + 0.16 * i, 70 * i, fs::absolute(bunny).c_str(), mode);
      yaml += b;
    }
    const Scene s = load_scene(write(std::string(mode) + ".yaml", yaml));
    World w(world_config(s, 1), s.bodies);
    const TriangleMesh& m = *s.bodies[0].colliders[0].mesh;
    const Collider& col = s.bodies[0].colliders[0];
    auto world_point = [&](int body, const Vec3& v) {
      return w.local_to_world(body, col.p_BC + col.q_BC * v);
    };
    double worst = 0;
    int pairs = 0;
    std::vector<ContactData> contacts;
    for (int i = 1; i <= 3 * 240; ++i) {
      w.step();
      if (i < 120 || i % 30) continue;  // every 1/8 s from 0.5 s, while the pile falls and settles
      contacts.clear();
      w.contacts(contacts);
      for (const ContactData& c : contacts) {
        if (c.body_a >= 5 || c.body_b >= 5) continue;  // bunny on bunny
        // Shapes touching (a manifold within the speculative distance may be centimetres apart).
        int touching = -1;
        for (int j = 0; j < c.count; ++j)
          if (c.points[j].separation <= 1e-3) touching = j;
        if (touching < 0) continue;
        ++pairs;
        const Vec3 at = c.points[touching].p_W;
        double closest = 1e9;
        for (int side = 0; side < 2; ++side) {
          const int a = side ? c.body_b : c.body_a, b = side ? c.body_a : c.body_b;
          std::vector<std::array<Vec3, 3>> near;
          for (const auto& t : m.triangles) {
            const std::array<Vec3, 3> tw{world_point(b, m.vertices[t[0]]), world_point(b, m.vertices[t[1]]),
                                         world_point(b, m.vertices[t[2]])};
            if ((tw[0] - at).norm() < 0.03) near.push_back(tw);
          }
          for (const Vec3& v : m.vertices) {
            const Vec3 vw = world_point(a, v);
            if ((vw - at).norm() > 0.03) continue;
            for (const auto& t : near)
              closest = std::min(closest, point_triangle_distance(vw, t[0], t[1], t[2]));
          }
        }
        worst = std::max(worst, closest);
      }
    }
    std::printf("[measure] %s: %d touching bunny pairs sampled, widest gap %.2f mm\n", mode, pairs,
                1000 * worst);
    EXPECT_GT(pairs, 0) << mode;
    return worst;
  };
  const double hulls = gap("hull"), parts = gap("decompose");
  RecordProperty("hull_gap_mm", std::to_string(1000 * hulls));
  RecordProperty("decomposed_gap_mm", std::to_string(1000 * parts));
  EXPECT_LT(parts, 1e-3) << "hulls: " << hulls;
  EXPECT_GT(hulls, 3 * parts);
  unsetenv("SIMREEL_CACHE_DIR");
}

// The kuka arm fixed to the ground and held by its joint motors (the file's effort limits) stays put.
TEST(ImportCorpus, KukaHeldByItsMotorsStaysPut) {
  if (!fs::exists(kCorpus)) GTEST_SKIP() << "no " << kCorpus << " (the shared corpus)";
  const std::string scene = write("kuka.yaml", "ground: true\nimports: [ { file: " +
                                                   fs::absolute(kCorpus / "kuka_iiwa/model.urdf").string() +
                                                   ", fixed_base: true, hold: true, on_ground: true } ]\n");
  const Scene s = load_scene(scene);
  World w(world_config(s, 1), s.bodies);
  for (int i = 0; i < 2 * 240; ++i) w.step();
  for (int j = 0; j < w.joint_count(); ++j) EXPECT_NEAR(w.joint_position(j), 0, 1e-9) << j;
}

}  // namespace
}  // namespace simreel
