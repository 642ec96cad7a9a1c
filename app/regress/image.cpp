#include "app/regress/image.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "sim/error.hpp"

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
  if (png_get_rowbytes(png, info) != (png_size_t)w * 4) png_error(png, "unexpected row size after conversion");
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

std::string pixel_hash(const Image& img) {
  // FNV-1a, 64 bits: offset basis 14695981039346656037, prime 1099511628211 (Fowler, Noll, Vo).
  uint64_t h = 14695981039346656037ull;
  constexpr uint64_t kPrime = 1099511628211ull;
  auto feed = [&](const uint8_t* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kPrime;
  };
  const char tag[] = "simreel-rgba8";
  feed(reinterpret_cast<const uint8_t*>(tag), sizeof tag - 1);
  const uint32_t dims[2] = {(uint32_t)img.width, (uint32_t)img.height};
  for (uint32_t d : dims) {
    const uint8_t le[4] = {uint8_t(d), uint8_t(d >> 8), uint8_t(d >> 16), uint8_t(d >> 24)};
    feed(le, 4);
  }
  feed(img.rgba.data(), img.rgba.size());
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)h);
  return hex;
}

bool identical(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         (a.rgba.empty() || std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size()) == 0);
}

}  // namespace simreel
