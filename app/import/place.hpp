// A Model (app/import/model.hpp) placed into a scene: its links become bodies, its joints simreel
// joints, its visual geometry what is drawn and its collision geometry what collides.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/import/model.hpp"
#include "app/import/urdf.hpp"

namespace simreel {

struct Scene;
class MeshLibrary;

// Whose mass properties a link gets (docs/import.md):
//   check     the file's, and a warning naming the link and both values when its collision
//             geometry at the file's mass disagrees (a principal moment off by more than 25%, or
//             the centre of mass more than 10% of the link's size away)
//   geometry  computed from the collision geometry, scaled to the file's mass
//   file      the file's, unchecked
enum class InertiaPolicy { check, geometry, file };

struct ImportSpec {
  std::string file;         ///< resolved path of the URDF or MJCF file
  std::string name;         ///< prefix of its body and joint names ("NAME/link"); "" none
  ModelPose pose;           ///< where the model's frame sits in the world
  bool fixed_base = false;  ///< the root link is welded to the world (static)
  InertiaPolicy inertia = InertiaPolicy::check;
  ImportPaths paths;
  bool show_colliders = false;  ///< draw the collision shapes instead of the visual ones
  bool hold = false;            ///< each moving joint held at its start by a motor (the file's effort)
  /// The model's links collide with each other (never a body and its parent, nor pairs the file
  /// excludes); unset: the format's default (MJCF yes, as MuJoCo; URDF no, as PyBullet).
  std::optional<bool> self_collision;
  bool decompose = false;  ///< moving links' collision meshes collide as convex decompositions
  /// Moved up or down so that the lowest point of its collision shapes rests at ground_height.
  bool on_ground = false;
  double ground_height = 0;  ///< m
  /// Start values of joint coordinates by the file's joint names (rad, m): the model is placed
  /// in that pose (simreel's coordinates are zero there, its limits shifted to match).
  std::map<std::string, double> joint_positions;
  /// Start rotations of ball joints by name (a key's unit quaternion: the child's frame turned
  /// about the joint's anchor, in its own axes, from the file's pose).
  std::map<std::string, Quat> ball_rotations;
  /// A named pose of the file (MJCF <key>): its free bodies placed and its joints started there
  /// (joint_positions given here win); "" none.
  std::string keyframe;
  /// A camera of the file (MJCF <camera name>) that becomes the scene's camera; "" none.
  std::string camera;
  SourceRef src;  ///< the import's place in the scene file
};

// Appends the model's bodies (after the scene's own), looks, joints, ignored pairs, notes and
// warnings to `scene`. A link welded to its parent by a fixed joint becomes part of its parent's
// body (its shapes and mass join it); a link with no parent is free (six freedoms) unless
// `fixed_base`; a URDF root link named `world` with nothing in it is the world. Throws InputError
// naming the file, line and link for what no simulation can take (a moving link with no mass and
// nothing to weigh).
void place_model(const Model& model, const ImportSpec& spec, Scene& scene, MeshLibrary& meshes);

// spec.keyframe applied to the model before it is placed: a free body's pose becomes the key's
// (the file's world frame), each hinge or slide coordinate's value minus its `ref` joins
// spec.joint_positions unless given there, each ball joint's rotation spec.ball_rotations. Throws
// InputError naming the import for a key the file lacks or one whose numbers do not fit the file's
// joints.
void apply_keyframe(Model& model, ImportSpec& spec, std::vector<std::string>& notes);

}  // namespace simreel
