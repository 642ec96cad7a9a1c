#include "app/view/motion_blur.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace simreel {

namespace {

// 8-bit code value -> linear light on 24 bits (2^24 - 1 is white), and the midpoints between
// neighbouring values, for the way back to the nearest code value. With 24 bits the 256 values
// are distinct (1 -> 5092, 2 -> 10185) and 64 samples of white sum to under 2^30.
struct GammaTables {
  std::array<uint32_t, 256> linear;
  std::array<uint32_t, 255> mid;
  GammaTables() {
    for (int v = 0; v < 256; ++v) {  // the sRGB curve (IEC 61966-2-1) the frames are encoded with
      const double c = v / 255.0, l = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
      linear[v] = (uint32_t)std::lround(16777215.0 * l);
    }
    for (int v = 0; v < 255; ++v) mid[v] = linear[v] + (linear[v + 1] - linear[v]) / 2;
  }
  // The code value whose linear value is nearest (ties to the lower one).
  uint8_t encode(uint32_t lin) const {
    return (uint8_t)(std::lower_bound(mid.begin(), mid.end(), lin) - mid.begin());
  }
};

const GammaTables& tables() {
  static const GammaTables t;
  return t;
}

}  // namespace

std::vector<BlurSample> blur_samples(const MotionBlurSpec& mb, long step, long previous) {
  std::vector<BlurSample> out;
  const int n = std::max(1, mb.samples);
  const double open = mb.shutter * (double)std::max(0L, step - previous);  // steps
  for (int j = n - 1; j >= 0; --j) {                                       // from the shutter's opening on
    const long s = std::max(0L, step - (n > 1 ? std::lround(open * j / (n - 1)) : 0L));
    if (!out.empty() && out.back().step == s)
      ++out.back().weight;
    else
      out.push_back({s, 1});
  }
  return out;
}

BlurAccumulator::BlurAccumulator(int samples) : samples_(samples) {
  if (samples < 1 || samples > 64) throw std::invalid_argument("motion blur takes 1 to 64 samples");
}

void BlurAccumulator::add(const uint8_t* rgba, size_t pixels, int weight) {
  if (weight <= 0) return;
  const GammaTables& g = tables();
  if (weight_ == 0) sum_.assign(pixels * 4, 0);
  weight_ += weight;
  const uint32_t w = (uint32_t)weight;
  for (size_t i = 0; i < pixels * 4; i += 4) {
    sum_[i] += w * g.linear[rgba[i]];
    sum_[i + 1] += w * g.linear[rgba[i + 1]];
    sum_[i + 2] += w * g.linear[rgba[i + 2]];
    sum_[i + 3] += w * rgba[i + 3];
  }
}

void BlurAccumulator::finish(uint8_t* out) {
  const GammaTables& g = tables();
  const uint32_t n = (uint32_t)std::max(1, weight_), half = n / 2;
  for (size_t i = 0; i < sum_.size(); i += 4) {
    out[i] = g.encode((sum_[i] + half) / n);
    out[i + 1] = g.encode((sum_[i + 1] + half) / n);
    out[i + 2] = g.encode((sum_[i + 2] + half) / n);
    out[i + 3] = (uint8_t)((sum_[i + 3] + half) / n);
  }
  weight_ = 0;
}

}  // namespace simreel
