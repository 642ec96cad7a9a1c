// A scene's teaching overlays: per body `show:` items and the scene-level `overlays:`
// block, as parsed from YAML (documented key by key in scenes/README.md). What they look like is
// app/view/overlays.hpp's business; this file knows no GL.
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
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/joints.hpp>
#include <simreel/math.hpp>

namespace YAML {
class Node;
}

namespace simreel {

struct Scene;
namespace scene_yaml {
class Ctx;
}

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
  forces,             ///< the scene's forces on the body: arrows, torques, springs, drag (and gravity)
  contacts,           ///< contact points, normals and contact forces on the body
  joints,             ///< the joint holding the body to its parent: the pivot (a ball), the axis, the limits
  joint_forces,       ///< the force and torque the parent exerts on the body through that joint
  momentum,           ///< linear momentum m v, kg m/s, arrow from the centre of mass
  angular_momentum_about,  ///< L_O = L + (c - O) x m v about a fixed world point O, arrow from O
  snapshot,                ///< a translucent copy of the body as it was at given times, kept on screen after
};
const char* to_string(ShowKind k);

using ShowRgb = std::array<float, 3>;  ///< linear RGB in [0, 1]

struct ShowItem {
  ShowKind kind = ShowKind::axes;
  std::optional<ShowRgb> color;  ///< default: the kind's Okabe-Ito colour (app/view/overlays.cpp)
  /// Arrows: m per unit of the quantity (m per rad/s, m per kg m^2/s, m per m/s); none: the run's
  /// largest magnitude is drawn 2x the body's radius. Axes: m, the length of each axis.
  std::optional<double> scale;
  double width = 1;    ///< thickness factor (arrows, axes); trails: px
  double opacity = 1;  ///< in [0, 1]; inertia shapes default to 0.35
  double xray = 0;     ///< opacity of the parts hidden behind bodies (0: not drawn; `xray: true` is 0.35)
  Vec3 point = Vec3::Zero();    ///< trail: m, the body point traced (in `frame` at t = 0);
                                ///< angular_momentum_about: m, the world point O
  bool point_in_world = false;  ///< trail `frame: world`: `point` is where the point is at t = 0
  double length = 3;            ///< trail: s of history shown
  /// forces, joint_forces: m per N m for torques (none: automatic, as `scale`).
  std::optional<double> torque_scale;
  bool gravity = false;  ///< forces: also draw the weight m g at the centre of mass
  bool at_tip =
      false;  ///< forces: the arrow ends at the point of action (`anchor: tip`) instead of starting there
  bool points = true;         ///< contacts: a dot at each contact point
  bool normals = true;        ///< contacts: the contact normal at each point
  bool arrows = true;         ///< contacts: the contact force at each point (forces: the arrows)
  std::vector<double> at;     ///< snapshot: s, the times the copies show the body at
  bool springs = true;        ///< forces: springs drawn as zig-zag lines
  bool spring_lines = false;  ///< forces: ... or as straight lines (`springs: line`: strings, cords)
};

// One field of a HUD line: a quantity ({name}, {body.name}, {name.x}, {|name|}, {joint.name}), or an
// expression over quantities ({a.m * a.v.x + b.m * b.v.x}, {deg(arm.angle)}, {mean(top.precession, 2)}),
// each with an optional Python-style spec after ':' ([+][width][.precision][f|e|g|d]).
struct HudField {
  std::string name;    ///< t, frame, E, E_drift, L_drift; omega, omega_body, L, v, position; angle, ...
                       ///< "expr": an expression; mean, period_of, last_zero, first_contact: measured
  int body = -1;       ///< per-body quantities: the body's index (first_contact: the first body or -1)
  int component = -1;  ///< 0 1 2 for .x .y .z; -1 the whole vector or a scalar
  bool norm = false;   ///< |name|
  std::string printf;  ///< the spec as a printf conversion, e.g. "%+.1e"
  int joint = -1;      ///< per-joint quantities (angle, speed, period and their 2nd-coordinate forms)
  int coord = 0;       ///< ... the joint coordinate: 0, or 1 for angle2, speed2, period2

  // An expression: postfix code over `terms` (quantities, numbers and measured values), evaluated on
  // a fixed stack of kMaxDepth values (app/view/quantities.hpp).
  struct Op {
    enum Kind : uint8_t { number, term, add, sub, mul, div, pow, neg, fn1, atan2 } kind = number;
    double value = 0;                ///< number: the value
    int arg = -1;                    ///< term: index into terms
    double (*fn)(double) = nullptr;  ///< fn1: sqrt, abs, deg, rad, sin, cos, tan, exp, log
  };
  static constexpr int kMaxDepth = 32;
  std::vector<Op> code;
  std::vector<HudField> terms;  ///< expr: its operands; a measured value: its argument (terms[0])
  double window = 0;            ///< mean: s, over the last `window` seconds (0: since t = 0)
  int body2 = -1;               ///< first_contact(a, b): the other body
  std::string source;           ///< as written (a measured value's identity)
  bool is_expr() const { return name == "expr"; }
  bool is_meter() const {
    return name == "mean" || name == "period_of" || name == "last_zero" || name == "first_contact";
  }
  /// A number, not a vector printed as (x, y, z).
  bool scalar() const;
  /// Whether the field or any of its terms is the quantity `name`.
  bool uses(const std::string& name) const;
};
struct HudLine {
  std::vector<std::string> text;  ///< literal text before each field, then the text after the last
  std::vector<HudField> fields;   ///< text.size() == fields.size() + 1
  std::string source;             ///< as written
};

// Text shown over a time range, fading in and out.
struct Caption {
  std::string text;                 ///< TeX subset (render/tex.hpp)
  double from = 0, to = 0;          ///< s of simulated time: shown for from <= t < to
  double fade = 0.3;                ///< s, fade in after `from` and out before `to`
  std::string position = "bottom";  ///< bottom, top, center
};

// Text attached to a body: anchored at its projected centre of mass, plus an offset.
struct BodyLabel {
  int body = -1;
  std::string text;
  bool has_offset = false;       ///< no offset: just above the body's drawn outline
  double dx = 0, dy = 0;         ///< px at 720 lines, right and up
  std::optional<ShowRgb> color;  ///< of the text; default white on the dark panel
};

struct LegendEntry {
  std::string text;
  ShowRgb color{0, 0, 0};
};
struct Legend {
  bool shown = false;
  std::string corner = "top_right";
  std::vector<LegendEntry> items;  ///< empty: filled from the show items that have colours
};

// An inset plot of quantities against time, drawn as the clip advances.
struct PlotSpec {
  std::vector<HudField> quantities;  ///< scalars: t-free HUD names, a component or |...| of a vector
  std::vector<std::string> labels;   ///< legend text per quantity (TeX subset)
  std::vector<std::optional<ShowRgb>> colors;  ///< per quantity; none: Okabe-Ito in order
  double rect[4] = {0.62, 0.62, 0.36, 0.34};   ///< x, y, w, h: fractions of the frame, from the top left
  bool auto_range = true;
  double y_min = 0, y_max = 1;  ///< y_range, when given
  std::string title;            ///< over the plot, optional
};

// Arrows of a group of bodies taken together (`overlays: system:`): its centre of mass C, total
// momentum P, velocity of C (P / M) and angular momentum about C, drawn from C.
struct SystemSpec {
  std::vector<int> bodies;      ///< the members (moving bodies)
  std::vector<ShowItem> show;   ///< momentum, velocity, angular_momentum, center_of_mass
  std::string name = "system";  ///< the legend's word for it
};

struct OverlaySpec {
  std::vector<std::vector<ShowItem>> show;  ///< per body, parallel to Scene::bodies
  std::vector<HudLine> hud;                 ///< lines, top first
  /// top_left, top_right, bottom_left, bottom_right, or auto: the corner the moving bodies cross
  /// least over the clip (their paths from a pre-pass that runs anyway, else where they start;
  /// app/view/overlays_screen.cpp), top_left on a tie or with a moving camera
  std::string hud_corner = "auto";
  std::string title;     ///< drawn at the top centre (shrunk to fit the width)
  double text_size = 1;  ///< factor on the default text size (3.2% of the height)
  std::vector<Caption> captions;
  std::vector<BodyLabel> labels;
  Legend legend;
  std::vector<PlotSpec> plots;
  std::vector<SystemSpec> systems;
  bool any() const;
};

// Reads every body's `show:` and the top-level `overlays:` into s.overlays; throws InputError
// "FILE:LINE:COL: KEY: what" as load_scene does. Called by load_scene once the bodies are read.
void load_overlays(const YAML::Node& root, const std::string& path, Scene& s);

// One body's `show:` list (body: its index in s.bodies), checked as load_overlays checks it; an
// empty list is allowed (a pane's `show:` uses it to hide a body's items).
std::vector<ShowItem> read_show_list(const YAML::Node& list, const scene_yaml::Ctx& c, const Scene& s,
                                     size_t body);

// A quantity as a HUD field or plot names it: "[|][body.]name[.x|.y|.z][|]" or "[joint.]name".
// `default_body`: the body of per-body names without a prefix (-1: the first moving body); a
// per-joint name without a prefix takes the scene's first joint that has a coordinate. Throws
// InputError through `fail` with the message.
HudField parse_quantity(const std::string& field, const Scene& s, int default_body,
                        const std::function<void(const std::string&)>& fail);

// A HUD field or plot quantity: a quantity as parse_quantity reads it, or an expression
// (docs in scenes/README.md, "HUD expressions"): numbers, quantities, + - * / ^, parentheses,
// |x|, sqrt abs deg rad sin cos tan exp log atan2, and the values measured over the physics steps
// mean(q) and mean(q, T), period(q), last_zero(q), first_contact, first_contact(a), first_contact(a, b).
HudField parse_field(const std::string& field, const Scene& s, int default_body,
                     const std::function<void(const std::string&)>& fail);

// The scalar names and the per-body vector names a HUD field may use.
const std::vector<std::string>& hud_scalar_names();
const std::vector<std::string>& hud_body_names();
const std::vector<std::string>& hud_body_scalar_names();  ///< tilt, precession, m, KE: a number per body
/// angle, speed, period, angle2, speed2, period2: a number per joint (rad or m, rad/s or m/s, s)
const std::vector<std::string>& hud_joint_names();

// The moving side of a joint as the World takes it: a joint written [child, world] (or with a
// static body as its child) is turned round. Sets parent and child; false if neither moves.
bool joint_sides(const JointDef& j, const std::vector<BodyDef>& bodies, int& parent, int& child);

}  // namespace simreel
