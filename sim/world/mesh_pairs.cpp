// The contact set's narrow phase for pairs with a static triangle mesh (sim/collision/narrow/mesh.hpp):
// one Contact record per manifold, several per pair, consecutive in contacts_ or resting_ (same key).
// Each new manifold is warm-started from last step's record of the pair whose normal is closest to its
// own (within kMatchCos), each record used once; points by feature id as for every pair.
#include <algorithm>
#include <cmath>

#include "sim/base/pair_key.hpp"
#include "sim/collision/narrow/mesh.hpp"
#include "sim/dynamics/integrators.hpp"
#include "sim/world/contact_set.hpp"

namespace simreel {

namespace {
constexpr double kMatchCos = 0.9;  // ~26 degrees
}

int ContactSet::collide_mesh_pair(const Step& in, const CollideJob& job, Contact* out, int& points,
                                  double& deepest) const {
  const ShapeTable& st = *in.shapes;
  const int a = pair_first(job.key), b = pair_second(job.key);
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const MotionState& sa = in.state[A.body];
  const MotionState& sb = in.state[B.body];
  const bool mesh_is_a = A.geom.kind == CollideKind::mesh;
  const int convex = mesh_is_a ? b : a;
  const ShapeRecord& M = mesh_is_a ? A : B;
  const ShapeRecord& C = mesh_is_a ? B : A;
  const Pose xm = ShapeTable::world_pose(M, in.state[M.body]);
  const Pose xc = in.pose(convex, C);
  const double reach_a = in.extents->shape_reach[a] * sa.w_P.norm();
  const double reach_b = in.extents->shape_reach[b] * sb.w_P.norm();
  const double closing = ((sa.v_W - sb.v_W).norm() + reach_a + reach_b) * in.dt;
  const double spec = in.speculative_distance + closing;
  Manifold m[kMaxMeshManifolds];
  Vec3 offset[kMaxMeshManifolds][4];  // mesh to shape: the shape's anchor minus the mesh's, across the normal
  // A fast pair's speculative manifolds are taken where it will touch (collide_mesh_ahead).
  int nm = fast_pair(in, a, b, closing)
               ? collide_mesh_ahead(in, convex, mesh_is_a ? a : b, in.speculative_distance, m, offset)
               : -1;
  if (nm < 0) {
    // The convex shape's box as the broad phase grew it (this step's motion and the speculative
    // distance), so every triangle it can reach this step is queried.
    const Aabb& box = in.boxes[convex];
    nm = collide_mesh(M.geom, xm, C.geom, xc, box.lo, box.hi, spec, m);
    for (int i = 0; i < nm; ++i)
      for (int j = 0; j < 4; ++j) offset[i][j].setZero();
  }
  const Contact* old = prev_record(job);
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
    new_contact(st, c, a, b, prev);
    c.normal_W = n_AB;
    c.count = m[i].count;
    for (int j = 0; j < c.count; ++j) {
      ContactPoint& p = c.points[j];
      p.id = m[i].points[j].id;
      p.p_W = m[i].points[j].p_W;
      p.separation = m[i].points[j].separation;
      p.offset_W = mesh_is_a ? offset[i][j] : Vec3(-offset[i][j]);
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

// A fast pair's speculative manifolds, taken where it will touch (as collide_ahead does for two
// convex shapes, sim/world/continuous.cpp): the convex shape c's motion over the step is predicted from its
// velocity (and gravity), swept against the mesh m's triangles to the time it comes within half the
// speculative distance of one (mesh_toi), the manifolds are made there (every triangle within twice
// that distance: the hit one and its neighbours), and the shape's points are carried back to the
// step's start with its body, the mesh's staying where they are; offset: the shape's anchor minus
// the mesh's across the normal (the sliding until the impact). Returns the manifolds, 0 if the
// prediction comes nowhere near the mesh, -1 if a triangle is that close already (then collide as
// usual).
int ContactSet::collide_mesh_ahead(const Step& in, int c, int mi, double speculative, Manifold out[],
                                   Vec3 offset[][4]) {
  if (!(speculative > 0)) return -1;
  const ShapeTable& st = *in.shapes;
  const ShapeRecord& C = st[c];
  const ShapeRecord& M = st[mi];
  const MotionState& s = in.state[C.body];
  const double dt = in.dt;
  Vec3 x1 = s.x_W + dt * s.v_W;
  if (in.model[C.body].inv_mass > 0) x1 += (0.5 * dt * dt) * in.gravity;
  const Quat q1 = (rotation_increment(s.q_WP * s.w_P, dt) * s.q_WP).normalized();
  const Sweep sw = make_sweep(s.x_W, s.q_WP, x1, q1);
  // The shape's box over the prediction (grown by how far a rotation's arc strays from its chord).
  Aabb box = ShapeTable::bounds(C.geom, shape_pose(C, sw.x0, sw.q0));
  const Aabb end = ShapeTable::bounds(C.geom, shape_pose(C, x1, q1));
  const double arc = in.extents->sweep_reach(c) * (1.0 - std::cos(0.5 * sw.angle));
  box.lo = box.lo.cwiseMin(end.lo) - Vec3::Constant(arc);
  box.hi = box.hi.cwiseMax(end.hi) + Vec3::Constant(arc);
  const double t = ContinuousCollision::mesh_toi(st, *in.extents, in.state, c, mi, sw, box, 0.5 * speculative,
                                                 0.25 * speculative, false);
  if (t < 0) return -1;
  if (t >= 1) return 0;
  const Vec3 xt = sw.x_at(t);
  const Quat qt = sw.q_at(t);
  const Pose xc = shape_pose(C, xt, qt);
  const Aabb bt = ShapeTable::bounds(C.geom, xc);
  const Vec3 grow = Vec3::Constant(2.0 * speculative);
  const int nm = collide_mesh(M.geom, ShapeTable::world_pose(M, in.state[M.body]), C.geom, xc, bt.lo - grow,
                              bt.hi + grow, 2.0 * speculative, out);
  const Mat3 R0 = sw.q0.toRotationMatrix(), Rt = qt.toRotationMatrix();
  for (int i = 0; i < nm; ++i) {
    const Vec3& n = out[i].normal_W;  // mesh to shape
    for (int j = 0; j < out[i].count; ++j) {
      ManifoldPoint& p = out[i].points[j];
      const Vec3 pM = p.p_W - (0.5 * p.separation) * n;
      const Vec3 pC = sw.x0 + R0 * (Rt.transpose() * (p.p_W + (0.5 * p.separation) * n - xt));
      p.separation = n.dot(pC - pM);
      p.p_W = 0.5 * (pM + pC);
      offset[i][j] = (pC - pM) - p.separation * n;
    }
  }
  return nm;
}

}  // namespace simreel
