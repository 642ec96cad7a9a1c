// Fast approximate anti-aliasing on the CPU, after T. Lottes, "FXAA" (NVIDIA white paper, 2009)
// and his FXAA 3.11 quality preset: find pixels on a luma edge, estimate where the edge crosses
// the pixel from how far the edge runs each way, and blend the pixel with its neighbour across the
// edge by that much (or by a sub-pixel amount for features smaller than a pixel).
//
// Why on the CPU: on llvmpipe every full-screen pass costs ~5 ms of fixed per-pixel work and 4x
// MSAA costs ~13 ms a 720p frame (6.5 ms of it the resolve); this pass touches only the pixels on
// an edge (a few percent) after one cheap contrast test per pixel.
#pragma once
#include <cstdint>
#include <vector>

namespace simreel {

struct FxaaBuffers {
  std::vector<uint8_t> luma;  ///< one byte per pixel, sized on first use, then reused
  std::vector<uint8_t> edge;  ///< one row of edge flags
  struct Change {
    uint32_t index;  ///< pixel
    uint8_t rgb[3];
  };
  std::vector<Change> changes;  ///< blended pixels, applied once every pixel has been read
};

// In place on an RGBA8 image of width x height, rows top first. Every decision reads the image as
// it was on entry; alpha is left alone.
void fxaa(uint8_t* rgba, int width, int height, FxaaBuffers& buffers);
// The same without AVX2 (one step of the edge search at a time): what fxaa() runs on a CPU without
// it; the same bytes (tests compare the two).
void fxaa_portable(uint8_t* rgba, int width, int height, FxaaBuffers& buffers);

}  // namespace simreel
