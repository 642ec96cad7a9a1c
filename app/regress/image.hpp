// Decoded images for visual regression: PNG in and out through libpng, and a hash of the
// decoded pixels so that a golden frame's identity does not depend on how its file was compressed.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace simreel {

// RGBA8, rows top first, no padding: pixel (x, y) is rgba[4 * (y * width + x) + 0..3].
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// Reads a PNG of any colour type and depth: grey, grey + alpha, palette (with or without tRNS),
// RGB and RGBA, 1-16 bits, interlaced or not, all converted to RGBA8 (16-bit samples scaled to 8
// bits with rounding; no gamma or colour-space conversion; alpha 255 where the file has none). Throws
// InputError (include/simreel/error.hpp) whose message starts with the path on any failure: missing or
// unreadable file, not a PNG, corrupt or truncated data (including a missing IEND), or a side over
// 16384 (simreel's largest frame).
Image read_png(const std::string& path);

// The same from PNG bytes in memory; `name` stands for the path in error messages.
Image decode_png(const uint8_t* data, size_t size, const std::string& name);

// PNG bytes of the image: RGB when every pixel is opaque (as render/png_writer.hpp writes frames),
// else RGBA; 8 bits, not interlaced, zlib level 6, no tIME/tEXt or other varying chunks, so the
// same pixels give the same bytes (with the same libpng and zlib). Throws std::runtime_error if
// libpng fails (an empty image, say).
std::vector<uint8_t> encode_png(const Image& img);

// encode_png's bytes written to `path`; throws std::runtime_error if the file cannot be written.
void write_png_file(const std::string& path, const Image& img);

// XXH64 (xxHash's 64-bit hash, the same value libxxhash's XXH64() gives) of the RGBA bytes, with
// the seed width x 2^32 + height, as 16 lowercase hex digits; about 0.3 ms for 1280 x 720. Two
// images with the same size and bytes always hash alike, whatever PNG file they came from; the
// size alone (16 x 4 vs 4 x 16 with the same bytes) changes the hash. Collision odds: XXH64 is not
// cryptographic, but for images not built to collide the chance that a changed image keeps its
// golden's hash is about 2^-64 (5e-20) per comparison, and the chance that any two of N goldens
// share a hash about N^2 / 2^65 (3e-8 for a million goldens). Not for inputs chosen by an adversary.
std::string pixel_hash(const Image& img);

// Same size and the same RGBA bytes (exact mode).
bool identical(const Image& a, const Image& b);

}  // namespace simreel
