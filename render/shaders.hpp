// The renderer's GLSL programs and the arithmetic they share with tests.
//
// On llvmpipe every fragment runs the shader on the CPU, so the lit shader is written for it
// (measured on the 100-box benchmark frame, llvmpipe worker CPU per 720p frame):
// - two specialisations: the ground (constant normal, checker) and bodies (no checker);
// - the specular power x^48 by repeated squaring instead of pow() (exp2/log2): 0.6 ms;
// - gamma encoding x^(1/2.2) by a fitted sum of roots (gamma_encode) instead of pow(): 1.1 ms.
// Light-space coordinates stay divided per fragment: interpolating them already divided (exact
// for the orthographic light) made the cached ground's footprints differ from the full ground by
// up to 8 levels at a few shadow-edge pixels (tests/render: CachedGroundLooksLikeTheFullGround).
#pragma once
#include <string>

namespace simreel {

// x^(1/2.2) for x in [0, 1], as the fragment shader computes it: with s = sqrt(x), q = sqrt(s),
//   c0 s + c1 q + x (c2 + c3 q).
// Coefficients from an iteratively reweighted least-squares (near-minimax) fit over [0, 1], dense
// near 0 where the curve is steepest. Largest error 8.3e-4, a fifth of an 8-bit level: the
// encoded value rounds to the same level as pow() or the next one (tests/render/shaders_test).
inline constexpr float kGammaFit[4] = {1.103299715f, 0.047538824f, -0.351024566f, 0.201012415f};
float gamma_encode(float x);

enum class LitKind { body, ground };

const char* lit_vertex_shader();
std::string lit_fragment_shader(LitKind kind);  ///< kGammaFit written into the source
const char* depth_vertex_shader();
// The overlay pass (render/overlay.hpp): instanced unit solids, or ribbons with a colour per vertex.
const char* overlay_vertex_shader(bool ribbon);
std::string overlay_fragment_shader(bool ribbon);
const char* depth_fragment_shader();

// Compiles and links; throws std::runtime_error with the driver's log on failure. Needs a
// current GL context.
unsigned link_program(const char* vertex_source, const char* fragment_source);

}  // namespace simreel
