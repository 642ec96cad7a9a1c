// Who drew a frame: the facts that decide whether two machines give byte-identical pixels.
// llvmpipe's output depends on its version (Mesa, LLVM), its vector width (128 or 256 bits, from
// the CPU or LP_NATIVE_VECTOR_WIDTH) and the CPU features LLVM generates code for; the GL backend
// (OSMesa or EGL) and llvmpipe's thread count do not change it (tests/app/cli/cli_test.cpp checks both).
#pragma once
#include <string>

#include "app/cli/goldens.hpp"

namespace simreel {

// Keys: simreel, gl_backend, gl_renderer, gl_version, llvmpipe_vector_width, cpu_features,
// LP_NATIVE_VECTOR_WIDTH (when set). `description` is Renderer::description():
// "BACKEND: RENDERER, VERSION".
Fingerprint fingerprint(const std::string& description);

// Whether frames drawn under the two fingerprints are expected to be byte-identical: the same
// renderer, GL version and CPU features (the backend and simreel's version do not matter).
bool same_pixels_expected(const Fingerprint& a, const Fingerprint& b);

// Whether the two fingerprints name the same rasterizer: the same GL renderer and version, the
// llvmpipe vector width left out ("llvmpipe (LLVM 15.0.6, 256 bits)" and "..., 128 bits)" are
// one). Frames of the same rasterizer differ at most by noise the default portable tolerance
// passes (measured: 128 and 256 bits drew byte-identical frames, app/regress/metrics.hpp);
// another rasterizer or Mesa version needs CompareOptions::cross_renderer().
bool same_rasterizer(const Fingerprint& a, const Fingerprint& b);

}  // namespace simreel
