#define GL_GLEXT_PROTOTYPES 1
#include "render/shaders.hpp"

#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace simreel {

float srgb_encode(float x) {
  const float c = std::fmin(std::fmax(x, 0.0f), 1.0f), s = std::sqrt(c), q = std::sqrt(s), e = std::sqrt(q);
  if (c <= 0.0031308f) return 12.92f * c;
  return kSrgbFit[0] * s + kSrgbFit[1] * q + kSrgbFit[4] * e + c * (kSrgbFit[2] + kSrgbFit[3] * q);
}

namespace {

// Bodies are drawn instanced, one draw per distinct mesh: each frame the items' model matrices
// and colours go into a buffer texture (5 RGBA32F texels per item) and a_item, a per-instance
// attribute, is the item's slot there (render/renderer.cpp, group_items). With u_batched == 0 a
// single mesh is drawn with the u_model and u_color uniforms (the ground).
// MATERIAL (1 or 0) is defined above this text by lit_vertex_shader(): a mesh file's look
// (render/material.hpp) comes in per vertex as a_tint (rgb, and a: 1 to take it, 0 to keep the
// item's colour) and a_uv (texture coordinates, v up from the image's bottom row).
const char* kLitVS = R"(
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in uint a_item;
#if MATERIAL
layout(location = 3) in vec4 a_tint;
layout(location = 4) in vec2 a_uv;
out vec4 v_tint;
out vec2 v_uv;
#endif
uniform mat4 u_model, u_viewproj, u_lightvp;
uniform vec3 u_color;
uniform int u_batched;
uniform samplerBuffer u_items;
out vec3 v_pos;
out vec3 v_nrm;
out vec3 v_lpos;
flat out vec3 v_color;
void main() {
  mat4 model = u_model;
  v_color = u_color;
  if (u_batched == 1) {
    int b = int(a_item) * 5;
    model = mat4(texelFetch(u_items, b), texelFetch(u_items, b + 1), texelFetch(u_items, b + 2),
                 texelFetch(u_items, b + 3));
    v_color = texelFetch(u_items, b + 4).rgb;
  }
#if MATERIAL
  v_tint = a_tint;
  v_uv = vec2(a_uv.x, 1.0 - a_uv.y);  // images are uploaded top row first
#endif
  vec4 w = model * vec4(a_pos, 1.0);
  v_pos = w.xyz;
  v_nrm = mat3(model) * a_nrm;
  // Light-space coordinates mapped to [0, 1]: the light is orthographic (w = 1), so they are
  // linear across a triangle and can be interpolated.
  v_lpos = (u_lightvp * w).xyz * 0.5 + 0.5;
  gl_Position = u_viewproj * w;
}
)";

// Key light: Blinn-Phong, shadowed with one bilinear depth-compare tap (edges soft over a texel); fill: a
// hemisphere ambient from ground bounce to sky. Lighting is done in linear RGB, then sRGB-encoded.
// GROUND, SHADOWED, MATERIAL (1 or 0) and srgb_encode() are defined above this text by
// lit_fragment_shader().
const char* kLitFS = R"(
in vec3 v_pos;
in vec3 v_nrm;
in vec3 v_lpos;
flat in vec3 v_color;
#if MATERIAL
in vec4 v_tint;
in vec2 v_uv;
uniform sampler2D u_albedo;  // sRGB texture: sampled in linear light, mipmapped
#endif
#if GROUND
uniform vec3 u_color2;  // the checker's odd tiles
#endif
#if GROUND_TEXTURE
uniform sampler2D u_ground_tex;  // sRGB, repeating every u_ground_tex_size m
uniform float u_ground_tex_size;
#endif
uniform vec3 u_light_dir, u_eye;
uniform int u_shadows;
uniform float u_tile, u_bias;
uniform sampler2DShadow u_shadow_map;
out vec4 o_color;
float lit_fraction() {
#if !SHADOWED
  // The ground's shadows are the bodies projected onto it (kGroundShadowVS) unless they are soft;
  // a convex body no other body can shadow is never in shadow where it faces the light.
  return 1.0;
#else
  if (u_shadows == 0 || v_lpos.z > 1.0) return 1.0;
#if SOFT
  // render.quality: high: a 4 x 4 grid of bilinear taps one texel apart (64 depth tests), a
  // penumbra about four texels wide.
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_map, 0));
  float sum = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      sum += texture(u_shadow_map, vec3(v_lpos.xy + (vec2(i, j) - 1.5) * texel, v_lpos.z - u_bias));
  return sum / 16.0;
#endif
  // One bilinear comparison tap: 4 depth tests, weighted. Two taps half a texel apart along the
  // diagonal (8 tests, a little softer) cost 0.4 s more CPU on the 100-box benchmark's 300
  // frames, and looked the same on the pile (bench/README.md).
  return texture(u_shadow_map, vec3(v_lpos.xy, v_lpos.z - u_bias));
#endif
}

void main() {
  vec3 base = v_color;
#if MATERIAL
  base = mix(v_color, v_tint.rgb, v_tint.a) * texture(u_albedo, v_uv).rgb;
#endif
#if GROUND
  vec3 n = vec3(0.0, 0.0, gl_FrontFacing ? 1.0 : -1.0);
#if GROUND_TEXTURE
  base = texture(u_ground_tex, vec2(v_pos.x, -v_pos.y) / u_ground_tex_size).rgb;
#else
  ivec2 c = ivec2(floor(v_pos.xy / u_tile));
  if (((c.x + c.y) & 1) == 1) base = u_color2;
#endif
#else
  vec3 n = normalize(v_nrm);
  if (!gl_FrontFacing) n = -n;
#endif
  float ndl = max(dot(n, u_light_dir), 0.0);
  vec3 v = normalize(u_eye - v_pos);
  vec3 h = normalize(u_light_dir + v);
  // 0.22 (n.h)^48 by squaring: x^48 = (x^16)^3.
  float c1 = max(dot(n, h), 0.0), c2 = c1 * c1, c4 = c2 * c2, c8 = c4 * c4, c16 = c8 * c8;
  float spec = ndl > 0.0 ? 0.22 * (c16 * c16 * c16) : 0.0;
  float sh = lit_fraction();
  vec3 fill = mix(vec3(0.16, 0.15, 0.14), kSky, 0.5 + 0.5 * n.z);
  vec3 lin = base * (fill + 1.15 * ndl * sh * vec3(1.0, 0.97, 0.92)) + spec * sh;
  o_color = vec4(srgb_encode(lin), 1.0);
}
)";

// Shadows on the ground (Blinn 1988, "Me and my (fake) shadow"): the ground is a plane and the key
// light directional, so the shadow a body casts on the ground is exactly its triangles projected
// along the light onto the plane, p - L (p_z - z_g) / L_z. Each body is drawn once more, flattened,
// with a constant shader writing the ground's colour in shadow (ambient only, computed on the CPU:
// u_shade, one per checker colour), never a blend, so overlapping triangles give the same pixel.
// Clip distances keep only what lies above the plane (a part below it casts nothing on the
// ground's top: the plane cuts the triangles exactly, the flattening being affine) and only what
// falls on the ground's square.
const char* kGroundShadowVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 2) in uint a_item;
uniform mat4 u_viewproj;
uniform vec3 u_light_dir;
uniform float u_ground_z, u_half;
uniform samplerBuffer u_items;
out vec2 v_xy;
out float gl_ClipDistance[5];
void main() {
  int b = int(a_item) * 5;
  mat4 model = mat4(texelFetch(u_items, b), texelFetch(u_items, b + 1), texelFetch(u_items, b + 2),
                    texelFetch(u_items, b + 3));
  vec3 w = (model * vec4(a_pos, 1.0)).xyz;
  float h = w.z - u_ground_z;
  vec2 p = w.xy - u_light_dir.xy * (h / u_light_dir.z);
  gl_ClipDistance[0] = h;
  gl_ClipDistance[1] = u_half - p.x;
  gl_ClipDistance[2] = u_half + p.x;
  gl_ClipDistance[3] = u_half - p.y;
  gl_ClipDistance[4] = u_half + p.y;
  v_xy = p;
  gl_Position = u_viewproj * vec4(p, u_ground_z, 1.0);
}
)";
// TEXTURED and srgb_encode() are defined above this text by ground_shadow_fragment_shader(): a
// textured ground's shadow is its texel times the ambient fill (u_fill), as the lit ground's.
const char* kGroundShadowFS = R"(
in vec2 v_xy;
uniform float u_tile;
uniform vec3 u_shade[2];
#if TEXTURED
uniform sampler2D u_ground_tex;
uniform float u_ground_tex_size;
uniform vec3 u_fill;
#endif
out vec4 o_color;
void main() {
#if TEXTURED
  o_color = vec4(srgb_encode(texture(u_ground_tex, vec2(v_xy.x, -v_xy.y) / u_ground_tex_size).rgb * u_fill), 1.0);
#else
  ivec2 c = ivec2(floor(v_xy / u_tile));
  o_color = vec4(u_shade[(c.x + c.y) & 1], 1.0);
#endif
}
)";

// The sky: a full-frame triangle behind everything, coloured by the elevation e of the view ray
// through each pixel: the horizon colour at e = 0, the zenith colour from 30 degrees up, and below
// the horizon (seen where no ground is drawn, or past its edge) a backdrop darkening to 0.7x the
// horizon colour 30 degrees down; in between t (2 - t) of t = 2|sin e| (ease-out: no crease at the
// horizon). The ray's direction is linear in the pixel's position for a perspective camera, so
// it is interpolated from the triangle's corners (u_dirs, made on the CPU) and only normalised per
// pixel.
const char* kSkyVS = R"(#version 330 core
uniform vec3 u_dirs[3];
out vec3 v_dir;
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  v_dir = u_dirs[gl_VertexID];
  gl_Position = vec4(p, 1.0, 1.0);
}
)";
const char* kSkyFS = R"(
in vec3 v_dir;
uniform vec3 u_horizon, u_zenith;
out vec4 o_color;
void main() {
  float e = normalize(v_dir).z, a = min(2.0 * abs(e), 1.0), t = a * (2.0 - a);
  vec3 end = e >= 0.0 ? u_zenith : 0.7 * u_horizon;
  o_color = vec4(srgb_encode(mix(u_horizon, end, t)), 1.0);
}
)";

const char* kDepthVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 2) in uint a_item;
uniform mat4 u_mvp;
uniform int u_batched;
uniform samplerBuffer u_items;
void main() {
  if (u_batched == 1) {
    int b = int(a_item) * 5;
    mat4 model = mat4(texelFetch(u_items, b), texelFetch(u_items, b + 1), texelFetch(u_items, b + 2),
                      texelFetch(u_items, b + 3));
    gl_Position = u_mvp * (model * vec4(a_pos, 1.0));
  } else {
    gl_Position = u_mvp * vec4(a_pos, 1.0);
  }
}
)";
const char* kDepthFS = R"(#version 330 core
void main() {}
)";

// The overlay pass (render/overlay.hpp): unlit, a flat colour with a little headlight shading so
// that a rod reads as round; gamma-encoded like the lit pass. Solids are unit meshes instanced
// with a model matrix, colour and x-ray opacity per instance; ribbons are plain triangles with a
// colour per vertex. u_xray 1 draws only hidden parts (depth test GREATER), faded to the
// item's x-ray opacity, and discards items without one.
const char* kOverlaySolidVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in vec4 i_m0;
layout(location = 3) in vec4 i_m1;
layout(location = 4) in vec4 i_m2;
layout(location = 5) in vec4 i_m3;
layout(location = 6) in vec4 i_color;
uniform mat4 u_viewproj;
out vec3 v_pos;
out vec3 v_nrm;
flat out vec4 v_color;
flat out float v_xray;
void main() {
  // The model matrix is affine: its bottom row (0, 0, 0, 1) need not be sent, and the first
  // column's w carries the x-ray strength instead.
  mat4 model = mat4(vec4(i_m0.xyz, 0.0), i_m1, i_m2, i_m3);
  vec4 w = model * vec4(a_pos, 1.0);
  v_pos = w.xyz;
  // Instances have orthogonal columns (a rotation times a scaling): the inverse transpose is the
  // matrix with each column divided by its squared length (no inverse() per vertex on llvmpipe).
  mat3 m = mat3(model);
  v_nrm = m * (a_nrm / vec3(dot(m[0], m[0]), dot(m[1], m[1]), dot(m[2], m[2])));
  v_color = i_color;
  v_xray = i_m0.w;
  gl_Position = u_viewproj * w;
}
)";
const char* kOverlayRibbonVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec4 a_color;
uniform mat4 u_viewproj;
uniform float u_ribbon_xray;
out vec3 v_pos;
out vec3 v_nrm;
flat out vec4 v_color;
flat out float v_xray;
out vec4 v_rgba;
void main() {
  v_pos = a_pos;
  v_nrm = vec3(0.0);
  v_color = vec4(0.0);
  v_rgba = a_color;
  v_xray = u_ribbon_xray;
  gl_Position = u_viewproj * vec4(a_pos, 1.0);
}
)";
// RIBBON (1 or 0) and srgb_encode() are defined above this text by overlay_fragment_shader().
const char* kOverlayFS = R"(
in vec3 v_pos;
in vec3 v_nrm;
flat in vec4 v_color;
flat in float v_xray;
#if RIBBON
in vec4 v_rgba;
#endif
uniform vec3 u_eye;
uniform int u_xray;
out vec4 o_color;

void main() {
  float alpha = 1.0;
  if (u_xray == 1) {
    if (v_xray <= 0.0) discard;
    alpha = v_xray;
  }
#if RIBBON
  vec4 c = v_rgba;
#else
  vec3 n = normalize(v_nrm);
  float facing = abs(dot(n, normalize(u_eye - v_pos)));
  vec4 c = vec4(v_color.rgb * (0.62 + 0.38 * facing), v_color.a);
#endif
  o_color = vec4(srgb_encode(c.rgb), c.a * alpha);
}
)";

GLuint compile(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("shader compilation failed: ") + log);
  }
  return s;
}

}  // namespace

bool lit_material(LitKind kind) {
  return kind == LitKind::body_material || kind == LitKind::body_material_unshadowed;
}

std::string lit_vertex_shader(LitKind kind) {
  return std::string("#version 330 core\n#define MATERIAL ") + (lit_material(kind) ? "1" : "0") + kLitVS;
}
const char* depth_vertex_shader() {
  return kDepthVS;
}
const char* depth_fragment_shader() {
  return kDepthFS;
}
const char* ground_shadow_vertex_shader() {
  return kGroundShadowVS;
}
const char* sky_vertex_shader() {
  return kSkyVS;
}

const char* overlay_vertex_shader(bool ribbon) {
  return ribbon ? kOverlayRibbonVS : kOverlaySolidVS;
}

// The GLSL of srgb_encode (render/shaders.hpp), its coefficients printed with %.9g so that each
// reads back as the same float.
std::string srgb_glsl() {
  char b[600];
  std::snprintf(b, sizeof b,
                "vec3 srgb_encode(vec3 x) {\n"
                "  vec3 c = clamp(x, 0.0, 1.0), s = sqrt(c), q = sqrt(s), e = sqrt(q);\n"
                "  vec3 f = %.9g * s + %.9g * q + %.9g * e + c * (%.9g + %.9g * q);\n"
                "  return mix(f, 12.92 * c, lessThanEqual(c, vec3(0.0031308)));\n"
                "}\n",
                (double)kSrgbFit[0], (double)kSrgbFit[1], (double)kSrgbFit[4], (double)kSrgbFit[2],
                (double)kSrgbFit[3]);
  return b;
}

std::string ground_shadow_fragment_shader(bool textured) {
  return std::string("#version 330 core\n#define TEXTURED ") + (textured ? "1" : "0") + "\n" + srgb_glsl() +
         kGroundShadowFS;
}

// Ambient occlusion from the depth buffer alone (after Bavoil and Sainz's screen-space AO and
// McGuire's Alchemy AO): each pixel's view-space position P from its depth, its normal N from the
// position's screen derivatives, and 12 samples on a golden-angle spiral within 0.35 m of it; a
// sample at S occludes by max(0, N . (S - P) / |S - P| - 0.1), fading beyond 0.35 m, so a flat
// ground occludes nothing. The spiral turns by a 4 x 4 pattern of pixel positions (deterministic;
// FXAA and the 2x2 chroma of video smooth the pattern). Written as an occlusion factor that
// blending multiplies into the frame: 1 for sky, at most 45% darker in a tight corner.
const char* kAoFS = R"(#version 330 core
uniform sampler2D u_depth;
uniform mat4 u_inv_proj;
uniform vec2 u_texel;
uniform float u_px_per_m;
out vec4 o_color;
vec3 view_pos(vec2 uv) {
  vec4 p = u_inv_proj * vec4(uv * 2.0 - 1.0, texture(u_depth, uv).r * 2.0 - 1.0, 1.0);
  return p.xyz / p.w;
}
void main() {
  vec2 uv = gl_FragCoord.xy * u_texel;
  float d = texture(u_depth, uv).r;
  if (d >= 1.0) {
    o_color = vec4(1.0);
    return;
  }
  vec3 p = view_pos(uv);
  vec3 n = normalize(cross(dFdx(p), dFdy(p)));
  if (dot(n, p) > 0.0) n = -n;  // towards the camera
  const float R = 0.35;
  float r_px = min(R * u_px_per_m / max(-p.z, 1e-3), 80.0);
  ivec2 q = ivec2(gl_FragCoord.xy) & 3;
  float a0 = float(q.x + 4 * q.y) * (6.2831853 / 16.0);
  float occ = 0.0;
  for (int i = 0; i < 12; ++i) {
    float t = (float(i) + 0.5) / 12.0, a = a0 + float(i) * 2.3999632;
    vec2 off = vec2(cos(a), sin(a)) * (r_px * sqrt(t));
    vec3 v = view_pos(uv + off * u_texel) - p;
    float len = length(v);
    occ += max(0.0, dot(n, v) / max(len, 1e-4) - 0.1) * (1.0 - smoothstep(0.5 * R, R, len));
  }
  o_color = vec4(vec3(1.0 - 0.45 * min(1.0, occ / 12.0 * 1.6)), 1.0);
}
)";

std::string ao_fragment_shader() {
  return kAoFS;
}

std::string sky_fragment_shader() {
  return "#version 330 core\n" + srgb_glsl() + kSkyFS;
}

std::string overlay_fragment_shader(bool ribbon) {
  return std::string("#version 330 core\n#define RIBBON ") + (ribbon ? "1" : "0") + "\n" + srgb_glsl() +
         kOverlayFS;
}

std::string lit_fragment_shader(LitKind kind, bool soft) {
  char head[512];
  const bool ground = kind == LitKind::ground || kind == LitKind::ground_textured;
  // %.9g prints each float so that it reads back as the same float.
  std::snprintf(head, sizeof head,
                "#version 330 core\n#define GROUND %d\n#define GROUND_TEXTURE %d\n#define SHADOWED %d\n"
                "#define SOFT %d\n#define MATERIAL %d\n"
                "const vec3 kSky = vec3(%.9g, %.9g, %.9g);\n",
                ground ? 1 : 0, kind == LitKind::ground_textured ? 1 : 0,
                kind == LitKind::body || kind == LitKind::body_material || (ground && soft) ? 1 : 0,
                soft ? 1 : 0, lit_material(kind) ? 1 : 0, (double)kFillSky[0], (double)kFillSky[1],
                (double)kFillSky[2]);
  return head + srgb_glsl() + kLitFS;
}

std::array<float, 3> ground_shadow_color(const std::array<float, 3>& ground) {
  std::array<float, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = srgb_encode(ground[k] * kFillSky[k]);
  return c;
}

unsigned link_program(const char* vs, const char* fs) {
  const GLuint v = compile(GL_VERTEX_SHADER, vs);
  GLuint f = 0;
  try {
    f = compile(GL_FRAGMENT_SHADER, fs);
  } catch (...) {
    glDeleteShader(v);
    throw;
  }
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw std::runtime_error(std::string("shader link failed: ") + log);
  }
  return p;
}

}  // namespace simreel
