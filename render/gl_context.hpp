// An off-screen OpenGL 3.3+ core context, made current on the calling thread. The renderer draws
// into its own framebuffer objects and reads frames back with glReadPixels, so it needs no default
// framebuffer at all: exactly what a headless EGL (surfaceless) context offers. The OSMesa backend
// is the one Debian 12 ships; OSMesa left Mesa in 25.1, and an EGL backend slots in here.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

namespace simreel {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual void make_current() = 0;  ///< several renderers may live in one thread
  virtual void finish() = 0;
  virtual std::string description() const = 0;  ///< renderer and version strings
};

// Throws std::runtime_error if no context can be made.
std::unique_ptr<GlContext> make_offscreen_context();

}  // namespace simreel
