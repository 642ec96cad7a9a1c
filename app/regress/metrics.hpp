// Image comparison for visual regression (issue 11): a rendered frame against its golden.
//
// A pixel differs when its colour distance in YIQ exceeds a threshold (pixelmatch's measure,
// after Kotsarenko & Ramos 2010); differing pixels that look like anti-aliasing in either image
// (Vysniauskas 2009, as pixelmatch applies it) are set aside. The frame fails when the counted
// differing pixels are too many in all or too many in one 8-connected cluster. PSNR, SSIM and the
// largest channel difference are reported beside the verdict; they do not decide it.
//
// Every colour measure sees the images composited over white (pixelmatch's convention; simreel's
// frames are opaque, where it changes nothing); max_channel_delta alone is over the raw RGBA bytes.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "app/regress/image.hpp"

namespace simreel {

struct CompareOptions {
  // YIQ colour distance threshold, 0..1, pixelmatch's meaning: a pixel differs when its squared
  // YIQ distance exceeds threshold^2 x 35215, the largest possible (black against white). A grey
  // step of d levels has squared distance 0.5053 d^2, so a threshold t lets grey steps of up to
  // 264 t levels through (0.1: 26 levels); 0 counts any change at all.
  double threshold = 0.1;
  // Differing pixels judged anti-aliasing in either image are reported but not counted.
  bool ignore_antialiasing = true;
  // Fail when counted differing pixels / all pixels exceeds this.
  double max_diff_ratio = 0.001;
  // Fail when any 8-connected cluster of counted differing pixels has more pixels than this.
  int max_cluster = 16;

  // Any pixel whose (composited) colour changes at all fails: threshold 0, no anti-aliasing
  // allowance, no differing pixel allowed.
  static CompareOptions exact() { return {0.0, false, 0.0, 0}; }
};

struct Cluster {
  int x0, y0, x1, y1;  // inclusive bounding box
  int pixels;
};

struct CompareResult {
  bool same_size = true;
  long differing = 0;      // counted (not anti-aliasing) differing pixels
  long antialiased = 0;    // differing pixels judged anti-aliasing and ignored
  double diff_ratio = 0;   // differing / (w*h)
  int largest_cluster = 0;
  std::vector<Cluster> clusters;  // largest first (ties: top, then left), at most 32
  double psnr = INFINITY;         // dB over RGB (peak 255, mean over the three channels), +inf when equal
  double ssim = 1;  // mean SSIM on luma, 8x8 windows every 4 px (see metrics.cpp), 1 when equal
  double max_channel_delta = 0;  // largest |difference| of one RGBA byte, 0..255
  bool pass = true;
  std::string reason;  // why it failed, in words; "" when it passed
};

// Compares `actual` against `expected`. Images of different sizes give same_size false, pass
// false and a reason naming both sizes (nothing else is measured). If `diff` is given it is
// replaced by a heat map of the expected image's size: the expected image's luma faded toward
// white as background, counted differing pixels red, ignored anti-aliasing pixels yellow (for a
// size mismatch: the expected image faded, with nothing marked). Throws std::invalid_argument if an
// image's buffer does not hold width x height x 4 bytes.
CompareResult compare_images(const Image& expected, const Image& actual, const CompareOptions& o,
                             Image* diff = nullptr);

}  // namespace simreel
