// Joints: bodies connected into mechanisms (docs/joints.md). A joint ties a child body to a parent
// body, or to the fixed world, at an anchor point; it leaves the child some freedoms (a hinge one
// rotation, a slider one translation, a ball joint every rotation) and removes the rest exactly.
//
// Every joint is described at t = 0, in world coordinates: the anchor and axes are where the
// bodies are placed then, and each joint coordinate (angle in rad, offset in m) is zero in that
// start pose. A mechanism whose joints form a tree is simulated in joint coordinates, so its joints
// never open; its bodies' positions and velocities are read out as every other body's.
#pragma once
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

//   revolute   a hinge: rotation about `axis` through `anchor` (1 coordinate, rad)
//   prismatic  a slider: translation along `axis` (1 coordinate, m); no rotation
//   spherical  a ball joint at `anchor`: every rotation (3 freedoms; coordinate: a rotation)
//   fixed      a weld: no relative motion (0 coordinates)
//   universal  a Cardan joint at `anchor`: rotation about `axis` (fixed in the parent), then about
//              `axis2` (fixed in the child, perpendicular to `axis` at t = 0); 2 coordinates, rad
//   wheel      a wheel on a suspension: the child (the wheel) slides along `axis` (the suspension
//              travel, m: coordinate 0, where `spring` and `limits` act), turns about `axis` if it
//              has `steering` (rad: coordinate 1), and spins about `axis2` (its axle,
//              perpendicular to `axis`: the last coordinate, rad, where `motor` and `friction` act)
//   distance   the parent's point `anchor` and the child's point `anchor2` are held `length` apart
//              (a rigid rod; both bodies turn freely about their points), or, as a rope, kept
//              between `min_length` and `max_length` (slack between them; at max_length it only
//              pulls, at a positive min_length it only pushes). Coordinate: the length, m, where
//              `spring` acts (rest: a length)
//   pulley     a rope from the parent's `anchor` up to the fixed point `pulley_anchors[0]`, over
//              the pulley to `pulley_anchors[1]` and down to the child's `anchor2`: the lengths
//              keep L0 + ratio L1 <= their start value. With a `wheel` (a body on a revolute joint
//              whose rim the rope leaves at the two pulley anchors) the rope turns it without
//              slipping, so the wheel's inertia takes part. Coordinates: L0 and L1, m
enum class JointType { revolute, prismatic, spherical, fixed, universal, wheel, distance, pulley };
const char* to_string(JointType t);
std::optional<JointType> joint_type_from_name(std::string_view name);
const char*
joint_type_names();  ///< "revolute, prismatic, spherical, fixed, universal, wheel, distance, pulley"

/// A spring along a joint's coordinate: generalised force -stiffness (q - rest) - damping q'.
/// Revolute and universal: N m/rad, N m s/rad, rad; prismatic: N/m, N s/m, m. Spherical: a torque
/// -stiffness phi - damping w (N m/rad, N m s/rad), phi the child's rotation vector relative to the
/// parent since the start pose (|phi| <= pi) and w their relative angular velocity; rest is 0.
struct JointSpring {
  double stiffness = 0;
  double damping = 0;
  double rest = 0;
};

/// Stops on a joint's coordinate (revolute, prismatic, and each coordinate of a universal joint):
/// lower <= q <= upper, rad or m, with 0 (the start pose) inside. Reaching a stop is an impact:
/// the coordinate's rate reverses to -restitution times itself (the rest of the mechanism takes
/// the impulse through its inertia), and a rate left under 1e-6 (rad/s, m/s) rests on the stop.
struct JointLimits {
  double lower = 0;
  double upper = 0;
  double restitution = 0;  ///< in [0, 1]
};

/// Stops on a ball joint (spherical), by the swing-twist decomposition of the child's rotation
/// relative to the parent about the joint's `axis` (a world direction at t = 0, fixed in both
/// bodies from then on): the swing tilts the child's axis away from the parent's by at most `cone`
/// rad; the twist turns the child about its own axis, between twist_lower and twist_upper (rad).
/// Or, without an axis, `angle` bounds the whole rotation's angle from the start pose (MJCF's ball
/// joint range). Reaching any is an impact on that angle alone (its rate reverses to -restitution
/// times itself, the rest of the mechanism takes the impulse through its inertia), and an angle
/// left at rest on its stop stays there while the stop pushes.
struct BallLimits {
  double cone = std::numeric_limits<double>::infinity();          ///< rad, in (0, pi); inf: none
  double angle = std::numeric_limits<double>::infinity();         ///< rad, in (0, pi); inf: none
  double twist_lower = -std::numeric_limits<double>::infinity();  ///< rad, in [-pi, 0]; -inf: none
  double twist_upper = std::numeric_limits<double>::infinity();   ///< rad, in [0, pi]; inf: none
  double restitution = 0;                                         ///< in [0, 1]
};

/// A motor on a revolute or prismatic joint's coordinate (or one of a universal joint's angles),
/// with a bounded force: while it can, it
/// holds the coordinate's rate at its target exactly; when the load needs more than max_force it
/// pushes with max_force.
///   speed     target rate `speed` (rad/s, m/s)
///   position  drives the coordinate to `position` (rad, m): target rate
///             clamp((position - q) / time_constant, -speed, speed), so the approach is exponential
///             with that time constant once within speed * time_constant of the target
///
/// On a spherical joint the motor drives the child's angular velocity relative to the parent, w,
/// in the child's axes (the world's at the start pose), with max_force bounding the torque about
/// each of those three axes (a box, as MuJoCo's and Jolt's per-axis motor limits):
///   speed     w = `angular_velocity` (rad/s): a constant vector, so a turn about a fixed axis
///   position  drives the rotation from the start pose to `rotation` (a rotation vector, rad: axis
///             times angle, its axis in the world's axes at the start pose): w = e / time_constant
///             with e the rotation vector still to go (in the child's axes), its length capped at
///             `speed`; e then shrinks along its own axis as exp(-t / time_constant)
struct JointMotor {
  enum class Mode { speed, position };
  Mode mode = Mode::speed;
  double speed = 0;            ///< rad/s or m/s; position mode: the largest approach rate (inf: none)
  double position = 0;         ///< rad or m (position mode)
  double time_constant = 0.1;  ///< s (position mode)
  double max_force = 0;        ///< N m (revolute, spherical: per axis) or N (prismatic), > 0
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s, spherical speed mode (child's axes)
  Vec3 rotation = Vec3::Zero();          ///< rad, spherical position mode (rotation vector, |.| < pi)
};

/// A coordinate that follows another's (URDF's mimic; a pair of gears, a belt): this joint's
/// coordinate q stays multiplier times joint `leader`'s, both zero in the start pose, by a
/// constraint row, so the two move as one freedom and the row's force is what couples them. The
/// follower and its leader are revolute or prismatic joints of the tree (neither closes a loop).
///
/// With a range, the combination q - multiplier q_leader is only kept within [lower, upper] (rad
/// or m, 0 inside): a stop on it, met with restitution 0 (MJCF's limited fixed tendon, such as a
/// hamstring spanning hip and knee), and the two joints otherwise move freely.
///
/// `also` adds leaders: q - multiplier q_leader - sum m_k q_k is the combination held (an MJCF
/// fixed tendon over three or more joints, c1 q1 + c2 q2 + c3 q3 within a range).
struct JointMimic {
  int leader = -1;  ///< joint index
  double multiplier = 1;
  std::optional<std::pair<double, double>> range = std::nullopt;
  std::vector<std::pair<int, double>> also = {};  ///< further leaders: (joint index, multiplier)
};

struct JointDef {
  std::string name;  ///< for messages and read-outs; unique
  JointType type = JointType::revolute;
  int parent = -1;               ///< body index, or -1 for the fixed world
  int child = -1;                ///< body index (dynamic)
  Vec3 anchor_W = Vec3::Zero();  ///< m, world point at t = 0
  Vec3 axis_W = Vec3::UnitZ();   ///< revolute, prismatic, universal; spherical with ball_limits: world
                                 ///< direction at t = 0
  Vec3 axis2_W = Vec3::UnitX();  ///< universal: the child's axis at t = 0
  std::optional<JointSpring> spring;
  std::optional<JointLimits> limits;  ///< revolute, prismatic, universal (both coordinates)
  std::optional<JointMotor>
      motor;  ///< revolute, prismatic, wheel (its axle), spherical; universal: the angle about axis
  std::optional<JointMotor> motor2;       ///< universal: the angle about axis2
  std::optional<JointMimic> mimic;        ///< revolute, prismatic: follows another coordinate
  std::optional<BallLimits> ball_limits;  ///< spherical: cone and twist stops about axis_W, angle
  /// Rotor inertia on the coordinate (MJCF's armature; a geared motor's reflected inertia): kg m^2
  /// on a revolute joint (each angle of a universal one), kg on a prismatic one. It adds to the
  /// mechanism's mass matrix on that coordinate only; its kinetic energy armature q'^2 / 2 is part of
  /// World::kinetic_energy.
  double armature = 0;
  /// Coulomb friction on the coordinate: N m (revolute, universal) or N (prismatic); it holds the
  /// joint still while the load needs no more, and otherwise acts against the motion. On a
  /// spherical joint: N m about each of the child's axes (MuJoCo's frictionloss on a ball joint).
  double friction = 0;
  /// wheel: a steering coordinate about `axis`, driven to its position by this motor (position
  /// mode; without it the wheel does not steer).
  std::optional<JointMotor> steering;
  // distance and pulley joints.
  Vec3 anchor2_W = Vec3::Zero();  ///< m, the child's point, world at t = 0
  /// distance: m. A rigid rod when neither bound is set (its length: the anchors' start distance);
  /// a rope otherwise: max_length (default: the start distance) at least the start distance,
  /// min_length (default 0: none) at most it.
  std::optional<double> min_length, max_length;
  double restitution = 0;  ///< a rope reaching its max (min) length rebounds with this, in [0, 1]
  Vec3 pulley_anchor_W[2] = {Vec3::Zero(), Vec3::Zero()};  ///< pulley: m, fixed world points
  double ratio = 1;  ///< pulley: L0 + ratio L1 is what the rope keeps (a block and tackle: 2, ...)
  int wheel = -1;    ///< pulley: the wheel body (on a revolute joint), or -1 for a massless pulley
  bool collide_connected = false;  ///< false: the two bodies never collide with each other
};

// How mechanisms are integrated (scene key `simulation.joints`, docs/joints.md "Integrators").
//  - dopri5 (the default): an embedded Runge-Kutta 5(4) pair (Dormand-Prince) whose step adapts to
//    keep each step's estimated error under `tolerance`, relative to the coordinate's size with the
//    same value as an absolute floor (rad, m, rad/s, m/s): the frame step is split into as many
//    internal steps as that needs, and the last one is carried to the next frame.
//  - verlet: velocity Verlet on the joint coordinates, `substeps` equal steps a frame (0: as many
//    as keep the mechanism's fastest mode stable, measured as it runs), one derivative a step;
//    second order, no artificial damping, energy errors bounded rather than tolerance-small: a
//    20-link chain swinging from 30 degrees keeps its energy to 2e-4 of M g N l in 2.1
//    derivatives a frame, where dopri5 at tolerance 1e-3 keeps 1e-7 in 8. A frame whose motion
//    the fixed steps do not resolve (a whip, a stiff damper's transient) is taken by dopri5 at
//    `tolerance`. For throughput where the error is judged by eye. A mechanism with limits,
//    motors, friction, loops, ropes or ball and free joints keeps dopri5 (a warning).
enum class JointIntegrator { dopri5, verlet };
struct JointSettings {
  JointIntegrator integrator = JointIntegrator::dopri5;
  double tolerance = 1e-10;  ///< dopri5 (and the frames verlet hands it)
  int max_steps = 100000;    ///< internal steps per frame step before the run stops with an error
  int substeps = 0;          ///< verlet: steps a frame, or 0 to choose them from the fastest mode
};

}  // namespace simreel
