#define GL_GLEXT_PROTOTYPES 1
#include "render/gl_context.hpp"

#include <GL/gl.h>
#include <malloc.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#if SIMREEL_HAVE_OSMESA
#include <GL/osmesa.h>
#endif
#if SIMREEL_HAVE_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif

#include "sim/base/enum_names.hpp"

namespace simreel {
namespace {

thread_local GlContext* current = nullptr;  // the context this thread last bound

// llvmpipe allocates and frees large blocks every frame. With glibc's default thresholds the heap
// was trimmed back to the system and regrown, page fault by page fault, each frame: a 1280x720
// frame with shadows took 24.7 ms instead of 12.8 ms (half of it in the kernel). Keep freed
// memory in the process instead; the renderer's footprint is bounded anyway.
void keep_freed_memory() {
#ifdef __GLIBC__
  static const bool tuned = [] {
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    return true;
  }();
  (void)tuned;
#endif
}

std::string gl_strings() {
  const char* r = (const char*)glGetString(GL_RENDERER);
  const char* v = (const char*)glGetString(GL_VERSION);
  return std::string(r ? r : "?") + ", " + (v ? v : "?");
}

#if SIMREEL_HAVE_OSMESA
class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() : buf_(kSide * kSide * 4) {
    keep_freed_memory();
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
    try {
      make_current();
    } catch (...) {
      OSMesaDestroyContext(ctx_);
      throw;
    }
  }
  ~OsMesaContext() override { OSMesaDestroyContext(ctx_); }
  void finish() override { glFinish(); }
  std::string description() const override { return "OSMesa: " + gl_strings(); }

 private:
  // OSMesa needs a buffer to make the context current; frames go to FBOs, so a token one does.
  void bind() override {
    if (!OSMesaMakeCurrent(ctx_, buf_.data(), GL_UNSIGNED_BYTE, kSide, kSide))
      throw std::runtime_error("OSMesa could not make its context current");
  }
  static constexpr int kSide = 16;
  std::vector<uint8_t> buf_;
  OSMesaContext ctx_ = nullptr;
};
#endif

#if SIMREEL_HAVE_EGL
std::string egl_error(const char* what) {
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%04x", (unsigned)eglGetError());
  return std::string("EGL: ") + what + " (error " + hex + ")";
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    keep_freed_memory();
    const auto get_display = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!get_display) throw std::runtime_error("EGL: no eglGetPlatformDisplayEXT (EGL_EXT_platform_base)");
    // Mesa's surfaceless platform needs no window system and no device file; failing that, the
    // first device EGL lists (EGL_EXT_platform_device).
    dpy_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (dpy_ == EGL_NO_DISPLAY || !eglInitialize(dpy_, &major, &minor)) {
      const auto query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
      EGLDeviceEXT device = nullptr;
      EGLint n = 0;
      if (!query_devices || !query_devices(1, &device, &n) || n < 1)
        throw std::runtime_error(egl_error("neither the surfaceless platform nor a device is available"));
      dpy_ = get_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
      if (dpy_ == EGL_NO_DISPLAY || !eglInitialize(dpy_, &major, &minor))
        throw std::runtime_error(egl_error("could not initialise a display on the first device"));
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error(egl_error("no desktop OpenGL"));
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              3,
                              EGL_CONTEXT_MINOR_VERSION,
                              3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    // No config and no surface (EGL_KHR_no_config_context, EGL_KHR_surfaceless_context): frames
    // go to the renderer's own framebuffer objects.
    ctx_ = eglCreateContext(dpy_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (ctx_ == EGL_NO_CONTEXT)
      throw std::runtime_error(egl_error("could not create an OpenGL 3.3 core context without a config"));
    try {
      make_current();
    } catch (...) {
      eglDestroyContext(dpy_, ctx_);
      throw;
    }
  }
  ~EglContext() override {
    if (eglGetCurrentContext() == ctx_) eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy_, ctx_);
    // The display is shared by every context on it and reference-counted by nothing: it stays
    // initialised, here and when a constructor fails (eglTerminate would pull it from under other
    // renderers).
  }
  void finish() override { glFinish(); }
  std::string description() const override { return "EGL: " + gl_strings(); }

 private:
  void bind() override {
    if (!eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
      throw std::runtime_error(egl_error("could not make the context current without a surface"));
  }
  EGLDisplay dpy_ = EGL_NO_DISPLAY;
  EGLContext ctx_ = EGL_NO_CONTEXT;
};
#endif

}  // namespace

GlContext::~GlContext() {
  if (current == this) current = nullptr;
}

void GlContext::make_current() {
  if (current == this) return;
  bind();
  current = this;
}

namespace {
constexpr EnumNames<GlBackend, 2> kGlBackends{{"osmesa", "egl"}};
static_assert(kGlBackends.complete());
}  // namespace

const char* to_string(GlBackend b) {
  return kGlBackends(b);
}

std::optional<GlBackend> gl_backend_from_name(const std::string& name) {
  return kGlBackends.parse(name);
}

bool gl_backend_built(GlBackend b) {
  return b == GlBackend::osmesa ? SIMREEL_HAVE_OSMESA : SIMREEL_HAVE_EGL;
}

GlBackend default_gl_backend() {
  return SIMREEL_HAVE_OSMESA ? GlBackend::osmesa : GlBackend::egl;
}

std::unique_ptr<GlContext> make_offscreen_context(GlBackend backend) {
#if SIMREEL_HAVE_OSMESA
  if (backend == GlBackend::osmesa) return std::make_unique<OsMesaContext>();
#endif
#if SIMREEL_HAVE_EGL
  if (backend == GlBackend::egl) return std::make_unique<EglContext>();
#endif
  throw std::runtime_error(std::string("this simreel was built without the ") + to_string(backend) +
                           " backend");
}

}  // namespace simreel
