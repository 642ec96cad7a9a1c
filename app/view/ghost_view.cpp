#include "app/view/ghost_view.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include <simreel/error.hpp>

namespace simreel {

GhostView::GhostView(const Scene& scene, const World& world) {
  for (int i = 0; i < world.body_count() && i < (int)scene.looks.size(); ++i) {
    const GhostSpec& g = scene.looks[i].ghost;
    if (!g.on) continue;
    try {
      // Default colour: the body's, lightened halfway to white.
      const std::array<float, 3> c = g.color ? *g.color : lightened(scene.looks[i].color);
      ghosts_.push_back({i, ghost_motion(world, i),
                         world.principal_orientation(i).conjugate() * world.orientation(i),
                         Rgba{c[0], c[1], c[2], (float)g.opacity}, g.offset});
    } catch (const std::domain_error& e) {
      throw InputError(scene.path + ": bodies[" + std::to_string(i) + "].ghost: body '" + world.def(i).name +
                       "' has no closed-form motion to draw: " + e.what());
    }
  }
}

void draw_body_copy(const World& w, const SceneMeshes& meshes, int body, const Vec3& x, const Quat& q_WB,
                    const Rgba& color, double inflate, DrawList& dl) {
  const Vec3 eye = dl.camera.eye;
  const Mat3 R_WB = q_WB.toRotationMatrix();
  const Vec3 c_B = w.local_centroid(body);
  const BodyDef& d = w.def(body);
  for (size_t k = 0; k < d.colliders.size(); ++k) {
    const int m = meshes.mesh_of[body][k];
    if (m < 0) continue;
    const RenderMesh& rm = meshes.meshes[m];
    const Collider& c = d.colliders[k];
    // Collider vertex p_C -> world: x + s R_WB (p_BC + R_BC p_C - c_B), grown by s about the centre.
    const Mat3 R = R_WB * c.q_BC.toRotationMatrix();
    const Vec3 o = R_WB * (c.p_BC - c_B);
    const double s = inflate;
    const float* v = rm.vertices.data();
    for (size_t f = 0; f + 2 < rm.indices.size(); f += 3) {
      Vec3 p[3], n[3];
      for (int j = 0; j < 3; ++j) {
        const float* a = v + 6 * rm.indices[f + j];
        p[j] = x + s * (o + R * Vec3(a[0], a[1], a[2]));
        n[j] = R * Vec3(a[3], a[4], a[5]);
      }
      // Front faces only (a solid's far side would double the copy's density), unless the mesh is
      // drawn two-sided.
      const Vec3 face = (p[1] - p[0]).cross(p[2] - p[0]);
      if (!rm.two_sided && face.dot(eye - p[0]) <= 0) continue;
      for (int j = 0; j < 3; ++j) {
        const Vec3 view = (eye - p[j]).normalized();
        const double lit = 0.5 + 0.5 * std::fabs(n[j].normalized().dot(view));
        OverlayVertex ov;
        for (int q = 0; q < 3; ++q) ov.pos[q] = (float)p[j][q];
        for (int q = 0; q < 3; ++q) ov.rgba[q] = (float)(color[q] * lit);
        ov.rgba[3] = color[3];
        dl.overlay.ribbons.push_back(ov);
      }
    }
  }
}

void GhostView::build(const World& w, const SceneMeshes& meshes, DrawList& dl) const {
  const double t = w.time();
  for (const Ghost& g : ghosts_) {
    const Quat q_WB = g.motion.orientation(t) * g.q_PB;
    const Vec3 x = g.motion.position(t) + g.offset;  // centre of mass, drawn
    draw_body_copy(w, meshes, g.body, x, q_WB, g.color, kGhostInflate, dl);
  }
}

}  // namespace simreel
