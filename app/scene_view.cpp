#include "app/scene_view.hpp"

#include <stdexcept>

namespace simreel {

namespace {

// The scene's appearance as the renderer takes it: a colour per collider (its file's material,
// else the body's), whether it is drawn, and the drawn size of planes.
SceneStyles styles_of(const Scene& scene) {
  SceneStyles out(scene.looks.size());
  for (size_t i = 0; i < scene.looks.size(); ++i) {
    const BodyLook& L = scene.looks[i];
    for (size_t k = 0; k < L.colliders.size(); ++k)
      out[i].push_back(
          {L.collider_color(k), L.drawn, L.colliders[k].plane_size, L.colliders[k].normals.get()});
  }
  return out;
}

}  // namespace

SceneView::SceneView(const Scene& scene, const World& world, const ViewOptions& o)
    : meshes(world, styles_of(scene)) {
  RenderSettings& rs = settings;
  if (!o.gl.empty()) {
    const auto b = gl_backend_from_name(o.gl);
    if (!b) throw std::invalid_argument("unknown --gl '" + o.gl + "' (osmesa, egl)");
    if (!gl_backend_built(*b))
      throw std::invalid_argument("this simreel was built without the " + o.gl + " backend");
    rs.gl = *b;
  }
  rs.width = o.width > 0 ? o.width : scene.video.width;
  rs.height = o.height > 0 ? o.height : scene.video.height;
  aa = scene.render.antialiasing;
  if (!o.aa.empty()) {
    const auto m = antialiasing_from_name(o.aa);
    if (!m) throw std::invalid_argument("unknown --aa '" + o.aa + "' (fxaa, msaa2, msaa4, none)");
    aa = *m;
  }
  rs.msaa = aa == AntiAliasing::msaa4 ? 4 : aa == AntiAliasing::msaa2 ? 2 : 1;
  rs.fxaa = aa == AntiAliasing::fxaa;
  rs.shadows = scene.render.shadows && !o.no_shadows;
  rs.background = scene.render.background;
  rs.ground = scene.render.ground;
  rs.ground_height = scene.render.ground_height;
  rs.ground_size = scene.render.ground_size;
  rs.ground_tile = scene.render.ground_tile;

  camera.eye = scene.camera.position;
  camera.target = scene.camera.look_at;
  camera.up = scene.camera.up;
  camera.fov_deg = scene.camera.fov;
  for (int i = 0; i < world.body_count(); ++i)
    if (world.def(i).name == scene.camera.follow) follow = i;
  // A following camera moves every frame: caching the ground would only redraw the cache.
  rs.cache_ground = follow < 0;
}

const uint8_t* SceneView::draw(Renderer& r, const World& world, uint8_t* out) {
  build_draw_list(world, meshes, camera, follow, dl_);
  return r.render(dl_, out);
}

}  // namespace simreel
