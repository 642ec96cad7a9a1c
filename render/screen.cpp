#include "render/screen.hpp"

#include <algorithm>

namespace simreel {

namespace {

// d + (s - d) a / 255, rounded, in integers.
inline uint8_t blend(uint8_t d, uint8_t s, int a) {
  const int v = (int)d * (255 - a) + (int)s * a;
  return (uint8_t)((v + 127) / 255);
}

}  // namespace

void composite(const ScreenLayer& layer, uint8_t* rgba, int width, int height) {
  for (const ScreenRect& r : layer.rects) {
    const int x0 = std::max(r.x0, 0), x1 = std::min(r.x1, width);
    const int y0 = std::max(r.y0, 0), y1 = std::min(r.y1, height);
    const int a = r.color[3];
    for (int y = y0; y < y1; ++y) {
      uint8_t* p = rgba + ((size_t)y * width + x0) * 4;
      for (int x = x0; x < x1; ++x, p += 4)
        for (int c = 0; c < 3; ++c) p[c] = blend(p[c], r.color[c], a);
    }
  }
  for (const ScreenGlyph& g : layer.glyphs) {
    const GlyphBitmap& b = *g.bitmap;
    const int x0 = std::max(g.x, 0), x1 = std::min(g.x + b.width, width);
    const int y0 = std::max(g.y, 0), y1 = std::min(g.y + b.height, height);
    for (int y = y0; y < y1; ++y) {
      const uint8_t* cov = b.coverage.data() + (size_t)(y - g.y) * b.width + (x0 - g.x);
      uint8_t* p = rgba + ((size_t)y * width + x0) * 4;
      for (int x = x0; x < x1; ++x, p += 4, ++cov) {
        if (!*cov) continue;
        const int a = (*cov * g.color[3] + 127) / 255;
        for (int c = 0; c < 3; ++c) p[c] = blend(p[c], g.color[c], a);
      }
    }
  }
}

}  // namespace simreel
