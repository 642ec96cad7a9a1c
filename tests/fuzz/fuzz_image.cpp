// libFuzzer harness: the texture decoder (render/image.cpp, FFmpeg's image decoders behind a
// signature check) on arbitrary bytes. A std::runtime_error is the right answer to bad input; an
// image reported as decoded must hold exactly width x height RGBA texels within the size limit.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "render/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The last byte picks the name, so TGA (recognised by its name only) is reached too.
  const std::string name = size && (data[size - 1] & 1) ? "x.tga" : "x.png";
  try {
    const simreel::TextureImage im =
        simreel::decode_image(std::string_view(reinterpret_cast<const char*>(data), size), name);
    if (im.width < 1 || im.height < 1 || im.width > simreel::kMaxImageSide ||
        im.height > simreel::kMaxImageSide || im.rgba.size() != (size_t)im.width * im.height * 4) {
      std::fprintf(stderr, "FINDING: decoded image of %dx%d with %zu bytes\n", im.width, im.height,
                   im.rgba.size());
      std::abort();
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
