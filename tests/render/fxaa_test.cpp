// FXAA against the exact answer: a hard-edged half-plane, where each pixel's true value is the
// fraction of its area on the bright side (computed here by 64 x 64 supersampling).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "render/fxaa.hpp"

namespace simreel {
namespace {

constexpr int W = 96, H = 64;

// Bright (230) above the line y = y0 + slope * x, dark (30) below; `coverage` the exact pixel
// means, `img` what a one-sample rasteriser gives (the pixel centre decides).
struct HalfPlane {
  std::vector<uint8_t> img;
  std::vector<double> coverage;
  HalfPlane(double slope, double y0) : img((size_t)W * H * 4), coverage((size_t)W * H) {
    auto bright = [&](double x, double y) { return y < y0 + slope * x; };
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        int in = 0;
        for (int j = 0; j < 64; ++j)
          for (int i = 0; i < 64; ++i) in += bright(x + (i + 0.5) / 64, y + (j + 0.5) / 64);
        coverage[(size_t)y * W + x] = 30 + 200 * in / 4096.0;
        const uint8_t v = bright(x + 0.5, y + 0.5) ? 230 : 30;
        uint8_t* p = &img[4 * ((size_t)y * W + x)];
        p[0] = p[1] = p[2] = v;
        p[3] = 255;
      }
  }
  // Root-mean-square difference from the exact coverage over pixels the edge passes through.
  double rms_on_edge(const std::vector<uint8_t>& im) const {
    double se = 0;
    int n = 0;
    for (size_t i = 0; i < coverage.size(); ++i)
      if (coverage[i] > 31 && coverage[i] < 229) {
        se += std::pow(im[4 * i] - coverage[i], 2);
        ++n;
      }
    return std::sqrt(se / n);
  }
};

// Shallow edges are where aliasing shows (long stair steps) and where FXAA's edge search earns
// its keep. The aliased image is off by 52-58 grey levels (rms, of 200) on edge pixels and FXAA
// brings that to 13-22; the test asks for at least half, and every pixel away from the edge
// untouched.
TEST(Fxaa, ShallowEdgeApproachesTheExactCoverage) {
  for (double slope : {0.1, 0.22, -0.15, 0.4}) {
    const HalfPlane hp(slope, 20.3);
    std::vector<uint8_t> out = hp.img;
    FxaaBuffers buf;
    fxaa(out.data(), W, H, buf);
    const double before = hp.rms_on_edge(hp.img), after = hp.rms_on_edge(out);
    EXPECT_LT(after, 0.5 * before) << "slope " << slope << ": rms " << before << " -> " << after;
    for (size_t i = 0; i < hp.coverage.size(); ++i) {
      const int y = (int)(i / W), x = (int)(i % W);
      const double line = 20.3 + slope * (x + 0.5);
      if (std::fabs(y + 0.5 - line) > 3) {
        ASSERT_EQ(out[4 * i], hp.img[4 * i]) << x << "," << y;
      }
    }
  }
}

TEST(Fxaa, SteepEdgesToo) {  // the same by symmetry with x and y swapped: a near-vertical edge
  const HalfPlane hp(0.12, 10.0);
  std::vector<uint8_t> t(hp.img.size());
  // Transpose into a H x W image (so the edge is near vertical), run, and compare transposed.
  std::vector<uint8_t> tout((size_t)W * H * 4);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 4; ++c) tout[4 * ((size_t)x * H + y) + c] = hp.img[4 * ((size_t)y * W + x) + c];
  FxaaBuffers buf;
  fxaa(tout.data(), H, W, buf);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 4; ++c) t[4 * ((size_t)y * W + x) + c] = tout[4 * ((size_t)x * H + y) + c];
  EXPECT_LT(hp.rms_on_edge(t), 0.5 * hp.rms_on_edge(hp.img));
}

TEST(Fxaa, FlatAndLowContrastImagesAreUntouched) {
  std::vector<uint8_t> img((size_t)W * H * 4);
  for (size_t i = 0; i < img.size(); ++i) img[i] = (uint8_t)(100 + (i / 4) % 7);  // below threshold
  std::vector<uint8_t> out = img;
  FxaaBuffers buf;
  fxaa(out.data(), W, H, buf);
  EXPECT_EQ(img, out);
}

// With AVX2, the edge search reads all eight positions of a side at once and picks the first that
// ends it; without, it steps. The same bytes on images whose edges end at every distance and run
// into the image's borders: random blocks and lines over a random background, and noise; several
// sizes (the vector luma pass leaves a different remainder for each).
TEST(Fxaa, TheVectorEdgeSearchGivesThePortableBytes) {
  std::mt19937 rng(5);
  long changed = 0;
  for (const auto& [w, h] : {std::pair{96, 64}, std::pair{61, 37}, std::pair{200, 9}, std::pair{9, 120}}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<uint8_t> img((size_t)w * h * 4);
      // Every fifth image noise (every pixel an edge: its luma and blends checked everywhere),
      // the others a quiet background.
      for (size_t i = 0; i < img.size(); ++i)
        img[i] = (uint8_t)(trial % 5 == 0 ? rng() % 256 : 40 + rng() % 8);
      for (int k = 0; k < 12; ++k) {  // blocks and near-horizontal / near-vertical lines
        const int x0 = (int)(rng() % w), y0 = (int)(rng() % h), len = 1 + (int)(rng() % 60);
        const double slope = ((int)(rng() % 200) - 100) / 400.0;
        const bool vertical = rng() % 2, block = rng() % 3 == 0;
        const uint8_t c = (uint8_t)(90 + rng() % 160);
        for (int t = 0; t < len; ++t)
          for (int u = 0; u < (block ? len / 3 + 1 : 1); ++u) {
            int x = vertical ? x0 + (int)std::lround(slope * t) + u : x0 + t;
            int y = vertical ? y0 + t : y0 + (int)std::lround(slope * t) + u;
            if (x < 0 || x >= w || y < 0 || y >= h) continue;
            for (int ch = 0; ch < 3; ++ch) img[4 * ((size_t)y * w + x) + ch] = (uint8_t)(c - 20 * ch);
          }
      }
      std::vector<uint8_t> a = img, b = img;
      FxaaBuffers ba, bb;
      fxaa(a.data(), w, h, ba);
      fxaa_portable(b.data(), w, h, bb);
      ASSERT_EQ(a, b) << w << "x" << h << " trial " << trial;
      changed += (long)bb.changes.size();
    }
  }
  EXPECT_GT(changed, 2000);  // edges were there to smooth
}

}  // namespace
}  // namespace simreel
