// The frames of a scene as `render` and `check` draw them: one view (app/view/scene_view.hpp), or a
// split screen of panes (the scene's `panes:` and `variants:`, app/scene/scene_views.hpp).
//
// Panes are laid out in a grid (`columns` per row, all in one row by default) with a thin dark
// gutter between them, under a band holding the scene's title when it has one. Each pane is a
// SceneView of its own size with its own renderer: its camera, its title (drawn as the pane's
// overlay title), its HUD with its world's values. The panes' images are copied into the whole
// frame, which is then finished once as a single view's is: FXAA (on the video writer's thread in
// `simreel render`), then every pane's text moved into place, so text stays sharp. Each variant is its own
// World and FrameLoop, advanced at every frame, in the order the variants are listed, to the step nearest the
// simulated time the main world shows: frames are a function of the scene alone, the same for any --threads.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/runner/frame_loop.hpp"
#include "app/view/motion_blur.hpp"
#include "app/view/scene_view.hpp"
#include "render/fxaa.hpp"
#include "render/renderer.hpp"
#include "render/text.hpp"

namespace simreel {

// Where a pane sits in the frame: [x0, x0 + width) x [y0, y0 + height), px, y down.
struct PaneRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};
// The panes' rectangles in a width x height frame: n panes, `columns` per row (0: one row), under
// a band `top` px high. Throws std::invalid_argument when a pane would be under 16 px a side.
std::vector<PaneRect> layout_panes(int n, int columns, int width, int height, int top);

class SceneFrames {
 public:
  // `main` at the scene's initial state; `post`: who runs FXAA and the screen layer of a single
  // view or of the whole split screen.
  SceneFrames(const Scene& scene, FrameLoop& main, const ViewOptions& o,
              PostStage post = PostStage::renderer);
  ~SceneFrames();

  // FrameLoop::Hooks::step for the main loop: every pane's trails on the main world.
  std::function<void(const World&)> step_hook();
  // Draws the frame of the main world's present state (variants advanced to the same simulated
  // time first). `frame`: the video frame's number for the HUD (-1: from the world's time). With
  // post == caller, FXAA (if caller_fxaa()) and screen() are left to the caller.
  // With motion blur the frame is the average of the states blur_hooks() had drawn and this one.
  const uint8_t* draw(const World& main, uint8_t* out = nullptr, long frame = -1);
  // Motion blur (render.motion_blur; nothing without it): sets hooks.sample_steps and hooks.sample
  // so that each frame averages the states in its shutter interval (app/view/motion_blur.hpp).
  // `plan`: the plan whose frames the targets number (the video's for render, the simulation's
  // for check); a target of none (render --at) opens the shutter over 1/fps of simulated time.
  // The overlays' 3D geometry (arrows, trails) is blurred with the bodies; the 2D layer (HUD,
  // captions, plots) is the frame's own, sharp.
  void blur_hooks(FrameLoop::Hooks& hooks, const FramePlan& plan);
  const ScreenLayer& screen() const;  ///< the frame's 2D layer of the last draw()
  bool caller_fxaa() const;           ///< whether the caller must run FXAA (post == caller)
  std::string description() const;    ///< the renderer's
  int width() const { return width_; }
  int height() const { return height_; }
  bool split() const { return !panes_.empty(); }
  // For the warning about empty frames: whether the frame shows no body at all to a camera fixed
  // in the world (false when no pane's camera is: a following or riding camera always sees one).
  bool shows_nothing(const World& main) const;
  // The variants advanced to the main world's present time, as draw() does first.
  void sync(const World& main) { advance_variants(main); }
  // Everything the frames depend on besides the main world's present state: the variants' worlds
  // (advanced to the main world's time: sync() first) and every view's history (trails, periods, a
  // damped follow). A render that restores the main world's state and this at a frame draws the
  // frames after it as a straight render does (app/view/view_state.hpp).
  void save_history(std::ostream& os) const;
  void restore_history(std::istream& is);
  // Every world drawn, main first, then the variants in order (check compares all their states).
  std::vector<const World*> worlds() const;
  /// The variants' notes and the images that could not be decoded (SceneMeshes::notes).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  struct Variant;
  struct Pane;
  void advance_variants(const World& main);
  void compose(const World& main, uint8_t* img, long frame);  // the panes, before the post stage
  const uint8_t* raw(const World& main, long frame);          // the frame before the post stage
  void post(uint8_t* img);                                    // FXAA and text, if post_ says so
  void blur_sample(const FrameTarget& t, const World& main);

  int width_, height_;
  PostStage post_;
  // A single view.
  std::unique_ptr<SceneView> view_;
  std::unique_ptr<Renderer> renderer_;
  // A split screen.
  std::vector<std::unique_ptr<Variant>> variants_;
  std::vector<std::unique_ptr<Pane>> panes_;
  ScreenLayer title_layer_;  // the title band's text
  ScreenLayer screen_;       // the frame's: the title band's and every pane's text, in place
  bool fxaa_ = false;
  FxaaBuffers fxaa_buffers_;
  std::unique_ptr<Font> title_font_;
  std::string title_;
  int band_ = 0;  // px, the title band's height
  std::vector<uint8_t> frame_;
  std::vector<std::string> notes_;
  std::vector<double> radii_;
  FrameLoop* main_;
  // Motion blur: the frame's sum, and the samples of the target being drawn.
  MotionBlurSpec blur_spec_;
  std::unique_ptr<BlurAccumulator> blur_;
  std::vector<BlurSample> blur_samples_;
  long frame_steps_ = 1;      // steps in 1/fps of simulated time
  std::vector<uint8_t> raw_;  // a split screen's sub-frame
};

}  // namespace simreel
