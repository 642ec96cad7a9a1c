// The image comparison behind simreel check / diff (app/regress/): hand-made images with known
// differences, and PNG reading and writing.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "app/regress/image.hpp"
#include "app/regress/metrics.hpp"
#include <simreel/error.hpp>
#include "tests/scratch.hpp"

namespace simreel {
namespace {

Image filled(int w, int h, uint8_t r, uint8_t g, uint8_t b, uint8_t a = 255) {
  Image img{w, h, std::vector<uint8_t>((size_t)w * h * 4)};
  for (size_t i = 0; i < img.rgba.size(); i += 4) {
    img.rgba[i] = r, img.rgba[i + 1] = g, img.rgba[i + 2] = b, img.rgba[i + 3] = a;
  }
  return img;
}

uint8_t* px(Image& img, int x, int y) {
  return &img.rgba[((size_t)y * img.width + x) * 4];
}
void set(Image& img, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
  uint8_t* p = px(img, x, y);
  p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
}

// Something like a rendered frame: smooth gradients plus a little deterministic texture, so that
// most pixels differ from their neighbours.
Image textured(int w, int h) {
  Image img = filled(w, h, 0, 0, 0);
  uint32_t s = 12345;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s = s * 1664525u + 1013904223u;
      const int noise = (int)(s >> 29);  // 0..7
      set(img, x, y, (uint8_t)(40 + x * 150 / w + noise), (uint8_t)(60 + y * 120 / h + noise),
          (uint8_t)(100 + (x + y) % 50));
    }
  return img;
}

// A straight band (a thick line) drawn with anti-aliasing: each pixel is the background blended
// with the line colour by the fraction of its area inside the band, estimated on a 16 x 16 grid
// of sub-samples. The band is all points within half_width of the line through (x0 + offset, 0)
// at `angle` radians from the vertical.
Image band(int w, int h, double x0, double angle, double half_width) {
  Image img = filled(w, h, 235, 235, 230);
  const double nx = std::cos(angle), ny = std::sin(angle);  // unit normal of the band's axis
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int inside = 0;
      for (int sy = 0; sy < 16; ++sy)
        for (int sx = 0; sx < 16; ++sx) {
          const double X = x + (sx + 0.5) / 16, Y = y + (sy + 0.5) / 16;
          inside += std::abs((X - x0) * nx + Y * ny) <= half_width;
        }
      const double f = inside / 256.0;
      auto mix = [&](double bg, double fg) { return (uint8_t)std::lround(bg + (fg - bg) * f); };
      set(img, x, y, mix(235, 30), mix(235, 40), mix(230, 90));
    }
  return img;
}

// ---------------------------------------------------------------- the comparison

TEST(RegressMetrics, IdenticalImages) {
  const Image a = textured(64, 48);
  Image diff;
  const CompareResult r = compare_images(a, a, CompareOptions{}, &diff);
  EXPECT_TRUE(r.pass);
  EXPECT_TRUE(r.same_size);
  EXPECT_EQ(r.differing, 0);
  EXPECT_EQ(r.antialiased, 0);
  EXPECT_EQ(r.largest_cluster, 0);
  EXPECT_TRUE(r.clusters.empty());
  EXPECT_TRUE(std::isinf(r.psnr) && r.psnr > 0);
  EXPECT_EQ(r.ssim, 1.0);
  EXPECT_EQ(r.max_channel_delta, 0);
  EXPECT_EQ(r.reason, "");
  // The heat map is the faded expected image: grey, light, nothing marked.
  ASSERT_EQ(diff.width, 64);
  ASSERT_EQ(diff.height, 48);
  for (size_t i = 0; i < diff.rgba.size(); i += 4) {
    ASSERT_EQ(diff.rgba[i], diff.rgba[i + 1]);
    ASSERT_EQ(diff.rgba[i], diff.rgba[i + 2]);
    ASSERT_GE(diff.rgba[i], 180);
  }
  EXPECT_TRUE(compare_images(a, a, CompareOptions::exact()).pass);
}

TEST(RegressMetrics, OneLevelShiftPassesButNotExact) {
  const Image a = textured(96, 64);
  Image b = a;
  for (size_t i = 0; i < b.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) ++b.rgba[i + c];
  const CompareResult r = compare_images(a, b, CompareOptions{});
  EXPECT_TRUE(r.pass) << r.reason;
  EXPECT_EQ(r.differing, 0);
  EXPECT_EQ(r.max_channel_delta, 1);
  EXPECT_NEAR(r.psnr, 10 * std::log10(255.0 * 255.0), 1e-9);  // MSE exactly 1: 48.13 dB
  EXPECT_LT(r.ssim, 1.0);
  EXPECT_GT(r.ssim, 0.999);
  EXPECT_TRUE(compare_images(a, b, CompareOptions::cross_renderer()).pass);
  const CompareResult e = compare_images(a, b, CompareOptions::exact());
  EXPECT_FALSE(e.pass);
  EXPECT_EQ(e.differing, 96 * 64);
}

TEST(RegressMetrics, SmallBlockChangeFailsByCluster) {
  // 640 x 480: 25 pixels are 0.008% of the frame, under the ratio limit; the cluster decides.
  const Image a = textured(640, 480);
  Image b = a;
  for (int y = 200; y < 205; ++y)
    for (int x = 300; x < 305; ++x) set(b, x, y, 250, 30, 30);
  const CompareOptions o;
  ASSERT_LT(25.0 / (640 * 480), o.max_diff_ratio);
  ASSERT_LT(o.max_cluster, 25);
  Image diff;
  const CompareResult r = compare_images(a, b, o, &diff);
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.differing, 25);
  EXPECT_EQ(r.antialiased, 0);
  EXPECT_EQ(r.largest_cluster, 25);
  ASSERT_EQ(r.clusters.size(), 1u);
  const Cluster& c = r.clusters[0];
  EXPECT_EQ(c.x0, 300);
  EXPECT_EQ(c.y0, 200);
  EXPECT_EQ(c.x1, 304);
  EXPECT_EQ(c.y1, 204);
  EXPECT_EQ(r.reason, "cluster of 25 px at (300,200)-(304,204) > " + std::to_string(o.max_cluster));
  EXPECT_LT(r.psnr, 60);
  EXPECT_LT(r.ssim, 1.0);
  EXPECT_GT(r.max_channel_delta, 100);
  // Red where the block changed, grey elsewhere.
  EXPECT_EQ(px(diff, 302, 202)[0], 255);
  EXPECT_EQ(px(diff, 302, 202)[1], 0);
  EXPECT_EQ(px(diff, 10, 10)[0], px(diff, 10, 10)[1]);
}

TEST(RegressMetrics, ScatteredPixelsFailByRatio) {
  // Every 8th pixel of every 8th row changed: 1.6% of the pixels, each alone (no cluster > 1).
  const Image a = textured(160, 120);
  Image b = a;
  int changed = 0;
  for (int y = 0; y < 120; y += 8)
    for (int x = 0; x < 160; x += 8, ++changed) set(b, x, y, 255, 255, 255);
  const CompareResult r = compare_images(a, b, CompareOptions{});
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.differing, changed);
  EXPECT_EQ(r.largest_cluster, 1);
  EXPECT_EQ(r.clusters.size(), 32u);  // capped
  EXPECT_DOUBLE_EQ(r.diff_ratio, changed / (160.0 * 120.0));
  EXPECT_EQ(r.reason.find(std::to_string(changed) + " differing pixels (1.56%) > "), 0u) << r.reason;
  EXPECT_EQ(r.reason.find("cluster"), std::string::npos);
}

TEST(RegressMetrics, ClustersAreEightConnectedAndSortedBySize) {
  const Image a = filled(40, 30, 200, 200, 200);
  Image b = a;
  // A diagonal of 4 pixels (one cluster only if diagonal neighbours connect), a 3 x 2 block, and a
  // single pixel.
  for (int k = 0; k < 4; ++k) set(b, 5 + k, 5 + k, 0, 0, 0);
  for (int y = 20; y < 22; ++y)
    for (int x = 30; x < 33; ++x) set(b, x, y, 0, 0, 0);
  set(b, 1, 28, 0, 0, 0);
  const CompareResult r = compare_images(a, b, CompareOptions{});
  ASSERT_EQ(r.clusters.size(), 3u);
  EXPECT_EQ(r.clusters[0].pixels, 6);
  EXPECT_EQ(r.clusters[0].x0, 30);
  EXPECT_EQ(r.clusters[0].y1, 21);
  EXPECT_EQ(r.clusters[1].pixels, 4);
  EXPECT_EQ(r.clusters[1].x0, 5);
  EXPECT_EQ(r.clusters[1].y0, 5);
  EXPECT_EQ(r.clusters[1].x1, 8);
  EXPECT_EQ(r.clusters[1].y1, 8);
  EXPECT_EQ(r.clusters[2].pixels, 1);
  EXPECT_EQ(r.largest_cluster, 6);
  EXPECT_EQ(r.differing, 11);
}

TEST(RegressMetrics, SubPixelShiftOfAntiAliasedBandIsAntiAliasing) {
  // A 5 px band at 20 degrees, moved by 0.3 px: only its edge pixels change, and those are
  // anti-aliasing between two flat areas that both images share.
  const double angle = 20 * M_PI / 180;
  const Image a = band(120, 90, 50.0, angle, 2.5), b = band(120, 90, 50.3, angle, 2.5);
  CompareOptions o;
  Image diff;
  const CompareResult r = compare_images(a, b, o, &diff);
  EXPECT_TRUE(r.pass) << r.reason;
  EXPECT_GT(r.antialiased, 90);  // both edges, 90 rows
  EXPECT_LE(r.differing, 2);     // (a stray where the band leaves the frame is allowed)
  bool yellow = false;
  for (size_t i = 0; i < diff.rgba.size(); i += 4)
    yellow |= diff.rgba[i] == 255 && diff.rgba[i + 1] == 255 && diff.rgba[i + 2] == 0;
  EXPECT_TRUE(yellow);
  // The same pixels counted when anti-aliasing is not set aside: now the shift fails.
  o.ignore_antialiasing = false;
  const CompareResult s = compare_images(a, b, o);
  EXPECT_FALSE(s.pass);
  EXPECT_EQ(s.antialiased, 0);
  EXPECT_EQ(s.differing, r.differing + r.antialiased);
}

TEST(RegressMetrics, SolidEdgeMovedIsNotAntiAliasing) {
  // A hard-edged square (no blending) moved by one pixel: the pixels that change are not between a
  // darker and a brighter neighbour, so they are counted.
  Image a = filled(60, 60, 220, 220, 220), b = a;
  for (int y = 20; y < 40; ++y)
    for (int x = 20; x < 40; ++x) set(a, x, y, 20, 20, 20), set(b, x + 1, y, 20, 20, 20);
  const CompareResult r = compare_images(a, b, CompareOptions{});
  EXPECT_EQ(r.antialiased, 0);
  EXPECT_EQ(r.differing, 40);  // a column of 20 lost on the left, gained on the right
  EXPECT_EQ(r.largest_cluster, 20);
  EXPECT_FALSE(r.pass);
}

TEST(RegressMetrics, ChangeOverAnEdgeIsNotAntiAliasing) {
  // In the expected image column 20 is a grey anti-aliasing column between black and white. The
  // actual image paints a textured patch over it: each grey pixel still lies between a darker and
  // a brighter flat neighbour in the expected image, but those neighbours are not flat in the
  // actual one, so the change is counted (pixelmatch asks for flatness in both images).
  Image a = filled(40, 40, 230, 230, 230);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 20; ++x) set(a, x, y, 20, 20, 20);
    set(a, 20, y, 125, 125, 125);
  }
  Image b = a;
  for (int y = 14; y < 26; ++y)
    for (int x = 14; x < 26; ++x)
      set(b, x, y, (uint8_t)((x * 37 + y * 91) % 256), (uint8_t)((x * 53 + y * 17 + 100) % 256),
          (uint8_t)((x * 11 + y * 71 + 50) % 256));
  Image diff;
  const CompareResult r = compare_images(a, b, CompareOptions{}, &diff);
  EXPECT_FALSE(r.pass);
  for (int y = 17; y < 24; ++y) {  // (the texture at (20, 16) is near the grey: under the threshold)
    EXPECT_EQ(px(diff, 20, y)[0], 255) << "y " << y;
    EXPECT_EQ(px(diff, 20, y)[1], 0) << "y " << y;  // red, not yellow
  }
}

TEST(RegressMetrics, ThresholdFollowsYiqDistance) {
  // A grey step of d levels has squared YIQ distance 0.5053 d^2; threshold t lets through
  // d <= t sqrt(35215 / 0.5053) = 264 t: at 0.1, 26 passes and 27 does not.
  const Image a = filled(20, 20, 100, 100, 100);
  Image b = a, c = a;
  set(b, 10, 10, 126, 126, 126);
  set(c, 10, 10, 127, 127, 127);
  CompareOptions o;
  o.threshold = 0.1;
  o.max_cluster = 0;
  EXPECT_EQ(compare_images(a, b, o).differing, 0);
  EXPECT_EQ(compare_images(a, c, o).differing, 1);
  EXPECT_FALSE(compare_images(a, c, o).pass);
}

// Mean SSIM written out plainly (Wang et al. 2004, eq. 13): every 8 x 8 window at a multiple of 4,
// on 8-bit luma round(0.29889531 R + 0.58662247 G + 0.11448223 B) in 16-bit fixed point, sample
// (co)variances over n - 1, C1 = (0.01 x 255)^2, C2 = (0.03 x 255)^2.
double reference_ssim(const Image& a, const Image& b) {
  auto luma = [](const Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
    return (double)((p[0] * 19588 + p[1] * 38445 + p[2] * 7503 + 32768) >> 16);
  };
  const double c1 = 2.55 * 2.55, c2 = 7.65 * 7.65;
  double total = 0;
  int windows = 0;
  for (int y0 = 0; y0 + 8 <= a.height; y0 += 4)
    for (int x0 = 0; x0 + 8 <= a.width; x0 += 4) {
      double mx = 0, my = 0;
      for (int y = y0; y < y0 + 8; ++y)
        for (int x = x0; x < x0 + 8; ++x) mx += luma(a, x, y), my += luma(b, x, y);
      mx /= 64, my /= 64;
      double vx = 0, vy = 0, cov = 0;
      for (int y = y0; y < y0 + 8; ++y)
        for (int x = x0; x < x0 + 8; ++x) {
          const double dx = luma(a, x, y) - mx, dy = luma(b, x, y) - my;
          vx += dx * dx, vy += dy * dy, cov += dx * dy;
        }
      vx /= 63, vy /= 63, cov /= 63;
      total += (2 * mx * my + c1) * (2 * cov + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++windows;
    }
  return total / windows;
}

TEST(RegressMetrics, SsimMatchesAPlainComputation) {
  // 70 x 45: sizes that are not multiples of 4 (the last 2 columns and 1 row are in no window).
  const Image a = textured(70, 45);
  Image local = a, everywhere = a, edge = a;
  for (int y = 10; y < 14; ++y)
    for (int x = 33; x < 39; ++x) set(local, x, y, 0, 0, 0);  // one spot: most windows unchanged
  set(local, 55, 30, 250, 250, 250);  // single pixels in the last column and the last row of a block
  set(local, 20, 35, 250, 250, 250);
  for (size_t i = 0; i < everywhere.rgba.size(); i += 4) everywhere.rgba[i + 1] /= 2;
  set(edge, 69, 44, 255, 255, 255);  // outside every window: SSIM stays 1
  for (const Image* b : {&local, &everywhere}) {
    const CompareResult r = compare_images(a, *b, CompareOptions{});
    EXPECT_NEAR(r.ssim, reference_ssim(a, *b), 1e-12);
    EXPECT_LT(r.ssim, 0.99);
  }
  EXPECT_EQ(compare_images(a, edge, CompareOptions{}).ssim, 1.0);
}

TEST(RegressMetrics, SizeMismatchIsReported) {
  const Image a = filled(10, 20, 1, 2, 3), b = filled(20, 10, 1, 2, 3);
  Image diff;
  const CompareResult r = compare_images(a, b, CompareOptions{}, &diff);
  EXPECT_FALSE(r.same_size);
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.reason.find("10x20"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("20x10"), std::string::npos) << r.reason;
  EXPECT_EQ(diff.width, 10);
  EXPECT_EQ(diff.height, 20);
  const Image empty;
  EXPECT_FALSE(compare_images(a, empty, CompareOptions{}).pass);
  EXPECT_TRUE(compare_images(empty, empty, CompareOptions{}).pass);
  Image bad = a;
  bad.rgba.pop_back();
  EXPECT_THROW(compare_images(a, bad, CompareOptions{}), std::invalid_argument);
}

TEST(RegressMetrics, TranslucentPixelsAreSeenOverWhite) {
  // Two transparent pixels of different colours look the same (white); a half-transparent black
  // is mid grey.
  Image a = filled(8, 8, 0, 0, 0, 0), b = filled(8, 8, 255, 0, 0, 0);
  const CompareResult r = compare_images(a, b, CompareOptions::exact());
  EXPECT_TRUE(r.pass);
  EXPECT_EQ(r.max_channel_delta, 255);
  const Image grey = filled(8, 8, 128, 128, 128), half = filled(8, 8, 0, 0, 0, 128);
  EXPECT_EQ(compare_images(grey, half, CompareOptions{}).differing, 0);
  EXPECT_GT(compare_images(grey, half, CompareOptions{}).psnr, 45);
}

// ---------------------------------------------------------------- PNG

void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), (std::streamsize)bytes.size());
}

template <class F>
void expect_input_error(F f, const std::string& path, const std::string& words) {
  try {
    f();
    ADD_FAILURE() << "no exception for " << path;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find(path), 0u) << m;
    EXPECT_NE(m.find(words), std::string::npos) << m;
  }
}

TEST(RegressPng, BadFilesThrowInputErrorNamingTheFile) {
  const std::string missing = test::scratch("missing.png");
  expect_input_error([&] { read_png(missing); }, missing, "cannot open");

  const std::string text = test::scratch("text.png");
  write_bytes(text, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd', '\n'});
  expect_input_error([&] { read_png(text); }, text, "not a PNG");

  const std::string empty = test::scratch("empty.png");
  write_bytes(empty, {});
  expect_input_error([&] { read_png(empty); }, empty, "not a PNG");

  const std::vector<uint8_t> good = encode_png(textured(50, 40));
  // Cut inside the image data, and cut only the final IEND chunk (12 bytes).
  const std::string half = test::scratch("half.png");
  write_bytes(half, std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2));
  expect_input_error([&] { read_png(half); }, half, "truncated");
  const std::string no_end = test::scratch("no_end.png");
  write_bytes(no_end, std::vector<uint8_t>(good.begin(), good.end() - 12));
  expect_input_error([&] { read_png(no_end); }, no_end, "truncated");

  // A flipped byte in the image data: the chunk's CRC no longer matches.
  std::vector<uint8_t> flipped = good;
  flipped[good.size() / 2] ^= 0x55;
  const std::string corrupt = test::scratch("corrupt.png");
  write_bytes(corrupt, flipped);
  expect_input_error([&] { read_png(corrupt); }, corrupt, "corrupt");

  const std::string whole = test::scratch("whole.png");
  write_bytes(whole, good);
  EXPECT_NO_THROW(read_png(whole));
}

TEST(RegressPng, RoundTripIsExactAndDeterministic) {
  Image opaque = textured(73, 41);  // odd sizes
  Image translucent = opaque;
  for (size_t i = 3; i < translucent.rgba.size(); i += 28) translucent.rgba[i] = (uint8_t)(i % 256);
  for (const Image* img : {&opaque, &translucent}) {
    const std::vector<uint8_t> bytes = encode_png(*img);
    EXPECT_EQ(bytes, encode_png(*img));  // the same bytes every time
    const std::string path = test::scratch("rt.png");
    write_png_file(path, *img);
    const Image back = read_png(path);
    EXPECT_TRUE(identical(back, *img));
    EXPECT_TRUE(identical(decode_png(bytes.data(), bytes.size(), "mem"), *img));
    EXPECT_EQ(pixel_hash(back), pixel_hash(*img));
  }
  EXPECT_LT(encode_png(opaque).size(), encode_png(translucent).size());  // RGB when opaque
  EXPECT_THROW(encode_png(Image{}), std::runtime_error);
}

// A PNG written with libpng directly, of the given colour type and depth, from raw rows.
void write_raw_png(const std::string& path, int w, int h, int type, int depth,
                   const std::vector<std::vector<uint8_t>>& rows, int level = 9,
                   const std::vector<png_color>& palette = {}, const std::vector<uint8_t>& trns = {}) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_TRUE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, depth, type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, level);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), (int)palette.size());
  if (!trns.empty()) png_set_tRNS(png, info, trns.data(), (int)trns.size(), nullptr);
  png_write_info(png, info);
  for (const auto& row : rows) png_write_row(png, row.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

std::vector<uint8_t> rgba_at(const Image& img, int x, int y) {
  const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

TEST(RegressPng, OtherFormatsAreConvertedToRgba8) {
  using V = std::vector<uint8_t>;
  const std::string grey = test::scratch("grey.png");
  write_raw_png(grey, 2, 1, PNG_COLOR_TYPE_GRAY, 8, {{10, 200}});
  Image g = read_png(grey);
  EXPECT_EQ(rgba_at(g, 0, 0), (V{10, 10, 10, 255}));
  EXPECT_EQ(rgba_at(g, 1, 0), (V{200, 200, 200, 255}));

  const std::string grey1 = test::scratch("grey1.png");
  write_raw_png(grey1, 3, 1, PNG_COLOR_TYPE_GRAY, 1, {{0b10100000}});
  Image g1 = read_png(grey1);
  EXPECT_EQ(rgba_at(g1, 0, 0), (V{255, 255, 255, 255}));
  EXPECT_EQ(rgba_at(g1, 1, 0), (V{0, 0, 0, 255}));

  const std::string ga = test::scratch("grey_alpha.png");
  write_raw_png(ga, 1, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, {{77, 128}});
  EXPECT_EQ(rgba_at(read_png(ga), 0, 0), (V{77, 77, 77, 128}));

  const std::string pal = test::scratch("palette.png");
  write_raw_png(pal, 2, 1, PNG_COLOR_TYPE_PALETTE, 8, {{1, 0}}, 9, {{10, 20, 30}, {40, 50, 60}}, {99});
  Image p = read_png(pal);
  EXPECT_EQ(rgba_at(p, 0, 0), (V{40, 50, 60, 255}));
  EXPECT_EQ(rgba_at(p, 1, 0), (V{10, 20, 30, 99}));

  const std::string deep = test::scratch("rgb16.png");
  write_raw_png(deep, 1, 1, PNG_COLOR_TYPE_RGB, 16, {{0xff, 0xff, 0x7f, 0xff, 0x00, 0xff}});
  // Scaled with rounding, not cut to the high byte: 65535 -> 255, 32767 -> 127 (127.498),
  // 255 -> 1 (0.99; the high byte would give 0).
  EXPECT_EQ(rgba_at(read_png(deep), 0, 0), (V{255, 127, 1, 255}));

  // RGB with a tRNS colour key: pixels of that colour become transparent.
  const std::string keyed = test::scratch("rgb_trns.png");
  {
    FILE* f = std::fopen(keyed.c_str(), "wb");
    ASSERT_TRUE(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, 2, 1, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_color_16 key{};
    key.red = 7, key.green = 8, key.blue = 9;
    png_set_tRNS(png, info, nullptr, 0, &key);
    png_write_info(png, info);
    const uint8_t row[6] = {7, 8, 9, 7, 8, 10};
    png_write_row(png, row);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
  }
  Image k = read_png(keyed);
  EXPECT_EQ(rgba_at(k, 0, 0), (V{7, 8, 9, 0}));
  EXPECT_EQ(rgba_at(k, 1, 0), (V{7, 8, 10, 255}));

  // The same pixels written at two compression levels (and RGB vs RGBA): one pixel hash.
  const std::string rgb = test::scratch("rgb.png"), rgba = test::scratch("rgba.png");
  write_raw_png(rgb, 2, 1, PNG_COLOR_TYPE_RGB, 8, {{1, 2, 3, 4, 5, 6}}, 0);
  write_raw_png(rgba, 2, 1, PNG_COLOR_TYPE_RGB_ALPHA, 8, {{1, 2, 3, 255, 4, 5, 6, 255}}, 9);
  EXPECT_EQ(pixel_hash(read_png(rgb)), pixel_hash(read_png(rgba)));
}

TEST(RegressPng, PixelHashSeesOnePixelAndTheSize) {
  // XXH64 with seed width x 2^32 + height; values from libxxhash's XXH64().
  EXPECT_EQ(pixel_hash(Image{}), "ef46db3751d8e999");  // XXH64 of nothing, seed 0
  EXPECT_EQ(pixel_hash(Image{1, 1, {1, 2, 3, 4}}), "40e0bbfb0fd96f7d");
  Image v{16, 4, std::vector<uint8_t>(16 * 4 * 4)};
  for (size_t i = 0; i < v.rgba.size(); ++i) v.rgba[i] = (uint8_t)(i * 13 + 5);
  EXPECT_EQ(pixel_hash(v), "8b82351110066dee");  // 256 bytes: the 32-byte stripes

  const Image a = textured(16, 4);
  const std::string h = pixel_hash(a);
  EXPECT_EQ(h.size(), 16u);
  EXPECT_EQ(h, pixel_hash(a));
  Image b = a;
  b.rgba[4 * 37 + 1] ^= 1;  // one bit of one pixel
  EXPECT_NE(pixel_hash(b), h);
  Image t = a;  // the same bytes as 4 x 16
  std::swap(t.width, t.height);
  EXPECT_NE(pixel_hash(t), h);
  EXPECT_TRUE(identical(a, a));
  EXPECT_FALSE(identical(a, b));
  EXPECT_FALSE(identical(a, t));
}

}  // namespace
}  // namespace simreel
