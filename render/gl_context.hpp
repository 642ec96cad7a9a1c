// An off-screen OpenGL 3.3+ core context whose default framebuffer is a CPU-side RGBA buffer.
// The OSMesa backend is the one Debian 12 ships; OSMesa left Mesa in 25.1, so the renderer only
// talks to this interface and a headless EGL (surfaceless + pbuffer/FBO) backend can slot in.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

namespace simreel {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  // After finish(): the default framebuffer, RGBA8, top row first, width*height*4 bytes.
  virtual const uint8_t* pixels() const = 0;
  virtual void finish() = 0;
  virtual std::string description() const = 0;  ///< renderer and version strings
};

// Throws std::runtime_error if no context can be made.
std::unique_ptr<GlContext> make_offscreen_context(int width, int height);

}  // namespace simreel
