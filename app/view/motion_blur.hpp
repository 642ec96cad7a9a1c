// Motion blur (`render.motion_blur`, scenes/README.md): a frame averages images of the states the
// physics passes through while its shutter is open, drawn at physics steps. Nothing is simulated
// for the picture: the sub-frame states are steps the run takes anyway (FrameLoop::Hooks::sample),
// so the trajectory, the state at each frame and everything `simulate` reports are those of a run
// without blur, and a frame's samples depend on its own step alone (a partial render's frames are
// the full render's).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "app/scene/camera_motion.hpp"

namespace simreel {

struct BlurSample {
  long step = 0;   ///< physics step whose state is drawn
  int weight = 1;  ///< how many of the frame's samples fall on it
};

// The states a frame showing step `step` averages: `samples` moments evenly spaced from
// shutter * (step - previous) steps before it up to `step` itself, each on its nearest step (not
// before step 0); moments that share a step are one sample of that weight. Ascending; the last is
// `step`. `previous`: the step the frame before shows (the shutter is a share of the frame
// interval, which a `time:` block stretches or shrinks: a freeze frame is sharp).
std::vector<BlurSample> blur_samples(const MotionBlurSpec& mb, long step, long previous);

// The average of weighted images in linear light: each 8-bit channel (gamma 2.2, as the renderer
// encodes, render/shaders.hpp) is decoded to a 24-bit linear integer, summed, divided with
// rounding, and encoded to the nearest 8-bit value; alpha is averaged as it is. Integer sums:
// the result is the same on every machine and for any order of the samples; equal images
// average to themselves exactly.
class BlurAccumulator {
 public:
  explicit BlurAccumulator(int samples);  ///< total weight of a frame, 1..64
  // Adds an RGBA image of `pixels` pixels, `weight` times (all images of a frame the same size).
  void add(const uint8_t* rgba, size_t pixels, int weight);
  int weight() const { return weight_; }  ///< added so far
  int samples() const { return samples_; }
  // The average of what was added (whose weights must sum to samples()) into `out`; starts over.
  void finish(uint8_t* out);

 private:
  int samples_, weight_ = 0;
  std::vector<uint32_t> sum_;
};

}  // namespace simreel
