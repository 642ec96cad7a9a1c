// A scene's teaching overlays (app/scene/scene_overlays.hpp) turned into each frame's overlay geometry
// and screen layer (render/overlay.hpp, render/screen.hpp).
//
// Arrows scale themselves: before the run a pre-pass simulates the scene through the app's frame
// loop (the same physics, every step) and keeps each body's largest |omega|, |L| and |v|; that
// magnitude is drawn kArrowReach times the body's radius, unless the item gives `scale:`.
// Trails record a body point at a fixed cadence of physics steps through FrameLoop::Hooks::step,
// into ring buffers sized up front: a frame's trail is a function of the steps before it, the
// same in a partial render (--frames A:B, --at) as in the full one. Measured values (a joint's
// period, mean(q), ...: StepMeters, app/view/quantities.hpp) are recorded through the same hook.
// Frames are a function of (state, history of steps, camera, settings): no per-frame allocation
// once the buffers have grown (text glyphs are rasterised once, on first use).
#pragma once
#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <simreel/world.hpp>
#include "app/scene/scene.hpp"
#include "app/view/quantities.hpp"
#include "app/view/view_state.hpp"
#include "render/draw_list.hpp"
#include "render/plot.hpp"
#include "render/text.hpp"

namespace simreel {

inline constexpr double kArrowReach = 2.0;  ///< an auto-scaled arrow's longest, in body radii
inline constexpr double kForceReach = 3.0;  ///< an auto-scaled applied force's longest, in body radii
inline constexpr double kContactReach =
    1.0;  ///< an auto-scaled contact force's typical length, in body radii
inline constexpr double kContactQuantile = 0.9;  ///< ... is the contact forces' 90th percentile
inline constexpr double kReactionFloor =
    1e-6;  ///< joint_forces: a largest reaction under this fraction of its scale is round-off, not drawn
/// px at 720 lines: the least thickness of an arrow (times its `width`). An auto-scaled arrow is
/// 0.056 body radii thick: an 8 cm bob seen from 3 m at 720 lines is 2.6 px, from 6 m 1.3 px,
/// which reads as a hairline; 3 px reads as an arrow in a 1280x720 clip and in its GIF.
inline constexpr double kMinArrowPx = 3.0;
inline constexpr double kMinArrowPxSmall = 2.4;  ///< px: the least on any frame
inline constexpr long kMaxTrailPoints = 16384;   ///< a trail's samples at most (long trails sample sparser)

// The largest magnitudes over a run, per body.
struct Magnitudes {
  double omega = 0;    ///< rad/s
  double L = 0;        ///< kg m^2/s
  double v = 0;        ///< m/s
  double p = 0;        ///< kg m/s
  double L_about = 0;  ///< kg m^2/s, angular momentum about an `angular_momentum_about` item's point
  double force = 0;    ///< N, the largest applied force drawn as an arrow (force, spring and drag entries)
  double torque = 0;   ///< N m, the largest torque entry
  double joint_force = 0;   ///< N, the largest reaction force through the joint holding the body
  double joint_torque = 0;  ///< N m, ... and the largest reaction torque (World::joint_reaction)
};
// The pre-pass: every step of the scene from its initial state, through FrameLoop.
std::vector<Magnitudes> measure_magnitudes(const Scene& scene, int threads);
// The forces `forces:` applies to each body at the world's present state, as the `forces` item
// draws them: force(body, F_W, at_W, kind) for every force, spring (at each end) and drag entry
// acting now, torque(body, tau_W) for every torque entry (impulses are instantaneous: not drawn).
struct ForceVisitor {
  virtual void force(int body, const Vec3& F_W, const Vec3& at_W, ForceKind kind) = 0;
  virtual void torque(int body, const Vec3& tau_W) = 0;
  virtual ~ForceVisitor() = default;
};
void visit_forces(const World& w, ForceVisitor& v);
// The contact force on `body` at each of its contact points: F = (lambda n + friction share) / h,
// with lambda the point's normal impulse of the last substep, h = dt / substeps, the manifold's
// friction impulse shared among its points in proportion to lambda; n points into `body`.
// Calls f(point_W, normal_W (into the body), F_W) for each point of each touching manifold.
template <class F>
void visit_contacts(const World& w, int body, F&& f) {
  // The step's contacts and those of sleeping pairs (kept as they were when the pair fell asleep),
  // each read from `body`'s side. The buffer keeps its capacity: no allocation once warm.
  static thread_local std::vector<ContactData> pairs;
  pairs.clear();
  w.body_contacts(body, pairs);
  for (const ContactData& c : pairs)
    for (int j = 0; j < c.count; ++j) f(c.points[j].p_W, c.normal_W, c.points[j].force_W);
}

// Okabe-Ito colour-blind-safe palette (B. Wong, Nature Methods 8, 441, 2011), as linear RGB.
Rgba okabe_ito(int index, float alpha = 1);  ///< 0 black, 1 orange, 2 sky blue, 3 bluish green, 4 yellow,
                                             ///< 5 blue, 6 vermillion, 7 reddish purple, 8 dark yellow

// The colour overlaid variant k of `views` is drawn in, with its opacity: its `overlay.color`, else
// in turn Okabe-Ito sky blue, orange, reddish purple, bluish green, vermillion, blue (they read over
// the scene's own bodies).
Rgba variant_color(const ViewsSpec& views, size_t k);

// The colour an item is drawn in: its `color` or its kind's Okabe-Ito colour, with its opacity.
Rgba item_color(const ShowItem& s);

// The colour `joints` draws a rope in (rod: a distance joint without bounds or spring): its
// `color` if given, else dark tan (a rod: grey), with its opacity.
Rgba rope_color(const ShowItem& s, bool rod);

class SceneOverlays {
 public:
  // `body_radius`: m per body, its drawn size about its centre of mass. Runs the pre-pass if an
  // arrow scales itself. width x height: the frame (text sizes follow its height).
  // `store`: where the pre-pass's products are recorded, or replayed from instead of running it
  // (a chunk of a render, app/view/view_state.hpp); null: run it.
  // `fixed_camera`: the camera when it stands still over the clip (the HUD's `auto` corner is
  // chosen against the bodies' paths as it sees them; none: top_left).
  SceneOverlays(const Scene& scene, const World& world, const std::vector<double>& body_radius, int width,
                int height, int threads = 1, PrepassStore* store = nullptr,
                const CameraView* fixed_camera = nullptr);
  ~SceneOverlays();
  bool empty() const { return items_.empty() && !has_screen_; }
  bool has_trails() const { return !trails_.empty(); }
  // Whether record() must see every physics step: trails, or a joint's measured period.
  bool records_steps() const { return !trails_.empty() || !meters_.empty() || !snapshots_.empty(); }
  const StepMeters& meters() const { return meters_; }
  // Samples trail k can hold (its ring's size), and the physics steps between its samples.
  size_t trail_capacity(int k) const { return trails_[k].points.size(); }
  long trail_every(int k) const { return trails_[k].every; }

  // FrameLoop::Hooks::step: records the trails and the measured values.
  void record(const World& w);
  // The history record() gathered (trails, measured values), for a render that resumes mid-clip.
  void save_history(std::ostream& os) const;
  void restore_history(std::istream& is);
  // The world's present state into dl.overlay and dl.screen (dl.camera set already). frame: the
  // frame's number in the clip (HUD {frame}).
  void build(const World& w, long frame, DrawList& dl);
  // The `snapshot` items' copies taken by now, drawn with the bodies' render meshes into dl.overlay
  // (after build()).
  void build_snapshots(const World& w, const SceneMeshes& meshes, DrawList& dl) const;
  bool has_snapshots() const { return !snapshots_.empty(); }

  // The scale in use for a body's arrow item (m per unit), for tests. Forces, joint forces: m per N;
  // torques (kind forces or joint_forces, torque = true): m per N m; contacts: m per N.
  double arrow_scale(int body, ShowKind kind, bool torque = false) const;
  // Inset plot k, as drawn (for tests), and its samples.
  const InsetPlot& plot(int k) const { return *plots_[k].plot; }
  const std::vector<double>& plot_times(int k) const { return plots_[k].t; }
  const std::vector<float>& plot_values(int k, int q) const { return plots_[k].values[q]; }
  // What system k's item j draws at the world's state: an arrow from `from` along `vec` (m; for
  // center_of_mass, vec is zero and `from` the centre). For tests.
  void system_arrow(int k, int j, const World& w, Vec3& from, Vec3& vec) const;
  // What body `body`'s arrow item of `kind` (angular_velocity, angular_momentum, velocity, momentum,
  // angular_momentum_about) draws: from `from` along `vec` (m). False: the body shows none.
  bool item_arrow(int body, ShowKind kind, const World& w, Vec3& from, Vec3& vec) const;
  // A label's box on screen: centre x, y and size w, h (px), and which label it is.
  struct LabelBox {
    double x, y, w, h;
    size_t label;
  };
  // The labels of the last frame drawn, placed (kept apart and inside the frame). For tests.
  const std::vector<LabelBox>& label_boxes() const { return label_boxes_; }
  // The HUD's corner (`auto` resolved).
  const std::string& hud_corner() const { return hud_corner_; }
  // The legend's entries as drawn (filled from the show items when the scene lists none).
  const Legend& legend() const { return legend_; }
  // The colour the item of kind `kind` of body `body` is drawn in (its colour resolved against
  // the other items', resolve_colors in overlays.cpp).
  Rgba color_of(int body, ShowKind kind) const;
  // The title's size after shrinking it to fit the frame (px).
  int title_pixel_size() const { return title_font_ ? title_font_->pixel_size() : 0; }

 private:
  struct Item {
    int body;
    ShowItem spec;
    double scale = 0;          // arrows, poinsot: m per unit; axes: m; centre of mass: m radius
    double radius = 0;         // m, arrow shaft
    int trails[2] = {-1, -1};  // poinsot: its polhode and herpolhode
    double torque_scale = 0;   // forces: m per N m
    int joint = -1;            // joints, joint_forces: index into joints_
  };
  // A joint as the `joints` and `joint_forces` items draw it: the anchor in the child's frame (it
  // moves with the child), the axis fixed in the parent (or the world) and, universal, axis2 fixed
  // in the child. With limits, what the range is drawn from (all in the parent's frame, as the
  // bodies were at t = 0): the child's start direction from the pivot, perpendicular to the axis
  // (universal: also to axis2, with axis2 at t = 0), and a slider's anchor at t = 0.
  struct JointLook {
    int index = -1;  // the scene's (and the World's) joint index
    int parent = -1, child = -1;
    JointType type = JointType::revolute;
    Vec3 anchor_C, axis_P, axis2_C;
    double sign = 1;  // -1: written [child, world], the coordinate turns (slides) about -axis
    std::optional<JointLimits> limits;
    Vec3 start_P = Vec3::Zero(), start2_P = Vec3::Zero(), axis2_P = Vec3::Zero(), anchor_P = Vec3::Zero();
    std::optional<BallLimits> ball;  // a ball joint's cone and twist stops (about axis)
    Quat q_P0 = Quat::Identity(), q_C0 = Quat::Identity();  // the bodies' start orientations
  };
  // A rope (a distance or pulley joint) as the `joints` item of one of its end bodies draws it:
  // each end's point fixed in its body (in the world where that end is the world or a static
  // body), and a pulley's fixed points. A rope shown from both ends is drawn once, by the first.
  struct RopeLook {
    int index = -1;                        // the scene's (and the World's) joint index
    int body = -1;                         // the body whose `joints` item draws it
    JointType type = JointType::distance;  // distance or pulley
    int end[2] = {-1, -1};                 // the parent's and the child's body; -1: fixed (world points)
    Vec3 point[2] = {Vec3::Zero(), Vec3::Zero()};     // anchor, anchor2: in end[k]'s frame (or world)
    Vec3 pulley_W[2] = {Vec3::Zero(), Vec3::Zero()};  // pulley: its fixed points
    bool wheel = false;                               // pulley: over a wheel body (which draws itself)
    bool rod = false;                                 // distance: a rigid rod (no bounds, no spring)
  };
  struct Plot {
    PlotSpec spec;
    std::unique_ptr<InsetPlot> plot;
    std::vector<double> t;                   // s, the samples' times
    std::vector<std::vector<float>> values;  // per quantity
    std::vector<const float*> series;        // values[q].data()
    long every = 1;                          // steps between samples
    std::vector<float> now;                  // the values at the frame drawn
  };

  // What a trail traces: a body point (world), or Poinsot's contact point k omega, recorded on
  // the principal axes (the polhode, drawn on the moving body) or in the world (the herpolhode,
  // drawn on the fixed invariable plane), both from the centre of mass.
  enum class Source { point, polhode, herpolhode };
  struct Trail {
    int body;
    Source source = Source::point;
    double k = 0;  // m per rad/s (polhode, herpolhode)
    Vec3 p_B;      // m, the traced point in the body frame
    Rgba color;
    double width_px;
    long every;                // steps between samples
    long span;                 // steps of history shown
    std::vector<Vec3> points;  // ring
    std::vector<long> steps;   // ring, the step of each point
    size_t head = 0, count = 0;
    long last = -1;
    std::vector<Vec3> scratch;  // the drawn polyline, reused
    std::vector<Rgba> colors;   // its colours, reused
  };
  void build_screen(const World& w, long frame, const CameraView& cam, ScreenLayer& out);
  void build_forces(const Item& it, const World& w, const CameraView& cam, OverlayList& out);
  void build_contacts(const Item& it, const World& w, const CameraView& cam, OverlayList& out);
  void build_joint(const Item& it, const World& w, const CameraView& cam, OverlayList& out);
  // A ball joint's cone and twist stops (build_joint's, for a spherical joint with BallLimits).
  void ball_limits(const JointLook& L, const World& w, const Vec3& p, const Vec3& a, double len, double shaft,
                   double ball, const Rgba& color, float xray, OverlayList& out) const;
  void build_joint_forces(const Item& it, const World& w, const CameraView& cam, OverlayList& out);
  int add_joint_look(const Scene& scene, const World& world, int body);  // index into joints_, or -1
  int add_rope_looks(const Scene& scene, int body);  // the ropes at `body` (drawn by it or another)
  void build_ropes(const Item& it, const World& w, const CameraView& cam, OverlayList& out);
  void prepass(const Scene& scene, int threads, bool magnitudes, std::vector<Magnitudes>& mags,
               std::vector<Magnitudes>& system_mags, std::vector<double>& contact_forces);
  void save_prepass(std::ostream& os, const std::vector<Magnitudes>& mags,
                    const std::vector<Magnitudes>& system_mags, double contact_kth) const;
  void load_prepass(std::istream& is, std::vector<Magnitudes>& mags, std::vector<Magnitudes>& system_mags,
                    double& contact_kth);
  void make_screen(const Scene& scene, const World& world);
  void build_systems(const World& w, const CameraView& cam, OverlayList& out);
  void arrow_of(const Item& it, const World& w, Vec3& from, Vec3& vec) const;  // an arrow item's
  // m: an arrow's least shaft radius where a pixel is `px` m: kMinArrowPx thick at 720 lines, in
  // proportion on taller frames, and never under kMinArrowPxSmall on small ones (a GIF, a golden).
  double min_arrow_radius(double px) const {
    return 0.5 * std::max(kMinArrowPx * height_ / 720.0, kMinArrowPxSmall) * px;
  }
  void fill_legend(const Scene& scene);

  Vec3 sample(const Trail& t, const World& w) const;                   // what a trail records now
  Vec3 to_world(const Trail& t, const World& w, const Vec3& v) const;  // a recorded sample, drawn now
  void add_trail(int body, const ShowItem& s, Source src, const Rgba& color, int height);

  int width_, height_;
  double dt_, duration_, fps_;
  std::vector<double> body_radius_;
  std::vector<Item> items_;
  std::vector<Trail> trails_;
  std::vector<JointLook> joints_;
  std::vector<RopeLook> ropes_;
  StepMeters meters_;  // the HUD's and plot cursors' periods and measured values
  std::vector<HudLine> hud_;
  std::string hud_corner_, title_;
  std::vector<Caption> captions_;
  std::vector<BodyLabel> labels_;
  Legend legend_;
  std::vector<Plot> plots_;
  // `system:` groups, their items' scales (m per unit; center_of_mass: m radius) and shaft radius.
  struct SystemLook {
    SystemSpec spec;
    std::vector<double> scale;
    double radius = 0, size = 0;  // m: the arrows' shaft, the members' largest drawn radius
  };
  std::vector<SystemLook> systems_;
  // A `snapshot` item's copy: the body's pose at the first step at or after `at` (half a step's
  // tolerance), recorded by record() and drawn from then on.
  struct Snapshot {
    int body = -1;
    double at = 0;
    Rgba color;
    bool taken = false;
    Vec3 x = Vec3::Zero();  // m, the centre of mass
    Quat q = Quat::Identity();
  };
  std::vector<Snapshot> snapshots_;
  std::vector<std::vector<ShowItem>> show_;  // the scene's items, their colours resolved (legend)
  bool has_screen_ = false;
  size_t max_lines_ = 0;            // screen lines a frame may hold (plots), reserved once
  std::vector<char> shows_forces_;  // per body: has a `forces` item (springs drawn once)
  double E0_ = 0;
  Vec3 L0_ = Vec3::Zero();
  std::unique_ptr<Typeface> font_, title_font_, small_font_;
  std::vector<std::string> lines_;     // HUD text this frame, storage reused
  std::vector<LabelBox> label_boxes_;  // labels this frame
  // The HUD's `auto` corner: the moving bodies' centres of mass sampled over the pre-pass (every
  // kHudSampleEvery-th of the run, each sample all of them), and the fixed camera that sees them.
  std::vector<Vec3> hud_samples_;
  std::vector<int> hud_bodies_;
  std::optional<CameraView> hud_camera_;
  void choose_hud_corner(const World& world);  // labels this frame: centre x, y, w, h (px), index
  std::string scratch_text_;                   // storage reused
  std::vector<Vec3> spring_points_;            // a spring's zig-zag, reused
  std::vector<Rgba> spring_colors_;
};

// A linear RGB colour as the screen layer's display (sRGB-encoded) bytes.
Rgba8 to_display(const Rgba& linear);

}  // namespace simreel
