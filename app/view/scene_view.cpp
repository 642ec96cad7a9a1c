#include "app/view/scene_view.hpp"

#include <algorithm>
#include <cmath>
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
      out[i].push_back({L.collider_color(k), L.drawn, L.colliders[k].plane_size, L.colliders[k].normals.get(),
                        L.colliders[k].appearance.get()});
  }
  return out;
}

}  // namespace

// Each body's drawn size: the radius about its centre of mass that holds its drawn colliders.
static std::vector<double> body_radii(const World& w, const SceneMeshes& sm) {
  std::vector<double> r((size_t)w.body_count(), 0.0);
  for (int i = 0; i < w.body_count(); ++i) {
    const BodyDef& d = w.def(i);
    for (size_t k = 0; k < d.colliders.size(); ++k) {
      const int m = sm.mesh_of[i][k];
      if (m < 0) continue;
      r[i] = std::max(r[i], (d.colliders[k].p_BC - w.local_centroid(i)).norm() + sm.meshes[m].radius);
    }
    if (r[i] <= 0) r[i] = 0.5;
  }
  return r;
}

SceneView::SceneView(const Scene& scene, const World& world, const ViewOptions& o)
    : meshes(world, styles_of(scene)), fps_(scene.video.fps) {
  RenderSettings& rs = settings;
  if (!o.gl.empty()) {
    const auto b = gl_backend_from_name(o.gl);
    if (!b) throw std::invalid_argument("unknown --gl '" + o.gl + "' (osmesa, egl)");
    if (!gl_backend_built(*b))
      throw std::invalid_argument("this simreel was built without the " + o.gl + " backend");
    rs.gl = *b;
  }
  static_cast<RenderLook&>(rs) = scene.render;  // the scene's look, field for field
  rs.width = o.width > 0 ? o.width : scene.video.width;
  rs.height = o.height > 0 ? o.height : scene.video.height;
  if (!o.aa.empty()) {
    const auto m = antialiasing_from_name(o.aa);
    if (!m) throw std::invalid_argument("unknown --aa '" + o.aa + "' (fxaa, msaa2, msaa4, none)");
    rs.antialiasing = *m;
  }
  aa = rs.antialiasing;
  if (o.no_shadows) rs.shadows = false;

  camera.eye = scene.camera.position;
  camera.target = scene.camera.look_at;
  camera.up = scene.camera.up;
  camera.fov_deg = scene.camera.fov;
  for (int i = 0; i < world.body_count(); ++i) {
    if (world.def(i).name == scene.camera.follow) follow = i;
    if (world.def(i).name == scene.camera.frame_body) ride = i;
  }
  // A following camera moves every frame: caching the ground would only redraw the cache.
  rs.cache_ground = follow < 0 && ride < 0;
  if (scene.overlays.any())
    overlays = std::make_unique<SceneOverlays>(scene, world, body_radii(world, meshes), rs.width, rs.height,
                                               std::max(1, o.threads));
  for (const BodyLook& l : scene.looks)
    if (l.ghost.on && !ghosts) ghosts = std::make_unique<GhostView>(scene, world);
}

const uint8_t* SceneView::draw(Renderer& r, const World& world, uint8_t* out, long frame) {
  build_draw_list(world, meshes, camera, follow, dl_);
  if (ride >= 0) {  // camera.frame: the camera's points and up are in the body's frame
    dl_.camera.eye = world.local_to_world(ride, camera.eye);
    dl_.camera.target = world.local_to_world(ride, camera.target);
    dl_.camera.up = world.local_to_world_vec(ride, camera.up);
  }
  if (overlays) overlays->build(world, frame >= 0 ? frame : std::lround(world.time() * fps_), dl_);
  if (ghosts) {
    if (!overlays) dl_.overlay.clear();
    ghosts->build(world, meshes, dl_);
  }
  return r.render(dl_, out);
}

std::function<void(const World&)> SceneView::step_hook() {
  if (!overlays || !overlays->records_steps()) return {};
  SceneOverlays* o = overlays.get();
  return [o](const World& w) { o->record(w); };
}

}  // namespace simreel
