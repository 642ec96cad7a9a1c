// Split screen and variants (the scene's `panes:` and `variants:`, scenes/README.md): several
// views of a run side by side or in a grid, each with its own camera (a camera may ride in a
// body's frame) and title, and variants of the scene (another integrator or timestep), each its
// own World, shown in their own panes.
#pragma once
#include <yaml-cpp/yaml.h>
#include <array>

#include <optional>
#include <string>
#include <vector>

#include <simreel/math.hpp>
#include "app/scene/scene_overlays.hpp"
#include "app/scene/scene_yaml.hpp"
#include "sim/dynamics/integrators.hpp"

namespace simreel {

struct Scene;

// A variant's own start for a body that no joint holds: any of its pose and velocities.
struct VariantStart {
  int body = -1;
  std::optional<Vec3> position;  ///< m, body origin
  std::optional<Quat> orientation;
  std::optional<Vec3> linear_velocity, angular_velocity;  ///< m/s, rad/s, world
};

// A variant's start turned rigidly: `bodies` rotated by `angle` about the line through `about`
// along `axis`, with their velocities and the joints among them (a mechanism stays assembled). A
// joint from a turned body to one that is not (or to the world) must have its anchor on that line
// and, if it has an axis, the axis along it: turning a pendulum about its pivot.
struct VariantTurn {
  std::vector<int> bodies;
  Vec3 about = Vec3::Zero();  ///< m
  Vec3 axis = Vec3::UnitZ();  ///< unit
  double angle = 0;           ///< rad
};

// The same scene with other settings or another start, run as its own World.
struct VariantSpec {
  std::string name;
  std::optional<Integrator> integrator;  ///< every body's (per-body overrides dropped)
  std::optional<double> timestep;        ///< s (shortened as the scene's is, to divide 1/fps)
  std::vector<VariantStart> starts;      ///< `bodies:`
  std::optional<VariantTurn> turn;       ///< `turn:`
  /// `overlay:`: drawn over the scene's own bodies in the panes (or the single view) of the scene
  /// as given, as translucent copies in this colour, instead of in a pane of its own.
  bool overlay = false;
  /// linear RGB; none: the next of the overlay palette (app/view/overlays.hpp, variant_color)
  std::optional<std::array<float, 3>> overlay_color;
  double overlay_opacity = 0.75;
};

// A pane's camera: the scene's camera (after camera.auto) with these keys over it. Positions are
// in the world, or with `frame: { body: NAME }` in that body's frame (points relative to its
// origin, `up` a direction in its axes): the camera rides with the body, which then stands still
// in the pane while the world turns around it.
struct PaneCamera {
  std::optional<Vec3> position, look_at, up;  ///< m
  std::optional<double> fov;                  ///< degrees, vertical
  std::optional<std::string> follow;          ///< body name ("" turns the scene's follow off)
  std::optional<std::string> frame_body;      ///< body name ("" : the world frame)
};

struct PaneSpec {
  std::string title;    ///< drawn at the pane's top centre ("" none)
  std::string variant;  ///< "" the scene as given, else a variant's name
  PaneCamera camera;
  /// The pane's own show items of the bodies it names (body index, items; empty hides them);
  /// other bodies show the scene's.
  std::vector<std::pair<int, std::vector<ShowItem>>> show;
};

struct ViewsSpec {
  std::vector<VariantSpec> variants;
  std::vector<PaneSpec> panes;  ///< empty: one view (with variants: one pane each, made up)
  int columns = 0;              ///< panes per row; 0: all in one row
  bool split() const { return !panes.empty(); }
};

// Reads `variants:` and `panes:` into s.views (with variants and no panes: the scene and each
// variant side by side, titled by their integrator and timestep). Throws InputError
// "FILE:LINE:COL: KEY: what". Called by load_scene once the bodies and camera are read.
void load_views(const YAML::Node& root, const std::string& path, Scene& s);

// `camera.frame` / a pane camera's `frame`: "world" -> "", { body: NAME } -> NAME (checked
// against the scene's bodies by load_views).
std::string camera_frame_body(const YAML::Node& n, const scene_yaml::Ctx& c);

// That `name` is one of the scene's bodies, else InputError at n naming the nearest name.
void check_body(const Scene& s, const std::string& name, const YAML::Node& n, const scene_yaml::Ctx& c);

// The scene as a variant runs it (prepare_run applied to a new timestep, its note kept).
Scene variant_scene(const Scene& s, const VariantSpec& v);

}  // namespace simreel
