// The `forces`, `contacts` and `joint_forces` show items (app/view/overlays.hpp): the scene's applied
// forces, torques, springs and drag, the contact solver's points, normals and forces, and the force
// and torque through a joint, as 3D overlay geometry.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "app/view/overlays.hpp"
#include "render/camera.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {

namespace {

// A torque: a double-headed arrow along it (the engineering convention for a moment) and, round
// its middle, a 270-degree arc turning the way it turns (right-handed about it) with a head.
void torque_arrow(OverlayList& out, const Vec3& c, const Vec3& vec, double radius, double arc_radius,
                  const Rgba& color, float xray) {
  const double len = vec.norm();
  if (!(len > 0.1 * radius) || !std::isfinite(len)) return;
  const Vec3 d = vec / len;
  out.arrow(c, vec, radius, color, xray);
  const double head = std::min(6 * radius, 0.4 * len);
  if (len > 2.5 * head)
    out.cone(c + vec - head * d, -head * d, 2.5 * radius, color, xray);  // the second head
  Vec3 e1, e2;
  orthonormal_basis(d, e1, e2);
  const Vec3 m = c + 0.45 * vec;
  const int n = 18;
  const double span = 1.5 * M_PI;
  Vec3 prev = m + arc_radius * e1;
  for (int k = 1; k <= n; ++k) {
    const double th = span * k / n;
    const Vec3 p = m + arc_radius * (std::cos(th) * e1 + std::sin(th) * e2);
    out.rod(prev, p, 0.8 * radius, color, xray);
    prev = p;
  }
  const Vec3 t = -std::sin(span) * e1 + std::cos(span) * e2;  // the direction of turning at the end
  const double h = std::min(5 * radius, 0.6 * arc_radius);
  out.cone(prev + h * t, -h * t, 2.2 * radius, color, xray);
}

}  // namespace

void visit_forces(const World& w, ForceVisitor& v) {
  if (!w.has_forces()) return;
  const double t = w.time();
  const MotionState* st = &w.impl().state(0);
  const BodyModel* mo = &w.impl().model(0);
  struct Sink {
    ForceVisitor& v;
    const MotionState* st;
    ForceKind kind;
    void force(int i, const Vec3& F, const Vec3& at) { v.force(i, F, at, kind); }
    void central(int i, const Vec3& F) { v.force(i, F, st[i].x_W, kind); }
    void torque(int i, const Vec3& tau) { v.torque(i, tau); }
  };
  for (const ForceDef& f : w.config().forces) {
    if (is_impulse(f.kind)) continue;
    if (!(f.from <= t && t < f.to)) continue;
    Sink s{v, st, f.kind};
    evaluate_force(f, 1.0, st, mo, s);
  }
}

void SceneOverlays::build_forces(const Item& it, const World& w, const CameraView& cam, OverlayList& out) {
  const int i = it.body;
  const ShowItem& s = it.spec;
  const Rgba color = item_color(s);
  const float xray = (float)s.xray;
  const Vec3 c = w.centroid(i);
  const double R = body_radius_[i];
  const double px = pixel_size_at(cam, height_, std::max((c - cam.eye).norm(), 1e-3));
  const double radius = std::max(it.radius, min_arrow_radius(px) * s.width);
  if (s.arrows) {
    struct Draw : ForceVisitor {
      OverlayList& out;
      const Item& it;
      Rgba color, drag_color;
      double radius, R;
      float xray;
      Draw(OverlayList& o, const Item& i) : out(o), it(i) {}
      void force(int b, const Vec3& F, const Vec3& at, ForceKind kind) override {
        if (b != it.body || !(it.scale > 0)) return;
        const Vec3 v = F * it.scale;
        out.arrow(it.spec.at_tip ? Vec3(at - v) : at, v, radius, kind == ForceKind::drag ? drag_color : color,
                  xray);
      }
      void torque(int b, const Vec3& tau) override {
        if (b != it.body || !(it.torque_scale > 0)) return;
        torque_arrow(out, out_c, tau * it.torque_scale, radius, 0.45 * R, color, xray);
      }
      Vec3 out_c;
    } d(out, it);
    d.color = color;
    d.drag_color = okabe_ito(2, (float)s.opacity);  // sky blue
    d.radius = radius;
    d.R = R;
    d.xray = xray;
    d.out_c = c;
    visit_forces(w, d);
    if (s.gravity && it.scale > 0) {
      const Vec3 v = w.mass(i) * w.config().gravity * it.scale;
      out.arrow(s.at_tip ? Vec3(c - v) : c, v, radius, okabe_ito(0, (float)s.opacity), xray);
    }
  }
  if (!s.springs) return;
  // Springs: a zig-zag between the two ends, facing the camera, drawn once (by the first end's
  // item, or by the second's when the first body shows no forces).
  for (const ForceDef& f : w.config().forces) {
    if (f.kind != ForceKind::spring) continue;
    if (!(f.body == i || (f.body_b == i && !shows_forces_[f.body]))) continue;
    const double t = w.time();
    if (!(f.from <= t && t < f.to)) continue;
    const Vec3 pa = f.at_centroid ? w.centroid(f.body) : w.local_to_world(f.body, f.at_B);
    const Vec3 pb = f.body_b < 0
                        ? f.anchor_W
                        : (f.at_b_centroid ? w.centroid(f.body_b) : w.local_to_world(f.body_b, f.at_b_B));
    const Vec3 ab = pb - pa;
    const double L = ab.norm();
    if (!(L > 0)) continue;
    const Vec3 u = ab / L, mid = 0.5 * (pa + pb);
    Vec3 side = u.cross(cam.eye - mid);
    if (!(side.norm() > 1e-12)) continue;
    side.normalize();
    const double amp = std::max(0.05 * f.rest_length, 0.25 * body_radius_[f.body]);
    const double lead = 0.1 * L;
    const int zigs = 14;
    spring_points_.clear();
    spring_colors_.clear();
    spring_points_.push_back(pa);
    if (!s.spring_lines) {  // `springs: line` draws the straight line from end to end
      spring_points_.push_back(pa + lead * u);
      for (int k = 0; k < zigs; ++k)
        spring_points_.push_back(pa + (lead + (k + 0.5) * (L - 2 * lead) / zigs) * u +
                                 ((k % 2) ? -amp : amp) * side);
      spring_points_.push_back(pb - lead * u);
    }
    spring_points_.push_back(pb);
    const Rgba grey{0.06f, 0.06f, 0.07f, (float)s.opacity};
    spring_colors_.assign(2, grey);
    const double width = std::max(1.5, (s.spring_lines ? 1.5 : 2.5) * s.width * height_ / 720.0) *
                         pixel_size_at(cam, height_, std::max((mid - cam.eye).norm(), 1e-3));
    // Segment by segment: a ribbon through the sharp corners would narrow where it turns.
    for (size_t k = 0; k + 1 < spring_points_.size(); ++k)
      out.ribbon(&spring_points_[k], spring_colors_.data(), 2, cam.eye, width);
  }
}

void SceneOverlays::build_contacts(const Item& it, const World& w, const CameraView& cam, OverlayList& out) {
  const int i = it.body;
  const ShowItem& s = it.spec;
  const Rgba color = item_color(s);
  const float xray = (float)s.xray;
  const double R = body_radius_[i];
  const double px = pixel_size_at(cam, height_, std::max((w.centroid(i) - cam.eye).norm(), 1e-3));
  const double radius = std::max(it.radius, min_arrow_radius(px) * s.width);
  const double dot = std::max(0.045 * R, 2.0 * px), normal = 0.4 * R;
  const Rgba ink = okabe_ito(0, (float)s.opacity);
  visit_contacts(w, i, [&](const Vec3& p, const Vec3& n, const Vec3& F) {
    if (s.points) out.ellipsoid(p, Mat3::Identity(), Vec3::Constant(dot), ink, xray);
    if (s.normals) out.rod(p, p + normal * n, std::max(0.35 * radius, 0.5 * px), ink, xray);
    if (s.arrows && it.scale > 0) out.arrow(p, F * it.scale, radius, color, xray);
  });
}

// The force and torque the parent exerts on the child through the joint (World::joint_reaction),
// at the anchor: the force as an arrow from it, the torque as `forces` draws torques.
void SceneOverlays::build_joint_forces(const Item& it, const World& w, const CameraView& cam,
                                       OverlayList& out) {
  const JointLook& L = joints_[it.joint];
  const ShowItem& s = it.spec;
  if (!(it.scale > 0) && !(it.torque_scale > 0)) return;
  const Rgba color = item_color(s);
  const float xray = (float)s.xray;
  const Vec3 p = w.local_to_world(L.child, L.anchor_C);
  const double px = pixel_size_at(cam, height_, std::max((p - cam.eye).norm(), 1e-3));
  const double radius = std::max(it.radius, min_arrow_radius(px) * s.width);
  Vec3 F, tau;
  w.joint_reaction(L.index, F, tau);
  if (it.scale > 0) out.arrow(p, F * it.scale, radius, color, xray);
  if (it.torque_scale > 0)
    torque_arrow(out, p, tau * it.torque_scale, radius, 0.45 * body_radius_[L.child], color, xray);
}

}  // namespace simreel
