#define GL_GLEXT_PROTOTYPES 1
#include "render/renderer.hpp"

#include <GL/gl.h>
#include <GL/glext.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/camera.hpp"
#include "render/fxaa.hpp"
#include "render/gl_context.hpp"
#include "render/screen.hpp"
#include "render/shaders.hpp"

namespace simreel {
namespace {

using M4 = Eigen::Matrix4f;
using V3f = Eigen::Vector3f;

struct GpuMesh {
  GLuint vao = 0, vbo = 0, ebo = 0;
  GLsizei count = 0;
  bool two_sided = false;
  bool convex = false;                     ///< RenderMesh::convex
  V3f lo = V3f::Zero(), hi = V3f::Zero();  ///< m, bounding box in the mesh frame
  float reach = 0;                         ///< m, farthest vertex from the mesh origin
  GLuint xbo = 0;                          ///< RenderMesh::extras, if it has a file's look
  std::vector<RenderMesh::Part> parts;     ///< its index ranges by texture
  bool material() const { return xbo != 0; }
};

GpuMesh upload(const RenderMesh& m) {
  GpuMesh g;
  glGenVertexArrays(1, &g.vao);
  glBindVertexArray(g.vao);
  glGenBuffers(1, &g.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(m.vertices.size() * sizeof(float)), m.vertices.data(),
               GL_STATIC_DRAW);
  glGenBuffers(1, &g.ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(m.indices.size() * sizeof(uint32_t)), m.indices.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void*)0);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void*)(3 * sizeof(float)));
  if (!m.extras.empty()) {  // r g b a u v per vertex (render/tessellate.hpp)
    glGenBuffers(1, &g.xbo);
    glBindBuffer(GL_ARRAY_BUFFER, g.xbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(m.extras.size() * sizeof(float)), m.extras.data(),
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(3);
    glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void*)0);
    glEnableVertexAttribArray(4);
    glVertexAttribPointer(4, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void*)(4 * sizeof(float)));
    g.parts = m.parts;
  }
  g.count = (GLsizei)m.indices.size();
  g.two_sided = m.two_sided;
  g.convex = m.convex;
  if (!m.vertices.empty()) {
    g.lo = g.hi = V3f(m.vertices[0], m.vertices[1], m.vertices[2]);
    for (size_t i = 0; i + 5 < m.vertices.size(); i += 6) {
      const V3f p(m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]);
      g.lo = g.lo.cwiseMin(p);
      g.hi = g.hi.cwiseMax(p);
      g.reach = std::max(g.reach, p.norm());
    }
  }
  glBindVertexArray(0);
  return g;
}

// An image as an sRGB texture (sampled in linear light), mipmapped and repeating.
GLuint upload_texture(const TextureImage& im) {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, im.width, im.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               im.rgba.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  glBindTexture(GL_TEXTURE_2D, 0);
  return t;
}

// One specialisation of the lit program (render/shaders.hpp) and its uniform locations.
struct LitProgram {
  GLuint id = 0;
  GLint model = -1, viewproj = -1, lightvp = -1, color = -1, light_dir = -1, eye = -1, shadows = -1,
        tile = -1, bias = -1, map = -1, batched = -1, items = -1, albedo = -1, color2 = -1, ground_tex = -1,
        ground_tex_size = -1;

  void create(LitKind kind, bool soft = false) {
    id = link_program(lit_vertex_shader(kind).c_str(), lit_fragment_shader(kind, soft).c_str());
    model = glGetUniformLocation(id, "u_model");
    viewproj = glGetUniformLocation(id, "u_viewproj");
    lightvp = glGetUniformLocation(id, "u_lightvp");
    color = glGetUniformLocation(id, "u_color");
    light_dir = glGetUniformLocation(id, "u_light_dir");
    eye = glGetUniformLocation(id, "u_eye");
    shadows = glGetUniformLocation(id, "u_shadows");
    tile = glGetUniformLocation(id, "u_tile");
    bias = glGetUniformLocation(id, "u_bias");
    map = glGetUniformLocation(id, "u_shadow_map");
    batched = glGetUniformLocation(id, "u_batched");
    items = glGetUniformLocation(id, "u_items");
    albedo = glGetUniformLocation(id, "u_albedo");
    color2 = glGetUniformLocation(id, "u_color2");
    ground_tex = glGetUniformLocation(id, "u_ground_tex");
    ground_tex_size = glGetUniformLocation(id, "u_ground_tex_size");
    glUseProgram(id);
    glUniform1i(albedo, 2);      // texture unit 2
    glUniform1i(ground_tex, 3);  // texture unit 3
    glUniform1i(items, 1);       // texture unit 1
    glUniform1i(batched, 0);
    glUniform1i(map, 0);  // texture unit 0
  }
};

}  // namespace

struct Renderer::Impl {
  RenderSettings s;
  int msaa = 1;  // samples per pixel, as far as the GL allows
  std::unique_ptr<GlContext> ctx;
  LitProgram body_prog, body_flat_prog, ground_prog;  // the lit shader: bodies shadowed or not, ground
  // The same for meshes drawn with their file's look, made only when a scene has one; their
  // base-colour images (SceneMeshes::textures) and a white texel for parts without one.
  LitProgram mat_prog, mat_flat_prog;
  bool any_material = false;
  bool soft = false;  // render.quality: high with shadows: soft shadows from the map everywhere
  GLuint sky_prog = 0, sky_vao = 0, ground_tex = 0;
  GLint sky_dirs = -1, sky_horizon = -1, sky_zenith = -1;
  std::vector<GLuint> textures;
  GLuint white_tex = 0;
  GLuint depth = 0;
  GLint u_mvp = -1;
  // One GPU mesh per distinct scene mesh, however many items draw it: each frame the items are
  // grouped by mesh and each group is one instanced draw (see group_items). An item's model
  // matrix and colour sit in a buffer texture (5 RGBA32F texels per item, read by the lit and
  // depth vertex shaders, render/shaders.cpp, as "batched"); its slot there comes in as the
  // per-instance attribute a_item, from `slots_vbo` (0, 1, 2, ...) at the group's first slot.
  std::vector<GpuMesh> meshes;
  GpuMesh ground;
  GLuint items_tbo = 0, items_tex = 0, slots_vbo = 0;
  size_t items_capacity = 0, slots_capacity = 0;  // items the buffers hold
  std::vector<float> item_data;                   // 20 floats per item: model (column-major), colour, 0
  std::vector<int> group_size, group_base;        // per mesh: this frame's items, first slot
  // Per mesh and shadow role (classify_shadows), in slot order within the mesh's group: receivers
  // only, receivers and occluders, occluders only, neither: counts, and the next slot to fill.
  std::vector<std::array<int, 4>> group_role, group_next;
  // Per item this frame: kOccluder | kReceiver; light-space boxes and a sweep order (reused).
  static constexpr uint8_t kOccluder = 1, kReceiver = 2;
  std::vector<uint8_t> role;
  std::vector<V3f> box_lo, box_hi;
  std::vector<int> sweep;
  std::vector<int> groups, seen;  // meshes drawn this frame, in draw order
  GLint d_batched = -1, d_items = -1;
  // Shadows on the ground: the bodies flattened onto it along the light (ground_shadows).
  struct GroundShadowProgram {
    GLuint id = 0;
    GLint viewproj = -1, light_dir = -1, ground_z = -1, half = -1, tile = -1, shade = -1, items = -1,
          tex = -1, tex_size = -1, fill = -1;
  } gs;
  GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0;
  GLuint frame_fbo = 0, frame_color = 0, frame_depth = 0;  // single-sample, read back
  // The ground and sky without shadows, drawn once per camera and ground placement, copied into
  // each frame (see render()).
  GLuint cache_fbo = 0, cache_color = 0, cache_depth = 0;
  bool cache_valid = false;
  M4 cache_vp = M4::Zero(), cache_ground = M4::Zero();
  std::vector<uint8_t> frame;  // RGBA8, top row first
  FxaaBuffers fxaa_buffers;
  GLuint shadow_fbo = 0, shadow_tex = 0;
  std::vector<M4> last_models;  // poses the shadow map was drawn for
  M4 last_lightvp = M4::Zero();
  V3f light_dir = V3f(-0.45f, -0.30f, 0.84f).normalized();  // towards the key light
  RenderStats stats;

  // Colour and depth renderbuffers with `samples` samples (depth only if `with_depth`).
  void make_target(GLuint& fbo, GLuint& color, GLuint& depth_rb, int samples, bool with_depth) {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, s.width, s.height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (with_depth) {
      glGenRenderbuffers(1, &depth_rb);
      glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, s.width, s.height);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    }
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("framebuffer incomplete (" + std::to_string(s.width) + "x" +
                               std::to_string(s.height) + ", " + std::to_string(samples) + " samples)");
  }

  // Frames are drawn into our own framebuffers, never the context's default one: with MSAA into a
  // multisampled one resolved into `frame_fbo`, else into `frame_fbo` directly; then read back.
  // Reading back from our own single-sample framebuffer costs 0.2 ms at 720p on llvmpipe; a
  // copy into OSMesa's default framebuffer (y-flipped) took 5.5 ms as a shader blit. The 4x MSAA
  // resolve costs ~6.5 ms either way.
  void setup_targets() {
    make_target(frame_fbo, frame_color, frame_depth, 0, msaa <= 1);
    if (msaa > 1) make_target(msaa_fbo, msaa_color, msaa_depth, msaa, true);
    if (s.cache_ground) make_target(cache_fbo, cache_color, cache_depth, msaa > 1 ? msaa : 0, true);
    frame.resize((size_t)s.width * s.height * 4);
    if (s.shadows) {
      glGenTextures(1, &shadow_tex);
      glBindTexture(GL_TEXTURE_2D, shadow_tex);
      // 16-bit depth: half the memory of 24-bit (stored in 32), 0.5-0.8 ms less llvmpipe work a
      // 720p frame at 1024^2 (clear, depth writes, compare fetches). Its step, 1/65536 of the
      // frustum's depth (~0.5 mm over 30 m), is far below the compare bias (u_bias, 0.0015).
      glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT16, s.shadow_size, s.shadow_size, 0,
                   GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
      const float border[4] = {1, 1, 1, 1};
      glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
      glGenFramebuffers(1, &shadow_fbo);
      glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_tex, 0);
      glDrawBuffer(GL_NONE);
      glReadBuffer(GL_NONE);
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("shadow framebuffer incomplete");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  // Orthographic light frustum around the bodies' bounding sphere: only bodies receive shadows
  // from the map (the ground's are the bodies projected onto it, ground_shadows).
  static float light_radius(const DrawList& dl) { return (float)dl.bounds_radius * 1.02f; }  ///< m
  M4 light_view(const DrawList& dl) const {
    const V3f c = dl.bounds_center.cast<float>();
    const V3f eye = c + light_dir * (light_radius(dl) + 1.0f);
    const V3f up = std::fabs(light_dir.z()) > 0.99f ? V3f::UnitY() : V3f::UnitZ();
    return look_at(eye, c, up);
  }
  M4 light_viewproj(const DrawList& dl) const {
    const float r = light_radius(dl);
    float far = 2 * r + 1.0f;
    if (soft && s.ground) {  // deep enough to reach the ground under the bodies' cylinder of light
      const float eye_z = (float)dl.bounds_center.z() + light_dir.z() * (r + 1.0f);
      far = std::max(far, (eye_z - (float)s.ground_height) / light_dir.z() + 2 * r);
    }
    return ortho(r, 0.0f, far) * light_view(dl);
  }
  float ground_texture_size() const {
    return (float)(s.ground_texture_size > 0 ? s.ground_texture_size : 2 * s.ground_tile);
  }

  // The sky behind everything: a triangle covering the frame, its corners' view rays (linear in
  // the pixel position) from the inverse projection; no depth.
  void sky_pass(const M4& vp, const V3f& eye) {
    if (!s.sky_gradient) return;  // the clear colour is the sky
    const M4 inv = vp.inverse();
    float dirs[9];
    const float corners[3][2] = {{-1, -1}, {3, -1}, {-1, 3}};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector4f p = inv * Eigen::Vector4f(corners[k][0], corners[k][1], 1, 1);
      const V3f d = p.head<3>() / p.w() - eye;
      dirs[3 * k] = d.x(), dirs[3 * k + 1] = d.y(), dirs[3 * k + 2] = d.z();
    }
    glUseProgram(sky_prog);
    glUniform3fv(sky_dirs, 3, dirs);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);  // its winding is counter-clockwise; the bodies' front faces are clockwise
    glDepthMask(GL_FALSE);
    glBindVertexArray(sky_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDepthMask(GL_TRUE);
    glEnable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
  }
  void setup_sky() {
    sky_prog = link_program(sky_vertex_shader(), sky_fragment_shader().c_str());
    sky_dirs = glGetUniformLocation(sky_prog, "u_dirs");
    glUseProgram(sky_prog);
    glUniform3f(glGetUniformLocation(sky_prog, "u_horizon"), s.horizon[0], s.horizon[1], s.horizon[2]);
    glUniform3f(glGetUniformLocation(sky_prog, "u_zenith"), s.background[0], s.background[1],
                s.background[2]);
    glGenVertexArrays(1, &sky_vao);
    glUseProgram(0);
  }

  bool poses_unchanged(const DrawList& dl, const M4& lvp) const {
    if (last_models.size() != dl.items.size() || lvp != last_lightvp) return false;
    for (size_t i = 0; i < dl.items.size(); ++i)
      if (dl.items[i].model != last_models[i]) return false;
    return true;
  }

  void shadow_pass(const DrawList& dl, const M4& lvp) {
    if (poses_unchanged(dl, lvp)) {
      ++stats.shadow_reused;
      return;
    }
    ++stats.shadow_passes;
    last_models.resize(dl.items.size());
    for (size_t i = 0; i < dl.items.size(); ++i) last_models[i] = dl.items[i].model;
    last_lightvp = lvp;
    // No occluder, no receiver: nothing reads the map for these poses.
    if (std::none_of(role.begin(), role.end(), [](uint8_t r) { return r & kOccluder; })) return;
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    glViewport(0, 0, s.shadow_size, s.shadow_size);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth);
    glFrontFace(GL_CCW);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.0f);
    glUniformMatrix4fv(u_mvp, 1, GL_FALSE, lvp.data());
    draw_bodies(d_batched, Subset::occluders);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }

  // The per-instance slot attribute (location 2) of each body mesh, read from slots_vbo.
  void attach_slots(GpuMesh& g) {
    glBindVertexArray(g.vao);
    glBindBuffer(GL_ARRAY_BUFFER, slots_vbo);
    glEnableVertexAttribArray(2);
    glVertexAttribIPointer(2, 1, GL_UNSIGNED_INT, 0, (void*)0);
    glVertexAttribDivisor(2, 1);
    glBindVertexArray(0);
  }

  void setup_items(size_t mesh_count) {
    glGenBuffers(1, &slots_vbo);
    glGenBuffers(1, &items_tbo);
    glGenTextures(1, &items_tex);
    group_size.assign(mesh_count, 0);
    group_base.assign(mesh_count, 0);
    group_role.assign(mesh_count, {});
    group_next.assign(mesh_count, {});
    groups.reserve(mesh_count);
    seen.reserve(mesh_count);
    reserve_items(std::max<size_t>(1, mesh_count));
  }

  // Room for n items in the buffer texture and the slot buffer; grows (to twice the need) only
  // when too small, so a steady draw list allocates nothing per frame.
  void reserve_items(size_t n) {
    if (n <= items_capacity) return;
    const size_t cap = std::max<size_t>(2 * n, 64);
    std::vector<uint32_t> slots(cap);
    for (size_t i = 0; i < cap; ++i) slots[i] = (uint32_t)i;
    glBindBuffer(GL_ARRAY_BUFFER, slots_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(cap * sizeof(uint32_t)), slots.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_TEXTURE_BUFFER, items_tbo);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(cap * 20 * sizeof(float)), nullptr, GL_STREAM_DRAW);
    glBindTexture(GL_TEXTURE_BUFFER, items_tex);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, items_tbo);
    item_data.resize(cap * 20);
    items_capacity = slots_capacity = cap;
  }

  // Which bodies can shadow another (occluders: drawn into the shadow map) and which another can
  // shadow (receivers: drawn with the shadow lookup). On llvmpipe the map and the lookups cost as
  // much as 0.8 s of CPU in the 100-box benchmark's 300 frames, while its boxes, spinning in a
  // layer, rarely shadow each other. A convex solid facing the light is never in its own shadow;
  // anything else (mesh files, planes) is both. Body A can shadow body B only if their boxes
  // (each item's mesh bounding box, posed) overlap across the light, widened by two texels for the
  // bilinear tap, and part of A lies nearer the light than part of B: a sweep over light-space x.
  // With more than 2048 items, or pairs past 64 a item, every item is both (as with no sorting).
  void classify_shadows(const DrawList& dl) {
    const size_t n = dl.items.size();
    role.assign(n, 0);
    if (!s.shadows) return;
    auto all_both = [&] { std::fill(role.begin(), role.end(), kOccluder | kReceiver); };
    if (n > 2048 || soft) return all_both();  // soft: every body shadows the ground through the map
    const M4 view = light_view(dl);
    const float margin = 2 * 2 * light_radius(dl) / (float)s.shadow_size;  // m: two texels
    box_lo.resize(n);
    box_hi.resize(n);
    sweep.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const DrawItem& it = dl.items[i];
      const GpuMesh& g = meshes[it.mesh];
      if (!g.convex) role[i] = kOccluder | kReceiver;
      const M4 m = view * it.model;
      V3f lo = V3f::Constant(INFINITY), hi = V3f::Constant(-INFINITY);
      for (int k = 0; k < 8; ++k) {
        const V3f corner((k & 1) ? g.hi.x() : g.lo.x(), (k & 2) ? g.hi.y() : g.lo.y(),
                         (k & 4) ? g.hi.z() : g.lo.z());
        const V3f p = m.block<3, 3>(0, 0) * corner + m.block<3, 1>(0, 3);
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      }
      box_lo[i] = lo, box_hi[i] = hi;
      sweep[i] = (int)i;
    }
    std::sort(sweep.begin(), sweep.end(), [&](int a, int b) {
      return box_lo[a].x() < box_lo[b].x() || (box_lo[a].x() == box_lo[b].x() && a < b);
    });
    size_t pairs = 0;
    for (size_t i = 0; i < n; ++i) {
      const int a = sweep[i];
      for (size_t j = i + 1; j < n && box_lo[sweep[j]].x() <= box_hi[a].x() + margin; ++j) {
        if (++pairs > 64 * n) return all_both();
        const int b = sweep[j];
        if (box_lo[a].y() > box_hi[b].y() + margin || box_lo[b].y() > box_hi[a].y() + margin) continue;
        // The light looks along -z: nearer the light is larger z.
        if (box_hi[a].z() > box_lo[b].z()) role[a] |= kOccluder, role[b] |= kReceiver;
        if (box_hi[b].z() > box_lo[a].z()) role[b] |= kOccluder, role[a] |= kReceiver;
      }
    }
  }
  // The order of the roles within a mesh's group: receivers (shadowed) first, occluders (in the
  // map) in the middle, so each is one run of slots.
  static int role_rank(uint8_t r) {
    return r == kReceiver ? 0 : r == (kOccluder | kReceiver) ? 1 : r == kOccluder ? 2 : 3;
  }

  // This frame's items grouped by mesh, into the buffer texture: the meshes in the order of their
  // first item, one-sided ones first, then the two-sided (drawn without culling), as the single
  // batched draw of all bodies did before meshes were shared (the same triangles in the same order
  // when no two items share a mesh); within a group, items by shadow role (role_rank), then in
  // draw list order.
  void group_items(const DrawList& dl) {
    const size_t n = dl.items.size();
    for (const DrawItem& it : dl.items)
      if (it.mesh < 0 || it.mesh >= (int)meshes.size())
        throw std::invalid_argument("draw item's mesh " + std::to_string(it.mesh) + " is not one of the " +
                                    std::to_string(meshes.size()) + " meshes uploaded");
    for (int m : groups) group_size[m] = 0, group_role[m] = {};  // the last frame's
    seen.clear();
    classify_shadows(dl);
    for (size_t i = 0; i < n; ++i) {
      const int m = dl.items[i].mesh;
      if (group_size[m]++ == 0) seen.push_back(m);
      ++group_role[m][role_rank(role[i])];
    }
    groups.clear();
    for (bool two : {false, true})
      for (int m : seen)
        if (meshes[m].two_sided == two) groups.push_back(m);
    int next = 0;
    for (int m : groups) {
      group_base[m] = next;
      for (int r = 0; r < 4; ++r) group_next[m][r] = next, next += group_role[m][r];
    }
    reserve_items(n);
    for (size_t i = 0; i < n; ++i) {
      const DrawItem& it = dl.items[i];
      float* d = &item_data[20 * (size_t)group_next[it.mesh][role_rank(role[i])]++];
      std::copy(it.model.data(), it.model.data() + 16, d);
      d[16] = it.color[0], d[17] = it.color[1], d[18] = it.color[2], d[19] = 0;
    }
    if (n) {
      glBindBuffer(GL_TEXTURE_BUFFER, items_tbo);
      glBufferSubData(GL_TEXTURE_BUFFER, 0, (GLsizeiptr)(n * 20 * sizeof(float)), item_data.data());
    }
  }

  // Which of this frame's items a draw takes (classify_shadows).
  enum class Subset { all, receivers, others, occluders };

  // The bodies of `which`, with the program in use (lit, depth or ground shadow): one instanced
  // draw per mesh drawn this frame (group_items).
  // kind: which meshes (Meshes::plain, ::material, ::any); with `textured` each of a material
  // mesh's parts is drawn with its image bound to unit 2.
  enum class Meshes { any, plain, material };
  void draw_bodies(GLint batched_loc, Subset which = Subset::all, Meshes kind = Meshes::any,
                   bool textured = false) {
    glUniform1i(batched_loc, 1);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, items_tex);
    glActiveTexture(GL_TEXTURE0);
    glBindBuffer(GL_ARRAY_BUFFER, slots_vbo);
    for (int m : groups) {
      const GpuMesh& g = meshes[m];
      if ((kind == Meshes::plain && g.material()) || (kind == Meshes::material && !g.material())) continue;
      glBindVertexArray(g.vao);
      const std::array<int, 4>& c = group_role[m];
      const int first = which == Subset::others ? c[0] + c[1] : which == Subset::occluders ? c[0] : 0;
      const int count = which == Subset::all         ? group_size[m]
                        : which == Subset::receivers ? c[0] + c[1]
                        : which == Subset::others    ? c[2] + c[3]
                                                     : c[1] + c[2];
      if (count == 0) continue;
      glVertexAttribIPointer(2, 1, GL_UNSIGNED_INT, 0,
                             (void*)((size_t)(group_base[m] + first) * sizeof(uint32_t)));
      if (g.two_sided) glDisable(GL_CULL_FACE);
      if (textured && g.material()) {
        for (const RenderMesh::Part& part : g.parts) {
          glActiveTexture(GL_TEXTURE2);
          glBindTexture(GL_TEXTURE_2D, part.texture >= 0 ? textures[part.texture] : white_tex);
          glDrawElementsInstanced(GL_TRIANGLES, (GLsizei)part.count, GL_UNSIGNED_INT,
                                  (void*)((size_t)part.first * sizeof(uint32_t)), count);
        }
        glActiveTexture(GL_TEXTURE0);
      } else {
        glDrawElementsInstanced(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr, count);
      }
      if (g.two_sided) glEnable(GL_CULL_FACE);
    }
    glBindVertexArray(0);
    glUniform1i(batched_loc, 0);
  }

  void setup_ground_shadows() {
    gs.id =
        link_program(ground_shadow_vertex_shader(), ground_shadow_fragment_shader(ground_tex != 0).c_str());
    for (auto [loc, name] : {std::pair{&gs.viewproj, "u_viewproj"},
                             {&gs.light_dir, "u_light_dir"},
                             {&gs.ground_z, "u_ground_z"},
                             {&gs.half, "u_half"},
                             {&gs.tile, "u_tile"},
                             {&gs.shade, "u_shade"},
                             {&gs.items, "u_items"},
                             {&gs.tex, "u_ground_tex"},
                             {&gs.tex_size, "u_ground_tex_size"},
                             {&gs.fill, "u_fill"}})
      *loc = glGetUniformLocation(gs.id, name);
    glUseProgram(gs.id);
    glUniform1i(gs.items, 1);  // texture unit 1
    glUniform3f(gs.light_dir, light_dir.x(), light_dir.y(), light_dir.z());
    glUniform1f(gs.ground_z, (float)s.ground_height);
    glUniform1f(gs.half, (float)(s.ground_size / 2));
    glUniform1f(gs.tile, (float)s.ground_tile);
    glUniform1i(gs.tex, 3);  // texture unit 3
    glUniform1f(gs.tex_size, ground_texture_size());
    glUniform3f(gs.fill, kFillSky[0], kFillSky[1], kFillSky[2]);
    const std::array<float, 3> even = ground_shadow_color(s.ground_color),
                               odd = ground_shadow_color(s.ground_color2);
    const float shade[6] = {even[0], even[1], even[2], odd[0], odd[1], odd[2]};
    glUniform3fv(gs.shade, 2, shade);
    glUseProgram(0);
  }

  // Shadows on the ground: every body drawn once more, flattened onto the ground plane along the
  // light, in the ground's shadowed colour (render/shaders.cpp, kGroundShadowVS: exact for any
  // mesh, hard-edged; FXAA or MSAA smooth the edges like any other). Closed meshes (the one-sided
  // primitives) only need their triangles facing the light: a ray from a ground point towards the
  // light that meets the body enters it through one, unless it starts inside the body, where the
  // body itself hides that point from a camera above the ground. Those triangles land on the plane
  // facing up, i.e. front-facing from above, and back-face culling keeps them. Two-sided meshes
  // (mesh files, planes) draw every triangle. Overlaps write the same colour again: no stencil.
  // Over the ground's depth: in front of it by a hair; no depth is written either way. Measured on
  // the 100-box benchmark (llvmpipe CPU for 300 frames at 720p): 1.16 s for the footprints this
  // replaced (the least-area rectangle around each body's projected bounding box, shaded with two
  // shadow-map taps a pixel), see bench/README.md.
  void ground_shadows(const M4& vp, bool over_ground_depth) {
    glUseProgram(gs.id);
    glUniformMatrix4fv(gs.viewproj, 1, GL_FALSE, vp.data());
    for (int k = 0; k < 5; ++k) glEnable(GL_CLIP_DISTANCE0 + k);
    if (over_ground_depth) {
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(-1.0f, -4.0f);
    }
    glDepthMask(GL_FALSE);
    draw_bodies(-1);
    glDepthMask(GL_TRUE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    for (int k = 0; k < 5; ++k) glDisable(GL_CLIP_DISTANCE0 + k);
  }

  // One mesh with whatever program and uniforms are set; two-sided meshes without culling.
  static void draw_mesh(const GpuMesh& g) {
    glBindVertexArray(g.vao);
    if (g.two_sided) glDisable(GL_CULL_FACE);
    glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
    if (g.two_sided) glEnable(GL_CULL_FACE);
  }

  // The camera of a frame: projection and eye, and the ground's placement.
  struct View {
    M4 proj;    // view to clip, y flipped (for the ambient occlusion's view-space positions)
    M4 vp;      // world to clip, y flipped (see view())
    V3f eye;    // m
    M4 ground;  // the ground plane's model matrix
  };
  View view(const DrawList& dl) const {
    const CameraView& cam = dl.camera;
    View v;
    v.eye = cam.eye.cast<float>();
    const float dist = (cam.eye - dl.bounds_center).norm();
    const float reach = dist + (float)dl.bounds_radius + (s.ground ? (float)s.ground_size : 0.0f);
    // Depth range: a function of this frame alone (a frame must not depend on the frames drawn
    // before it), rounded to powers of two so the projection, and with it the cached ground,
    // changes only when the bodies' distance changes by a factor of two. Near: half the distance
    // to the bodies' bounding sphere (at most a tenth of the camera's distance), rounded down; far:
    // 1.5x the farthest reach, rounded up. 24-bit depth keeps ~1e-4 relative resolution over that.
    // Overlay geometry reaching nearer than the bodies pulls the near plane in to half its distance.
    float need_near = std::max(0.01f, std::min(0.1f * dist, dist - (float)dl.bounds_radius) * 0.5f);
    if (!dl.overlay.empty())
      need_near = std::max(0.01f, std::min(need_near, 0.5f * overlay_nearest(dl.overlay, v.eye)));
    const float need_far = reach * 1.5f;
    const float near = std::max(0.01f, std::exp2(std::floor(std::log2(need_near))));
    const float far = std::exp2(std::ceil(std::log2(std::max(need_far, 2 * near))));
    // Drawn upside down (y negated in clip space, so the winding that faces the camera turns
    // clockwise): glReadPixels returns the bottom row first, which is then the top of the image.
    const M4 flip_y = Eigen::Vector4f(1, -1, 1, 1).asDiagonal();
    v.proj = flip_y * perspective((float)(cam.fov_deg * M_PI / 180.0), (float)s.width / s.height, near, far);
    v.vp = v.proj * look_at(v.eye, cam.target.cast<float>(), cam.up.cast<float>());
    // Fixed in the world, centred on the origin: it must not move under the bodies between frames
    // (it used to re-centre on them in whole checker periods, a visible jump of two tiles).
    v.ground = M4::Identity();
    v.ground(2, 3) = (float)s.ground_height;
    return v;
  }

  // Pass 2: sky, ground and bodies, lit and shadowed, into the frame's target (left bound).
  void bodies_pass(const DrawList& dl, const View& v, const M4& lvp) {
    const GLuint target = msaa > 1 ? msaa_fbo : frame_fbo;
    glViewport(0, 0, s.width, s.height);
    const std::array<float, 3>& clear = s.sky_gradient ? s.horizon : s.background;
    glClearColor(srgb_encode(clear[0]), srgb_encode(clear[1]), srgb_encode(clear[2]), 1.0f);
    const M4& vp = v.vp;
    const V3f& eye = v.eye;
    const M4& ground = v.ground;

    glFrontFace(GL_CW);
    for (const LitProgram* lp : {&body_prog, &body_flat_prog, &ground_prog, &mat_prog, &mat_flat_prog}) {
      if (lp->id == 0) continue;
      glUseProgram(lp->id);
      glUniformMatrix4fv(lp->viewproj, 1, GL_FALSE, vp.data());
      glUniformMatrix4fv(lp->lightvp, 1, GL_FALSE, lvp.data());
      glUniform3f(lp->light_dir, light_dir.x(), light_dir.y(), light_dir.z());
      glUniform3f(lp->eye, eye.x(), eye.y(), eye.z());
      glUniform1f(lp->tile, (float)s.ground_tile);
      // Depth bias: about two shadow-map texels of depth, relative to the frustum depth.
      glUniform1f(lp->bias, 0.0015f);
      glUniform1i(lp->shadows, s.shadows ? 1 : 0);
    }
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, ground_tex);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, shadow_tex);

    // The ground covers most of the frame, and on llvmpipe every covered pixel runs the lit shader
    // on the CPU (7.4 ms a 720p frame for the ground alone, before the shader was trimmed; with a
    // constant-colour shader the whole frame's llvmpipe work fell from 12 to 4.3 ms). Unshadowed, it
    // depends only on the camera and its placement: draw it once into a cache, copy the cache into
    // each frame (a copy-speed blit, ~1 ms with depth), and draw the shadows over it
    // (ground_shadows).
    // A camera that follows a body would redraw the cache every frame for nothing: the caller says
    // so up front (RenderSettings::cache_ground false), and the ground is drawn directly then. The
    // choice is a setting, never a guess from earlier frames, so every frame is drawn the same way
    // whichever frames came before it; the cache's content depends only on the projection.
    // The cache holds the sky, and the ground unless its shadows come from the map (soft).
    const bool cached = s.cache_ground;
    const bool ground_in_cache = s.ground && !soft;
    if (cached) {
      if (!cache_valid || vp != cache_vp || ground != cache_ground) {
        glBindFramebuffer(GL_FRAMEBUFFER, cache_fbo);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        sky_pass(vp, eye);
        if (ground_in_cache) draw(ground_prog, this->ground, ground, s.ground_color);
        cache_vp = vp;
        cache_ground = ground;
        cache_valid = true;
        ++stats.ground_cached;
      } else {
        ++stats.ground_reused;
      }
    }
    // The ground's depth matters only if the ground can hide part of a body: the camera below the
    // plane, or a body reaching under it. Otherwise (the usual case) the cache's colour is enough,
    // and the shadows need no depth offset against the ground's own depth (on llvmpipe the
    // polygon offset and the depth copy cost ~1.5 ms a 720p frame).
    bool ground_depth = s.ground && (!cached || eye.z() <= (float)s.ground_height);
    for (size_t i = 0; s.ground && i < dl.items.size() && !ground_depth; ++i)
      ground_depth = dl.items[i].model(2, 3) - meshes[dl.items[i].mesh].reach < (float)s.ground_height;
    if (cached) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, cache_fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
      glBlitFramebuffer(0, 0, s.width, s.height, 0, 0, s.width, s.height,
                        GL_COLOR_BUFFER_BIT | (ground_depth ? GL_DEPTH_BUFFER_BIT : 0), GL_NEAREST);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    if (!cached) {
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      sky_pass(vp, eye);
      if (s.ground) draw(ground_prog, this->ground, ground, s.ground_color);
    } else if (!ground_depth) {
      glClear(GL_DEPTH_BUFFER_BIT);
    }
    if (cached && s.ground && !ground_in_cache) draw(ground_prog, this->ground, ground, s.ground_color);
    // Shadows on the ground, unless the camera is below it: its underside faces away from the
    // light (no key light, no specular), so a shadow there changes nothing. Over the ground's depth
    // they go first and write no depth, so the bodies then meet the ground's own depth exactly as
    // without shadows; without it they go last, where the bodies hide part of them.
    const bool shadows_on_ground = s.ground && s.shadows && !soft && eye.z() > (float)s.ground_height;
    if (shadows_on_ground && ground_depth) ground_shadows(vp, true);
    const Meshes plain = any_material ? Meshes::plain : Meshes::any;
    glUseProgram(body_prog.id);
    draw_bodies(body_prog.batched, Subset::receivers, plain);
    if (any_material) {
      glUseProgram(mat_prog.id);
      draw_bodies(mat_prog.batched, Subset::receivers, Meshes::material, true);
    }
    glUseProgram(body_flat_prog.id);
    draw_bodies(body_flat_prog.batched, Subset::others, plain);
    if (any_material) {
      glUseProgram(mat_flat_prog.id);
      draw_bodies(mat_flat_prog.batched, Subset::others, Meshes::material, true);
    }
    if (shadows_on_ground && !ground_depth) ground_shadows(vp, false);
  }

  // The frame's target resolved (MSAA) and read back into img (RGBA8, top row first).
  void read_back(uint8_t* img) {
    if (msaa > 1) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frame_fbo);
      glBlitFramebuffer(0, 0, s.width, s.height, 0, 0, s.width, s.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, frame_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, s.width, s.height, GL_RGBA, GL_UNSIGNED_BYTE, img);  // waits for the frame
  }

  // Base-colour images as sRGB textures (sampled in linear light), mipmapped and repeating;
  // larger than the GL takes, halved until they fit (render/image.hpp, shrink_image).
  void setup_textures(const SceneMeshes& sm) {
    mat_prog.create(LitKind::body_material, soft);
    mat_flat_prog.create(LitKind::body_material_unshadowed, soft);
    GLint max_side = 4096;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
    auto make = [](const TextureImage& im) { return upload_texture(im); };
    for (const TextureImage& im : sm.textures) {
      if (im.width > max_side || im.height > max_side) {
        TextureImage small = im;
        shrink_image(small, max_side);
        textures.push_back(make(small));
      } else {
        textures.push_back(make(im));
      }
    }
    TextureImage white;
    white.width = white.height = 1;
    white.rgba = {255, 255, 255, 255};
    white_tex = make(white);
    glBindTexture(GL_TEXTURE_2D, 0);
  }

  // ---- screen-space ambient occlusion (render.quality: high): the frame's depth copied into a
  // texture, then a full-frame pass that darkens each pixel by how much of the hemisphere above
  // its surface nearby geometry fills, multiplied into the colour (blending), before the overlay.
  GLuint ao_prog = 0, ao_fbo = 0, ao_depth = 0, ao_vao = 0;
  GLint ao_inv_proj = -1, ao_scale = -1;
  void setup_ao() {
    ao_prog = link_program(sky_vertex_shader(), ao_fragment_shader().c_str());
    ao_inv_proj = glGetUniformLocation(ao_prog, "u_inv_proj");
    ao_scale = glGetUniformLocation(ao_prog, "u_px_per_m");
    glUseProgram(ao_prog);
    glUniform1i(glGetUniformLocation(ao_prog, "u_depth"), 4);  // texture unit 4
    glUniform2f(glGetUniformLocation(ao_prog, "u_texel"), 1.0f / s.width, 1.0f / s.height);
    glGenTextures(1, &ao_depth);
    glBindTexture(GL_TEXTURE_2D, ao_depth);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, s.width, s.height, 0, GL_DEPTH_COMPONENT,
                 GL_UNSIGNED_INT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glGenFramebuffers(1, &ao_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, ao_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, ao_depth, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("ambient occlusion framebuffer incomplete");
    glGenVertexArrays(1, &ao_vao);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
  }
  void ao_pass(const View& v) {
    if (!ao_prog) setup_ao();
    const GLuint target = msaa > 1 ? msaa_fbo : frame_fbo;
    // The depth, resolved to one sample (the nearest) with MSAA.
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, ao_fbo);
    glBlitFramebuffer(0, 0, s.width, s.height, 0, 0, s.width, s.height, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    glUseProgram(ao_prog);
    const M4 inv = v.proj.inverse();
    glUniformMatrix4fv(ao_inv_proj, 1, GL_FALSE, inv.data());
    glUniform1f(ao_scale,
                0.5f * s.height * v.proj(1, 1) * -1.0f);  // px per m at 1 m (the y flip's sign undone)
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_2D, ao_depth);
    glActiveTexture(GL_TEXTURE0);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ZERO, GL_SRC_COLOR);  // colour x occlusion factor
    glBindVertexArray(ao_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glEnable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
  }

  // ---- the overlay pass (render/overlay.hpp): set up on the first frame that has overlays, so a
  // scene without any does no extra GL work at all.
  struct OverlayProgram {
    GLuint id = 0;
    GLint viewproj = -1, eye = -1, xray = -1, ribbon_xray = -1;
  };
  OverlayProgram ov_solid, ov_ribbon;
  GpuMesh ov_mesh[kOverlayShapes];
  GLuint ov_inst_vbo[kOverlayShapes] = {};
  size_t ov_inst_capacity[kOverlayShapes] = {};
  GLuint ov_ribbon_vao = 0, ov_ribbon_vbo = 0;
  size_t ov_ribbon_capacity = 0;
  // Per instance: model (column-major, x-ray strength in place of its bottom-left 0), rgba.
  static constexpr int kOverlayInstanceFloats = 20;
  std::vector<float> ov_staging;
  bool ov_ready = false;

  static OverlayProgram overlay_program(bool ribbon) {
    OverlayProgram p;
    p.id = link_program(overlay_vertex_shader(ribbon), overlay_fragment_shader(ribbon).c_str());
    p.viewproj = glGetUniformLocation(p.id, "u_viewproj");
    p.eye = glGetUniformLocation(p.id, "u_eye");
    p.xray = glGetUniformLocation(p.id, "u_xray");
    p.ribbon_xray = glGetUniformLocation(p.id, "u_ribbon_xray");
    return p;
  }

  void setup_overlay() {
    ov_solid = overlay_program(false);
    ov_ribbon = overlay_program(true);
    RenderMesh unit[kOverlayShapes] = {tessellate_cylinder(1, 1, 12), tessellate_cone(1, 1, 16),
                                       tessellate_sphere(1, 16)};
    for (size_t i = 2; i < unit[0].vertices.size(); i += 6) unit[0].vertices[i] += 0.5f;  // z from 0 to 1
    for (int k = 0; k < kOverlayShapes; ++k) {
      ov_mesh[k] = upload(unit[k]);
      glBindVertexArray(ov_mesh[k].vao);
      glGenBuffers(1, &ov_inst_vbo[k]);
      glBindBuffer(GL_ARRAY_BUFFER, ov_inst_vbo[k]);
      const GLsizei stride = kOverlayInstanceFloats * sizeof(float);
      for (int c = 0; c < 4; ++c) {
        glEnableVertexAttribArray(2 + c);
        glVertexAttribPointer(2 + c, 4, GL_FLOAT, GL_FALSE, stride, (void*)(4 * c * sizeof(float)));
        glVertexAttribDivisor(2 + c, 1);
      }
      glEnableVertexAttribArray(6);
      glVertexAttribPointer(6, 4, GL_FLOAT, GL_FALSE, stride, (void*)(16 * sizeof(float)));
      glVertexAttribDivisor(6, 1);
    }
    glGenVertexArrays(1, &ov_ribbon_vao);
    glBindVertexArray(ov_ribbon_vao);
    glGenBuffers(1, &ov_ribbon_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, ov_ribbon_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex), (void*)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex), (void*)(3 * sizeof(float)));
    glBindVertexArray(0);
    ov_ready = true;
  }

  // Uploads into `vbo`, growing it (to twice the need) only when it is too small.
  static void stream(GLuint vbo, size_t& capacity, const void* data, size_t bytes) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    if (bytes > capacity) {
      capacity = 2 * bytes;
      glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)capacity, nullptr, GL_STREAM_DRAW);
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, data);
  }

  // The nearest distance (m) from the eye to the overlay geometry (bounding spheres), for the
  // near plane: an arrow may reach closer to the camera than the bodies.
  static float overlay_nearest(const OverlayList& ov, const V3f& eye) {
    float near = INFINITY;
    for (int k = 0; k < kOverlayShapes; ++k)
      for (const OverlayInstance& in : ov.instances[k]) {
        const V3f c =
            (in.model * Eigen::Vector4f(0, 0, k == (int)OverlayShape::sphere ? 0.0f : 0.5f, 1)).head<3>();
        const float r = in.model.col(0).head<3>().norm() + in.model.col(1).head<3>().norm() +
                        in.model.col(2).head<3>().norm();
        near = std::min(near, (c - eye).norm() - r);
      }
    for (const OverlayVertex& v : ov.ribbons)
      near = std::min(near, (V3f(v.pos[0], v.pos[1], v.pos[2]) - eye).norm());
    return near;
  }

  // Pass 3: the overlay geometry into the bound target, over the bodies' depth. Hidden parts of
  // x-ray items first (depth test GREATER against the bodies alone, faded, no depth written), then
  // everything visible (solids opaque or translucent with depth, then ribbons without).
  void overlay_pass(const OverlayList& ov, const M4& vp, const V3f& eye) {
    if (!ov_ready) setup_overlay();
    size_t count[kOverlayShapes];
    bool any_xray = ov.ribbon_xray > 0 && !ov.ribbons.empty();
    bool translucent = !ov.ribbons.empty();  // blending only when needed: it costs llvmpipe a read
    for (int k = 0; k < kOverlayShapes; ++k) {
      const auto& v = ov.instances[k];
      count[k] = v.size();
      if (v.empty()) continue;
      ov_staging.resize(kOverlayInstanceFloats * v.size());
      float* d = ov_staging.data();
      for (const OverlayInstance& in : v) {
        std::copy(in.model.data(), in.model.data() + 16, d);
        d[3] = in.xray;  // in place of the affine model's bottom-left 0 (the shader puts the 0 back)
        std::copy(in.color.begin(), in.color.end(), d + 16);
        d += kOverlayInstanceFloats;
        any_xray = any_xray || in.xray > 0;
        translucent = translucent || in.color[3] < 1;
      }
      stream(ov_inst_vbo[k], ov_inst_capacity[k], ov_staging.data(), ov_staging.size() * sizeof(float));
    }
    if (!ov.ribbons.empty())
      stream(ov_ribbon_vbo, ov_ribbon_capacity, ov.ribbons.data(), ov.ribbons.size() * sizeof(OverlayVertex));
    for (const OverlayProgram* p : {&ov_solid, &ov_ribbon}) {
      glUseProgram(p->id);
      glUniformMatrix4fv(p->viewproj, 1, GL_FALSE, vp.data());
      glUniform3f(p->eye, eye.x(), eye.y(), eye.z());
      glUniform1f(p->ribbon_xray, ov.ribbon_xray);
    }
    if (translucent || any_xray) glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    auto solids = [&] {
      glUseProgram(ov_solid.id);
      for (int k = 0; k < kOverlayShapes; ++k)
        if (count[k]) {
          glBindVertexArray(ov_mesh[k].vao);
          glDrawElementsInstanced(GL_TRIANGLES, ov_mesh[k].count, GL_UNSIGNED_INT, nullptr,
                                  (GLsizei)count[k]);
        }
    };
    auto ribbons = [&] {
      if (ov.ribbons.empty()) return;
      glUseProgram(ov_ribbon.id);
      glDisable(GL_CULL_FACE);
      glBindVertexArray(ov_ribbon_vao);
      glDrawArrays(GL_TRIANGLES, 0, (GLsizei)ov.ribbons.size());
      glEnable(GL_CULL_FACE);
    };
    if (any_xray) {
      for (const OverlayProgram* p : {&ov_solid, &ov_ribbon}) {
        glUseProgram(p->id);
        glUniform1i(p->xray, 1);
      }
      glDepthFunc(GL_GREATER);
      glDepthMask(GL_FALSE);
      solids();
      ribbons();
      glDepthFunc(GL_LESS);
      glDepthMask(GL_TRUE);
      for (const OverlayProgram* p : {&ov_solid, &ov_ribbon}) {
        glUseProgram(p->id);
        glUniform1i(p->xray, 0);
      }
    }
    solids();
    glDepthMask(GL_FALSE);
    ribbons();
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glBindVertexArray(0);
  }

  // One mesh with the program `lp` (made current here) at pose `model` in colour `color`.
  static void draw(const LitProgram& lp, const GpuMesh& g, const M4& model,
                   const std::array<float, 3>& color) {
    glUseProgram(lp.id);
    glUniformMatrix4fv(lp.model, 1, GL_FALSE, model.data());
    glUniform3f(lp.color, color[0], color[1], color[2]);
    draw_mesh(g);
  }
};

Renderer::Renderer(const RenderSettings& s, const SceneMeshes& sm) : p_(std::make_unique<Impl>()) {
  Impl& P = *p_;
  P.s = s;
  P.ctx = make_offscreen_context(s.gl);
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  P.msaa = std::max(1, std::min(s.msaa(), (int)max_samples));
  P.soft = s.quality == RenderQuality::high && s.shadows;
  P.body_prog.create(LitKind::body, P.soft);
  P.body_flat_prog.create(LitKind::body_unshadowed, P.soft);
  if (!s.ground_texture.empty()) {  // an unreadable image is the scene's error: it says which
    TextureImage im = read_image(s.ground_texture);
    GLint max_side = 4096;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
    shrink_image(im, max_side);
    P.ground_tex = upload_texture(im);
  }
  P.ground_prog.create(P.ground_tex ? LitKind::ground_textured : LitKind::ground, P.soft);
  glUseProgram(P.ground_prog.id);
  glUniform3f(P.ground_prog.color2, s.ground_color2[0], s.ground_color2[1], s.ground_color2[2]);
  glUniform1f(P.ground_prog.ground_tex_size, P.ground_texture_size());
  P.setup_sky();
  P.depth = link_program(depth_vertex_shader(), depth_fragment_shader());
  P.u_mvp = glGetUniformLocation(P.depth, "u_mvp");
  P.d_batched = glGetUniformLocation(P.depth, "u_batched");
  P.d_items = glGetUniformLocation(P.depth, "u_items");
  glUseProgram(P.depth);
  glUniform1i(P.d_items, 1);
  glUniform1i(P.d_batched, 0);
  glUseProgram(0);
  P.setup_items(sm.meshes.size());
  for (const RenderMesh& m : sm.meshes) {
    P.meshes.push_back(upload(m));
    P.attach_slots(P.meshes.back());
    ++P.stats.meshes;
    P.stats.mesh_bytes += m.bytes();
    P.any_material = P.any_material || !m.extras.empty();
  }
  if (P.any_material) P.setup_textures(sm);
  if (s.ground) P.ground = upload(tessellate_plane(s.ground_size));
  if (s.ground && s.shadows) P.setup_ground_shadows();
  P.setup_targets();
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  if (glGetError() != GL_NO_ERROR) throw std::runtime_error("OpenGL error while setting up the renderer");
}

Renderer::~Renderer() = default;

const uint8_t* Renderer::render(const DrawList& dl, uint8_t* out) {
  Impl& P = *p_;
  const RenderSettings& s = P.s;
  P.ctx->make_current();
  const M4 lvp = P.light_viewproj(dl);
  P.group_items(dl);
  if (s.shadows) P.shadow_pass(dl, lvp);  // pass 1
  const Impl::View v = P.view(dl);
  P.bodies_pass(dl, v, lvp);                                         // pass 2
  if (s.quality == RenderQuality::high) P.ao_pass(v);                // ambient occlusion
  if (!dl.overlay.empty()) P.overlay_pass(dl.overlay, v.vp, v.eye);  // pass 3
  uint8_t* img = out ? out : P.frame.data();
  P.read_back(img);
  ++P.stats.frames;
  if (s.post == PostStage::renderer) {  // pass 4, else the caller's
    if (s.fxaa()) fxaa(img, s.width, s.height, P.fxaa_buffers);
    if (!dl.screen.empty()) composite(dl.screen, img, s.width, s.height);
  }
  return img;
}

const RenderStats& Renderer::stats() const {
  return p_->stats;
}
std::string Renderer::description() const {
  return p_->ctx->description();
}

}  // namespace simreel
