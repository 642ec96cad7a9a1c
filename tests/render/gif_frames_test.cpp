// GIF output through FFmpeg's palette filters (render/gif_frames.hpp), written by the video writer
// and decoded back with libavcodec.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "render/video_writer.hpp"
#include "tests/render/decode.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

constexpr int W = 160, H = 120;

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
constexpr uint8_t kSky[3] = {203, 217, 232};

// Frame k: a flat sky (rows 0-39, never touched), a band of 160 x 20 colours (a two-channel ramp,
// more colours than a palette holds) that shifts with k, and a red square moving right.
std::vector<uint8_t> frame(int k) {
  std::vector<uint8_t> img((size_t)W * H * 4, 255);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      uint8_t* p = &img[4 * ((size_t)y * W + x)];
      p[0] = kSky[0], p[1] = kSky[1], p[2] = kSky[2];
      if (y >= 80 && y < 100) {
        p[0] = (uint8_t)((x + 3 * k) * 255 / (W + 90));
        p[1] = (uint8_t)(12 * (y - 80));
        p[2] = 90;
      }
      if (y >= 50 && y < 70 && x >= 4 * k && x < 4 * k + 20) p[0] = 220, p[1] = 30, p[2] = 20;
    }
  return img;
}

std::string write_gif(const std::string& name, int frames, int gif_width = 0, double gif_fps = 0,
                      std::vector<uint8_t> (*make)(int) = frame) {
  const std::string path = test::scratch(name);
  VideoSettings vs;
  vs.path = path;
  vs.width = W;
  vs.height = H;
  vs.fps = 30;
  vs.gif_width = gif_width;
  vs.gif_fps = gif_fps;
  VideoWriter v(vs);
  for (int k = 0; k < frames; ++k) v.push(make(k).data());
  v.finish();
  return path;
}

// The sky stays one colour, the source's (not a dither of palette entries around it: the writer of
// before this one gave 3 alternating entries on a flat sky); the ramp and the square come through;
// the same frames give the same bytes; nothing is left beside the GIF.
TEST(Gif, FlatColoursStayFlatAndTheFileIsDeterministic) {
  const std::string a = write_gif("a.gif", 30), b = write_gif("b.gif", 30);
  const test::Decoded d = test::decode(a, true);
  EXPECT_EQ(d.codec, "gif");
  ASSERT_EQ(d.frames, 30);
  ASSERT_EQ(d.width, W);
  ASSERT_EQ(d.height, H);
  for (int k = 0; k < d.frames; ++k) {
    const std::vector<uint8_t>& f = d.rgba[k];
    const std::vector<uint8_t> src = frame(k);
    for (int i = 0; i < W * 40; ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(f[4 * i + c], f[c]) << "frame " << k << " sky pixel " << i << " differs from the first";
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], kSky[c], 2) << "frame " << k;
    // Square and ramp: every pixel within a palette step of the source, on average close.
    double err = 0;
    for (int i = W * 50; i < W * 100; ++i)
      for (int c = 0; c < 3; ++c) err += std::abs(f[4 * i + c] - src[4 * i + c]);
    EXPECT_LT(err / (W * 50 * 3), 3.0) << "frame " << k;
  }
  EXPECT_TRUE(bytes(a) == bytes(b)) << "the same frames gave different GIFs";
  for (const auto& e : std::filesystem::directory_iterator(test::scratch_dir()))
    EXPECT_TRUE(e.path().filename() == "a.gif" || e.path().filename() == "b.gif") << e.path();
}

// Frame k is a flat grey of level 8 k: which rendered frame each GIF frame shows is readable.
std::vector<uint8_t> grey(int k) {
  return std::vector<uint8_t>((size_t)W * H * 4, (uint8_t)(8 * k));
}

// --gif-width and --gif-fps: 80 px wide (height by the aspect ratio), 10 frames/s from 30: GIF frame
// j at j / 10 s shows rendered frame 3 j (the one at that time), and the clip lasts as long.
TEST(Gif, ScaledAndAtALowerFrameRate) {
  const test::Decoded d = test::decode(write_gif("s.gif", 30, 80, 10, grey), true);
  EXPECT_EQ(d.width, 80);
  EXPECT_EQ(d.height, 60);
  ASSERT_EQ(d.frames, 10);
  for (int j = 0; j < d.frames; ++j) {
    EXPECT_NEAR(d.times[j], 0.1 * j, 0.006) << j;  // GIF delays are whole hundredths
    EXPECT_NEAR(d.rgba[j][0], 8 * 3 * j, 1) << "GIF frame " << j << " shows the wrong rendered frame";
  }
  EXPECT_NEAR(d.duration, 1.0, 0.011);
  // 30 frames/s is stored as delays of 3, 4, 3 hundredths: 1 s for 30 frames, not 0.9 s.
  EXPECT_NEAR(test::decode(write_gif("t.gif", 30)).duration, 1.0, 0.011);
}

}  // namespace
}  // namespace simreel
