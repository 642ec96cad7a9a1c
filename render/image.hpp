// Base-colour images for textures: decoded by FFmpeg's image decoders (libavcodec), which simreel
// links for video already and which OSS-Fuzz fuzzes, so no further image library is needed.
// Formats: PNG, JPEG, GIF (its first frame), BMP, WebP, TGA (by name: it has no signature)
// and the raw RGBA of render/material.hpp. Decoding is bit-exact (AV_CODEC_FLAG_BITEXACT and
// swscale's bit-exact conversion), so a texture gives the same texels on every machine.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace simreel {

struct TextureImage {
  int width = 0, height = 0;  ///< px
  std::vector<uint8_t> rgba;  ///< sRGB-encoded RGBA8, top row first
};

// Throws std::runtime_error saying what is wrong ("'NAME': not an image simreel reads (...)",
// "'NAME': broken PNG data", ...) for anything that is not a whole, decodable image of at most
// kMaxImageSide px a side. `name` names the image in messages; its extension tells a TGA.
inline constexpr int kMaxImageSide = 16384;
inline constexpr int kMaxTextureSide = 4096;  ///< px: larger images are halved to this for drawing
TextureImage decode_image(std::string_view bytes, const std::string& name);
TextureImage read_image(const std::string& file);  ///< decode_image of the file's bytes

// Halves an image (2x2 box average, in linear light) until neither side exceeds max_side.
void shrink_image(TextureImage& im, int max_side);

}  // namespace simreel
