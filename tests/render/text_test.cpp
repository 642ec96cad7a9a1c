// Text for the screen layer (render/text.hpp): shaped and rasterised the same way every time,
// placed by the font's metrics, composited without blur.
#include <gtest/gtest.h>

#include <vector>

#include "render/screen.hpp"
#include "render/text.hpp"

namespace simreel {
namespace {

constexpr int W = 200, H = 60;

// The string drawn white on black; returns the image.
std::vector<uint8_t> draw_text(Font& f, const std::string& s, int x, int baseline) {
  ScreenLayer layer;
  f.draw(s, x, baseline, {255, 255, 255, 255}, &layer);
  std::vector<uint8_t> img((size_t)W * H * 4, 0);
  composite(layer, img.data(), W, H);
  return img;
}

// The box of lit pixels in columns [x0, x1): {left, top, right, bottom} (inclusive), -1 if none.
std::array<int, 4> ink_box(const std::vector<uint8_t>& img, int x0, int x1) {
  std::array<int, 4> b{-1, -1, -1, -1};
  for (int y = 0; y < H; ++y)
    for (int x = x0; x < x1; ++x)
      if (img[((size_t)y * W + x) * 4] > 64) {
        if (b[0] < 0) b = {x, y, x, y};
        b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y)};
      }
  return b;
}

TEST(Text, GlyphsSitOnTheBaselineWhereTheFontPutsThem) {
  Font f(default_font_path(), 24);
  const int x = 10, baseline = 40;
  const std::vector<uint8_t> img = draw_text(f, "Hg", x, baseline);
  const int h_advance = f.width("H");
  // H: from the pen (DejaVu's left bearing ~2 px) up to the cap height (0.729 em = 17.5 px),
  // standing on the baseline.
  const auto H_box = ink_box(img, 0, x + h_advance);
  EXPECT_NEAR(H_box[0], x + 2, 1);
  EXPECT_EQ(H_box[3], baseline - 1);
  EXPECT_NEAR(baseline - H_box[1], 17.5, 1.0);
  // g: starts after H's advance and descends below the baseline (descender ~0.24 em).
  const auto g_box = ink_box(img, x + h_advance, W);
  EXPECT_GE(g_box[0], x + h_advance);
  EXPECT_LT(g_box[0], x + h_advance + 4);
  EXPECT_GT(g_box[3], baseline + 3);
  EXPECT_GT(f.width("Hg"), h_advance);
}

TEST(Text, SameBytesEveryTimeAndFromEveryFontInstance) {
  Font a(default_font_path(), 22), b(default_font_path(), 22);
  const std::string s = "t = 3.00 s  ω₁ = +0.25 rad/s  E/E₀ − 1 = -5.5e-11";
  const auto first = draw_text(a, s, 3, 30);
  EXPECT_EQ(first, draw_text(a, s, 3, 30));  // from the glyph cache
  EXPECT_EQ(first, draw_text(b, s, 3, 30));  // rasterised afresh
  // Moved by whole pixels, the same pixels moved.
  const auto moved = draw_text(a, s, 4, 31);
  for (int y = 0; y + 1 < H; ++y)
    for (int x = 0; x + 1 < W; ++x)
      ASSERT_EQ(first[((size_t)y * W + x) * 4], moved[((size_t)(y + 1) * W + x + 1) * 4]) << x << "," << y;
}

TEST(Text, UnicodeSymbolsHaveGlyphs) {
  Font f(default_font_path(), 20);
  // Each symbol leaves ink (DejaVu Sans has omega, subscripts, arrows and the minus sign).
  for (const char* s : {"ω", "₁", "₀", "→", "−", "²", "θ̇"}) {
    const auto img = draw_text(f, s, 10, 40);
    EXPECT_GE(ink_box(img, 0, W)[0], 0) << s;
  }
}

TEST(Text, CompositeBlendsAndClips) {
  ScreenLayer l;
  l.rects.push_back({-5, -5, 3, 2, {255, 0, 0, 255}});
  l.rects.push_back({0, 0, 10, 10, {0, 0, 255, 128}});
  std::vector<uint8_t> img((size_t)W * H * 4, 100);
  composite(l, img.data(), W, H);
  EXPECT_EQ(img[0], (255 * 127 + 0 * 128 + 127) / 255);  // red, then half blue over it
  EXPECT_EQ(img[2], (0 * 127 + 255 * 128 + 127) / 255);
  EXPECT_EQ(img[3], 100);                  // alpha left alone
  EXPECT_EQ(img[(10 * W + 10) * 4], 100);  // outside both
}

}  // namespace
}  // namespace simreel
