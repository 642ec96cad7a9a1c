// The 2D screen layer: what is drawn over a finished frame in pixel coordinates (text, panels),
// after anti-aliasing, on the CPU. A layer is a list of commands that refer to glyph bitmaps
// owned by a Font (render/text.hpp), cheap to copy into the video writer's queue with its frame.
// Compositing is integer arithmetic: the same bytes on every machine and every run.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace simreel {

using Rgba8 = std::array<uint8_t, 4>;  ///< display (gamma-encoded) RGB and alpha, 0-255

// One rasterised glyph: 8-bit coverage, rows top first.
struct GlyphBitmap {
  int width = 0, height = 0;      ///< px
  int left = 0, top = 0;          ///< px, from the pen position to the bitmap's top-left (top: up)
  std::vector<uint8_t> coverage;  ///< width * height
};

struct ScreenGlyph {
  const GlyphBitmap* bitmap = nullptr;  ///< owned by the Font, which outlives every frame using it
  int x = 0, y = 0;                     ///< px, the bitmap's top-left pixel (y down)
  Rgba8 color{255, 255, 255, 255};
};

struct ScreenRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< px, [x0, x1) x [y0, y1), y down
  Rgba8 color{0, 0, 0, 128};
};

struct ScreenLayer {
  std::vector<ScreenRect> rects;    ///< drawn first, in order
  std::vector<ScreenGlyph> glyphs;  ///< then these, in order
  void clear() {
    rects.clear();
    glyphs.clear();
  }
  bool empty() const { return rects.empty() && glyphs.empty(); }
};

// Blends the layer over an RGBA8 image (rows top first) in place; clipped to the image. Alpha of
// the image is left alone.
void composite(const ScreenLayer& layer, uint8_t* rgba, int width, int height);

}  // namespace simreel
