#include "render/draw_list.hpp"

#include <Eigen/Geometry>

namespace simreel {

SceneMeshes::SceneMeshes(const World& w, const SceneStyles& styles) {
  mesh_of.resize(w.body_count());
  for (int i = 0; i < w.body_count(); ++i) {
    const std::vector<Collider>& cols = w.def(i).colliders;
    for (size_t k = 0; k < cols.size(); ++k) {
      const ColliderStyle st =
          (size_t)i < styles.size() && k < styles[i].size() ? styles[i][k] : ColliderStyle{};
      if (!st.drawn) {
        mesh_of[i].push_back(-1);
        continue;
      }
      mesh_of[i].push_back((int)meshes.size());
      meshes.push_back(tessellate_collider(cols[k], st.plane_size, st.normals));
      colors.push_back(st.color);
    }
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
      const int mesh = sm.mesh_of[i][k];
      if (mesh < 0) continue;
      const Collider& c = d.colliders[k];
      Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
      T_BC.linear() = c.q_BC.toRotationMatrix();
      T_BC.translation() = c.p_BC;
      const Eigen::Isometry3d T = T_WB * T_BC;
      DrawItem it;
      it.mesh = mesh;
      it.model = T.matrix().cast<float>();
      it.color = sm.colors[mesh];
      out.items.push_back(it);
      const double r = sm.meshes[it.mesh].radius;
      lo = lo.cwiseMin(T.translation() - Vec3::Constant(r));
      hi = hi.cwiseMax(T.translation() + Vec3::Constant(r));
    }
  }
  if (out.items.empty()) lo = hi = Vec3::Zero();  // nothing drawn (a ground alone)
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
