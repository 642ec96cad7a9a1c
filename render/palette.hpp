// A 256-colour palette fitted to an image (median cut), and error-diffusion mapping onto it: what
// GIF output uses. The palette is fitted once, to the clip's first frame, and kept for the whole
// clip: a simulation clip keeps its background, ground and body colours, and one palette means
// no colour flicker between frames.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace simreel {

struct Palette {
  std::array<uint32_t, 256> argb{};  ///< 0xAARRGGBB, as FFmpeg's PAL8 expects; unused entries 0
  int size = 0;
  std::vector<uint8_t> nearest;  ///< 32768 entries: 5-5-5 bit RGB -> nearest palette index
};

// Median cut over a 5-bit-per-channel histogram of the RGBA image: the box holding the most
// pixels times its longest side is split at the median of that side until there are `colors`
// boxes; each entry is its box's mean colour.
Palette fit_palette(const uint8_t* rgba, int width, int height, int colors = 256);

// Floyd-Steinberg: each pixel takes the nearest entry to its colour plus the error carried from
// its neighbours. `out` is width x height indices with row stride `out_stride`. `scratch` holds
// two rows of carried error; it is sized on first use and reused (no allocation per frame).
void map_to_palette(const Palette& p, const uint8_t* rgba, int width, int height, uint8_t* out,
                    int out_stride, std::vector<int>& scratch);

}  // namespace simreel
