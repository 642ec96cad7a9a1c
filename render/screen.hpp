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

// A straight line, anti-aliased: a pixel's coverage falls from 1 to 0 over the pixel at the
// line's edge (its distance from the segment against half the width, plus half a pixel).
struct ScreenLine {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< px, continuous coordinates (a pixel's centre at +0.5), y down
  float width = 1;                       ///< px
  Rgba8 color{255, 255, 255, 255};
};

struct ScreenLayer {
  std::vector<ScreenRect> rects;    ///< drawn first, in order
  std::vector<ScreenLine> lines;    ///< then these (plots' axes and curves)
  std::vector<ScreenGlyph> glyphs;  ///< then these, in order
  void clear() {
    rects.clear();
    lines.clear();
    glyphs.clear();
  }
  bool empty() const { return rects.empty() && lines.empty() && glyphs.empty(); }
  // Appends `other`'s commands (storage reused once grown).
  void append(const ScreenLayer& other) {
    rects.insert(rects.end(), other.rects.begin(), other.rects.end());
    lines.insert(lines.end(), other.lines.begin(), other.lines.end());
    glyphs.insert(glyphs.end(), other.glyphs.begin(), other.glyphs.end());
  }
};

// Blends the layer over an RGBA8 image (rows top first) in place; clipped to the image. Alpha of
// the image is left alone.
void composite(const ScreenLayer& layer, uint8_t* rgba, int width, int height);

}  // namespace simreel
