// RGBA8 to YUV 4:2:0 planar, BT.709 limited range (Y in [16, 235], Cb/Cr in [16, 240]): the
// pixel format every H.264/VP9 player opens. Replaces libswscale's generic path (~2 ms a 720p
// frame here) with one fixed-point pass.
#pragma once
#include <cstdint>

namespace simreel {

// width and height even. Chroma is the 2x2 block's mean colour, i.e. sited at the block's centre;
// the video writer tags its streams AVCHROMA_LOC_CENTER to say so (H.264's untagged default is
// left-sited, a quarter-pixel chroma shift).
void rgba_to_yuv420_bt709(const uint8_t* rgba, int width, int height, uint8_t* y, int y_stride, uint8_t* cb,
                          int cb_stride, uint8_t* cr, int cr_stride);

}  // namespace simreel
