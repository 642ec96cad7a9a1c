// Every render setting and its default, in one place. A scene's `render:` block sets the
// RenderLook part (app/scene/scene.hpp's RenderSpec is this struct); the command line and the programs
// that draw frames set the rest. No GL here: app/ parses scenes without the renderer.
#pragma once
#include <array>

namespace simreel {

inline constexpr int kDefaultWidth = 1280, kDefaultHeight = 720;  ///< px, of a video and a frame

// fxaa: edge anti-aliasing on the CPU after readback (cheap); msaa2/msaa4: GL multisampling
// (smoother, ~13 ms more a 720p frame on llvmpipe); none.
enum class AntiAliasing { none, fxaa, msaa2, msaa4 };

// What a scene says about its look (the `render:` block, scenes/README.md).
struct RenderLook {
  bool shadows = true;
  AntiAliasing antialiasing = AntiAliasing::fxaa;
  std::array<float, 3> background{0.60f, 0.70f, 0.82f};  ///< linear RGB, top of the sky
  bool ground = false;                                   ///< draw a checkered ground plane
  double ground_height = 0;                              ///< m, z of the plane
  double ground_size = 20;                               ///< m, side of the square
  double ground_tile = 1;                                ///< m, checker tile
};

// Where the frame's CPU stages run: FXAA and then the 2D screen layer (render/screen.hpp), which
// is composited after anti-aliasing so that text stays sharp.
enum class PostStage {
  renderer,  ///< Renderer::render returns the finished frame
  caller,    ///< Renderer::render returns the GL image; the caller finishes it (the video
             ///< writer's thread in `simreel render`: VideoSettings::fxaa and VideoWriter::commit)
};

}  // namespace simreel
