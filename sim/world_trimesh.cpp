// World's narrow phase for pairs with a static triangle mesh (sim/collide/mesh.hpp): one Contact
// record per manifold, several per pair, consecutive in contacts_ (same key). Each new manifold is
// warm-started from last step's record of the pair whose normal is closest to its own (within
// kMatchCos), each record used once; points by feature id as for every pair.
#include <algorithm>
#include <cmath>

#include "sim/collide/mesh.hpp"
#include "sim/world.hpp"

namespace simreel {

namespace {
constexpr double kMatchCos = 0.9;  // ~26 degrees
}

int World::collide_mesh_pair(const CollideJob& job, Contact* out, int& points, double& deepest) const {
  const ShapeTable& st = *shapes_;
  const int a = (int)(job.key >> 32), b = (int)(job.key & 0xFFFFFFFFu);
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const MotionState& sa = state_[A.body];
  const MotionState& sb = state_[B.body];
  const bool mesh_is_a = A.geom.kind == CollideKind::mesh;
  const int convex = mesh_is_a ? b : a;
  const ShapeRecord& M = mesh_is_a ? A : B;
  const ShapeRecord& C = mesh_is_a ? B : A;
  const Pose xm = ShapeTable::world_pose(M, state_[M.body]);
  const Pose xc = shape_moving_[convex] ? poses_[convex] : ShapeTable::world_pose(C, state_[C.body]);
  const double reach_a = (A.p_PC.norm() + A.geom.bounding_radius) * sa.w_P.norm();
  const double reach_b = (B.p_PC.norm() + B.geom.bounding_radius) * sb.w_P.norm();
  const double closing = ((sa.v_W - sb.v_W).norm() + reach_a + reach_b) * cfg_.dt;
  const double spec = cfg_.contacts.speculative_distance + closing;
  // The convex shape's box as the broad phase grew it (this step's motion and the speculative
  // distance), so every triangle it can reach this step is queried.
  const Aabb& box = boxes_[convex];
  Manifold m[kMaxMeshManifolds];
  const int nm = collide_mesh(M.geom, xm, C.geom, xc, box.lo, box.hi, spec, m);
  const Contact* old = job.prev >= 0 ? &contacts_[job.prev] : nullptr;
  const int old_count = job.prev_count;
  bool used[kMaxMeshManifolds * 4] = {};
  points = 0;
  deepest = 0;
  for (int i = 0; i < nm; ++i) {
    const Vec3 n_AB = mesh_is_a ? m[i].normal_W : Vec3(-m[i].normal_W);
    const Contact* prev = nullptr;
    double best = kMatchCos;
    for (int k = 0; k < old_count && k < (int)sizeof used; ++k) {
      const double d = old[k].normal_W.dot(n_AB);
      if (!used[k] && d > best) best = d, prev = &old[k];
    }
    if (prev) used[prev - old] = true;
    Contact& c = out[i];
    new_contact(c, a, b, prev);
    c.normal_W = n_AB;
    c.count = m[i].count;
    for (int j = 0; j < c.count; ++j) {
      ContactPoint& p = c.points[j];
      p.id = m[i].points[j].id;
      p.p_W = m[i].points[j].p_W;
      p.separation = m[i].points[j].separation;
      if (prev)
        for (int k = 0; k < prev->count; ++k)
          if (prev->points[k].id == p.id) {
            p.normal_impulse = prev->points[k].normal_impulse;
            break;
          }
      deepest = std::max(deepest, -p.separation);
    }
    points += c.count;
  }
  return nm;
}

}  // namespace simreel
