// PNG files from RGBA frames (alpha dropped), via libpng. No timestamps or other varying chunks,
// so identical frames give identical files.
#pragma once
#include <cstdint>
#include <string>

namespace simreel {

// Throws std::runtime_error if the file cannot be written.
void write_png(const std::string& path, const uint8_t* rgba, int width, int height);

}  // namespace simreel
