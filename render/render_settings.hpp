// Every render setting and its default, in one place. A scene's `render:` block sets the
// RenderLook part (app/scene/scene.hpp's RenderSpec is this struct); the command line and the programs
// that draw frames set the rest. No GL here: app/ parses scenes without the renderer.
#pragma once
#include <array>
#include <string>

namespace simreel {

inline constexpr int kDefaultWidth = 1280, kDefaultHeight = 720;  ///< px, of a video and a frame

// Frames between keyframes of an encoded video (the encoder's GOP): 2 s of video. A render split
// into chunks cuts on these intervals (app/cli/chunks.hpp), so its join keeps this cadence.
inline long keyframe_interval(double fps) {
  return fps * 2 < 1 ? 1 : (long)(fps * 2);
}

// fxaa: edge anti-aliasing on the CPU after readback (cheap); msaa2/msaa4: GL multisampling
// (smoother, ~13 ms more a 720p frame on llvmpipe); none.
enum class AntiAliasing { none, fxaa, msaa2, msaa4 };

// standard: one bilinear shadow-map tap, the ground's shadows projected (hard-edged, exact);
// high: soft shadows (a 4x4 grid of bilinear taps, ~4 texels of penumbra) on bodies and the
// ground, whose shadows then come from the map too (drawn every frame, not cached).
enum class RenderQuality { standard, high };

// What a scene says about its look (the `render:` block, scenes/README.md).
struct RenderLook {
  bool shadows = true;
  AntiAliasing antialiasing = AntiAliasing::fxaa;
  RenderQuality quality = RenderQuality::standard;
  std::array<float, 3> background{0.30f, 0.46f, 0.74f};  ///< linear RGB, the sky straight up
  std::array<float, 3> horizon{0.78f, 0.84f, 0.91f};     ///< linear RGB, the sky at the horizon
  bool sky_gradient = true;  ///< false (`sky: flat`): `background` everywhere, a plain backdrop
  bool ground = false;       ///< draw a checkered ground plane
  double ground_height = 0;  ///< m, z of the plane
  double ground_size = 20;   ///< m, side of the square
  double ground_tile = 1;    ///< m, checker tile
  std::array<float, 3> ground_color{0.62f, 0.62f, 0.58f};         ///< linear RGB, even checker tiles
  std::array<float, 3> ground_color2{0.4464f, 0.4464f, 0.4176f};  ///< linear RGB, odd tiles (0.72x)
  std::string ground_texture;      ///< an image file drawn on the ground instead of the checker
  double ground_texture_size = 0;  ///< m, the image's side on the ground (0: two tiles)
};

// Where the frame's CPU stages run: FXAA and then the 2D screen layer (render/screen.hpp), which
// is composited after anti-aliasing so that text stays sharp.
enum class PostStage {
  renderer,  ///< Renderer::render returns the finished frame
  caller,    ///< Renderer::render returns the GL image; the caller finishes it (the video
             ///< writer's thread in `simreel render`: VideoSettings::fxaa and VideoWriter::commit)
};

}  // namespace simreel
