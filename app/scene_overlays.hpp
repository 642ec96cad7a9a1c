// A scene's teaching overlays (issue 12): per body `show:` items and the scene-level `overlays:`
// block, as parsed from YAML (documented key by key in scenes/README.md). What they look like is
// app/overlays.hpp's business; this file knows no GL.
//
//   bodies:
//     - name: handle
//       show:
//         - axes
//         - angular_momentum                                    # defaults
//         - { angular_velocity: { color: [1, 0, 1], scale: 0.2 } }   # scale: m per rad/s
//         - { trail: { point: [0.5, 0, 0], frame: body, length: 3.0 } }
//   overlays:
//     hud: ["t = {t:.2f} s"]
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "sim/types.hpp"

namespace YAML {
class Node;
}

namespace simreel {

struct Scene;

enum class ShowKind {
  axes,               ///< principal axes e1 e2 e3 at the centre of mass (red, green, blue)
  angular_velocity,   ///< omega, world frame, arrow from the centre of mass
  angular_momentum,   ///< L about the centre of mass, world frame
  velocity,           ///< velocity of the centre of mass
  center_of_mass,     ///< a ball at the centre of mass
  trail,              ///< the path of a body point, fading over `length` seconds
  inertia_box,        ///< the uniform box with the body's mass and principal moments
  inertia_ellipsoid,  ///< the uniform solid ellipsoid with the body's mass and principal moments
  cones,              ///< body and space cones: omega's cone about the symmetry axis and about L
  poinsot,            ///< the energy ellipsoid rolling on the invariable plane, polhode and herpolhode
};
const char* to_string(ShowKind k);

using ShowRgb = std::array<float, 3>;  ///< linear RGB in [0, 1]

struct ShowItem {
  ShowKind kind = ShowKind::axes;
  std::optional<ShowRgb> color;  ///< default: the kind's Okabe-Ito colour (app/overlays.cpp)
  /// Arrows: m per unit of the quantity (m per rad/s, m per kg m^2/s, m per m/s); none: the run's
  /// largest magnitude is drawn 2x the body's radius. Axes: m, the length of each axis.
  std::optional<double> scale;
  double width = 1;    ///< thickness factor (arrows, axes); trails: px
  double opacity = 1;  ///< in [0, 1]; inertia shapes default to 0.35
  double xray = 0;     ///< opacity of the parts hidden behind bodies (0: not drawn; `xray: true` is 0.35)
  Vec3 point = Vec3::Zero();    ///< trail: m, the body point traced (in `frame` at t = 0)
  bool point_in_world = false;  ///< trail `frame: world`: `point` is where the point is at t = 0
  double length = 3;            ///< trail: s of history shown
};

// One field of a HUD line: {name}, {body.name}, {name.x}, {|name|}, each with an optional
// Python-style spec after ':' ([+][width][.precision][f|e|g|d]).
struct HudField {
  std::string name;    ///< t, frame, E, E_drift, L_drift; omega, omega_body, L, v, position
  int body = -1;       ///< per-body quantities: the body's index
  int component = -1;  ///< 0 1 2 for .x .y .z; -1 the whole vector or a scalar
  bool norm = false;   ///< |name|
  std::string printf;  ///< the spec as a printf conversion, e.g. "%+.1e"
};
struct HudLine {
  std::vector<std::string> text;  ///< literal text before each field, then the text after the last
  std::vector<HudField> fields;   ///< text.size() == fields.size() + 1
  std::string source;             ///< as written
};

struct OverlaySpec {
  std::vector<std::vector<ShowItem>> show;  ///< per body, parallel to Scene::bodies
  std::vector<HudLine> hud;                 ///< lines, top first
  std::string hud_corner = "top_left";      ///< top_left, top_right, bottom_left, bottom_right
  std::string title;                        ///< drawn at the top centre
  double text_size = 1;                     ///< factor on the default text size (3.2% of the height)
  bool any() const;
};

// Reads every body's `show:` and the top-level `overlays:` into s.overlays; throws InputError
// "FILE:LINE:COL: KEY: what" as load_scene does. Called by load_scene once the bodies are read.
void load_overlays(const YAML::Node& root, const std::string& path, Scene& s);

// The scalar names and the per-body vector names a HUD field may use.
const std::vector<std::string>& hud_scalar_names();
const std::vector<std::string>& hud_body_names();

}  // namespace simreel
