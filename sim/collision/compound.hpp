// Compound bodies in the broad phase (Jolt's StaticCompoundShape, Bullet's btCompoundShape): a body
// with many colliding shapes enters the broad phase once, as a box around all of them, and keeps a
// tree of its shapes' boxes in its own principal frame, built once (the shapes never move within
// the body). A compound that touches nothing costs one box a step whatever its shape count: a body
// of 16,000 boxes falling freely paid 1.5 ms a step for 16,000 world boxes and fat-box updates.
//
// Where a compound's box overlaps another box, its tree is walked with each node's box mapped to
// the world (the box around the rotated node box, grown by the body's margin this step), and only
// the shapes reached get world boxes of their own. The mapped box of a shape holds the shape's
// tight world box grown by the shape's own margin (the tight box lies in the box around the
// rotated local box, and the body's margin is the largest of its shapes'), so the walk finds every
// shape whose box this step overlaps the query: a compound changes which boxes the broad phase
// keeps, never the pairs it reports.
#pragma once
#include <vector>

#include "sim/collision/body_extents.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/geometry/bvh.hpp"

namespace simreel {

class CompoundProxies {
 public:
  // Makes a compound of every body with at least `min_shapes` shapes in `sweep` (the non-plane
  // colliding shapes); min_shapes < 2: none.
  void build(const ShapeTable& st, const BodyExtents& ext, const std::vector<int>& sweep, int min_shapes,
             int bodies);
  int count() const { return (int)compounds_.size(); }
  int of_body(int b) const { return body_compound_.empty() ? -1 : body_compound_[b]; }  ///< -1: none
  int of_shape(int k) const { return shape_compound_.empty() ? -1 : shape_compound_[k]; }
  int body(int c) const { return compounds_[c].body; }
  const std::vector<int>& members(int c) const { return compounds_[c].members; }  ///< ascending

  // Compound c's frame this step: its body's pose (R_WP, x_W), speeds |v| (m/s) and |w| (rad/s)
  // and the step's speculative distance (m) and dt (s). Returns its world box: the tree's root
  // mapped to the world, grown by the body's margin spec + (|v| + reach |w|) dt.
  Aabb place(int c, const Mat3& R_WP, const Vec3& x_W, double v, double w, double spec, double dt);
  // m, what a shape's box margin was at the last place (spec + (|v| + reach_k |w|) dt, as the
  // world computes it for a shape of its own): shape k of compound c, whose reach is `reach`.
  double member_margin(int c, double reach) const {
    const Compound& q = compounds_[c];
    return box_margin(q.spec, q.v, reach, q.w, q.dt);
  }

  // f(shape) for every shape of compound c whose mapped box overlaps `box`: every shape whose box
  // of the last place (within its margin of the shape) does, and perhaps a few more.
  template <typename F>
  void query(int c, const Aabb& box, F&& f) const;
  // f(shape) for every shape of compound c whose mapped box reaches the side n . x <= d of a
  // plane (n unit, world).
  template <typename F>
  void query_plane(int c, const Vec3& n, double d, F&& f) const;

 private:
  struct Compound {
    int body = -1;
    std::vector<int> members;
    Bvh tree;  ///< over the members' boxes in the body's principal frame (items: index in members)
    // The last place: rotation, its entries' magnitudes, position, and how far mapped boxes grow
    // (the margin and a round-off allowance).
    Mat3 R = Mat3::Identity(), A = Mat3::Identity();
    Vec3 x = Vec3::Zero();
    double grow = 0, reach = 0;  ///< m
    double v = 0, w = 0, spec = 0, dt = 0;
  };
  // The mapped box of a local box [lo, hi] at the compound's last place.
  static void map(const Compound& q, const Vec3& lo, const Vec3& hi, Vec3& c, Vec3& e) {
    const Vec3 lc = 0.5 * (lo + hi), le = 0.5 * (hi - lo);
    c = q.R * lc + q.x;
    e = q.A * le + Vec3::Constant(q.grow);
  }
  std::vector<Compound> compounds_;
  std::vector<int> body_compound_, shape_compound_;
};

template <typename F>
void CompoundProxies::query(int c, const Aabb& box, F&& f) const {
  const Compound& q = compounds_[c];
  const Vec3 bc = 0.5 * (box.lo + box.hi), be = 0.5 * (box.hi - box.lo);
  q.tree.query_if(
      [&](const Vec3& lo, const Vec3& hi) {
        Vec3 mc, me;
        map(q, lo, hi, mc, me);
        return ((mc - bc).cwiseAbs().array() <= (me + be).array()).all();
      },
      [&](int item) { f(q.members[item]); });
}

template <typename F>
void CompoundProxies::query_plane(int c, const Vec3& n, double d, F&& f) const {
  const Compound& q = compounds_[c];
  const Vec3 an = n.cwiseAbs();
  q.tree.query_if(
      [&](const Vec3& lo, const Vec3& hi) {
        Vec3 mc, me;
        map(q, lo, hi, mc, me);
        return n.dot(mc) - me.dot(an) <= d;
      },
      [&](int item) { f(q.members[item]); });
}

}  // namespace simreel
