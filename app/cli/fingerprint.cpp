#include "app/cli/fingerprint.hpp"

#include <cstdlib>
#include <regex>

#include "app/cli/commands.hpp"

namespace simreel {

namespace {

std::string cpu_features() {
  std::string out;
  __builtin_cpu_init();
  auto add = [&](bool has, const char* name) {
    if (has) out += (out.empty() ? "" : " ") + std::string(name);
  };
  // The x86 features LLVM's code generation for llvmpipe's shaders depends on.
  add(__builtin_cpu_supports("sse4.1"), "sse4.1");
  add(__builtin_cpu_supports("sse4.2"), "sse4.2");
  add(__builtin_cpu_supports("avx"), "avx");
  add(__builtin_cpu_supports("avx2"), "avx2");
  add(__builtin_cpu_supports("fma"), "fma");
  add(__builtin_cpu_supports("f16c"), "f16c");
  add(__builtin_cpu_supports("avx512f"), "avx512f");
  return out;
}

}  // namespace

Fingerprint fingerprint(const std::string& description) {
  Fingerprint f;
  f.emplace_back("simreel", kVersion);
  std::string backend, rest = description;
  if (const size_t colon = description.find(": "); colon != std::string::npos) {
    backend = description.substr(0, colon);
    rest = description.substr(colon + 2);
  }
  // GL_VERSION starts with a digit ("4.5 (Core Profile) Mesa 22.3.6"); GL_RENDERER may hold
  // commas ("llvmpipe (LLVM 15.0.6, 256 bits)"): split at the last ", " before a digit.
  std::string renderer = rest, version;
  for (size_t p = rest.rfind(", "); p != std::string::npos;
       p = p ? rest.rfind(", ", p - 1) : std::string::npos) {
    if (p + 2 < rest.size() && std::isdigit((unsigned char)rest[p + 2])) {
      renderer = rest.substr(0, p);
      version = rest.substr(p + 2);
      break;
    }
    if (p == 0) break;
  }
  f.emplace_back("gl_backend", backend);
  f.emplace_back("gl_renderer", renderer);
  f.emplace_back("gl_version", version);
  std::smatch m;
  const std::regex bits("([0-9]+) bits");
  f.emplace_back("llvmpipe_vector_width", std::regex_search(renderer, m, bits) ? m[1].str() : "");
  f.emplace_back("cpu_features", cpu_features());
  if (const char* w = std::getenv("LP_NATIVE_VECTOR_WIDTH")) f.emplace_back("LP_NATIVE_VECTOR_WIDTH", w);
  return f;
}

bool same_pixels_expected(const Fingerprint& a, const Fingerprint& b) {
  for (const char* k : {"gl_renderer", "gl_version", "cpu_features"})
    if (fingerprint_value(a, k) != fingerprint_value(b, k) || fingerprint_value(a, k).empty()) return false;
  return true;
}

bool same_rasterizer(const Fingerprint& a, const Fingerprint& b) {
  const std::regex width(",? *[0-9]+ bits");
  auto renderer = [&](const Fingerprint& f) {
    return std::regex_replace(fingerprint_value(f, "gl_renderer"), width, "");
  };
  return renderer(a) == renderer(b) &&
         fingerprint_value(a, "gl_version") == fingerprint_value(b, "gl_version");
}

}  // namespace simreel
