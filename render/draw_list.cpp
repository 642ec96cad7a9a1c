#include "render/draw_list.hpp"

#include <Eigen/Geometry>

namespace simreel {

SceneMeshes::SceneMeshes(const World& w) {
  for (int i = 0; i < w.body_count(); ++i) {
    first_mesh.push_back((int)meshes.size());
    for (const Collider& c : w.def(i).colliders) meshes.push_back(tessellate_collider(c));
  }
}

void build_draw_list(const World& w, const SceneMeshes& sm, const CameraView& cam, int follow,
                     DrawList& out) {
  out.items.clear();
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (int i = 0; i < w.body_count(); ++i) {
    Eigen::Isometry3d T_WB = Eigen::Isometry3d::Identity();
    T_WB.linear() = w.rotation(i);
    T_WB.translation() = w.origin_position(i);
    const BodyDef& d = w.def(i);
    for (size_t k = 0; k < d.colliders.size(); ++k) {
      const Collider& c = d.colliders[k];
      Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
      T_BC.linear() = c.q_BC.toRotationMatrix();
      T_BC.translation() = c.p_BC;
      const Eigen::Isometry3d T = T_WB * T_BC;
      DrawItem it;
      it.mesh = sm.first_mesh[i] + (int)k;
      it.model = T.matrix().cast<float>();
      it.color = c.color ? *c.color : d.color;
      out.items.push_back(it);
      const double r = sm.meshes[it.mesh].radius;
      lo = lo.cwiseMin(T.translation() - Vec3::Constant(r));
      hi = hi.cwiseMax(T.translation() + Vec3::Constant(r));
    }
  }
  out.bounds_center = 0.5 * (lo + hi);
  out.bounds_radius = std::max(0.5 * (hi - lo).norm(), 1e-3);
  out.camera = cam;
  if (follow >= 0) {
    const Vec3 c = w.centroid(follow);
    out.camera.eye = cam.eye + (c - cam.target);
    out.camera.target = c;
  }
}

}  // namespace simreel
