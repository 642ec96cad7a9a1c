#include "app/scene/scene_camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/scene/scene.hpp"
#include "app/scene/scene_views.hpp"

namespace simreel {

using namespace scene_yaml;

namespace {

std::string secs(double t) {
  char b[40];
  std::snprintf(b, sizeof b, "%g", t);
  return b;
}

double fov_of(const YAML::Node& n, const Ctx& c) {
  const double f = positive(n, c);
  if (f >= 179) c.fail(n, "must be below 179 degrees");
  return f;
}

// What is wrong with a camera at `eye` looking at `target` ("" if nothing).
std::string bad_view(const Vec3& eye, const Vec3& target, const Vec3& up, double fov) {
  const Vec3 d = target - eye;
  if (!(d.norm() > 1e-9 * std::max(1.0, eye.norm()))) return "the camera's position reaches its look_at";
  if (!(up.cross(d).norm() > 1e-9 * up.norm() * d.norm()))
    return "the up direction is parallel to the viewing direction (or zero)";
  if (!(fov > 0 && fov < 179))
    return "the field of view is " + secs(fov) + " degrees (it must lie in (0, 179))";
  return "";
}

CameraPath load_path(const YAML::Node& p, const Ctx& c, const CameraSpec& cam) {
  if (!p.IsSequence() || p.size() == 0)
    c.fail(p,
           "expected a list of keys like { t: 0, position: [x, y, z], look_at: [x, y, z] }, got " + show(p));
  std::vector<CameraKey> keys;
  for (size_t i = 0; i < p.size(); ++i) {
    const Ctx kc = c.index(i);
    const YAML::Node n = p[i];
    if (!n.IsMap()) kc.fail(n, "expected a key { t: S, position: [x, y, z], ... }, got " + show(n));
    check_keys(n, kc, {"t", "position", "look_at", "up", "fov"});
    if (!n["t"]) kc.fail(n, "needs 't' (s of simulated time at which the camera is here)");
    CameraKey k;
    k.t = non_negative(n["t"], kc.child("t"));
    if (n["position"]) k.position = vec<3>(n["position"], kc.child("position"));
    if (n["look_at"]) k.look_at = vec<3>(n["look_at"], kc.child("look_at"));
    if (n["up"]) k.up = vec<3>(n["up"], kc.child("up"));
    if (n["fov"]) k.fov = fov_of(n["fov"], kc.child("fov"));
    if (!k.position && !k.look_at && !k.up && !k.fov)
      kc.fail(n, "gives none of position, look_at, up, fov: a key says where the camera is at t");
    if (!keys.empty() && k.t <= keys.back().t)
      kc.child("t").fail(n["t"], k.t == keys.back().t
                                     ? "another key is already at t = " + secs(k.t) + " s"
                                     : "t = " + secs(k.t) + " s is before the previous key's (" +
                                           secs(keys.back().t) + " s): keys go in time order");
    keys.push_back(k);
  }
  CameraPath path(keys);
  // The view must make sense all along the path, not at the keys only (a spline between two keys
  // can carry the eye through the target): checked at each key and at 64 moments between keys.
  auto check = [&](double t, const YAML::Node& n, const Ctx& at, const std::string& when) {
    Vec3 eye = cam.position, target = cam.look_at, up = cam.up;
    double fov = cam.fov;
    path.apply(t, eye, target, up, fov);
    if (const std::string bad = bad_view(eye, target, up, fov); !bad.empty()) at.fail(n, when + bad);
  };
  for (size_t i = 0; i < keys.size(); ++i) {
    check(keys[i].t, p[i], c.index(i), "");
    if (i + 1 < keys.size())
      for (int j = 1; j < 64; ++j) {
        const double t = keys[i].t + (keys[i + 1].t - keys[i].t) * j / 64;
        check(t, p[i], c.index(i),
              "between this key and the next, at t = " + secs(t) +
                  " s (the path through the keys is a "
                  "smooth curve): ");
      }
  }
  return path;
}

CameraOrbit load_orbit(const YAML::Node& o, const Ctx& c, const CameraSpec& cam, const Scene& s) {
  if (!o.IsMap()) c.fail(o, "expected a mapping like { center: [x, y, z], period: 10 }, got " + show(o));
  check_keys(o, c, {"center", "body", "radius", "height", "period", "degrees_per_second", "start_angle"});
  CameraOrbit orb;
  if (o["center"] && o["body"])
    c.child("body").fail(o["body"], "an orbit circles a point (center) or a body: give one");
  orb.center = cam.look_at;
  if (o["center"]) orb.center = vec<3>(o["center"], c.child("center"));
  if (o["body"]) {
    orb.body = text(o["body"], c.child("body"));
    check_body(s, orb.body, o["body"], c.child("body"));
  }
  if (o["period"] && o["degrees_per_second"])
    c.child("degrees_per_second")
        .fail(o["degrees_per_second"], "give the speed once: period or degrees_per_second");
  if (o["period"]) {
    const double T = number(o["period"], c.child("period"));
    if (T == 0) c.child("period").fail(o["period"], "must not be zero (s a turn; negative turns clockwise)");
    orb.rate = 2 * M_PI / T;
  } else if (o["degrees_per_second"]) {
    orb.rate = number(o["degrees_per_second"], c.child("degrees_per_second")) * M_PI / 180;
  } else {
    c.fail(o, "needs period (s a turn) or degrees_per_second");
  }
  // Unless given, the orbit starts where the camera block puts the camera: its offset from
  // look_at gives the radius, height and start angle.
  const Vec3 off = cam.position - cam.look_at;
  orb.radius = std::hypot(off.x(), off.y());
  orb.height = off.z();
  orb.start_angle = std::atan2(off.y(), off.x());
  if (o["radius"]) orb.radius = positive(o["radius"], c.child("radius"));
  if (o["height"]) orb.height = number(o["height"], c.child("height"));
  if (o["start_angle"]) orb.start_angle = number(o["start_angle"], c.child("start_angle")) * M_PI / 180;
  if (!(orb.radius > 0))
    c.fail(o, "camera.position is straight above or below camera.look_at: give the orbit a radius");
  // The up direction stays fixed while the eye goes round: it must never line up with the view.
  for (int k = 0; k < 16; ++k) {
    const double a = orb.start_angle + k * M_PI / 8;
    const Vec3 view = -Vec3(orb.radius * std::cos(a), orb.radius * std::sin(a), orb.height);
    if (!(cam.up.cross(view).norm() > 1e-9 * cam.up.norm() * view.norm()))
      c.fail(o, "camera.up is parallel to the viewing direction somewhere on the orbit");
  }
  return orb;
}

}  // namespace

std::string camera_follow(const YAML::Node& n, const Ctx& c, double& damping) {
  damping = 0;
  if (n.IsScalar()) return text(n, c);
  if (!n.IsMap()) c.fail(n, "expected a body name or { body: NAME, damping: S }, got " + show(n));
  check_keys(n, c, {"body", "damping"});
  if (!n["body"]) c.fail(n, "needs 'body' (the name of the body the camera follows)");
  if (n["damping"]) damping = non_negative(n["damping"], c.child("damping"));
  return text(n["body"], c.child("body"));
}

void load_camera_motion(const YAML::Node& root, const std::string& path, Scene& s) {
  const YAML::Node cam = root["camera"];
  if (!cam || !cam.IsMap()) return;
  const Ctx c = Ctx(path, "").child("camera");
  CameraSpec& cs = s.camera;
  const YAML::Node p = cam["path"], o = cam["orbit"];
  if (!p && !o) return;
  const char* what = p ? "path" : "orbit";
  if (p && o) c.child("orbit").fail(o, "a camera on a path does not also orbit: give one of path, orbit");
  if (cs.fit)
    c.child("auto").fail(cam["auto"], std::string("camera.auto places a still camera; camera.") + what +
                                          " moves it: give one");
  if (!cs.follow.empty())
    c.child("follow").fail(cam["follow"], std::string("a camera on ") + (p ? "a path" : "an orbit") +
                                              " does not also follow a body" +
                                              (p ? "" : " (orbit: { body: NAME } circles one)"));
  if (o && !cs.frame_body.empty())
    c.child("frame").fail(cam["frame"],
                          "an orbit circles a point or a body in the world; a camera riding in a body's "
                          "frame is placed by hand (a path works in the body's frame)");
  if (o && !cs.aim.empty())
    c.child("aim").fail(cam["aim"], "an orbit looks at its centre or its body: give one of orbit, aim");
  if (p && !cs.aim.empty())
    for (size_t i = 0; i < p.size(); ++i)
      if (p[i].IsMap() && p[i]["look_at"])
        c.child("path").index(i).child("look_at").fail(
            p[i]["look_at"],
            "camera.aim turns the camera to its bodies: a path's look_at keys would too; give one");
  if (p) cs.path = load_path(p, c.child("path"), cs);
  if (o) cs.orbit = load_orbit(o, c.child("orbit"), cs, s);
}

MotionBlurSpec motion_blur(const YAML::Node& n, const Ctx& c) {
  if (!n.IsMap()) c.fail(n, "expected a mapping like { samples: 8, shutter: 0.5 }, got " + show(n));
  check_keys(n, c, {"samples", "shutter"});
  MotionBlurSpec mb;
  if (!n["samples"]) c.fail(n, "needs 'samples' (images averaged per frame, 2 to 64; 1 turns blur off)");
  const double k = number(n["samples"], c.child("samples"));
  if (k != std::floor(k) || k < 1 || k > 64)
    c.child("samples").fail(n["samples"], "expected a whole number from 1 to 64, got " + show(n["samples"]));
  mb.samples = (int)k;
  if (n["shutter"]) {
    mb.shutter = number(n["shutter"], c.child("shutter"));
    if (!(mb.shutter > 0 && mb.shutter <= 1))
      c.child("shutter").fail(
          n["shutter"], "must lie in (0, 1]: the share of the frame interval the shutter is open, got " +
                            show(n["shutter"]));
  }
  return mb;
}

}  // namespace simreel
