// The renderer's GLSL programs and the arithmetic they share with tests.
//
// On llvmpipe every fragment runs the shader on the CPU, so the lit shader is written for it
// (measured on the 100-box benchmark frame, llvmpipe worker CPU per 720p frame):
// - two specialisations: the ground (constant normal, checker) and bodies (no checker);
// - the specular power x^48 by repeated squaring instead of pow() (exp2/log2): 0.6 ms;
// - gamma encoding x^(1/2.2) by a fitted sum of roots (gamma_encode) instead of pow(): 1.1 ms.
// The ground samples no shadow map: its shadows are the bodies projected onto it along the light
// (ground_shadow_*_shader), a flat colour, exact, with hard edges.
#pragma once
#include <array>
#include <string>

namespace simreel {

// x^(1/2.2) for x in [0, 1], as the fragment shader computes it: with s = sqrt(x), q = sqrt(s),
//   c0 s + c1 q + x (c2 + c3 q).
// Coefficients from an iteratively reweighted least-squares (near-minimax) fit over [0, 1], dense
// near 0 where the curve is steepest. Largest error 8.3e-4, a fifth of an 8-bit level: the
// encoded value rounds to the same level as pow() or the next one (tests/render/shaders_test).
inline constexpr float kGammaFit[4] = {1.103299715f, 0.047538824f, -0.351024566f, 0.201012415f};
float gamma_encode(float x);

// The lit shader's ground checker (its odd tiles are kCheckerDark times the ground colour) and the
// sky end of its hemisphere fill, the whole fill of a surface facing straight up.
inline constexpr float kCheckerDark = 0.72f;
inline constexpr float kFillSky[3] = {0.30f, 0.34f, 0.42f};

// The ground's colour in the key light's shadow, gamma-encoded: what the lit ground shader gives
// seen from above with the light blocked (ambient only, no specular), gamma_encode(base kFillSky),
// base the ground colour or, on odd checker tiles, kCheckerDark of it. The ground shadow pass
// (ground_shadow_*_shader) writes it.
std::array<float, 3> ground_shadow_color(const std::array<float, 3>& ground, bool odd_tile);

// body: lit and shadowed by the shadow map; body_unshadowed: the same without the map (for bodies
// no other body can shadow, render/renderer.cpp: classify_shadows); ground: the checker, no map.
// body_material and body_material_unshadowed: the same for meshes drawn with their file's look
// (per-vertex colours and a base-colour texture, render/material.hpp).
enum class LitKind { body, body_unshadowed, ground, body_material, body_material_unshadowed };
bool lit_material(LitKind kind);

std::string lit_vertex_shader(LitKind kind);
std::string lit_fragment_shader(LitKind kind);  ///< kGammaFit written into the source
const char* depth_vertex_shader();
// The overlay pass (render/overlay.hpp): instanced unit solids, or ribbons with a colour per vertex.
const char* overlay_vertex_shader(bool ribbon);
std::string overlay_fragment_shader(bool ribbon);
const char* depth_fragment_shader();
// Shadows on the ground: the bodies projected along the light onto the ground plane, drawn in the
// ground's shadowed colour (render/renderer.cpp, ground_shadows).
const char* ground_shadow_vertex_shader();
const char* ground_shadow_fragment_shader();

// Compiles and links; throws std::runtime_error with the driver's log on failure. Needs a
// current GL context.
unsigned link_program(const char* vertex_source, const char* fragment_source);

}  // namespace simreel
