#include "app/regress/metrics.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace simreel {

namespace {

// ---------------------------------------------------------------- colour
// YIQ (NTSC) weights and the distance between two colours from Kotsarenko & Ramos 2010, "Measuring
// perceived color difference using YIQ NTSC transmission color space in mobile applications", as
// pixelmatch uses them: delta = 0.5053 dY^2 + 0.299 dI^2 + 0.1957 dQ^2, whose largest value (black
// against white) is 35215.
constexpr double kYr = 0.29889531, kYg = 0.58662247, kYb = 0.11448223;
constexpr double kIr = 0.59597799, kIg = -0.27417610, kIb = -0.32180189;
constexpr double kQr = 0.21147017, kQg = -0.52261711, kQb = 0.31114694;
constexpr double kWy = 0.5053, kWi = 0.299, kWq = 0.1957;
constexpr double kMaxYiqDelta = 35215.0;

inline uint32_t word(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

// A channel composited over white: 255 + (c - 255) a / 255 (pixelmatch's blend).
inline double over_white(int c, int a) {
  return a == 255 ? c : 255.0 + (c - 255) * (a / 255.0);
}

struct Rgb {
  double r, g, b;
};
inline Rgb rgb(const uint8_t* p) {
  return {over_white(p[0], p[3]), over_white(p[1], p[3]), over_white(p[2], p[3])};
}
inline double luma(const uint8_t* p) {
  const Rgb c = rgb(p);
  return c.r * kYr + c.g * kYg + c.b * kYb;
}

// Squared YIQ distance of two pixels (YIQ is linear: the transform of the RGB difference).
inline double yiq_delta(const uint8_t* a, const uint8_t* b) {
  const Rgb ca = rgb(a), cb = rgb(b);
  const double dr = ca.r - cb.r, dg = ca.g - cb.g, db = ca.b - cb.b;
  const double y = dr * kYr + dg * kYg + db * kYb;
  const double i = dr * kIr + dg * kIg + db * kIb;
  const double q = dr * kQr + dg * kQg + db * kQb;
  return kWy * y * y + kWi * i * i + kWq * q * q;
}

// ---------------------------------------------------------------- anti-aliasing
// After Vysniauskas 2009, "Anti-aliased pixel and intensity slope detector", in pixelmatch's form.
// A pixel of `img` is taken for anti-aliasing when (1) at most 2 of its 8 neighbours have exactly
// its brightness (a pixel on the image border starts with one such neighbour counted), (2) it has
// both a darker and a brighter neighbour (it lies on an intensity slope), and (3) the darkest or
// the brightest neighbour sits in a flat area in BOTH images: more than 2 of that neighbour's own
// neighbours are exactly equal to it (again border pixels start at one), in `img` and in `other`.
// That is, the pixel is an edge pixel between two flat regions which both images share.
struct View {
  const uint8_t* px;
  int w, h;
  const uint8_t* at(int x, int y) const { return px + ((size_t)y * w + x) * 4; }
};

bool has_many_siblings(const View& img, int x1, int y1) {
  const int x0 = std::max(x1 - 1, 0), y0 = std::max(y1 - 1, 0);
  const int x2 = std::min(x1 + 1, img.w - 1), y2 = std::min(y1 + 1, img.h - 1);
  int zeroes = (x1 == x0 || x1 == x2 || y1 == y0 || y1 == y2) ? 1 : 0;
  const uint32_t c = word(img.at(x1, y1));
  for (int y = y0; y <= y2; ++y)
    for (int x = x0; x <= x2; ++x) {
      if (x == x1 && y == y1) continue;
      if (word(img.at(x, y)) == c && ++zeroes > 2) return true;
    }
  return false;
}

bool antialiased(const View& img, const View& other, int x1, int y1) {
  const int x0 = std::max(x1 - 1, 0), y0 = std::max(y1 - 1, 0);
  const int x2 = std::min(x1 + 1, img.w - 1), y2 = std::min(y1 + 1, img.h - 1);
  int zeroes = (x1 == x0 || x1 == x2 || y1 == y0 || y1 == y2) ? 1 : 0;
  const double yc = luma(img.at(x1, y1));
  double lo = 0, hi = 0;  // most negative and most positive brightness step to a neighbour
  int lox = 0, loy = 0, hix = 0, hiy = 0;
  for (int y = y0; y <= y2; ++y)
    for (int x = x0; x <= x2; ++x) {
      if (x == x1 && y == y1) continue;
      const double d = luma(img.at(x, y)) - yc;
      if (d == 0) {
        if (++zeroes > 2) return false;  // too many equal neighbours: not on an edge
      } else if (d < lo) {
        lo = d, lox = x, loy = y;
      } else if (d > hi) {
        hi = d, hix = x, hiy = y;
      }
    }
  if (lo == 0 || hi == 0) return false;  // no darker or no brighter neighbour: not on a slope
  return (has_many_siblings(img, lox, loy) && has_many_siblings(other, lox, loy)) ||
         (has_many_siblings(img, hix, hiy) && has_many_siblings(other, hix, hiy));
}

// ---------------------------------------------------------------- SSIM
// Wang, Bovik, Sheikh & Simoncelli 2004, "Image quality assessment: from error visibility to
// structural similarity", eq. 13 with C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 255, on 8-bit luma
// (the Y above, rounded), over 8 x 8 windows (the paper's section III.B before its Gaussian
// variant) placed every 4 pixels, as x264 and FFmpeg do: sums over 4 x 4 blocks, each window the
// sum of 2 x 2 blocks. The mean over all windows is returned. Pixels past the last whole 4 x 4 block
// (the right and bottom w % 4, h % 4) are left out; an image under 8 px on a side is one window.
// Sample variances divide by n - 1 as in the paper.
constexpr double kC1 = (0.01 * 255) * (0.01 * 255), kC2 = (0.03 * 255) * (0.03 * 255);

// 8-bit luma in 16-bit fixed point: 19588 + 38445 + 7503 = 65536 (kYr, kYg, kYb x 65536, rounded).
inline int luma8(const uint8_t* p) {
  int r = p[0], g = p[1], b = p[2];
  const int a = p[3];
  if (a != 255) {  // over white, rounded
    r = 255 - ((255 - r) * a + 127) / 255;
    g = 255 - ((255 - g) * a + 127) / 255;
    b = 255 - ((255 - b) * a + 127) / 255;
  }
  return (r * 19588 + g * 38445 + b * 7503 + 32768) >> 16;
}

struct Sums {
  uint64_t sx = 0, sy = 0, ss = 0, sxy = 0;  // sum x, sum y, sum x^2 + y^2, sum xy
  void add(const Sums& o) { sx += o.sx, sy += o.sy, ss += o.ss, sxy += o.sxy; }
};

double ssim_window(const Sums& s, double n) {
  if (s.ss == 2 * s.sxy) return 1;  // sum (x - y)^2 = 0: the window is the same in both
  const double mx = s.sx / n, my = s.sy / n;
  const double dn = n > 1 ? n - 1 : 1;
  const double var_sum = ((double)s.ss - ((double)s.sx * s.sx + (double)s.sy * s.sy) / n) / dn;
  const double cov = ((double)s.sxy - (double)s.sx * s.sy / n) / dn;
  return (2 * mx * my + kC1) * (2 * cov + kC2) / ((mx * mx + my * my + kC1) * (var_sum + kC2));
}

// 4 x 4 blocks in which some pixel changed: only windows touching one need computing, every other
// window is the same in both images and scores exactly 1.
struct BlockGrid {
  int bw = 0, bh = 0;
  std::vector<uint8_t> dirty;
  BlockGrid(int w, int h) : bw(w / 4), bh(h / 4), dirty((size_t)bw * bh, 0) {}
  void mark(int x, int y) {
    const int bx = x / 4, by = y / 4;
    if (bx < bw && by < bh) dirty[(size_t)by * bw + bx] = 1;
  }
};

Sums block_sums(const View& a, const View& b, int bx, int by) {
  Sums s;
  for (int y = by * 4; y < by * 4 + 4; ++y) {
    const uint8_t* pa = a.at(bx * 4, y);
    const uint8_t* pb = b.at(bx * 4, y);
    uint32_t sx = 0, sy = 0, ss = 0, sxy = 0;  // 4 px: no overflow
    for (int k = 0; k < 4; ++k, pa += 4, pb += 4) {
      const uint32_t u = luma8(pa), v = luma8(pb);
      sx += u, sy += v, ss += u * u + v * v, sxy += u * v;
    }
    s.sx += sx, s.sy += sy, s.ss += ss, s.sxy += sxy;
  }
  return s;
}

double mean_ssim(const View& a, const View& b, const BlockGrid& g) {
  const int w = a.w, h = a.h;
  if (w < 8 || h < 8) {
    Sums s;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint64_t u = luma8(a.at(x, y)), v = luma8(b.at(x, y));
        s.sx += u, s.sy += v, s.ss += u * u + v * v, s.sxy += u * v;
      }
    return ssim_window(s, (double)w * h);
  }
  const int bw = g.bw, bh = g.bh;
  // Block sums of two block rows at a time, computed only for blocks of a dirty window.
  std::vector<Sums> prev(bw), cur(bw);
  std::vector<uint8_t> have_prev(bw, 0), have_cur(bw, 0);
  auto dirty = [&](int bx, int by) { return g.dirty[(size_t)by * bw + bx] != 0; };
  double total = 0;
  long clean = 0;
  for (int by = 1; by < bh; ++by) {
    std::swap(prev, cur);
    std::swap(have_prev, have_cur);
    if (by == 1) std::fill(have_prev.begin(), have_prev.end(), 0);
    std::fill(have_cur.begin(), have_cur.end(), 0);
    for (int bx = 0; bx + 1 < bw; ++bx) {
      if (!dirty(bx, by - 1) && !dirty(bx + 1, by - 1) && !dirty(bx, by) && !dirty(bx + 1, by)) {
        ++clean;
        continue;
      }
      for (int k = bx; k <= bx + 1; ++k) {
        if (!have_prev[k]) prev[k] = block_sums(a, b, k, by - 1), have_prev[k] = 1;
        if (!have_cur[k]) cur[k] = block_sums(a, b, k, by), have_cur[k] = 1;
      }
      Sums s = prev[bx];
      s.add(prev[bx + 1]);
      s.add(cur[bx]);
      s.add(cur[bx + 1]);
      total += ssim_window(s, 64);
    }
  }
  return (total + (double)clean) / ((double)(bw - 1) * (bh - 1));
}

// ---------------------------------------------------------------- clusters
// 8-connected components of the pixels marked kCounted, found by flood fill from each counted
// pixel (visited pixels are re-marked, so each is pushed once).
constexpr uint8_t kNone = 0, kCounted = 1, kAntialiased = 2, kVisited = 3;

std::vector<Cluster> find_clusters(std::vector<uint8_t>& mask, const std::vector<int>& seeds, int w, int h) {
  std::vector<Cluster> out;
  std::vector<int> stack;
  for (int seed : seeds) {
    if (mask[seed] != kCounted) continue;
    Cluster c{seed % w, seed / w, seed % w, seed / w, 0};
    mask[seed] = kVisited;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const int x = i % w, y = i / w;
      ++c.pixels;
      c.x0 = std::min(c.x0, x), c.x1 = std::max(c.x1, x);
      c.y0 = std::min(c.y0, y), c.y1 = std::max(c.y1, y);
      for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, h - 1); ++ny)
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, w - 1); ++nx) {
          const int j = ny * w + nx;
          if (mask[j] == kCounted) {
            mask[j] = kVisited;
            stack.push_back(j);
          }
        }
    }
    out.push_back(c);
  }
  std::sort(out.begin(), out.end(), [](const Cluster& p, const Cluster& q) {
    if (p.pixels != q.pixels) return p.pixels > q.pixels;
    if (p.y0 != q.y0) return p.y0 < q.y0;
    return p.x0 < q.x0;
  });
  return out;
}

// ---------------------------------------------------------------- words
// A ratio as a percentage with up to 3 significant digits: 0.0024 -> "0.24%", 1e-6 -> "0.0001%".
std::string percent(double r) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g%%", r * 100);
  return buf;
}

void check_buffer(const Image& img, const char* which) {
  if (img.width < 0 || img.height < 0 || img.rgba.size() != (size_t)img.width * img.height * 4)
    throw std::invalid_argument(std::string("compare_images: the ") + which +
                                " image's buffer does not hold width x height x 4 bytes");
}

// The heat map's background: the expected pixel's 8-bit luma faded toward white, 255 - (255 - Y) x
// 0.2 (51 / 255), rounded, through a table (integer only: a 720p background takes about 1 ms).
inline void put(uint8_t* d, uint8_t r, uint8_t g, uint8_t b) {
  d[0] = r, d[1] = g, d[2] = b, d[3] = 255;
}
void fill_faded(Image& out, const Image& src) {
  uint8_t fade[256];
  for (int y = 0; y < 256; ++y) fade[y] = (uint8_t)(255 - ((255 - y) * 51 + 127) / 255);
  const size_t n = (size_t)src.width * src.height;
  out.width = src.width;
  out.height = src.height;
  out.rgba.resize(n * 4);
  const uint8_t* s = src.rgba.data();
  uint8_t* d = out.rgba.data();
  for (size_t i = 0; i < n; ++i, s += 4, d += 4) {
    const uint8_t v = fade[luma8(s)];
    d[0] = v, d[1] = v, d[2] = v, d[3] = 255;
  }
}

}  // namespace

CompareResult compare_images(const Image& expected, const Image& actual, const CompareOptions& o,
                             Image* diff) {
  check_buffer(expected, "expected");
  check_buffer(actual, "actual");
  CompareResult r;
  const int w = expected.width, h = expected.height;
  const size_t n = (size_t)w * h;
  if (diff) fill_faded(*diff, expected);
  if (w != actual.width || h != actual.height) {
    r.same_size = false;
    r.pass = false;
    r.reason = "size differs: expected " + std::to_string(w) + "x" + std::to_string(h) + ", actual " +
               std::to_string(actual.width) + "x" + std::to_string(actual.height);
    return r;
  }
  if (n == 0 || std::memcmp(expected.rgba.data(), actual.rgba.data(), n * 4) == 0) return r;

  const View va{expected.rgba.data(), w, h}, vb{actual.rgba.data(), w, h};
  const double max_delta = kMaxYiqDelta * o.threshold * o.threshold;
  std::vector<uint8_t> mask(n, kNone);
  std::vector<int> counted;
  BlockGrid blocks(w, h);
  double sq_sum = 0;  // sum of squared RGB differences, composited over white
  int max_ch = 0;
  for (int y = 0; y < h; ++y) {
    const uint8_t* pa = va.at(0, y);
    const uint8_t* pb = vb.at(0, y);
    for (int x = 0; x < w; ++x, pa += 4, pb += 4) {
      if (word(pa) == word(pb)) continue;
      blocks.mark(x, y);
      for (int c = 0; c < 4; ++c) max_ch = std::max(max_ch, std::abs(pa[c] - pb[c]));
      const Rgb ca = rgb(pa), cb = rgb(pb);
      sq_sum += (ca.r - cb.r) * (ca.r - cb.r) + (ca.g - cb.g) * (ca.g - cb.g) + (ca.b - cb.b) * (ca.b - cb.b);
      if (!(yiq_delta(pa, pb) > max_delta)) continue;
      const size_t i = (size_t)y * w + x;
      if (o.ignore_antialiasing && (antialiased(va, vb, x, y) || antialiased(vb, va, x, y))) {
        mask[i] = kAntialiased;
        ++r.antialiased;
        if (diff) put(&diff->rgba[i * 4], 255, 255, 0);
      } else {
        mask[i] = kCounted;
        counted.push_back((int)i);
        if (diff) put(&diff->rgba[i * 4], 255, 0, 0);
      }
    }
  }
  r.max_channel_delta = max_ch;
  r.psnr = sq_sum > 0 ? 10 * std::log10(255.0 * 255.0 / (sq_sum / (3.0 * n))) : INFINITY;
  r.ssim = mean_ssim(va, vb, blocks);
  r.differing = (long)counted.size();
  r.diff_ratio = (double)r.differing / (double)n;
  std::vector<Cluster> clusters = find_clusters(mask, counted, w, h);
  if (!clusters.empty()) r.largest_cluster = clusters[0].pixels;
  if (clusters.size() > 32) clusters.resize(32);
  r.clusters = std::move(clusters);

  if (r.diff_ratio > o.max_diff_ratio)
    r.reason = std::to_string(r.differing) + " differing pixels (" + percent(r.diff_ratio) + ") > " +
               percent(o.max_diff_ratio);
  if (r.largest_cluster > o.max_cluster) {
    const Cluster& c = r.clusters[0];
    if (!r.reason.empty()) r.reason += "; ";
    r.reason += "cluster of " + std::to_string(c.pixels) + " px at (" + std::to_string(c.x0) + "," +
                std::to_string(c.y0) + ")-(" + std::to_string(c.x1) + "," + std::to_string(c.y1) + ") > " +
                std::to_string(o.max_cluster);
  }
  r.pass = r.reason.empty();
  return r;
}

}  // namespace simreel
