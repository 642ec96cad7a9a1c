#include "sim/collision/compound.hpp"

#include <algorithm>
#include <cmath>

namespace simreel {

void CompoundProxies::build(const ShapeTable& st, const BodyExtents& ext, const std::vector<int>& sweep,
                            int min_shapes, int bodies) {
  compounds_.clear();
  body_compound_.assign(bodies, -1);
  shape_compound_.assign(st.size(), -1);
  if (min_shapes < 2) return;
  std::vector<int> count(bodies, 0);
  for (int k : sweep) ++count[st[k].body];
  for (int b = 0; b < bodies; ++b) {
    if (count[b] < min_shapes) continue;
    body_compound_[b] = (int)compounds_.size();
    compounds_.emplace_back();
    compounds_.back().body = b;
  }
  for (int k : sweep) {
    const int c = body_compound_[st[k].body];
    if (c < 0) continue;
    compounds_[c].members.push_back(k);
    shape_compound_[k] = c;
  }
  std::vector<Vec3> lo, hi;
  for (Compound& q : compounds_) {
    std::sort(q.members.begin(), q.members.end());
    lo.clear();
    hi.clear();
    for (int k : q.members) {
      const ShapeRecord& r = st[k];
      Pose local;
      local.R = r.R_PC;
      local.p = r.p_PC;
      const Aabb b = ShapeTable::bounds(r.geom, local);
      lo.push_back(b.lo);
      hi.push_back(b.hi);
      q.reach = std::max(q.reach, ext.shape_reach[k]);
    }
    q.tree.build(lo, hi);
  }
}

Aabb CompoundProxies::place(int c, const Mat3& R_WP, const Vec3& x_W, double v, double w, double spec,
                            double dt) {
  Compound& q = compounds_[c];
  q.R = R_WP;
  q.A = R_WP.cwiseAbs();
  q.x = x_W;
  q.v = v, q.w = w, q.spec = spec, q.dt = dt;
  // The margin of the body's farthest-reaching shape, and an allowance for the round-off between a
  // shape's world box (made from its own world pose) and its mapped local box: both are within a
  // few ulps of |x| + reach, so 1e-9 of that is ample and costs nothing measurable.
  q.grow = box_margin(spec, v, q.reach, w, dt) + 1e-9 * (1.0 + x_W.cwiseAbs().maxCoeff() + q.reach);
  const Bvh::Node& root = q.tree.nodes().front();
  Vec3 mc, me;
  map(q, root.lo, root.hi, mc, me);
  return Aabb{mc - me, mc + me};
}

}  // namespace simreel
