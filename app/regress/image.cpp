#include "app/regress/image.hpp"

#include <png.h>

#include <bit>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <simreel/error.hpp>

namespace simreel {

namespace {

constexpr png_uint_32 kMaxSide = 16384;  // simreel's largest frame side (scenes/README.md)

// libpng reports errors through a callback that must not return; it longjmps back to the setjmp in
// decode_into / encode_into. Those functions create nothing with a destructor after setjmp and
// change none of their own locals that are read after the jump: the message goes into a fixed
// buffer owned by the caller, the pixels into the caller's Image or vector.
struct PngErr {
  char msg[200] = {};
  bool truncated = false;  // the data ran out (else libpng found it corrupt)
};

void on_error(png_structp png, png_const_charp msg) {
  auto* e = static_cast<PngErr*>(png_get_error_ptr(png));
  if (e) std::snprintf(e->msg, sizeof e->msg, "%s", msg ? msg : "libpng error");
  png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}  // warnings (unknown chunks, sRGB profiles) are not errors

struct Reader {
  const uint8_t* data;
  size_t size, pos;
};

void read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* r = static_cast<Reader*>(png_get_io_ptr(png));
  if (n > r->size - r->pos) {
    static_cast<PngErr*>(png_get_error_ptr(png))->truncated = true;
    png_error(png, "unexpected end of data");
  }
  std::memcpy(out, r->data + r->pos, n);
  r->pos += n;
}

// Returns "" on success, else what went wrong. `out` belongs to the caller: nothing with a
// destructor is created in this frame after setjmp.
std::string decode_into(const uint8_t* data, size_t size, Image& out, PngErr& err) {
  if (size < 8 || png_sig_cmp(data, 0, 8) != 0) return "not a PNG file";
  Reader rd{data, size, 0};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, on_error, on_warning);
  if (!png) return "libpng: out of memory";
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return "libpng: out of memory";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    if (err.truncated) return "truncated PNG (the data ends after " + std::to_string(size) + " bytes)";
    return std::string("corrupt PNG (libpng: ") + err.msg + ")";
  }
  png_set_read_fn(png, &rd, read_bytes);
  png_set_user_limits(png, kMaxSide, kMaxSide);
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  const int type = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
  // Everything to 8-bit RGBA: palette -> RGB, grey below 8 bits -> 8, tRNS -> alpha, 16 -> 8
  // (rounded), grey -> RGB, opaque alpha added where there is none.
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_scale_16(png);
  if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if (!(type & PNG_COLOR_MASK_ALPHA)) png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != (png_size_t)w * 4)
    png_error(png, "unexpected row size after conversion");
  out.width = (int)w;
  out.height = (int)h;
  out.rgba.assign((size_t)w * h * 4, 0);
  for (int p = 0; p < passes; ++p)
    for (png_uint_32 y = 0; y < h; ++y) png_read_row(png, out.rgba.data() + (size_t)y * w * 4, nullptr);
  png_read_end(png, nullptr);  // checks the chunks after the image data up to IEND
  png_destroy_read_struct(&png, &info, nullptr);
  return "";
}

void append_bytes(png_structp png, png_bytep data, png_size_t n) {
  auto* v = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  v->insert(v->end(), data, data + n);
}
void flush_nothing(png_structp) {}

std::string encode_into(const Image& img, bool alpha, std::vector<uint8_t>& out, PngErr& err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, on_error, on_warning);
  if (!png) return "libpng: out of memory";
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return "libpng: out of memory";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return std::string("libpng: ") + err.msg;
  }
  png_set_write_fn(png, &out, append_bytes, flush_nothing);
  png_set_IHDR(png, info, (png_uint_32)img.width, (png_uint_32)img.height, 8,
               alpha ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_write_info(png, info);
  if (!alpha) png_set_filler(png, 0, PNG_FILLER_AFTER);  // rows are RGBA: skip the alpha byte
  const size_t stride = (size_t)img.width * 4;
  for (int y = 0; y < img.height; ++y) png_write_row(png, img.rgba.data() + (size_t)y * stride);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return "";
}

}  // namespace

Image decode_png(const uint8_t* data, size_t size, const std::string& name) {
  Image img;
  PngErr err;
  const std::string e = decode_into(data, size, img, err);
  if (!e.empty()) throw InputError(name + ": " + e);
  return img;
}

Image read_png(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::vector<uint8_t> bytes;
  uint8_t buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw InputError(path + ": read error");
  return decode_png(bytes.data(), bytes.size(), path);
}

std::vector<uint8_t> encode_png(const Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.rgba.size() != (size_t)img.width * img.height * 4)
    throw std::runtime_error("encode_png: empty image or pixel buffer of the wrong size");
  bool alpha = false;
  for (size_t i = 3; i < img.rgba.size(); i += 4) alpha |= img.rgba[i] != 255;
  std::vector<uint8_t> out;
  PngErr err;
  const std::string e = encode_into(img, alpha, out, err);
  if (!e.empty()) throw std::runtime_error("encode_png: " + e);
  return out;
}

void write_png_file(const std::string& path, const Image& img) {
  const std::vector<uint8_t> bytes = encode_png(img);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (std::fclose(f) != 0 || !ok) {
    std::remove(path.c_str());
    throw std::runtime_error("cannot write '" + path + "'");
  }
}

namespace {

// XXH64 (Yann Collet's xxHash, 64-bit variant), written from its published specification
// (xxhash.com, "xxHash fast digest algorithm", XXH64): 32-byte stripes in four lanes, then the
// 8-, 4- and 1-byte tail and the final avalanche. Agrees with libxxhash's XXH64().
constexpr uint64_t kP1 = 0x9E3779B185EBCA87ull, kP2 = 0xC2B2AE3D27D4EB4Full, kP3 = 0x165667B19E3779F9ull,
                   kP4 = 0x85EBCA77C2B2AE63ull, kP5 = 0x27D4EB2F165667C5ull;

inline uint64_t rotl(uint64_t x, int r) {
  return (x << r) | (x >> (64 - r));
}
inline uint64_t read64(const uint8_t* p) {  // little-endian, whatever the host
  if constexpr (std::endian::native == std::endian::little) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
  } else {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
  }
}
inline uint64_t read32(const uint8_t* p) {
  return (uint64_t)p[0] | (uint64_t)p[1] << 8 | (uint64_t)p[2] << 16 | (uint64_t)p[3] << 24;
}
inline uint64_t xxh_round(uint64_t acc, uint64_t input) {
  return rotl(acc + input * kP2, 31) * kP1;
}
inline uint64_t xxh_merge(uint64_t acc, uint64_t v) {
  return (acc ^ xxh_round(0, v)) * kP1 + kP4;
}

uint64_t xxh64(const uint8_t* p, size_t len, uint64_t seed) {
  const uint8_t* const end = p + len;
  uint64_t h;
  if (len >= 32) {
    uint64_t v1 = seed + kP1 + kP2, v2 = seed + kP2, v3 = seed, v4 = seed - kP1;
    for (; end - p >= 32; p += 32) {
      v1 = xxh_round(v1, read64(p));
      v2 = xxh_round(v2, read64(p + 8));
      v3 = xxh_round(v3, read64(p + 16));
      v4 = xxh_round(v4, read64(p + 24));
    }
    h = rotl(v1, 1) + rotl(v2, 7) + rotl(v3, 12) + rotl(v4, 18);
    h = xxh_merge(xxh_merge(xxh_merge(xxh_merge(h, v1), v2), v3), v4);
  } else {
    h = seed + kP5;
  }
  h += (uint64_t)len;
  for (; end - p >= 8; p += 8) h = rotl(h ^ xxh_round(0, read64(p)), 27) * kP1 + kP4;
  if (end - p >= 4) {
    h = rotl(h ^ (read32(p) * kP1), 23) * kP2 + kP3;
    p += 4;
  }
  for (; p < end; ++p) h = rotl(h ^ (*p * kP5), 11) * kP1;
  h ^= h >> 33;
  h *= kP2;
  h ^= h >> 29;
  h *= kP3;
  h ^= h >> 32;
  return h;
}

}  // namespace

std::string pixel_hash(const Image& img) {
  const uint64_t seed = (uint64_t)(uint32_t)img.width << 32 | (uint32_t)img.height;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx",
                (unsigned long long)xxh64(img.rgba.data(), img.rgba.size(), seed));
  return hex;
}

bool identical(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         (a.rgba.empty() || std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size()) == 0);
}

}  // namespace simreel
