// A scene file (YAML, documented key by key in scenes/README.md) turned into bodies and settings.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <simreel/body.hpp>
#include "app/scene/camera_motion.hpp"
#include "app/scene/ghost.hpp"
#include "app/scene/scene_overlays.hpp"
#include "app/scene/scene_time.hpp"
#include "app/scene/scene_views.hpp"
#include "render/material.hpp"
#include "render/render_settings.hpp"
#include "sim/dynamics/forces.hpp"
#include "sim/dynamics/integrators.hpp"
#include "sim/solver/contact_settings.hpp"

namespace simreel {

struct VideoSpec {
  int width = kDefaultWidth;    ///< px
  int height = kDefaultHeight;  ///< px
  double fps = 30;              ///< frames per second of simulated time
};

struct CameraSpec {
  Vec3 position = Vec3(8, -8, 5);  ///< m
  Vec3 look_at = Vec3::Zero();     ///< m
  Vec3 up = Vec3::UnitZ();
  double fov = 40;     ///< degrees, vertical
  std::string follow;  ///< body name: look_at tracks its centre of mass, position keeps its offset
  /// `auto: true`: simulate first, then aim at the middle of everything that moves over the run
  /// and back off (along position - look_at) until all of it is in view (app/runner/camera_fit.hpp).
  bool fit = false;
  /// `frame: { body: NAME }`: position, look_at and up are in that body's frame and the camera
  /// rides with it (app/scene/scene_views.hpp); "" for the world.
  std::string frame_body;
  /// s, `follow: { body, damping }`: the time constant the camera lags the body by (0: rigid)
  double follow_damping = 0;
  /// `aim: BODY` or `aim: [BODY, ...]`: at every frame the camera turns to the bodies' centre of
  /// mass (mass-weighted), staying where it is (in the world, or in `frame`'s body); look_at is
  /// only its direction until the first frame.
  std::vector<std::string> aim;
  CameraPath path;                   ///< `path:` keys (app/scene/camera_motion.hpp); empty: none
  std::optional<CameraOrbit> orbit;  ///< `orbit:`
};

const char* to_string(AntiAliasing a);
std::optional<AntiAliasing> antialiasing_from_name(const std::string& name);

// The `render:` block: the look, whose fields and defaults live with the renderer's settings.
using RenderSpec = RenderLook;

// The top-level `ground`: a static body named "ground" with one plane collider (origin (0, 0, height),
// normal +z) and the checkered ground drawn under the scene (render.ground draws without colliding).
struct GroundSpec {
  double height = 0;                       ///< m, z of the plane
  double friction = 0.6;                   ///< Coulomb coefficient
  double restitution = 0;                  ///< in [0, 1]
  double size = RenderLook{}.ground_size;  ///< m, side of the drawn square (the plane is infinite)
  double tile = RenderLook{}.ground_tile;  ///< m, checker tile
};

using Rgb = std::array<float, 3>;  ///< linear RGB in [0, 1]

// Appearance, which sim/ knows nothing of: drawing only.
struct ColliderLook {
  /// The collider's `color`, else its mesh file's material unless the body has a `color`.
  std::optional<Rgb> color;
  double plane_size = 10;  ///< m, side of the square drawn for a plane collider
  /// A mesh collider's shading normals from its file (per triangle corner), if it gives them.
  std::shared_ptr<const std::vector<std::array<Eigen::Vector3f, 3>>> normals;
  /// Its mesh file's materials, textures and vertex colours (render/material.hpp), unless a
  /// `color` on the collider or its body overrides them.
  std::shared_ptr<const MeshAppearance> appearance;
  /// False for an imported link's collision shape (its visual shapes are what is drawn), unless
  /// the import shows its colliders.
  bool drawn = true;
};
struct BodyLook {
  Rgb color{0.8f, 0.8f, 0.8f};          ///< the body's `color`
  std::vector<ColliderLook> colliders;  ///< parallel to the body's colliders
  bool drawn = true;                    ///< false for the ground body: the renderer's ground draws it
  GhostSpec ghost;                      ///< its exact motion drawn translucent (app/scene/ghost.hpp)
  // What a collider is drawn in: its file's material, else the body colour.
  Rgb collider_color(size_t k) const {
    return k < colliders.size() && colliders[k].color ? *colliders[k].color : color;
  }
};

// The scene-level `test:` block: what `simreel check` compares (its options override it).
struct TestSpec {
  std::string frames =
      "0%, 25%, 50%, 75%, 100%";  ///< frame spec (app/scene/frame_plan.hpp): by time, so fps may change
  int width = 480, height = 270;  ///< px: goldens small enough for git
};

struct Scene {
  std::string path;             ///< as given
  std::string name;             ///< file stem: default output out/<name>.mp4
  double duration = 10.0;       ///< s
  double timestep = 1.0 / 240;  ///< s
  Integrator integrator = Integrator::automatic;
  Vec3 gravity = Vec3(0, 0, -9.81);  ///< m/s^2
  bool gravity_given = false;        ///< simulation.gravity is in the file (an import's does not apply)
  VideoSpec video;
  CameraSpec camera;
  RenderSpec render;
  /// The scene gives its sky or its ground's colours or tiles itself: an imported file's sky and
  /// floor checker (MJCF) are not taken (otherwise the first file's that has them are).
  bool look_given = false;
  bool camera_given = false;   ///< the scene file has a `camera:` (an import's file camera may not also)
  MotionBlurSpec motion_blur;  ///< render.motion_blur (app/scene/camera_motion.hpp)
  std::vector<BodyDef> bodies;
  std::vector<BodyLook> looks;               ///< parallel to bodies
  std::optional<GroundSpec> ground;          ///< the top-level `ground` (its body is the last of `bodies`)
  ContactSettings contacts;                  ///< simulation.contacts
  bool restitution_threshold_given = false;  ///< simulation.contacts.restitution_threshold is in the file
  TestSpec test;                             ///< test: what `simreel check` compares
  OverlaySpec overlays;  ///< bodies' `show:` and the `overlays:` block (app/scene/scene_overlays.hpp)
  TimeSpec time;         ///< `time:`: playback speed, segments, holds (app/scene/scene_time.hpp)
  ViewsSpec views;       ///< `panes:` and `variants:` (app/scene/scene_views.hpp)
  std::vector<std::pair<int, int>> ignore_pairs;  ///< simulation.ignore_pairs, as body indices
  std::vector<ForceDef> forces;    ///< the `forces:` list, by body index (app/scene/scene_forces.cpp)
  std::vector<JointDef> joints;    ///< the `joints:` list, by body index (app/scene/scene_joints.cpp)
  JointSettings joint_settings;    ///< simulation.joints
  std::vector<std::string> notes;  ///< what was done with mesh defects and ignored keys, with file and body
  /// What is probably wrong in the input though it loads (an imported link's inertia that its own
  /// geometry contradicts): printed as `warning:` lines and listed in `--json` warnings.
  std::vector<std::string> warnings;
  /// The files the scene read besides itself (meshes, images, robot files), as resolved: what its
  /// goldens record so that `simreel check` notices when one changes.
  std::vector<std::string> inputs;
};

// Throws InputError "FILE:LINE:COL: KEY: what is wrong" for anything a user could get wrong:
// YAML that yaml-cpp would read silently otherwise (a duplicate key, a second document, a quoted or
// !!str number, hexadecimal outside collision bits, a list as a key) and values that make no body
// (a mass that is a non-finite density, an inertia that overflows) included.
Scene load_scene(const std::string& path);
// The same from the file's text; `path` names it in messages and mesh files are looked up beside it.
Scene load_scene_text(const std::string& yaml, const std::string& path);

// Nearest candidate by edit distance, if close enough to be a likely typo.
std::optional<std::string> nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace simreel
