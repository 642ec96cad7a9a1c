// GL passes over a draw list: shadow depth from the key light (orthographic frustum fitted to the
// bodies, skipped while nothing moved), then the lit pass (Blinn-Phong key light with 2 bilinear
// PCF taps, hemisphere fill, checker ground, gamma 2.2) into an FBO (multisampled and resolved if
// msaa > 1), read back, then FXAA on the CPU if enabled.
#pragma once
#include <array>
#include <cstdint>
#include <memory>

#include "render/draw_list.hpp"
#include "render/gl_context.hpp"

namespace simreel {

struct RenderSettings {
  GlBackend gl = default_gl_backend();  ///< OSMesa or EGL; the same frames on llvmpipe
  int width = 1280, height = 720;       ///< px
  int msaa = 1;                         ///< 1, 2 or 4 samples per pixel (GL multisampling)
  bool fxaa = true;  ///< CPU edge anti-aliasing after readback (render/fxaa.hpp); `simreel render`
                     ///< leaves it to the video writer's thread instead (VideoSettings::fxaa)
  bool shadows = true;
  int shadow_size =
      1024;  ///< px, square shadow map over the fitted frustum (2048 costs ~1 ms more a 720p frame)
  std::array<float, 3> background{0.60f, 0.70f, 0.82f};  ///< linear RGB
  bool ground = false;
  double ground_height = 0, ground_size = 20, ground_tile = 1;  ///< m
  std::array<float, 3> ground_color{0.62f, 0.62f, 0.58f};
  /// Draw the unshadowed ground once per projection and copy it into each frame (see
  /// Renderer::render); false for a camera that moves every frame (one that follows a body).
  bool cache_ground = true;
};

struct RenderStats {
  long frames = 0, shadow_passes = 0, shadow_reused = 0;
  long ground_cached = 0, ground_reused = 0;  ///< frames that drew / copied the cached ground
};

class Renderer {
 public:
  Renderer(const RenderSettings& s, const SceneMeshes& meshes);  ///< uploads every mesh once
  ~Renderer();
  // Draws and returns the frame: RGBA8, top row first, width*height*4 bytes, valid until the next
  // call; read back into `out` instead of the renderer's own buffer if given.
  const uint8_t* render(const DrawList& dl, uint8_t* out = nullptr);
  const RenderStats& stats() const;
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace simreel
