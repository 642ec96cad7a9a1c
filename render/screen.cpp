#include "render/screen.hpp"

#include <algorithm>
#include <cmath>

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
  for (const ScreenLine& l : layer.lines) {
    // Coverage from the distance d of the pixel's centre to the segment: clamp(w/2 + 1/2 - d, 0, 1).
    const float hw = 0.5f * l.width;
    const float ex = hw + 1.0f;
    const int x0 = std::max(0, (int)std::floor(std::min(l.x0, l.x1) - ex));
    const int x1 = std::min(width, (int)std::ceil(std::max(l.x0, l.x1) + ex));
    const int y0 = std::max(0, (int)std::floor(std::min(l.y0, l.y1) - ex));
    const int y1 = std::min(height, (int)std::ceil(std::max(l.y0, l.y1) + ex));
    const float dx = l.x1 - l.x0, dy = l.y1 - l.y0, len2 = dx * dx + dy * dy;
    for (int y = y0; y < y1; ++y) {
      uint8_t* p = rgba + ((size_t)y * width + x0) * 4;
      for (int x = x0; x < x1; ++x, p += 4) {
        const float px = x + 0.5f - l.x0, py = y + 0.5f - l.y0;
        float t = len2 > 0 ? (px * dx + py * dy) / len2 : 0.0f;
        t = std::min(1.0f, std::max(0.0f, t));
        const float qx = px - t * dx, qy = py - t * dy;
        const float cover = hw + 0.5f - std::sqrt(qx * qx + qy * qy);
        if (cover <= 0) continue;
        const int a = (int)std::lround(std::min(1.0f, cover) * l.color[3]);
        for (int c = 0; c < 3; ++c) p[c] = blend(p[c], l.color[c], a);
      }
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
