#include "app/runner/camera_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/runner/frame_loop.hpp"

namespace simreel {

std::vector<double> body_radii(const World& w) {
  std::vector<double> out(w.body_count(), 0.0);
  for (int i = 0; i < w.body_count(); ++i) {
    const BodyDef& b = w.def(i);
    const Vec3 c = w.local_centroid(i);
    double r = 0;
    for (const Collider& col : b.colliders) {
      double extent = 0;
      switch (col.shape) {
        case ShapeKind::box:
          extent = 0.5 * col.size.norm();
          break;
        case ShapeKind::sphere:
          extent = col.radius;
          break;
        case ShapeKind::capsule:
          extent = 0.5 * col.height;
          break;
        case ShapeKind::cylinder:
          extent = std::hypot(col.radius, 0.5 * col.height);
          break;
        case ShapeKind::ellipsoid:
          extent = col.radii.maxCoeff();
          break;
        case ShapeKind::mesh:
          if (col.mesh)
            for (const Vec3& v : col.mesh->vertices) extent = std::max(extent, v.norm());
          break;
        case ShapeKind::plane:
          continue;
      }
      r = std::max(r, (col.p_BC - c).norm() + extent);
    }
    out[i] = r;
  }
  return out;
}

std::string fit_camera(Scene& scene, int threads) {
  if (!scene.camera.fit) return "";
  FrameLoop loop(scene, threads);
  const std::vector<double> radii = body_radii(loop.world());
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  FrameLoop::Hooks h;
  h.frame = [&](const FrameTarget&, const World& w) {
    for (int i = 0; i < w.body_count(); ++i) {
      if (radii[i] <= 0) continue;
      lo = lo.cwiseMin(w.centroid(i) - Vec3::Constant(radii[i]));
      hi = hi.cwiseMax(w.centroid(i) + Vec3::Constant(radii[i]));
    }
  };
  loop.run(loop.all_frames(), h, false);
  if (!(lo.x() <= hi.x())) return "camera.auto: nothing to frame (no body has a finite size)";
  const Vec3 centre = 0.5 * (lo + hi);
  // Back off along the viewing direction until every corner of the box lies inside the view
  // pyramid, with a 10% margin on each side: in camera coordinates (right r, up u, forward f) a
  // corner at offset q from the centre needs |q.r| <= tan(half_h) (D + q.f), the same with q.u and
  // half_v, where D is the camera's distance from the centre. (A bounding sphere instead would back
  // a long flat scene off far more than it needs.)
  const double aspect = (double)scene.video.width / scene.video.height;
  const double tv = std::tan(0.5 * scene.camera.fov * M_PI / 180) / 1.1, th = tv * aspect;
  Vec3 dir = scene.camera.position - scene.camera.look_at;
  dir = dir.norm() > 0 ? dir.normalized() : Vec3(1, -1, 0.6).normalized();
  const Vec3 f = -dir;
  Vec3 r = f.cross(scene.camera.up);
  r = r.norm() > 0 ? r.normalized() : f.unitOrthogonal();
  const Vec3 u = r.cross(f);
  double distance = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    const Vec3 q = corner - centre;
    distance = std::max({distance, std::fabs(q.dot(r)) / th - q.dot(f), std::fabs(q.dot(u)) / tv - q.dot(f)});
  }
  distance = std::max(distance, 1e-3);
  scene.camera.look_at = centre;
  scene.camera.position = centre + distance * dir;
  char b[200];
  std::snprintf(b, sizeof b,
                "camera.auto: looking at (%.3g, %.3g, %.3g) from (%.3g, %.3g, %.3g), %.3g m away", centre.x(),
                centre.y(), centre.z(), scene.camera.position.x(), scene.camera.position.y(),
                scene.camera.position.z(), distance);
  return b;
}

bool any_body_in_view(const World& w, const std::vector<double>& radii, const Vec3& eye, const Vec3& target,
                      const Vec3& up, double fov_deg, double aspect) {
  // Camera frame: f forward, r right, u up. A sphere is in view when it reaches in front of the
  // camera and within the four side planes of the view pyramid.
  const Vec3 f = (target - eye).normalized();
  const Vec3 r = f.cross(up).normalized();
  const Vec3 u = r.cross(f);
  const double tv = std::tan(0.5 * fov_deg * M_PI / 180), th = tv * aspect;
  // Unit normals of the side planes, pointing into the pyramid.
  const Vec3 planes[4] = {(f * tv + u).normalized().cross(r), r.cross((f * tv - u).normalized()),
                          u.cross((f * th + r).normalized()), (f * th - r).normalized().cross(u)};
  for (int i = 0; i < w.body_count(); ++i) {
    const Vec3 d = w.centroid(i) - eye;
    const double rad = radii[i];
    if (rad <= 0 || d.dot(f) < -rad) continue;
    bool inside = true;
    for (const Vec3& n : planes) inside = inside && n.dot(d) >= -rad;
    if (inside) return true;
  }
  return false;
}

int body_around(const World& w, const std::vector<double>& radii, const Vec3& p) {
  for (int i = 0; i < w.body_count(); ++i)
    if (radii[i] > 0 && (p - w.centroid(i)).norm() < radii[i]) return i;
  return -1;
}

}  // namespace simreel
