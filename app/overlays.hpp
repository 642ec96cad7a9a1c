// A scene's teaching overlays (app/scene_overlays.hpp) turned into each frame's overlay geometry
// and screen layer (render/overlay.hpp, render/screen.hpp).
//
// Arrows scale themselves: before the run a pre-pass simulates the scene through the app's frame
// loop (the same physics, every step) and keeps each body's largest |omega|, |L| and |v|; that
// magnitude is drawn kArrowReach times the body's radius, unless the item gives `scale:`.
// Trails record a body point at a fixed cadence of physics steps through FrameLoop::Hooks::step,
// into ring buffers sized up front: a frame's trail is a function of the steps before it, the
// same in a partial render (--frames A:B, --at) as in the full one.
// Frames are a function of (state, history of steps, camera, settings): no per-frame allocation
// once the buffers have grown (text glyphs are rasterised once, on first use).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "app/scene.hpp"
#include "render/draw_list.hpp"
#include "render/text.hpp"
#include "sim/world.hpp"

namespace simreel {

inline constexpr double kArrowReach = 2.0;  ///< an auto-scaled arrow's longest, in body radii

// The largest magnitudes over a run, per body.
struct Magnitudes {
  double omega = 0;  ///< rad/s
  double L = 0;      ///< kg m^2/s
  double v = 0;      ///< m/s
};
// The pre-pass: every step of the scene from its initial state, through FrameLoop.
std::vector<Magnitudes> measure_magnitudes(const Scene& scene, int threads);

// Okabe-Ito colour-blind-safe palette (B. Wong, Nature Methods 8, 441, 2011), as linear RGB.
Rgba okabe_ito(int index, float alpha = 1);  ///< 0 black, 1 orange, 2 sky blue, 3 bluish green, 4 yellow,
                                             ///< 5 blue, 6 vermillion, 7 reddish purple

class SceneOverlays {
 public:
  // `body_radius`: m per body, its drawn size about its centre of mass. Runs the pre-pass if an
  // arrow scales itself. width x height: the frame (text sizes follow its height).
  SceneOverlays(const Scene& scene, const World& world, const std::vector<double>& body_radius, int width,
                int height, int threads = 1);
  ~SceneOverlays();
  bool empty() const { return items_.empty() && hud_.empty() && title_.empty(); }
  bool has_trails() const { return !trails_.empty(); }

  // FrameLoop::Hooks::step: records the trails.
  void record(const World& w);
  // The world's present state into dl.overlay and dl.screen (dl.camera set already). frame: the
  // frame's number in the clip (HUD {frame}).
  void build(const World& w, long frame, DrawList& dl);

  // The scale in use for a body's arrow item (m per unit), for tests.
  double arrow_scale(int body, ShowKind kind) const;

 private:
  struct Item {
    int body;
    ShowItem spec;
    double scale = 0;          // arrows, poinsot: m per unit; axes: m; centre of mass: m radius
    double radius = 0;         // m, arrow shaft
    int trails[2] = {-1, -1};  // poinsot: its polhode and herpolhode
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
  void build_hud(const World& w, long frame, ScreenLayer& out);
  Vec3 sample(const Trail& t, const World& w) const;                   // what a trail records now
  Vec3 to_world(const Trail& t, const World& w, const Vec3& v) const;  // a recorded sample, drawn now
  void add_trail(int body, const ShowItem& s, Source src, const Rgba& color, int height);

  int width_, height_;
  double dt_, duration_, fps_;
  std::vector<double> body_radius_;
  std::vector<Item> items_;
  std::vector<Trail> trails_;
  std::vector<HudLine> hud_;
  std::string hud_corner_, title_;
  double E0_ = 0;
  Vec3 L0_ = Vec3::Zero();
  std::unique_ptr<Font> font_, title_font_;
  std::vector<std::string> lines_;  // HUD text this frame, storage reused
};

// A HUD line with its fields filled from the world; `out` keeps its storage. `fps`: the video's,
// for {video_t} = frame / fps (app/scene_time.hpp; 0: the simulated time).
void format_hud_line(const HudLine& line, const World& w, long frame, double E0, const Vec3& L0,
                     std::string& out, double fps = 0);

}  // namespace simreel
