// A scene as the renderer takes it: the render meshes and colours, the camera and the render
// settings, made in one place for every command that draws frames (render, check).
#pragma once
#include <string>

#include "app/scene.hpp"
#include "render/draw_list.hpp"
#include "render/renderer.hpp"
#include "sim/world.hpp"

namespace simreel {

// Overrides of the scene's drawing, from the command line.
struct ViewOptions {
  int width = 0, height = 0;  ///< px; 0: the scene's (odd sizes round up to even for video)
  std::string aa;             ///< "": the scene's; fxaa, msaa2, msaa4, none
  bool no_shadows = false;
  std::string gl;  ///< "": the default backend; osmesa, egl
};

struct SceneView {
  SceneMeshes meshes;
  CameraView camera;
  int follow = -1;  ///< body the camera tracks, or -1
  RenderSettings settings;
  AntiAliasing aa = AntiAliasing::fxaa;
  // Throws UsageError-like std::invalid_argument for an unknown backend or mode.
  SceneView(const Scene& scene, const World& world, const ViewOptions& o);
  // The frame of the world's present state, FXAA included when the settings ask for it in the
  // renderer; valid until the next call.
  const uint8_t* draw(Renderer& r, const World& world, uint8_t* out = nullptr);

 private:
  DrawList dl_;
};

}  // namespace simreel
