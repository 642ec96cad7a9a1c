#include "render/png_writer.hpp"

#include <png.h>

#include <cstdio>
#include <stdexcept>
#include <vector>

namespace simreel {

void write_png(const std::string& path, const uint8_t* rgba, int w, int h) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    std::remove(path.c_str());
    throw std::runtime_error("libpng failed writing '" + path + "'");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  png_set_filler(png, 0, PNG_FILLER_AFTER);  // input rows are RGBA: skip the alpha byte
  for (int y = 0; y < h; ++y) png_write_row(png, const_cast<png_bytep>(rgba + (size_t)y * w * 4));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(f) != 0) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace simreel
