// The frame in passes over a draw list (render/draw_list.hpp):
//   1. shadow: depth from the key light (orthographic frustum fitted to the bodies, skipped while
//      nothing moved) of the bodies that can shadow another (convex ones facing the light cast no
//      shadow on themselves), looked up only on the bodies another can shadow;
//   2. bodies: the lit pass (Blinn-Phong key light with a bilinear PCF tap, hemisphere fill,
//      checker ground, gamma 2.2) into an FBO, multisampled if MSAA is on; the ground's shadows are
//      the bodies drawn once more flattened onto it along the light (planar projected shadows);
//   3. overlay: unlit 3D geometry (arrows, axes, trails; render/overlay.hpp), depth-tested against
//      the bodies, hidden parts optionally drawn faded (x-ray);
//   then the MSAA resolve and the readback, and on the CPU
//   4. post: FXAA if enabled, then the 2D screen layer (text; render/screen.hpp) composited over
//      the anti-aliased image, so text stays sharp. RenderSettings::post says whether render()
//      does this stage or leaves it to the caller (the video writer's thread).
// A frame is a function of the draw list and the settings only: nothing carried over from earlier
// frames changes a pixel (caches are exact: the ground cache, the reused shadow map).
#pragma once
#include <array>
#include <cstdint>
#include <memory>

#include "render/draw_list.hpp"
#include "render/gl_context.hpp"
#include "render/render_settings.hpp"

namespace simreel {

// The scene's look (render/render_settings.hpp, where every default lives) and how to draw it.
struct RenderSettings : RenderLook {
  GlBackend gl = default_gl_backend();                 ///< OSMesa or EGL; the same frames on llvmpipe
  int width = kDefaultWidth, height = kDefaultHeight;  ///< px
  int shadow_size =
      1024;  ///< px, square shadow map over the fitted frustum (2048 costs ~1 ms more a 720p frame)
  /// Draw the unshadowed ground once per projection and copy it into each frame (see
  /// Renderer::render); false for a camera that moves every frame (one that follows a body).
  bool cache_ground = true;
  /// Where FXAA and the 2D screen layer run: in render(), or left to the caller (`simreel render`
  /// leaves them to the video writer's thread, VideoSettings::fxaa and VideoWriter::commit).
  PostStage post = PostStage::renderer;

  int msaa() const {  ///< GL samples per pixel: 1, 2 or 4
    return antialiasing == AntiAliasing::msaa4 ? 4 : antialiasing == AntiAliasing::msaa2 ? 2 : 1;
  }
  bool fxaa() const {
    return antialiasing == AntiAliasing::fxaa;
  }  ///< CPU edge anti-aliasing (render/fxaa.hpp)
};

struct RenderStats {
  long frames = 0, shadow_passes = 0, shadow_reused = 0;
  long ground_cached = 0, ground_reused = 0;  ///< frames that drew / copied the cached ground
  long meshes = 0;                            ///< body meshes uploaded: one per distinct scene mesh
  size_t mesh_bytes = 0;                      ///< their vertex and index data
};

class Renderer {
 public:
  Renderer(const RenderSettings& s, const SceneMeshes& meshes);  ///< uploads each distinct mesh once
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
