// An off-screen OpenGL 3.3+ core context, made current on the calling thread. The renderer draws
// into its own framebuffer objects and reads frames back with glReadPixels, so it needs no default
// framebuffer at all.
//
// Two backends, both Mesa: OSMesa (Debian 12's; removed from Mesa in 25.1) and EGL without a
// window system (Mesa's surfaceless platform, or else the first EGL device). On Debian 12 both run
// llvmpipe and give the same frames byte for byte. GL calls go through Mesa's shared dispatch,
// which both backends set; a build without OSMesa (-DSIMREEL_OSMESA=OFF) links libOpenGL instead.
#pragma once
#include <memory>
#include <optional>
#include <string>

namespace simreel {

enum class GlBackend { osmesa, egl };
const char* to_string(GlBackend b);
std::optional<GlBackend> gl_backend_from_name(const std::string& name);
bool gl_backend_built(GlBackend b);  ///< compiled into this binary
GlBackend default_gl_backend();      ///< OSMesa if built, else EGL

class GlContext {
 public:
  virtual ~GlContext();
  void make_current();  ///< several contexts may live in one thread; binds only when needed
  virtual void finish() = 0;
  virtual std::string description() const = 0;  ///< backend, renderer and version strings

 protected:
  virtual void bind() = 0;  ///< make current; throws std::runtime_error on failure
};

// Throws std::runtime_error, naming the backend and what failed, if no context can be made.
std::unique_ptr<GlContext> make_offscreen_context(GlBackend backend = default_gl_backend());

}  // namespace simreel
