#define GL_GLEXT_PROTOTYPES 1
#include "render/gl_context.hpp"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <stdexcept>
#include <vector>

namespace simreel {
namespace {

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext(int w, int h) : w_(w), h_(h), buf_((size_t)w * h * 4) {
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
    if (!OSMesaMakeCurrent(ctx_, buf_.data(), GL_UNSIGNED_BYTE, w, h)) {
      OSMesaDestroyContext(ctx_);
      throw std::runtime_error("OSMesa could not bind a " + std::to_string(w) + "x" + std::to_string(h) +
                               " buffer");
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 of the buffer is the top of the image
  }
  ~OsMesaContext() override { OSMesaDestroyContext(ctx_); }
  int width() const override { return w_; }
  int height() const override { return h_; }
  const uint8_t* pixels() const override { return buf_.data(); }
  void finish() override { glFinish(); }
  std::string description() const override {
    const char* r = (const char*)glGetString(GL_RENDERER);
    const char* v = (const char*)glGetString(GL_VERSION);
    return std::string("OSMesa: ") + (r ? r : "?") + ", " + (v ? v : "?");
  }

 private:
  int w_, h_;
  std::vector<uint8_t> buf_;
  OSMesaContext ctx_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> make_offscreen_context(int width, int height) {
  return std::make_unique<OsMesaContext>(width, height);
}

}  // namespace simreel
