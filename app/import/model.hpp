// A robot or rig as its file describes it, whatever the format (URDF, MJCF): links with their
// stated inertials and their visual and collision geometry, and the joints between them, each
// remembering the file and line it came from. The readers (app/import/urdf.cpp,
// app/import/mjcf.cpp) fill it; app/import/place.cpp turns it into scene bodies and joints.
// Poses are relative (a link's frame in its parent's, a shape's in its link's), as in both formats.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <simreel/joints.hpp>
#include <simreel/math.hpp>
#include <simreel/mesh.hpp>

namespace simreel {

// Where something came from, for messages: "robot.urdf:42: link 'base'".
struct SourceRef {
  std::string file;
  int line = 0;      ///< 1-based; 0 unknown
  std::string what;  ///< "link 'base'", "joint 'elbow'", "link 'base', collision 2"
  std::string str() const;
};

// A frame in a model file: a rotation then a translation. (Not named Pose: the narrow phase's
// simreel::Pose is another type, and two types of one name break the one-definition rule where
// both are linked: their std::vector code is merged.)
struct ModelPose {
  Vec3 p = Vec3::Zero();  ///< m
  Quat q = Quat::Identity();
  ModelPose operator*(const ModelPose& o) const { return {p + q * o.p, (q * o.q).normalized()}; }
  Vec3 operator*(const Vec3& x) const { return p + q * x; }
};

/// A floor drawn as a checker (MJCF's built-in checker texture on a plane): its two colours
/// (display RGB, as the file gives them) and the side of one square, m.
struct ModelChecker {
  std::array<float, 3> rgb1{}, rgb2{};
  double tile = 1;
};

/// A sky whose colour runs from `top` straight up to `bottom` straight down (MJCF's gradient
/// skybox), display RGB as the file gives them.
struct ModelSky {
  std::array<float, 3> top{}, bottom{};
};

/// A camera the file names (MJCF <camera>): it looks along its frame's -z with +y up.
struct ModelCamera {
  std::string name;
  int link = -1;     ///< the link it rides on; -1: the world
  ModelPose pose;    ///< in that link's frame (the world's for -1)
  double fovy = 45;  ///< degrees, vertical
  /// fixed: rides on its link; track, trackcom: keeps its world orientation and its offset from the
  /// link (its centre of mass); targetbody, targetbodycom: stays where it is and turns to `target`.
  enum class Mode { fixed, track, trackcom, targetbody, targetbodycom } mode = Mode::fixed;
  int target = -1;  ///< targetbody*: the link it turns to
  SourceRef src;
};

struct ModelShape {
  enum class Kind { box, sphere, cylinder, capsule, ellipsoid, mesh, plane };
  Kind kind = Kind::box;
  Vec3 size = Vec3::Ones();   ///< m, box full extents
  double radius = 0;          ///< m
  double length = 0;          ///< m, cylinder and capsule: along the shape's z, tip to tip for a capsule
  Vec3 radii = Vec3::Ones();  ///< m, ellipsoid
  std::string mesh_file;      ///< resolved path
  /// A mesh given in the file itself (MJCF `<mesh vertex=...>`: its convex hull), instead of a file.
  std::shared_ptr<const TriangleMesh> inline_mesh;
  Vec3 scale = Vec3::Ones();
  ModelPose pose;                             ///< in the link frame
  std::optional<std::array<float, 3>> color;  ///< display RGB (sRGB-encoded, as files give it)
  std::string texture;                        ///< resolved image path, or ""
  std::optional<ModelChecker> checker;        ///< a plane's built-in checker texture
  bool visual = false, collision = false;     ///< drawn; collides
  std::optional<double> friction;
  /// Coefficient of restitution where the file implies one (MJCF's solref: see the reader).
  std::optional<double> restitution;
  uint32_t group = 1, mask = 0xFFFFFFFFu;
  std::optional<double> density;  ///< kg/m^3 where the file gives one (MJCF)
  std::optional<double> mass;     ///< kg where the file gives the shape's mass (MJCF)
  /// Counts in the link's mass when the file states none: URDF's collision shapes (at the
  /// file's link mass), every MJCF geom of non-zero density or mass (MuJoCo's rule).
  bool weighs = false;
  SourceRef src;
};

struct ModelInertial {
  double mass = 0;              ///< kg
  Vec3 com = Vec3::Zero();      ///< m, link frame
  Mat3 inertia = Mat3::Zero();  ///< kg m^2 about the centre of mass, link frame (rotation applied)
  SourceRef src;
};

struct ModelLink {
  std::string name;
  ModelPose pose;  ///< in the parent link's frame (set by the reader for MJCF; from the joint for URDF)
  std::optional<ModelInertial> inertial;
  std::vector<ModelShape> shapes;
  /// A helper link (MJCF: a body with several joints becomes a chain of links, one joint each):
  /// the link it serves, which gives it 1e-9 of its mass; -1 for a link of the file.
  int helper_of = -1;
  SourceRef src;
};

struct ModelJoint {
  // revolute with limits, continuous (revolute without), prismatic, fixed, floating, planar,
  // spherical (Bullet's URDF extension and MJCF's ball).
  enum class Kind { revolute, continuous, prismatic, fixed, floating, planar, spherical };
  std::string name;
  Kind kind = Kind::fixed;
  int parent = -1, child = -1;                  ///< link indices; parent -1: the world
  Vec3 anchor = Vec3::Zero();                   ///< m, in the child link's frame
  Vec3 axis = Vec3::UnitX();                    ///< unit, in the child link's frame
  std::optional<std::array<double, 2>> limits;  ///< rad or m
  double effort = 0;                            ///< N m or N, the file's actuator bound (0: none)
  double velocity = 0;                          ///< rad/s or m/s, the file's speed bound (0: none)
  double damping = 0;                           ///< N m s/rad or N s/m
  double friction = 0;                          ///< N m or N
  double stiffness = 0, rest = 0;               ///< a spring on the coordinate (MJCF)
  double armature = 0;                          ///< kg m^2 or kg: rotor inertia (MJCF)
  /// URDF mimic: this coordinate is multiplier times joint `mimic_joint`'s plus offset.
  std::string mimic_joint;
  double mimic_multiplier = 1, mimic_offset = 0;
  /// MJCF's limited fixed tendon on two joints: this coordinate minus multiplier times joint
  /// `coupled_joint`'s is kept within coupled_range (both measured from the file's pose).
  std::string coupled_joint;
  double coupled_multiplier = 0;
  std::vector<std::pair<std::string, double>> coupled_more;  ///< further joints (a tendon over more than two)
  std::array<double, 2> coupled_range{0, 0};
  SourceRef coupled_src;
  /// Closes a loop (MJCF's equality connect or weld): not a tree edge; `anchor` is then in the
  /// child's frame and `parent` may be -1 (the world).
  bool loop = false;
  SourceRef src;
};

/// A rope between two links' points (MJCF's spatial tendon between two sites): with a limited
/// length, slack below max_length, pulling at it, pushing at min_length when one is given; with a
/// spring, pulling -stiffness (L - rest) - damping L' along it (within the bounds, or without
/// any: a spring alone).
struct ModelRope {
  std::string name;
  int link_a = -1, link_b = -1;                         ///< -1: the world
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  ///< m, in each link's frame (the world's)
  std::optional<double> min_length;                     ///< m
  std::optional<double> max_length;                     ///< m; none: no bounds (a spring alone)
  /// N/m, N s/m, m; a NaN rest is the length in the file's pose.
  std::optional<JointSpring> spring;
  SourceRef src;
};

struct Model {
  std::string file;    ///< as read
  std::string format;  ///< "urdf", "mjcf"
  std::string name;    ///< the robot's or model's name
  std::vector<ModelLink> links;
  std::vector<ModelJoint> joints;
  std::vector<std::string> notes;            ///< what was ignored or repaired, with file and line
  std::vector<std::pair<int, int>> exclude;  ///< link pairs that never collide (MJCF contact exclude)
  std::vector<ModelRope> ropes;
  std::vector<std::string> files;  ///< every file read: the model's and those it includes
  std::optional<ModelSky> sky;     ///< the file's sky, where it gives one
  std::vector<ModelCamera> cameras;
  std::optional<Vec3> gravity;  ///< m/s^2, world frame, where the file gives it (MJCF <option>)
  /// Named poses (MJCF <key qpos>), each the file's joint coordinates laid out as `qpos_layout`.
  struct Key {
    std::string name;
    std::vector<double> qpos;
    SourceRef src;
  };
  std::vector<Key> keys;
  /// The file's coordinates in its own order (MuJoCo's qpos: joints as the file writes them,
  /// depth first): a joint of `joints` (hinge, slide: 1 number, `ref` at the file's pose; ball: 4,
  /// a quaternion) or a free body's link (7: position, then quaternion w x y z).
  struct QposSlot {
    int joint = -1, link = -1;
    int width = 1;
    double ref = 0;  ///< rad or m
  };
  std::vector<QposSlot> qpos_layout;
};

}  // namespace simreel
