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
      out[i].push_back({L.collider_color(k), L.drawn && L.colliders[k].drawn, L.colliders[k].plane_size,
                        L.colliders[k].normals.get(), L.colliders[k].appearance.get()});
  }
  return out;
}

}  // namespace

// Each body's drawn size: the radius about its centre of mass that holds its drawn colliders.
// m per body: the radius of the sphere about its centre of mass holding everything drawn of it,
// from the drawn vertices themselves. (The meshes' own bounding spheres are about their collider
// origins: a mesh whose file origin lies far from its shape, Blender's Suzanne exported 2.5 m
// off, would size its arrows, axes and labels by that distance.)
static std::vector<double> body_radii(const World& w, const SceneMeshes& sm) {
  std::vector<double> r((size_t)w.body_count(), 0.0);
  for (int i = 0; i < w.body_count(); ++i) {
    const BodyDef& d = w.def(i);
    const Vec3 c = w.local_centroid(i);
    for (size_t k = 0; k < d.colliders.size(); ++k) {
      const int m = sm.mesh_of[i][k];
      if (m < 0) continue;
      const Collider& col = d.colliders[k];
      const std::vector<float>& v = sm.meshes[m].vertices;  // x y z nx ny nz, collider frame
      const Mat3 R = col.q_BC.toRotationMatrix();
      double r2 = 0;
      for (size_t a = 0; a + 5 < v.size(); a += 6)
        r2 = std::max(r2, (col.p_BC + R * Vec3(v[a], v[a + 1], v[a + 2]) - c).squaredNorm());
      r[i] = std::max(r[i], std::sqrt(r2));
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
  path = scene.camera.path;
  orbit = scene.camera.orbit;
  for (const std::string& name : scene.camera.aim)
    for (int i = 0; i < world.body_count(); ++i)
      if (world.def(i).name == name) aim.push_back(i);
  for (int i = 0; i < world.body_count(); ++i) {
    if (world.def(i).name == scene.camera.follow) follow = i;
    if (world.def(i).name == scene.camera.frame_body) ride = i;
    if (orbit && world.def(i).name == orbit->body) orbit_body = i;
  }
  if (follow >= 0 && scene.camera.follow_damping > 0)
    damped = std::make_unique<DampedFollow>(scene.camera.follow_damping);
  // A following or moving camera moves every frame: caching the ground would only redraw the cache.
  rs.cache_ground = follow < 0 && ride < 0 && !moving();
  if (scene.overlays.any())
    overlays = std::make_unique<SceneOverlays>(scene, world, body_radii(world, meshes), rs.width, rs.height,
                                               std::max(1, o.threads), o.prepass,
                                               follow < 0 && ride < 0 && !moving() ? &camera : nullptr);
  for (const BodyLook& l : scene.looks)
    if (l.ghost.on && !ghosts) ghosts = std::make_unique<GhostView>(scene, world);
}

const uint8_t* SceneView::draw(Renderer& r, const World& world, uint8_t* out, long frame) {
  // The camera at this moment: a function of the simulated time (path, orbit) and of the bodies'
  // states up to it (the orbit's body, the damped follow), never of the frames drawn before.
  CameraView cam = camera;
  const double t = world.time();
  if (!path.empty()) path.apply(t, cam.eye, cam.target, cam.up, cam.fov_deg);
  if (orbit) {
    cam.target = orbit_body >= 0 ? world.centroid(orbit_body) : orbit->center;
    cam.eye = orbit->eye(t, cam.target);
  }
  // A damped follow draws where its filter is (the rigid follow until the step hook has run).
  const bool lag = damped && damped->started();
  build_draw_list(world, meshes, cam, lag ? -1 : follow, dl_);
  if (lag) {
    dl_.camera.eye = cam.eye + (damped->position() - cam.target);
    dl_.camera.target = damped->position();
  }
  if (ride >= 0) {  // camera.frame: the camera's points and up are in the body's frame
    dl_.camera.eye = world.local_to_world(ride, cam.eye);
    dl_.camera.target = world.local_to_world(ride, cam.target);
    dl_.camera.up = world.local_to_world_vec(ride, cam.up);
  }
  if (!aim.empty()) {  // camera.aim: turned to the bodies' centre of mass, from where it stands
    Vec3 sum = Vec3::Zero();
    double mass = 0;
    for (int i : aim) {
      const double m = world.mass(i) > 0 ? world.mass(i) : 1.0;  // a massless static shape: its point
      sum += m * world.centroid(i);
      mass += m;
    }
    const Vec3 target = sum / mass;
    if ((target - dl_.camera.eye).norm() > 0) dl_.camera.target = target;
  }
  if (overlays) overlays->build(world, frame >= 0 ? frame : std::lround(world.time() * fps_), dl_);
  if (!overlays) dl_.overlay.clear();
  if (overlays && overlays->has_snapshots()) overlays->build_snapshots(world, meshes, dl_);
  if (ghosts) ghosts->build(world, meshes, dl_);
  for (const auto& [other, color] : overlaid)
    for (int i = 0; i < other->body_count(); ++i)
      if (other->type(i) == BodyType::dynamic)
        draw_body_copy(*other, meshes, i, other->centroid(i), other->orientation(i), color, kGhostInflate,
                       dl_);
  return r.render(dl_, out);
}

void SceneView::save_history(std::ostream& os) const {
  put(os, (uint8_t)(overlays ? 1 : 0));
  if (overlays) overlays->save_history(os);
  put(os, (uint8_t)(damped ? 1 : 0));
  if (damped) put(os, damped->state());
}

void SceneView::restore_history(std::istream& is) {
  uint8_t has = 0;
  get(is, has);
  if (has != (overlays ? 1 : 0)) throw InputError("a checkpoint's overlays are not the scene's");
  if (overlays) overlays->restore_history(is);
  get(is, has);
  if (has != (damped ? 1 : 0)) throw InputError("a checkpoint's camera follow is not the scene's");
  if (damped) {
    DampedFollow::State st;
    get(is, st);
    damped->set_state(st);
  }
}

std::function<void(const World&)> SceneView::step_hook() {
  SceneOverlays* o = overlays && overlays->records_steps() ? overlays.get() : nullptr;
  DampedFollow* f = damped.get();
  if (!o && !f) return {};
  const int body = follow;
  return [o, f, body](const World& w) {
    if (o) o->record(w);
    if (f) f->track(w.steps(), w.time(), w.centroid(body));
  };
}

}  // namespace simreel
