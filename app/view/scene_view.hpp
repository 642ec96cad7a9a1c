// A scene as the renderer takes it: the render meshes and colours, the camera, the render
// settings and the teaching overlays (app/view/overlays.hpp), made in one place for every command that
// draws frames (render, check).
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <simreel/world.hpp>
#include "app/scene/scene.hpp"
#include "app/view/ghost_view.hpp"
#include "app/view/overlays.hpp"
#include "render/draw_list.hpp"
#include "render/renderer.hpp"

namespace simreel {

// Overrides of the scene's drawing, from the command line.
struct ViewOptions {
  int width = 0, height = 0;  ///< px; 0: the scene's (odd sizes round up to even for video)
  std::string aa;             ///< "": the scene's; fxaa, msaa2, msaa4, none
  bool no_shadows = false;
  std::string gl;                   ///< "": the default backend; osmesa, egl
  int threads = 1;                  ///< for the overlays' pre-pass (frames are the same for any count)
  PrepassStore* prepass = nullptr;  ///< record or replay the pre-passes (app/view/view_state.hpp)
};

struct SceneView {
  SceneMeshes meshes;
  CameraView camera;
  int follow = -1;  ///< body the camera tracks, or -1
  int ride = -1;    ///< body whose frame the camera rides in (camera.frame), or -1: `camera` is then
                    ///< in that body's frame (points about its origin)
  // A moving camera (app/scene/camera_motion.hpp): `camera` is then the camera block's values,
  // which the path's keys, the orbit or the damped follow move at each frame.
  CameraPath path;                       ///< keys of `camera.path` (empty: none)
  std::optional<CameraOrbit> orbit;      ///< `camera.orbit`
  int orbit_body = -1;                   ///< the body the orbit circles, or -1 (its fixed centre)
  std::vector<int> aim;                  ///< `camera.aim`: the bodies whose centre of mass it turns to
  std::unique_ptr<DampedFollow> damped;  ///< `follow: { damping > 0 }`, advanced by step_hook()
  RenderSettings settings;
  AntiAliasing aa = AntiAliasing::fxaa;
  std::unique_ptr<SceneOverlays> overlays;  ///< null for a scene without `show:` or `overlays:`
  std::unique_ptr<GhostView> ghosts;        ///< null for a scene without `ghost:`
  /// Other worlds of the same scene (overlaid variants) drawn over this one's bodies as translucent
  /// copies of their moving bodies, each in its colour (with its opacity).
  std::vector<std::pair<const World*, Rgba>> overlaid;
  // Throws UsageError-like std::invalid_argument for an unknown backend or mode. `world` must be
  // at the scene's initial state (trails given in world coordinates, the HUD's E0 and L0).
  SceneView(const Scene& scene, const World& world, const ViewOptions& o);
  // The frame of the world's present state, with the post stage (FXAA, screen layer) when the
  // settings leave it to the renderer; valid until the next call. `frame`: the frame's number in
  // the clip for the HUD (-1: the nearest frame to the world's time).
  const uint8_t* draw(Renderer& r, const World& world, uint8_t* out = nullptr, long frame = -1);
  // The screen layer of the last draw(): for a caller that runs the post stage itself.
  const ScreenLayer& screen() const { return dl_.screen; }
  // The camera of the last draw(), in the world (after path, orbit, follow and riding).
  const CameraView& drawn_camera() const { return dl_.camera; }
  // The last frame's overlay geometry (arrows, ghosts, snapshots), for tests.
  const OverlayList& overlay() const { return dl_.overlay; }
  // Whether the camera moves by path or orbit (a fixed camera otherwise, unless it follows or rides).
  bool moving() const { return !path.empty() || orbit.has_value() || !aim.empty(); }
  // For FrameLoop::Hooks::step: records trails and joints' periods, and advances a damped follow,
  // at every physics step (empty if there is none of these).
  std::function<void(const World&)> step_hook();
  // What step_hook() has gathered (trails, periods, the damped follow), for a render that resumes
  // mid-clip (app/view/view_state.hpp).
  void save_history(std::ostream& os) const;
  void restore_history(std::istream& is);

 private:
  DrawList dl_;
  double fps_ = 30;
};

}  // namespace simreel
