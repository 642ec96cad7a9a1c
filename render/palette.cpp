#include "render/palette.hpp"

#include <algorithm>
#include <climits>

namespace simreel {
namespace {

constexpr int kBins = 1 << 15;  // 5-5-5 bit RGB
inline int bin_of(int r, int g, int b) {
  return ((r >> 3) << 10) | ((g >> 3) << 5) | (b >> 3);
}
inline int channel(int bin, int c) {  // 0..31
  return (bin >> (10 - 5 * c)) & 31;
}

struct Box {
  int begin, end;  // range of `bins` (occupied bin indices)
  long pixels;
  int axis, lo, hi;  // longest side
  long score() const { return hi > lo ? pixels * (hi - lo) : 0; }
};

}  // namespace

Palette fit_palette(const uint8_t* rgba, int width, int height, int colors) {
  std::vector<long> count(kBins, 0);
  const long n = (long)width * height;
  for (long i = 0; i < n; ++i) ++count[bin_of(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2])];
  std::vector<int> bins;
  for (int b = 0; b < kBins; ++b)
    if (count[b]) bins.push_back(b);

  auto measure = [&](Box& box) {
    int lo[3] = {31, 31, 31}, hi[3] = {0, 0, 0};
    box.pixels = 0;
    for (int i = box.begin; i < box.end; ++i) {
      box.pixels += count[bins[i]];
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], channel(bins[i], c));
        hi[c] = std::max(hi[c], channel(bins[i], c));
      }
    }
    box.axis = 0;
    for (int c = 1; c < 3; ++c)
      if (hi[c] - lo[c] > hi[box.axis] - lo[box.axis]) box.axis = c;
    box.lo = lo[box.axis];
    box.hi = hi[box.axis];
  };
  std::vector<Box> boxes;
  if (!bins.empty()) {
    boxes.push_back({0, (int)bins.size(), 0, 0, 0, 0});
    measure(boxes.back());
  }
  while ((int)boxes.size() < colors) {
    // Ties go to the lowest index, so the result depends on the image alone.
    auto it = std::max_element(boxes.begin(), boxes.end(),
                               [](const Box& a, const Box& b) { return a.score() < b.score(); });
    if (it == boxes.end() || it->score() == 0) break;
    Box& box = *it;
    const int axis = box.axis;
    std::sort(bins.begin() + box.begin, bins.begin() + box.end, [&](int a, int b) {
      const int ca = channel(a, axis), cb = channel(b, axis);
      return ca != cb ? ca < cb : a < b;
    });
    // Median by pixel count, keeping at least one bin on each side.
    long acc = 0;
    int cut = box.begin + 1;
    for (int i = box.begin; i < box.end - 1; ++i) {
      acc += count[bins[i]];
      cut = i + 1;
      if (2 * acc >= box.pixels) break;
    }
    Box right{cut, box.end, 0, 0, 0, 0};
    box.end = cut;
    measure(box);
    measure(right);
    boxes.push_back(right);
  }

  Palette p;
  p.size = (int)boxes.size();
  std::vector<int> rgb(3 * p.size);
  for (int k = 0; k < p.size; ++k) {
    // Mean colour of the box, from the bins' centres weighted by their pixel counts.
    double sum[3] = {0, 0, 0};
    for (int i = boxes[k].begin; i < boxes[k].end; ++i)
      for (int c = 0; c < 3; ++c) sum[c] += (double)count[bins[i]] * (channel(bins[i], c) * 8 + 4);
    for (int c = 0; c < 3; ++c) rgb[3 * k + c] = std::clamp((int)(sum[c] / boxes[k].pixels + 0.5), 0, 255);
    p.argb[k] =
        0xff000000u | (uint32_t)rgb[3 * k] << 16 | (uint32_t)rgb[3 * k + 1] << 8 | (uint32_t)rgb[3 * k + 2];
  }
  if (p.size == 0) {  // empty image: one black entry
    p.size = 1;
    p.argb[0] = 0xff000000u;
    rgb = {0, 0, 0};
  }
  p.nearest.resize(kBins);
  for (int b = 0; b < kBins; ++b) {
    const int r = channel(b, 0) * 8 + 4, g = channel(b, 1) * 8 + 4, bl = channel(b, 2) * 8 + 4;
    int best = 0, best_d = INT_MAX;
    for (int k = 0; k < p.size; ++k) {
      const int dr = r - rgb[3 * k], dg = g - rgb[3 * k + 1], db = bl - rgb[3 * k + 2];
      const int d = dr * dr + dg * dg + db * db;
      if (d < best_d) best_d = d, best = k;
    }
    p.nearest[b] = (uint8_t)best;
  }
  return p;
}

void map_to_palette(const Palette& p, const uint8_t* rgba, int width, int height, uint8_t* out,
                    int out_stride, std::vector<int>& scratch) {
  // Error rows in 1/16 units, one pixel of padding on each side.
  const size_t row = 3 * (size_t)(width + 2);
  scratch.assign(2 * row, 0);
  int* cur = scratch.data();
  int* next = scratch.data() + row;
  for (int y = 0; y < height; ++y) {
    std::fill(next, next + row, 0);
    const uint8_t* src = rgba + (size_t)y * width * 4;
    uint8_t* dst = out + (size_t)y * out_stride;
    for (int x = 0; x < width; ++x) {
      int v[3];
      int* e = cur + 3 * (x + 1);
      for (int c = 0; c < 3; ++c)
        v[c] = std::clamp(src[4 * x + c] + (e[c] + (e[c] >= 0 ? 8 : -8)) / 16, 0, 255);
      const int k = p.nearest[bin_of(v[0], v[1], v[2])];
      dst[x] = (uint8_t)k;
      const uint32_t q = p.argb[k];
      const int err[3] = {v[0] - (int)((q >> 16) & 255), v[1] - (int)((q >> 8) & 255), v[2] - (int)(q & 255)};
      int* n = next + 3 * (x + 1);
      for (int c = 0; c < 3; ++c) {
        e[3 + c] += 7 * err[c];   // right
        n[-3 + c] += 3 * err[c];  // below left
        n[c] += 5 * err[c];       // below
        n[3 + c] += err[c];       // below right
      }
    }
    std::swap(cur, next);
  }
}

}  // namespace simreel
