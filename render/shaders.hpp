// The renderer's GLSL programs and the arithmetic they share with tests.
//
// On llvmpipe every fragment runs the shader on the CPU, so the lit shader is written for it
// (measured on the 100-box benchmark frame, llvmpipe worker CPU per 720p frame):
// - two specialisations: the ground (constant normal, checker) and bodies (no checker);
// - the specular power x^48 by repeated squaring instead of pow() (exp2/log2): 0.6 ms;
// - the sRGB encoding by a fitted sum of roots (srgb_encode) instead of pow(): 1.1 ms.
// The ground samples no shadow map: its shadows are the bodies projected onto it along the light
// (ground_shadow_*_shader), a flat colour, exact, with hard edges.
#pragma once
#include <array>
#include <string>

namespace simreel {

// The sRGB encoding (IEC 61966-2-1: 12.92 x up to 0.0031308, 1.055 x^(1/2.4) - 0.055 above) of a
// linear value in [0, 1], as the fragment shaders compute it: above the linear segment, with
// s = sqrt(x), q = sqrt(s), e = sqrt(q),
//   c0 s + c1 q + c4 e + x (c2 + c3 q),
// four square roots instead of pow() (exp2/log2, ~1.1 ms a 720p frame on llvmpipe).
// Coefficients from an iteratively reweighted least-squares (near-minimax) fit over
// [0.0031308, 1], dense near the low end where the curve is steepest. Largest error 3.8e-5, a
// hundredth of an 8-bit level (tests/render/shaders_test).
inline constexpr float kSrgbFit[5] = {0.636357017f, 0.716423151f, -0.008719922f, -0.005760988f,
                                      -0.338337307f};
float srgb_encode(float x);

// kFillSky: the sky end of the lit shader's hemisphere fill, the whole fill of a surface facing
// straight up.
inline constexpr float kFillSky[3] = {0.30f, 0.34f, 0.42f};

// A ground colour in the key light's shadow, sRGB-encoded: what the lit ground shader gives seen
// from above with the light blocked (ambient only, no specular), srgb_encode(ground kFillSky). The
// ground shadow pass (ground_shadow_*_shader) writes it, one per checker colour.
std::array<float, 3> ground_shadow_color(const std::array<float, 3>& ground);

// body: lit and shadowed by the shadow map; body_unshadowed: the same without the map (for bodies
// no other body can shadow, render/renderer.cpp: classify_shadows); ground: the checker, no map.
// body_material and body_material_unshadowed: the same for meshes drawn with their file's look
// (per-vertex colours and a base-colour texture, render/material.hpp).
// ground_textured: the ground with render.ground_texture instead of the checker.
enum class LitKind {
  body,
  body_unshadowed,
  ground,
  body_material,
  body_material_unshadowed,
  ground_textured
};
bool lit_material(LitKind kind);

std::string lit_vertex_shader(LitKind kind);
// soft: render.quality high (soft shadows from the map, on the ground too).
std::string lit_fragment_shader(LitKind kind, bool soft = false);  ///< kSrgbFit written into the source
const char* depth_vertex_shader();
// The overlay pass (render/overlay.hpp): instanced unit solids, or ribbons with a colour per vertex.
const char* overlay_vertex_shader(bool ribbon);
std::string overlay_fragment_shader(bool ribbon);
const char* depth_fragment_shader();
// Shadows on the ground: the bodies projected along the light onto the ground plane, drawn in the
// ground's shadowed colour (render/renderer.cpp, ground_shadows).
const char* ground_shadow_vertex_shader();
std::string ground_shadow_fragment_shader(bool textured);
// The sky behind everything (render/renderer.cpp, sky_pass).
const char* sky_vertex_shader();
std::string sky_fragment_shader();
// Screen-space ambient occlusion (render.quality: high), drawn with sky_vertex_shader's triangle.
std::string ao_fragment_shader();

// Compiles and links; throws std::runtime_error with the driver's log on failure. Needs a
// current GL context.
unsigned link_program(const char* vertex_source, const char* fragment_source);

}  // namespace simreel
