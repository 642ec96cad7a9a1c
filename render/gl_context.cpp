#define GL_GLEXT_PROTOTYPES 1
#include "render/gl_context.hpp"

#include <GL/gl.h>
#include <GL/osmesa.h>
#include <malloc.h>

#include <stdexcept>
#include <vector>

namespace simreel {
namespace {

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() : buf_(kSide * kSide * 4) {
#ifdef __GLIBC__
    // llvmpipe allocates and frees large blocks every frame. With glibc's default thresholds the
    // heap was trimmed back to the system and regrown, page fault by page fault, each frame: a
    // 1280x720 frame with shadows took 24.7 ms instead of 12.8 ms (half of it in the kernel).
    // Keep freed memory in the process instead; the renderer's footprint is bounded anyway.
    static const bool tuned = [] {
      mallopt(M_MMAP_THRESHOLD, 256 << 20);
      mallopt(M_TRIM_THRESHOLD, 512 << 20);
      return true;
    }();
    (void)tuned;
#endif
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           0,
                           OSMESA_ACCUM_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw std::runtime_error("OSMesa could not create an OpenGL 3.3 core context");
    if (!bind()) {
      OSMesaDestroyContext(ctx_);
      throw std::runtime_error("OSMesa could not make its context current");
    }
  }
  void make_current() override {
    if (OSMesaGetCurrentContext() != ctx_ && !bind())
      throw std::runtime_error("OSMesa could not make its context current");
  }
  ~OsMesaContext() override {
    OSMesaDestroyContext(ctx_);
  }
  void finish() override {
    glFinish();
  }
  std::string description() const override {
    const char* r = (const char*)glGetString(GL_RENDERER);
    const char* v = (const char*)glGetString(GL_VERSION);
    return std::string("OSMesa: ") + (r ? r : "?") + ", " + (v ? v : "?");
  }

 private:
  // OSMesa needs a buffer to make the context current; frames go to FBOs, so a token one does.
  bool bind() {
    return OSMesaMakeCurrent(ctx_, buf_.data(), GL_UNSIGNED_BYTE, kSide, kSide);
  }
  static constexpr int kSide = 16;
  std::vector<uint8_t> buf_;
  OSMesaContext ctx_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> make_offscreen_context() {
  return std::make_unique<OsMesaContext>();
}

}  // namespace simreel
