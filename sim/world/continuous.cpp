// Stage "continuous": no tunnelling (docs/continuous-collision.md). After the step has
// moved every body (contact solver, free-flight integrators, kinematic bodies), each dynamic body
// that moved more than half its smallest width, or is flagged `bullet` and moved at all, is swept
// from its pose at the step's start to its pose now, against every shape its swept box meets
// (static, kinematic and dynamic bodies alike, the others swept over their own step's motion),
// and moved back to its earliest time of impact, keeping its velocity. The next step's speculative
// contact (found because the broad phase grows boxes by the velocity) then stops it at the
// surface. Box2D v3 and Box3D do this for dynamic bodies against static ones and bullets against
// dynamic ones, each against the others' end poses; here both sides move, so two fast dynamic
// bodies crossing each other are caught too (where Rapier tunnels: dimforge/rapier#984).
//
// Deterministic and independent of order: every time of impact is computed from the same sweeps
// (none moves a body until all are known), and each body then goes to the minimum of its own.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/base/pair_key.hpp"
#include "sim/collision/narrow/manifold.hpp"
#include "sim/dynamics/integrators.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {

namespace {
constexpr double kInfWidth = std::numeric_limits<double>::infinity();
}  // namespace

void WorldImpl::init_continuous() {
  ccd_.init(collide_enabled_ && cfg_.contacts.continuous, defs_, dynamic_, kinematic_, state_, *shapes_,
            sweep_shapes_, shape_moving_);
}

void ContinuousCollision::init(bool enabled, const std::vector<BodyDef>& defs,
                               const std::vector<int>& dynamic, const std::vector<int>& kinematic,
                               const std::vector<MotionState>& state, const ShapeTable& st,
                               const std::vector<int>& sweep_shapes, const std::vector<char>& shape_moving) {
  enabled_ = enabled;
  if (!enabled_) return;
  const int n = (int)defs.size();
  shape_swept_.assign(st.size(), 0);
  bullet_.assign(n, 0);
  for (int i : dynamic) bullet_[i] = defs[i].bullet;
  movers_ = dynamic;
  movers_.insert(movers_.end(), kinematic.begin(), kinematic.end());
  std::sort(movers_.begin(), movers_.end());
  x0_.assign(n, Vec3::Zero());
  q0_.assign(n, Quat::Identity());
  for (int i = 0; i < n; ++i) x0_[i] = state[i].x_W, q0_[i] = state[i].q_WP;
  toi_.assign(n, 1.0);
  sweeps_.assign(n, Sweep{});
  for (int i = 0; i < n; ++i) sweeps_[i] = make_sweep(x0_[i], q0_[i], x0_[i], q0_[i]);
  swept_boxes_.assign(st.size(), Aabb{});
  for (int k : sweep_shapes)
    if (!shape_moving[k])
      swept_boxes_[k] = ShapeTable::bounds(st[k].geom, ShapeTable::world_pose(st[k], state[st[k].body]));
}

// The contact set's fast pairs (contact_set.hpp), the narrow phase's side of continuous collision.
// A fast pair (one of its shapes can close on the other by more than half its own smallest width
// this step, or a bullet is in it): collide_ahead instead of collide. `closing` (the broad phase's
// bound on how far the pair can close, about the bodies' centres) bounds the shapes' own relative
// motion, so slow pairs are turned away without more work.
bool ContactSet::fast_pair(const Step& in, int a, int b, double closing) {
  if (!in.ccd->enabled()) return false;
  const ShapeRecord& A = (*in.shapes)[a];
  const ShapeRecord& B = (*in.shapes)[b];
  const BodyExtents& ext = *in.extents;
  const double slop4 = 4 * in.linear_slop;
  if (!(ext.shape_width[a] > slop4) || !(ext.shape_width[b] > slop4)) return false;  // as in stage_continuous
  if (in.ccd->bullet(A.body) || in.ccd->bullet(B.body)) return true;
  const double limit = 0.5 * std::min(in.model[A.body].is_static ? kInfWidth : ext.shape_width[a],
                                      in.model[B.body].is_static ? kInfWidth : ext.shape_width[b]);
  if (closing <= limit) return false;
  // The shapes' own motion: their centres' relative velocity and their spin about their centres.
  auto centre_velocity = [&](const ShapeRecord& r, Vec3& w) {
    const MotionState& s = in.state[r.body];
    w = s.q_WP * s.w_P;
    return Vec3(s.v_W + w.cross(s.q_WP * r.p_PC));
  };
  Vec3 wa, wb;
  const Vec3 va = centre_velocity(A, wa), vb = centre_velocity(B, wb);
  const double own =
      ((va - vb).norm() + wa.norm() * A.geom.bounding_radius + wb.norm() * B.geom.bounding_radius) * in.dt;
  return own > limit;
}

// The speculative manifold of a fast pair, taken where the pair will touch rather than where it is.
// A manifold made at the step's start from the closest features (what collide does, with the
// speculative range grown by how far the pair can close) is the wrong one for a body that moves
// several of its sizes in a step: a sphere shot past a wall's edge at an angle gets the edge's
// diagonal normal, and the solver stops it against that plane instead of the face it will hit (a
// ghost collision: with restitution 0 it bounced off at 10 m/s, measured). Here each body's motion
// over the step is predicted from its velocity (and gravity), the pair is swept to the time it
// comes within half the speculative distance (time_of_impact.hpp), the manifold is made there, and its points
// are carried back to the step's start with their bodies (each anchor fixed in its body), so the
// solver's speculative constraint is the one of the surfaces that will touch. The two anchors of a
// point then differ across the normal by the pair's sliding until the impact: `offset` (the
// solver reads it into the anchors; ContactPoint::offset_W). A pair that never
// comes that close in the prediction has no points (the continuous stage after the solve catches
// what the prediction missed); a pair touching already is collided as usual.
int ContactSet::collide_ahead(const Step& step, int a, int b, const Pose& xa, const Pose& xb,
                              double speculative, double closing, PairCache& cache, Manifold& m,
                              Vec3 offset[4]) {
  const ShapeTable& st = *step.shapes;
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const double dt = step.dt;
  auto predict = [&](int i) {
    const MotionState& s = step.state[i];
    Vec3 x1 = s.x_W + dt * s.v_W;
    if (step.model[i].inv_mass > 0) x1 += (0.5 * dt * dt) * step.gravity;
    const Quat q1 = (rotation_increment(s.q_WP * s.w_P, dt) * s.q_WP).normalized();
    return make_sweep(s.x_W, s.q_WP, x1, q1);
  };
  const Sweep sa = predict(A.body), sb = predict(B.body);
  ToiInput in;
  in.a = &A.geom;
  in.R_PA = A.R_PC;
  in.p_PA = A.p_PC;
  in.sa = &sa;
  in.reach_a = step.extents->sweep_reach(a);
  in.b = &B.geom;
  in.R_PB = B.R_PC;
  in.p_PB = B.p_PC;
  in.sb = &sb;
  in.reach_b = step.extents->sweep_reach(b);
  in.target = 0.5 * speculative;
  in.tolerance = 0.25 * speculative;
  const ToiOutput out = time_of_impact(in);
  if (out.state == ToiOutput::touching || !(speculative > 0))
    return simreel::collide(A.geom, xa, B.geom, xb, speculative + closing, cache, m);
  m.count = 0;
  if (out.state == ToiOutput::separated) return 0;
  const double t = out.t;
  const Vec3 xA = sa.x_at(t), xB = sb.x_at(t);
  const Quat qA = sa.q_at(t), qB = sb.q_at(t);
  const int n = simreel::collide(A.geom, shape_pose(A, xA, qA), B.geom, shape_pose(B, xB, qB),
                                 2.0 * speculative, cache, m);
  // Back to the start: each surface point keeps its place in its body.
  const Mat3 RA0 = sa.q0.toRotationMatrix(), RB0 = sb.q0.toRotationMatrix();
  const Mat3 RAt = qA.toRotationMatrix(), RBt = qB.toRotationMatrix();
  const Vec3& nrm = m.normal_W;
  for (int j = 0; j < n; ++j) {
    ManifoldPoint& p = m.points[j];
    const Vec3 pA = sa.x0 + RA0 * (RAt.transpose() * (p.p_W - (0.5 * p.separation) * nrm - xA));
    const Vec3 pB = sb.x0 + RB0 * (RBt.transpose() * (p.p_W + (0.5 * p.separation) * nrm - xB));
    p.separation = nrm.dot(pB - pA);
    p.p_W = 0.5 * (pA + pB);
    offset[j] = (pB - pA) - p.separation * nrm;
  }
  return n;
}

// The earliest time of impact (fraction of the step; 1: none) of convex shape c on sweep s with the
// triangles of static mesh shape m whose boxes meet c's box over the sweep, `box`, grown by the
// target gap. guarded: stage_continuous's fallbacks for triangles touched at the start; else a
// triangle touched at the start gives -1 (collide_mesh_pair then collides as usual).
double ContinuousCollision::mesh_toi(const ShapeTable& st, const BodyExtents& extents,
                                     const MotionState* state, int c, int m, const Sweep& s, const Aabb& box,
                                     double target, double tolerance, bool guarded, int* triangle) {
  const ShapeRecord& C = st[c];
  const ShapeRecord& M = st[m];
  ToiInput in;
  in.a = &C.geom;
  in.R_PA = C.R_PC;
  in.p_PA = C.p_PC;
  in.sa = &s;
  in.reach_a = extents.sweep_reach(c);
  in.target = target;
  in.tolerance = tolerance;
  const Vec3 grow = Vec3::Constant(target + tolerance);
  const ToiOutput out = mesh_time_of_impact(in, M.geom, ShapeTable::world_pose(M, state[M.body]),
                                            box.lo - grow, box.hi + grow, guarded, triangle);
  if (out.state == ToiOutput::touching) return -1;
  return out.state == ToiOutput::hit ? out.t : 1.0;
}

template <class MayTouch>
bool ContinuousCollision::step(const Step& in, MayTouch&& may_touch) {
  MotionState* state = in.state;
  const BodyExtents& ext = *in.extents;
  // Which bodies are swept: a dynamic body one of whose shapes moved more than half its smallest
  // width (Box2D's and Box3D's rule, there per body: here a 20 um tip on a large top does not make
  // the whole top fast), or a bullet that moved at all. The body's farthest point bounds every
  // shape's motion, so most bodies are turned away by one test.
  fast_.clear();
  const ShapeTable& shapes = *in.shapes;
  if (sweepable_.empty()) {
    sweepable_.assign(x0_.size(), 0);
    for (int i : *in.dynamic) sweepable_[i] = 1;
    covered_.assign(shapes.size(), 1);
    box_stamp_.assign(shapes.size(), -1);
    sweep_stamp_.assign(x0_.size(), -1);
    moved_.assign(x0_.size(), 0);
    turned_.assign(x0_.size(), 0);
    // Per shape, what the coverage test below needs of it, so that it reads no shape's record
    // (among 100,000 falling boxes the stage took 66-70 ns a body-step reading them, 48 with this
    // and the broad phase's changes of the same run):
    // 0 not tested (a plane, or a static shape), 1 a mesh (never covered), 2 any other.
    cover_kind_.assign(shapes.size(), 0);
    for (int k = 0; k < shapes.size(); ++k)
      if ((*in.shape_moving)[k] && shapes[k].geom.kind != CollideKind::plane)
        cover_kind_[k] = shapes[k].geom.kind == CollideKind::mesh ? 1 : 2;
  }
  for (int i : *in.awake) {
    const MotionState& s = state[i];
    const Vec3 dx = s.x_W - x0_[i];
    const double c = std::min(1.0, std::fabs(q0_[i].dot(s.q_WP)));
    const double angle = 2.0 * std::acos(c);
    const double d = dx.norm();
    moved_[i] = d;
    turned_[i] = angle;
    if (!sweepable_[i]) continue;
    const double motion = d + angle * ext.swept_reach[i];
    if (!(motion > 0) || (!bullet_[i] && motion <= 0.5 * ext.width[i])) continue;
    bool any = false;
    const Mat3 R0 = q0_[i].toRotationMatrix(), R1 = s.q_WP.toRotationMatrix();
    for (int k = ext.shape_begin[i]; k < ext.shape_begin[i + 1]; ++k) {
      const ShapeRecord& r = shapes[k];
      // Planes and shapes that touch nothing are not swept; nor shapes narrower than four slops
      // (0.4 mm by default): the solver lets any contact sink a slop, so their centre is not
      // outside what they touch even at rest (a 20 um tip on a spinning top was pulled back
      // every step and the top stopped precessing).
      if (!(ext.shape_width[k] > 4 * in.linear_slop) || !std::isfinite(ext.shape_width[k])) continue;
      const double m = (dx + (R1 - R0) * r.p_PC).norm() + angle * r.geom.bounding_radius;
      shape_swept_[k] = bullet_[i] || m > 0.5 * ext.shape_width[k];
      any = any || shape_swept_[k];
    }
    if (any) fast_.push_back(i);
  }
  if (fast_.empty()) return false;
  ++run_;
  in.profile->swept_bodies += (long)fast_.size();
  const ShapeTable& st = shapes;
  // Which shapes stay inside their broad-phase boxes (the candidate pairs below). Every point of a
  // shape moves by at most |dx| + angle reach, and its box (an exact support box for every kind
  // that moves) by no more, so its swept box grown by the gap lies in its broad-phase box when that
  // plus the arc's bulge and the gap is within the box's margin (1 um spare for the two boxes'
  // round-off).
  const double target = std::max(in.linear_slop, 1e-5), tolerance = 0.25 * target;
  const double grow = target + tolerance;
  const std::vector<char>& moving = *in.shape_moving;
  const std::vector<double>& margins = *in.margins;
  escaped_.clear();
  for (int i : *in.awake) {
    const double d = moved_[i], angle = turned_[i], bulge = 1.0 - std::cos(0.5 * angle);
    for (int k = ext.shape_begin[i]; k < ext.shape_begin[i + 1]; ++k) {
      if (cover_kind_[k] == 0) continue;
      // (A compound's shapes have their margins made only where a pair needed them: the same
      // formula from the speeds its box was made with.)
      const int c = in.compounds->of_shape(k);
      const double margin = c < 0 ? margins[k] : in.compounds->member_margin(c, ext.shape_reach[k]);
      covered_[k] = cover_kind_[k] == 2 &&
                    d + angle * ext.shape_reach[k] + ext.sweep_reach(k) * bulge + grow + 1e-6 <= margin;
      if (!covered_[k]) escaped_.push_back(k);
    }
  }
  // A body's sweep over the step, and a shape's box over it (its boxes at the start and at the
  // end, grown by how far a rotation's arc strays from its chord: r (1 - cos(angle / 2))), made
  // once a run when first asked for: every awake mover's below, a resting one's only if a pair
  // needs it.
  auto sweep = [&](int b) -> const Sweep& {
    if (sweep_stamp_[b] != run_) {
      sweep_stamp_[b] = run_;
      sweeps_[b] = make_sweep(x0_[b], q0_[b], state[b].x_W, state[b].q_WP);
    }
    return sweeps_[b];
  };
  auto swept_box = [&](int k) -> const Aabb& {
    if (!moving[k] || box_stamp_[k] == run_) return swept_boxes_[k];  // static: set once by init
    box_stamp_[k] = run_;
    const ShapeRecord& r = st[k];
    const Sweep& s = sweep(r.body);
    Aabb b = ShapeTable::bounds(r.geom, shape_pose(r, s.x0, s.q0));
    if (s.moves) {
      const Aabb e = ShapeTable::bounds(r.geom, shape_pose(r, s.x0 + s.dx, s.q1));
      const double arc = ext.sweep_reach(k) * (1.0 - std::cos(0.5 * s.angle));
      b.lo = b.lo.cwiseMin(e.lo) - Vec3::Constant(arc);
      b.hi = b.hi.cwiseMax(e.hi) + Vec3::Constant(arc);
    }
    swept_boxes_[k] = b;
    return swept_boxes_[k];
  };
  auto meet = [grow](const Aabb& A, const Aabb& B) {
    return !(B.lo.x() > A.hi.x() + grow || A.lo.x() > B.hi.x() + grow || A.lo.y() > B.hi.y() + grow ||
             B.lo.y() > A.hi.y() + grow || A.lo.z() > B.hi.z() + grow || B.lo.z() > A.hi.z() + grow);
  };
  // Candidate pairs: the pairs with a swept shape whose swept boxes meet (within the gap), found
  // without looking at every shape. A shape whose swept box, grown by the gap, lies in its
  // broad-phase box of this step is covered: two covered shapes whose swept boxes meet have
  // overlapping broad-phase boxes, so their pair is among the broad phase's. A shape that left its
  // box (the solver or a force changed its velocity during the step) queries the broad phase's
  // tree, whose fat boxes hold every covered shape's swept box, and meets the other escapees
  // directly. Box2D v3 and Box3D query their trees per fast body the same way; a sort and sweep
  // over every swept box made 2.3 million box tests a step among 10,000 falling boxes.
  pairs_.clear();
  for (uint64_t key : *in.broad_pairs) {
    const int a = pair_first(key), b = pair_second(key);
    if (!shape_swept_[a] && !shape_swept_[b]) continue;
    if (st[a].geom.kind == CollideKind::plane || st[b].geom.kind == CollideKind::plane) continue;
    if (meet(swept_box(a), swept_box(b))) pairs_.push_back(key);
  }
  const int ns = st.size();
  for (int e : escaped_) {
    const Aabb& E = swept_box(e);
    const Aabb Q{E.lo - Vec3::Constant(grow), E.hi + Vec3::Constant(grow)};
    auto visit = [&](int k) {
      if (k == e || !covered_[k] || (!shape_swept_[e] && !shape_swept_[k])) return;
      const int lo = std::min(e, k), hi = std::max(e, k);
      if (meet(E, swept_box(k)) && may_touch(lo, hi)) pairs_.push_back(pair_key(lo, hi));
    };
    // A compound's tree holds its shapes' broad-phase boxes as the broad phase's tree does.
    in.broad->query(Q, [&](int k) {
      if (k < ns)
        visit(k);
      else
        in.compounds->query(k - ns, Q, visit);
    });
  }
  if (escaped_.size() > 1) {  // escapees with each other: a sort and sweep over them alone
    const std::vector<Aabb>& bx = swept_boxes_;
    std::sort(escaped_.begin(), escaped_.end(), [&](int a, int b) {
      return bx[a].lo.x() < bx[b].lo.x() || (bx[a].lo.x() == bx[b].lo.x() && a < b);
    });
    for (size_t i = 0; i < escaped_.size(); ++i) {
      const int a = escaped_[i];
      for (size_t j = i + 1; j < escaped_.size(); ++j) {
        const int b = escaped_[j];
        if (bx[b].lo.x() > bx[a].hi.x() + grow) break;
        if (!shape_swept_[a] && !shape_swept_[b]) continue;
        const int lo = std::min(a, b), hi = std::max(a, b);
        if (meet(bx[a], bx[b]) && may_touch(lo, hi)) pairs_.push_back(pair_key(lo, hi));
      }
    }
  }
  for (int e : escaped_) covered_[e] = 1;
  for (int p : *in.plane_shapes)
    for (int i : fast_)
      for (int k = ext.shape_begin[i]; k < ext.shape_begin[i + 1]; ++k) {
        if (!shape_swept_[k] || !moving[k] || st[k].geom.kind == CollideKind::plane) continue;
        const int lo = std::min(p, k), hi = std::max(p, k);
        if (may_touch(lo, hi)) pairs_.push_back(pair_key(lo, hi));
      }
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  in.profile->toi_pairs += (long)pairs_.size();
  // Times of impact, all from the same sweeps.
  for (uint64_t key : pairs_) {
    const int a = pair_first(key), b = pair_second(key);
    const ShapeRecord& A = st[a];
    const ShapeRecord& B = st[b];
    if (A.geom.kind == CollideKind::mesh || B.geom.kind == CollideKind::mesh) {
      // A static triangle mesh: its triangles within the swept shape's box (the mesh is never the
      // swept side: it is static).
      const int c = A.geom.kind == CollideKind::mesh ? b : a;
      const double t = mesh_toi(st, ext, state, c, a == c ? b : a, sweeps_[st[c].body], swept_boxes_[c],
                                target, tolerance, true);
      if (t < 1 && t > 0) toi_[st[c].body] = std::min(toi_[st[c].body], t);
      continue;
    }
    ToiInput in;
    in.a = &A.geom;
    in.R_PA = A.R_PC;
    in.p_PA = A.p_PC;
    in.sa = &sweeps_[A.body];
    in.reach_a = ext.sweep_reach(a);
    in.b = &B.geom;
    in.R_PB = B.R_PC;
    in.p_PB = B.p_PC;
    in.sb = &sweeps_[B.body];
    in.reach_b = ext.sweep_reach(b);
    in.target = target;
    in.tolerance = tolerance;
    // Touching at the start (a resting or sliding contact, which the solver handles): the swept
    // sides' cores instead, then their centres (time_of_impact.hpp, time_of_impact_guarded).
    const ToiOutput out = time_of_impact_guarded(in, (shape_swept_[a] ? 1 : 0) | (shape_swept_[b] ? 2 : 0));
    if (out.state != ToiOutput::hit || !(out.t > 0)) continue;
    if (shape_swept_[a]) toi_[A.body] = std::min(toi_[A.body], out.t);
    if (shape_swept_[b]) toi_[B.body] = std::min(toi_[B.body], out.t);
  }
  // Each swept body that hits goes back to its earliest time of impact, its velocity unchanged;
  // unless it ended within a slop of that pose (the solver stopped it at the surface, as it
  // should: moving it back would only leave it hovering a target gap off the surface).
  const double keep = target + tolerance + in.linear_slop;
  for (int i : fast_) {
    for (int k = ext.shape_begin[i]; k < ext.shape_begin[i + 1]; ++k) shape_swept_[k] = 0;
    const Sweep& s = sweeps_[i];
    if (toi_[i] < 1 && (1.0 - toi_[i]) * (s.dx.norm() + s.angle * ext.swept_reach[i]) > keep) {
      state[i].x_W = s.x_at(toi_[i]);
      state[i].q_WP = s.q_at(toi_[i]);
      ++in.profile->toi_hits;
    }
    toi_[i] = 1.0;
  }
  return true;
}

bool WorldImpl::stage_continuous() {
  ContinuousCollision::Step in;
  in.state = state_.data();
  in.shapes = shapes_.get();
  in.extents = &extents_;
  in.islands = &islands_;
  // A jointed body moves with its mechanism's coordinates: it is an obstacle, never swept back.
  in.dynamic = joints_.empty() ? &dynamic_ : &unjointed_dynamic_;
  in.awake = &islands_.awake_bodies();
  in.broad_pairs = &contacts_.pairs();
  in.margins = &margins_;
  in.broad = &broad_;
  in.compounds = &compounds_;
  in.sweep_shapes = &sweep_shapes_;
  in.plane_shapes = &plane_shapes_;
  in.shape_moving = &shape_moving_;
  in.linear_slop = cfg_.contacts.linear_slop;
  in.profile = &profile_;
  return ccd_.step(in, [this](int a, int b) { return shapes_may_touch(a, b); });
}

}  // namespace simreel
