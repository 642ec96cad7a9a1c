// RGB to BT.709 limited-range YUV 4:2:0 against the standard's formula (ITU-R BT.709-6 items 3.2
// to 3.5, with the 8-bit quantisation of BT.601/709: Y = 16 + 219 E_Y, C = 128 + 224 E_C).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "render/yuv.hpp"

namespace simreel {
namespace {

struct Yuv {
  double y, cb, cr;
};
Yuv bt709(double r, double g, double b) {  // r, g, b in [0, 1]
  const double ey = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  return {16 + 219 * ey, 128 + 224 * (b - ey) / 1.8556, 128 + 224 * (r - ey) / 1.5748};
}

TEST(Yuv, FlatColoursMatchTheStandardToRounding) {
  const int w = 8, h = 4;
  const uint8_t colours[][3] = {{0, 0, 0},   {255, 255, 255}, {255, 0, 0},    {0, 255, 0},
                                {0, 0, 255}, {128, 128, 128}, {200, 120, 40}, {17, 99, 230}};
  for (const auto& c : colours) {
    std::vector<uint8_t> rgba((size_t)w * h * 4);
    for (int i = 0; i < w * h; ++i)
      for (int k = 0; k < 4; ++k) rgba[4 * i + k] = k < 3 ? c[k] : 255;
    std::vector<uint8_t> Y(w * h), U(w * h / 4), V(w * h / 4);
    rgba_to_yuv420_bt709(rgba.data(), w, h, Y.data(), w, U.data(), w / 2, V.data(), w / 2);
    const Yuv e = bt709(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
    // Rounded to the nearest level: within half a level plus the fixed-point error (< 0.02).
    for (uint8_t y : Y) EXPECT_NEAR(y, e.y, 0.52) << (int)c[0] << "," << (int)c[1] << "," << (int)c[2];
    for (uint8_t u : U) EXPECT_NEAR(u, e.cb, 0.52);
    for (uint8_t v : V) EXPECT_NEAR(v, e.cr, 0.52);
  }
}

TEST(Yuv, ChromaIsTheMeanOfEachTwoByTwoBlock) {
  // Left column red, right column blue in each 2x2 block: chroma of the mean colour (127.5, 0, 127.5).
  const int w = 4, h = 2;
  std::vector<uint8_t> rgba((size_t)w * h * 4, 0);
  for (int yy = 0; yy < h; ++yy)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &rgba[4 * (yy * w + x)];
      p[x % 2 ? 2 : 0] = 255;
      p[3] = 255;
    }
  std::vector<uint8_t> Y(w * h), U(2), V(2);
  rgba_to_yuv420_bt709(rgba.data(), w, h, Y.data(), w, U.data(), 2, V.data(), 2);
  const Yuv e = bt709(0.5, 0, 0.5);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(U[i], e.cb, 0.52);
    EXPECT_NEAR(V[i], e.cr, 0.52);
  }
  EXPECT_NEAR(Y[0], bt709(1, 0, 0).y, 0.52);
  EXPECT_NEAR(Y[1], bt709(0, 0, 1).y, 0.52);
}

// Wide images go through the vector pass (16 columns at a time where the CPU has AVX2), the rest
// of a row and narrow images through the scalar one. Each output depends on its 2x2 block only,
// so every block of a random wide image, converted alone as a 2x2 image (scalar), must give the
// same bytes; and every sample must match the standard's formula to rounding.
TEST(Yuv, WideImagesGiveTheBytesOfEachBlockAlone) {
  const int w = 16 * 5 + 6, h = 6;  // a scalar tail after the vector columns
  std::mt19937 rng(11);
  std::vector<uint8_t> rgba((size_t)w * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = (uint8_t)(i % 97 < 3 ? 255 * (i % 2) : rng() % 256);
  std::vector<uint8_t> Y((size_t)w * h), U((size_t)w * h / 4), V((size_t)w * h / 4);
  rgba_to_yuv420_bt709(rgba.data(), w, h, Y.data(), w, U.data(), w / 2, V.data(), w / 2);
  for (int by = 0; by < h / 2; ++by)
    for (int bx = 0; bx < w / 2; ++bx) {
      uint8_t block[16], y[4], u, v;
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 4; ++c)
          block[4 * k + c] = rgba[4 * ((size_t)(2 * by + k / 2) * w + 2 * bx + k % 2) + c];
      rgba_to_yuv420_bt709(block, 2, 2, y, 2, &u, 1, &v, 1);
      for (int k = 0; k < 4; ++k) {
        const uint8_t* p = block + 4 * k;
        ASSERT_EQ(Y[(size_t)(2 * by + k / 2) * w + 2 * bx + k % 2], y[k])
            << bx << "," << by << " pixel " << k;
        EXPECT_NEAR(y[k], bt709(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0).y, 0.52);
      }
      ASSERT_EQ(U[(size_t)by * w / 2 + bx], u) << bx << "," << by;
      ASSERT_EQ(V[(size_t)by * w / 2 + bx], v) << bx << "," << by;
      double r = 0, g = 0, b = 0;
      for (int k = 0; k < 4; ++k)
        r += block[4 * k] / 1020.0, g += block[4 * k + 1] / 1020.0, b += block[4 * k + 2] / 1020.0;
      EXPECT_NEAR(u, bt709(r, g, b).cb, 0.52);
      EXPECT_NEAR(v, bt709(r, g, b).cr, 0.52);
    }
}

}  // namespace
}  // namespace simreel
