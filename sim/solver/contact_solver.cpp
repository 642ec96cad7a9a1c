#include "sim/solver/contact_solver.hpp"

#include "sim/joints/articulation.hpp"
#include "sim/joints/contact_rows.hpp"

#include "sim/base/stage_clock.hpp"

#include <chrono>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/base/worker_pool.hpp"
#include "sim/dynamics/integrators.hpp"

namespace simreel {

ContactSolver::ContactSolver() : art_(std::make_unique<ArticulatedContacts>()) {}
ContactSolver::~ContactSolver() = default;

Softness make_softness(double hertz, double zeta, double h) {
  if (hertz == 0) return Softness{0, 1, 0};
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double a1 = 2.0 * zeta + h * omega;
  const double a2 = h * omega * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return Softness{omega / a1, a2 * a3, a3};
}

// A unit vector perpendicular to n, chosen from n alone (deterministic): n x e, with e the world
// axis least aligned with n.
Vec3 contact_tangent(const Vec3& n) {
  const Vec3 a = n.cwiseAbs();
  const Vec3 e =
      (a.x() <= a.y() && a.x() <= a.z()) ? Vec3::UnitX() : (a.y() <= a.z() ? Vec3::UnitY() : Vec3::UnitZ());
  return n.cross(e).normalized();
}

namespace {

// The block solve's matrices (ManifoldSolve::block) of a manifold's n points (1 to 4), im = 1/m_A +
// 1/m_B: K_ij = im + (r_A,i x n).I_A^-1 (r_A,j x n) + (r_B,i x n).I_B^-1 (r_B,j x n), the change of
// point i's normal velocity per unit impulse at point j (n.n = 1), fixed within the step (anchors
// and inertia are), inverted here once: (K + D)^-1 into soft (D = diag(K_ii) impulse_scale /
// mass_scale, the softness) and (K + eps diag(K))^-1 into rigid, symmetric, the lower triangle row
// by row. False if either is not positive definite.
template <class Point>  // ConstraintPoint or SweepPoint
Eigen::Matrix4d coupling(const Point* p, int n, double im) {
  Eigen::Matrix4d K = Eigen::Matrix4d::Identity();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) K(i, j) = K(j, i) = im + p[i].rnA.dot(p[j].IrnA) + p[i].rnB.dot(p[j].IrnB);
  return K;
}

template <class Point>
bool block_matrices(const Point* p, int n, double im, const Softness& soft_terms, double* soft,
                    double* rigid) {
  const Eigen::Matrix4d K = coupling(p, n, im);
  // D_ii = K_ii / a2 (a2 = mass_scale / impulse_scale): see ManifoldSolve::block.
  const double d = soft_terms.mass_scale > 0 ? soft_terms.impulse_scale / soft_terms.mass_scale : 0.0;
  Eigen::Matrix4d Ks = K, Kr = K;
  for (int i = 0; i < n; ++i) {
    Ks(i, i) += d * K(i, i);
    Kr(i, i) += kBlockRegularisation * K(i, i);
  }
  const Eigen::LLT<Eigen::Matrix4d> ls(Ks), lr(Kr);
  if (ls.info() != Eigen::Success || lr.info() != Eigen::Success) return false;
  const Eigen::Matrix4d Ms = ls.solve(Eigen::Matrix4d::Identity());
  const Eigen::Matrix4d Mr = lr.solve(Eigen::Matrix4d::Identity());
  for (int i = 0, e = 0; i < 4; ++i)
    for (int j = 0; j <= i; ++j, ++e) {
      soft[e] = 0.5 * (Ms(i, j) + Ms(j, i));
      rigid[e] = 0.5 * (Mr(i, j) + Mr(j, i));
    }
  return true;
}

// Normal velocity of a point: n.(vB - vA) + wB.(rB x n) - wA.(rA x n).
template <class Body, class Point>  // SolverBody or LocalBody; ConstraintPoint or SweepPoint
inline double normal_velocity(const Body& A, const Body& B, const Vec3& n, const Point& p) {
  return n.dot(B.v - A.v) + B.w.dot(p.rnB) - A.w.dot(p.rnA);
}

// Asks for a constraint's memory ahead of its solve: a sweep streams the constraints (1.7 KB each,
// 25 MB for the large pyramid) from memory, and the first loads of each stalled the solve (a third
// of its time in the pyramid, sampled). Changes no result.
inline void prefetch(const SweepConstraint& k) {
  const char* p = reinterpret_cast<const char*>(&k);
  for (size_t off = 0; off < sizeof(SweepConstraint); off += 64) __builtin_prefetch(p + off);
}

// Which side of a constraint is the static body (solver body 0): it would receive zeros, so it is
// not written at all, which also spares the solver a chain of read-modify-writes through one body
// shared by every ground contact.
enum Static { kNoneStatic = 0, kStaticA = 1, kStaticB = 2 };

// A normal impulse lambda n at the point. The static body (zero mass and inertia) receives zeros.
// (n / m made in prepare: one product fewer on Gauss-Seidel's chain.)
template <int kStatic = kNoneStatic, class Body>
inline void apply_normal(Body& A, Body& B, const SweepConstraint& k, const SweepPoint& p, double lambda) {
  if constexpr (kStatic != kStaticA) {
    A.v -= lambda * k.nA;
    A.w -= lambda * p.IrnA;
  }
  if constexpr (kStatic != kStaticB) {
    B.v += lambda * k.nB;
    B.w += lambda * p.IrnB;
  }
}

template <int kStatic = kNoneStatic>
inline void apply_at(SolverBody& A, SolverBody& B, const Vec3& rA, const Vec3& rB, const Vec3& P) {
  if constexpr (kStatic != kStaticA) {
    A.v -= A.inv_mass * P;
    A.w -= A.inv_I * rA.cross(P);
  }
  if constexpr (kStatic != kStaticB) {
    B.v += B.inv_mass * P;
    B.w += B.inv_I * rB.cross(P);
  }
}

// A tangent impulse P = d0 t0 + d1 t1 at the friction centre: the angular part from the responses
// made in prepare, I^-1 (f x P) = d0 I^-1 (f x t0) + d1 I^-1 (f x t1).
template <int kStatic = kNoneStatic, class Body>
inline void apply_tangent(Body& A, Body& B, const SweepConstraint& k, double d0, double d1) {
  const Vec3 P = d0 * k.t[0] + d1 * k.t[1];
  if constexpr (kStatic != kStaticA) {
    A.v -= A.inv_mass * P;
    A.w -= d0 * k.IfAt[0] + d1 * k.IfAt[1];
  }
  if constexpr (kStatic != kStaticB) {
    B.v += B.inv_mass * P;
    B.w += d0 * k.IfBt[0] + d1 * k.IfBt[1];
  }
}

}  // namespace

template <typename F>
void ContactSolver::on_workers(F&& f) const {
  if (pool_)
    pool_->run(f);
  else
    f(0, 1);
}

template <typename FS, typename FW>
void ContactSolver::by_colour(int w, int nw, FS&& scalar, FW&& wide) {
  const std::vector<int>& used = graph_.used();
  constexpr int kOverflow = ConstraintGraph::kOverflow;
  constexpr int kGroups = WorkerSchedule::kGroups;
  const bool overflow = graph_.overflow_count() > 0;
  auto items = [&](int g, int begin, int end) {
    if (begin >= end) return;
    if (g == 0)
      scalar(begin, end);
    else
      wide(begin, end);
  };
  if (nw == 1) {  // one worker (or the pool backing off): every colour whole, in turn
    for (const int c : used) {
      items(0, scalar_start_[c], scalar_start_[c + 1]);
      items(1, bundle_start_[c], bundle_start_[c + 1]);
    }
    if (overflow) scalar(scalar_start_[kOverflow], scalar_start_[kOverflow + 1]);
    return;
  }
  // Every worker's count is the same here (each advances once per colour of every call).
  const unsigned base = pool_->progress(w);
  const auto t0 = std::chrono::steady_clock::now();
  double waited = 0;
  for (size_t u = 0; u < used.size(); ++u) {
    // The others' items of the colours before, on bodies this worker's items share, are done.
    if (u > 0)
      for (int v = 0; v < nw; ++v)
        if (v != w) waited += pool_->await_progress(v, base + (unsigned)u);
    const WorkerSchedule::WorkRange* r = schedule_.ranges(used[u], w, nw);
    for (int g = 0; g < kGroups; ++g) {
      items(g, r[g * nw].lo, r[g * nw].a);
      items(g, r[g * nw].b, r[g * nw].hi);
    }
    pool_->advance(w);
    for (int g = 0; g < kGroups; ++g) items(g, r[g * nw].a, r[g * nw].b);
  }
  const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - waited;
  schedule_.add_busy(w, busy);
  if (overflow) {
    pool_->barrier();
    if (w == 0) scalar(scalar_start_[kOverflow], scalar_start_[kOverflow + 1]);
  }
}

// Which constraints go to the wide path (plain_, per constraint, and not in the overflow set),
// in bundles of four per colour in slot order, those resting and those apart in runs of their own;
// the rest to scalar_. The padding lanes are emptied here; the others are filled by set_lane.
void ContactSolver::assign_lanes() {
  const int ncons = (int)cons_.size();
  constexpr int kOverflow = ConstraintGraph::kOverflow;
  lane_of_.assign(ncons, -1);
  lane_slot_.clear();
  scalar_.clear();
  scalar_start_.assign(kOverflow + 2, 0);
  bundle_start_.assign(kOverflow + 2, 0);
  bundle_split_.assign(kOverflow + 2, 0);
  // Per slot: 0 scalar, 1 wide, 2 wide and apart at the step's start (every point's gap open).
  slot_plain_.resize(ncons);
  for (int j = 0; j < ncons; ++j) slot_plain_[graph_.slot(j)] = plain_[j] ? 1 + apart_[j] : 0;
  int lanes = 0;
  for (int c = 0; c <= kOverflow; ++c) {
    scalar_start_[c] = (int)scalar_.size();
    bundle_start_[c] = lanes / wide::kLanes;
    // The manifolds apart at the step's start after the others: they mostly stay apart (the sides
    // of the large pyramid's rows, a gap apart: a quarter of its manifolds), and a bundle of
    // them costs a look at their gaps (wide::solve).
    for (int kind = 1; kind <= 2; ++kind) {
      if (kind == 2) {  // the bundles apart start afresh (so each run of bundles is in slot order)
        lanes = (lanes + wide::kLanes - 1) / wide::kLanes * wide::kLanes;
        lane_slot_.resize(lanes, -1);
        bundle_split_[c] = lanes / wide::kLanes;
      }
      for (int slot = graph_.begin(c); slot < graph_.end(c); ++slot)
        if (slot_plain_[slot] == kind && c != kOverflow) {
          lane_of_[slot] = lanes++;
          lane_slot_.push_back(slot);
        }
    }
    for (int slot = graph_.begin(c); slot < graph_.end(c); ++slot)
      if (!slot_plain_[slot] || c == kOverflow) scalar_.push_back(slot);
    // The colour's last bundle padded with empty lanes.
    lanes = (lanes + wide::kLanes - 1) / wide::kLanes * wide::kLanes;
    lane_slot_.resize(lanes, -1);
  }
  scalar_start_[kOverflow + 1] = (int)scalar_.size();
  bundle_start_[kOverflow + 1] = lanes / wide::kLanes;
  bundles_.resize(lanes / wide::kLanes);
  for (int l = 0; l < lanes; ++l)  // the padding lanes (the ends of a colour's two runs)
    if (lane_slot_[l] < 0) wide::clear_lane(bundles_[l / wide::kLanes], l % wide::kLanes);
}

// A wide lane from the constraint's record (make_constraint), with its points' coupling K.
void ContactSolver::set_lane(int slot, const ContactConstraint& f) {
  const int lane = lane_of_[slot];
  const Eigen::Matrix4d K = coupling(f.p, f.count, sb_[f.a].inv_mass + sb_[f.b].inv_mass);
  double lower[10];
  for (int i = 0, e = 0; i < 4; ++i)
    for (int j = 0; j <= i; ++j, ++e) lower[e] = K(i, j);
  wide::set_lane(bundles_[lane / wide::kLanes], lane % wide::kLanes, f, lower, sb_[f.a].inv_I,
                 sb_[f.b].inv_I);
}

// Flattened for the same reason as solve_one (Eigen's 3x3 products called, not inlined).
__attribute__((flatten)) void ContactSolver::prepare(const SolverInput& in, const std::vector<int>& bodies,
                                                     const std::vector<Contact>& contacts,
                                                     std::vector<int>& solver_index) {
  in_ = in;
  bodies_ = bodies;
  const int nb = (int)bodies.size() + 1;
  sb_.resize(nb);
  I_W_.resize(nb);
  gyro_.resize(nb);
  gyro_w0_.resize(nb);
  accel_.resize(nb);
  ang_accel_.resize(nb);
  for (int k = 1; k < nb; ++k) solver_index[bodies[k - 1]] = k;
  const ContactSettings& cs = in.settings;
  const double h = in.dt / in.substeps;
  // Stiffer than the substep can resolve is pointless and rings: at most a quarter of its rate.
  const double hertz = std::min(cs.contact_hertz, 0.25 / h);
  soft_ = make_softness(hertz, cs.damping_ratio, h);
  static_soft_ = make_softness(2.0 * hertz, cs.damping_ratio, h);

  // One constraint per touching manifold whose pair moves under impulses, coloured (in contact
  // order) and stored in solve order. The records (large) are reused from the last step: every
  // field read later is written by make_constraint.
  wanted_.clear();
  articulated_.clear();
  edge_a_.clear();
  edge_b_.clear();
  track_candidate_of_.clear();
  plain_.clear();
  apart_.clear();
  int ncand = 0;
  any_restitution_ = false;
  for (int ci = 0; ci < (int)contacts.size(); ++ci) {
    const Contact& c = contacts[ci];
    if (c.count == 0) continue;
    if (in.articulations && (in.articulations->jointed(c.body_a) || in.articulations->jointed(c.body_b))) {
      articulated_.push_back(ci);
      continue;
    }
    if (solver_index[c.body_a] == 0 && solver_index[c.body_b] == 0) continue;
    // Maybe a tracked contact (make_constraint decides): one point, a round shape on either side.
    auto round = [](CollideKind kind) {
      return kind == CollideKind::cylinder || kind == CollideKind::sphere || kind == CollideKind::capsule ||
             kind == CollideKind::ellipsoid;
    };
    const bool candidate = c.count == 1 && (round((*in.shapes)[c.shape_a].geom.kind) ||
                                            round((*in.shapes)[c.shape_b].geom.kind));
    track_candidate_of_.push_back(candidate ? ncand++ : -1);
    // The wide path takes plain manifolds (sim/solver/contact_wide.hpp): no tracked point, restitution,
    // rolling resistance or regularised Coulomb friction.
    plain_.push_back(!candidate && c.restitution == 0 && cs.rolling_resistance == 0 && cs.slip_speed == 0);
    bool apart = true;
    for (int j = 0; j < c.count; ++j) apart = apart && c.points[j].separation > 0;
    apart_.push_back(apart);
    wanted_.push_back(ci);
    edge_a_.push_back(solver_index[c.body_a]);
    edge_b_.push_back(solver_index[c.body_b]);
    any_restitution_ = any_restitution_ || c.restitution > 0;
  }
  const int ncons = (int)wanted_.size();
  graph_.build(nb, ncons, edge_a_.data(), edge_b_.data());
  cons_.resize(ncons);
  sweep_.resize(ncons);
  assign_lanes();
  track_scratch_.resize(ncand);
  // Threads only where there is enough to split (a pool run and a barrier per colour cost a few
  // microseconds); the result is the same either way.
  pool_ = (in.pool && ncons >= kMinParallelConstraints) ? in.pool : nullptr;
  workers_ = pool_ ? pool_->size() : 1;
  struck_.resize(workers_);
  if (workers_ > 1) schedule_.split(schedule_layout());

  on_workers([&](int w, int nw) {
    int b, e;
    share(nb, w, nw, b, e);
    for (int k = b; k < e; ++k) {
      SolverBody& sb = sb_[k];
      sb = SolverBody{};
      I_W_[k].setZero();
      gyro_[k] = 0;
      accel_[k].setZero();
      ang_accel_[k].setZero();
      if (k == 0) continue;  // the static body: zero mass and inertia
      const int i = bodies[k - 1];
      const BodyModel& m = in.model[i];
      const MotionState& s = in.state[i];
      const Mat3 R = s.q_WP.toRotationMatrix();
      sb.v = s.v_W;
      sb.w = R * s.w_P;
      sb.inv_mass = m.inv_mass;
      sb.inv_I = R * m.inv_I_P.asDiagonal() * R.transpose();
      if (m.inv_mass > 0) {
        gyro_[k] = !m.isotropic;
        if (gyro_[k]) I_W_[k] = R * m.I_P.asDiagonal() * R.transpose();  // read for the gyroscopic term only
        accel_[k] = in.gravity;
        if (in.wrench) {
          accel_[k] += m.inv_mass * in.wrench[i].f_W;
          ang_accel_[k] = sb.inv_I * in.wrench[i].tau_W;
        }
      }
    }
    if (nw > 1) pool_->barrier();  // the constraints read the solver bodies
    // In solve order, so a bundle's lanes are written one after the other (in contact order they
    // were written at four different times, its cache lines fetched for each), and a wide lane's
    // record made on the stack (only its bundle is kept): the large pyramid's prepare 24% faster.
    share(ncons, w, nw, b, e);
    ContactConstraint scratch;
    for (int slot = b; slot < e; ++slot) {
      const int j = graph_.constraint_at(slot);
      const bool wide = lane_of_[slot] >= 0;
      ContactConstraint& k = wide ? scratch : cons_[slot];
      make_constraint(k, slot, track_candidate_of_[j], wanted_[j], contacts[wanted_[j]], solver_index);
      if (wide)
        set_lane(slot, k);
      else
        pack_sweep(slot, true);
    }
  });
  // The tracked contacts, in contact order (their records made in make_constraint), and their
  // tracked bodies, whose inertia follows them and whose gyroscopic term comes after the warm start.
  tracked_.clear();
  tracked_bodies_.clear();
  track_due_ = false;
  for (const TrackedContact& t : track_scratch_) {
    if (t.con < 0) continue;
    ContactConstraint& k = cons_[t.con];
    k.track = (int)tracked_.size();
    sweep_[t.con].track = k.track;
    tracked_.push_back(t);
    tracked_bodies_.push_back(t.side > 0 ? k.b : k.a);
  }
  std::sort(tracked_bodies_.begin(), tracked_bodies_.end());
  tracked_bodies_.erase(std::unique(tracked_bodies_.begin(), tracked_bodies_.end()), tracked_bodies_.end());
  for (int k : tracked_bodies_)
    if (gyro_[k]) gyro_[k] = 2;  // the gyroscopic term after the warm start (warm_start)
  // Every constraint on the wide path (none tracked, none bouncing): after the first substep the
  // warm start is made per body (warm_start).
  body_warm_ = scalar_.empty() && tracked_.empty() && !any_restitution_;
  need_dR_ = !scalar_.empty() || !tracked_.empty();
  warm_starts_ = 0;
  impulse_change_.resize(nb);
  impulse_change_[0] = BodyImpulse{};  // the static body
  art_->prepare(in.articulations, in, contacts, articulated_, solver_index, sb_, soft_, static_soft_);
  if (!art_->empty()) {
    // The free bodies' rows read their bodies' velocities as they are; the per-body warm start and
    // the rotation matrices assume every row is theirs.
    body_warm_ = false;
    need_dR_ = true;
  }
}

// One constraint from contact ci (c), at `slot`; `cand` its index in track_scratch_ or -1. Flattened as
// prepare.
__attribute__((flatten)) void ContactSolver::make_constraint(ContactConstraint& k, int slot, int cand, int ci,
                                                             const Contact& c,
                                                             const std::vector<int>& solver_index) {
  const ContactSettings& cs = in_.settings;
  k.a = solver_index[c.body_a];
  k.b = solver_index[c.body_b];
  k.contact = ci;
  k.n = c.normal_W;
  k.t[0] = contact_tangent(k.n);
  k.t[1] = k.n.cross(k.t[0]);
  k.friction = c.friction;
  k.restitution = c.restitution;
  k.rolling = cs.rolling_resistance;
  k.count = c.count;
  const SolverBody& A = sb_[k.a];
  const SolverBody& B = sb_[k.b];
  k.soft = (A.inv_mass == 0 || B.inv_mass == 0) ? static_soft_ : soft_;
  k.nA = A.inv_mass * k.n;
  k.nB = B.inv_mass * k.n;
  const Vec3 xA = in_.state[c.body_a].x_W, xB = in_.state[c.body_b].x_W;
  const double roundA = rounding_radius((*in_.shapes)[c.shape_a].geom);
  const double roundB = rounding_radius((*in_.shapes)[c.shape_b].geom);
  // Each body's anchor is on its own surface (the manifold point is their midpoint, A's surface
  // at -s/2 n from it, B's at +s/2 n): a sphere resting 0.5 mm deep rolls without slipping at
  // its true radius, not at the midpoint's (which would brake it by 2/7 of depth / radius).
  // Friction acts at the centre of the points. (Weighting them by last step's normal impulses,
  // a lagged centre of pressure, fed back into the impulses and set a stack of ten boxes
  // rocking at 0.3 m/s, measured; Box3D uses the plain centre too.)
  Vec3 centreA = Vec3::Zero(), centreB = Vec3::Zero();
  for (int j = 0; j < c.count; ++j) {
    centreA += c.points[j].p_W - (0.5 * c.points[j].separation) * k.n - 0.5 * c.points[j].offset_W;
    centreB += c.points[j].p_W + (0.5 * c.points[j].separation) * k.n + 0.5 * c.points[j].offset_W;
  }
  centreA /= c.count;
  centreB /= c.count;
  const Vec3 centre = 0.5 * (centreA + centreB);
  for (int j = 0; j < c.count; ++j) {
    const ContactPoint& cp = c.points[j];
    ConstraintPoint& p = k.p[j];
    p.rA = cp.p_W - (0.5 * cp.separation) * k.n - 0.5 * cp.offset_W - xA;
    p.rB = cp.p_W + (0.5 * cp.separation) * k.n + 0.5 * cp.offset_W - xB;
    normal_terms(p, k.n, A, B);
    p.cA = p.rA - roundA * k.n;
    p.cB = p.rB + roundB * k.n;
    p.adjusted_separation = cp.separation - k.n.dot(p.cB - p.cA);
    p.normal_impulse = cp.normal_impulse;
    p.max_normal_impulse = 0;
    p.vn_prev = normal_velocity(A, B, k.n, p);
    p.impact_velocity = 0;
    p.lever = (cp.p_W - centre).norm();
    p.bounced = false;
  }
  k.fA = centreA - xA;
  k.fB = centreB - xB;
  friction_terms(k, A, B);
  // Warm start: last step's friction impulse re-expressed in this step's tangent basis.
  k.tangent_impulse[0] = k.t[0].dot(c.friction_impulse_W);
  k.tangent_impulse[1] = k.t[1].dot(c.friction_impulse_W);
  k.InA = A.inv_I * k.n;
  k.InB = B.inv_I * k.n;
  const double kt = k.n.dot((A.inv_I + B.inv_I) * k.n);
  k.twist_mass = kt > 0 ? 1.0 / kt : 0.0;
  k.twist_impulse = c.twist_impulse;
  if (k.rolling > 0) {
    const Mat3 Kr = A.inv_I + B.inv_I;
    k.rolling_mass = std::fabs(Kr.determinant()) > 0 ? Mat3(Kr.inverse()) : Mat3::Zero();
    // Lever of the rolling resistance: the rounding radius of the rolling shape.
    k.rolling_lever = std::max(roundA, roundB);
    k.rolling_impulse = c.rolling_impulse;
  } else {
    k.rolling_mass.setZero();
    k.rolling_lever = 0;
    k.rolling_impulse.setZero();
  }
  // A contact whose point runs over a smooth surface (B's tried first): tracked per substep
  // (sim/collision/tracked_contacts.hpp); its gap follows the tracked point, not a centre of curvature. Its
  // record goes to the candidate's scratch slot (con: this constraint's slot, or -1 if not
  // tracked); prepare lists the records in contact order and sets k.track.
  k.track = -1;
  if (cand < 0) return;
  TrackedContact& t = track_scratch_[cand];
  t.con = -1;
  for (int side = 1; side >= -1 && c.count == 1; side -= 2) {
    if ((side > 0 ? k.b : k.a) == 0) continue;  // a static body's surface does not move
    t = TrackedContact{};
    if (!track_begin(t, k, c, *in_.shapes, in_.state, side)) continue;
    t.con = slot;
    if (track_point(t, k, A, B)) {
      normal_terms(k.p[0], k.n, A, B);
      friction_terms(k, A, B);
    }
    break;
  }
}

// A point's lever arms across the normal n, their I^-1 images, and its effective normal mass
// 1 / (1/m_A + 1/m_B + (r_A x n) I_A^-1 (r_A x n) + (r_B x n) I_B^-1 (r_B x n)) (Catto 2005).
void ContactSolver::normal_terms(ConstraintPoint& p, const Vec3& n, const SolverBody& A,
                                 const SolverBody& B) {
  p.rnA = p.rA.cross(n);
  p.rnB = p.rB.cross(n);
  p.IrnA = A.inv_I * p.rnA;
  p.IrnB = B.inv_I * p.rnB;
  const double kn = A.inv_mass + B.inv_mass + p.rnA.dot(p.IrnA) + p.rnB.dot(p.IrnB);
  p.normal_mass = kn > 0 ? 1.0 / kn : 0.0;
}

// Friction at the centre fA, fB: K_jk = (1/mA + 1/mB) d_jk + (fA x t_j).IA(fA x t_k) + (fB x t_j).IB(fB x
// t_k) and its inverse, the angular terms made once (an impulse's angular effect is linear in them).
void ContactSolver::friction_terms(ContactConstraint& k, const SolverBody& A, const SolverBody& B) {
  for (int j = 0; j < 2; ++j) {
    k.fAt[j] = k.fA.cross(k.t[j]);
    k.fBt[j] = k.fB.cross(k.t[j]);
    k.IfAt[j] = A.inv_I * k.fAt[j];
    k.IfBt[j] = B.inv_I * k.fBt[j];
  }
  const Vec3* at = k.fAt;
  const Vec3* bt = k.fBt;
  const Vec3* Iat = k.IfAt;
  const Vec3* Ibt = k.IfBt;
  Eigen::Matrix2d K;
  for (int j = 0; j < 2; ++j)
    for (int l = 0; l < 2; ++l)
      K(j, l) = (j == l ? A.inv_mass + B.inv_mass : 0.0) + at[j].dot(Iat[l]) + bt[j].dot(Ibt[l]);
  // The inverse written out (Eigen's 2x2 formula: the same operations, without the call).
  const double det = K(0, 0) * K(1, 1) - K(1, 0) * K(0, 1);
  if (det > 0) {
    const double inv_det = 1.0 / det;
    k.tangent_mass(0, 0) = K(1, 1) * inv_det;
    k.tangent_mass(1, 0) = -K(1, 0) * inv_det;
    k.tangent_mass(0, 1) = -K(0, 1) * inv_det;
    k.tangent_mass(1, 1) = K(0, 0) * inv_det;
  } else {
    k.tangent_mass.setZero();
  }
}

// What the sweeps read, copied (the same values: results do not change). Block terms from the copy.
void ContactSolver::pack_sweep(int slot, bool impulses) {
  const ContactConstraint& f = cons_[slot];
  SweepConstraint& k = sweep_[slot];
  k.a = f.a;
  k.b = f.b;
  k.count = f.count;
  k.track = f.track;
  k.n = f.n;
  k.t[0] = f.t[0];
  k.t[1] = f.t[1];
  k.nA = f.nA;
  k.nB = f.nB;
  k.friction = f.friction;
  k.restitution = f.restitution;
  k.rolling = f.rolling;
  k.tangent_mass = f.tangent_mass;
  for (int j = 0; j < 2; ++j) {
    k.fAt[j] = f.fAt[j];
    k.fBt[j] = f.fBt[j];
    k.IfAt[j] = f.IfAt[j];
    k.IfBt[j] = f.IfBt[j];
  }
  k.InA = f.InA;
  k.InB = f.InB;
  k.twist_mass = f.twist_mass;
  k.soft = f.soft;
  for (int j = 0; j < f.count; ++j) {
    const ConstraintPoint& fp = f.p[j];
    SweepPoint& p = k.p[j];
    p.rnA = fp.rnA;
    p.rnB = fp.rnB;
    p.IrnA = fp.IrnA;
    p.IrnB = fp.IrnB;
    p.cA = fp.cA;
    p.cB = fp.cB;
    p.adjusted_separation = fp.adjusted_separation;
    p.normal_mass = fp.normal_mass;
    p.lever = fp.lever;
    if (impulses) {
      p.normal_impulse = fp.normal_impulse;
      p.max_normal_impulse = fp.max_normal_impulse;
    }
  }
  if (impulses) {
    k.tangent_impulse[0] = f.tangent_impulse[0];
    k.tangent_impulse[1] = f.tangent_impulse[1];
    k.twist_impulse = f.twist_impulse;
  }
  block_terms(k, sb_[k.a], sb_[k.b]);
}

// The block solve's matrices (ManifoldSolve::block). K_ij = 1/m_A + 1/m_B + (r_A,i x n).I_A^-1 (r_A,j x n)
// + (r_B,i x n).I_B^-1 (r_B,j x n): the change of point i's normal velocity per unit impulse at
// point j (n.n = 1). Fixed within the step (anchors and inertia are), so inverted here once.
void ContactSolver::block_terms(SweepConstraint& k, const SolverBody& A, const SolverBody& B) {
  k.block = k.count >= 2 &&
            block_matrices(k.p, k.count, A.inv_mass + B.inv_mass, k.soft, k.block_soft, k.block_rigid);
}

namespace {

// Gyroscopic term by the implicit midpoint rule: I (w' - ws) + h m x I m = 0, m = (w0 + w')/2, ws the
// angular velocity the term is added to and w0 the substep's start (ws = w0 but for tracked bodies,
// whose contact impulse of the substep is in ws: see warm_start), solved by Newton from w' = ws
// (Jacobian I + h/2 (skew(m) I - skew(I m))). Second order, and it keeps the kinetic energy and |L| of
// torque-free rotation: a spinning top in contact precesses at the right rate (Catto's one-step
// implicit Euler, GDC 2015, damps it: 4.7% slow at 240 Hz for a top spinning at 54 rad/s, measured).
// Newton converges quadratically; three iterations reach rounding for h |w| up to about 1.
Vec3 midpoint_gyro(const Mat3& I, const Vec3& w0, const Vec3& ws, double h) {
  Vec3 w1 = ws;
  for (int it = 0; it < 3; ++it) {
    const Vec3 m = 0.5 * (w0 + w1);
    const Vec3 Im = I * m;
    const Vec3 f = I * (w1 - ws) + h * m.cross(Im);
    const Mat3 J = I + (0.5 * h) * (skew(m) * I - skew(Im));
    w1 -= J.inverse() * f;
  }
  return w1;
}

}  // namespace

// First, after a move, the tracked points found again (refresh_tracked), then each body's velocity.
// The refresh writes the tracked bodies' inertia (then a barrier) and each tracked constraint's own
// anchors and masses; the velocity update reads a body's world inertia and writes its v, w, which
// the refresh does not read: no barrier between them.
void ContactSolver::integrate_velocities(double h) {
  const bool refresh = track_due_;
  track_due_ = false;
  h_ = h;
  const bool capture = body_warm_ && warm_starts_ > 0;
  on_workers([&](int w, int nw) {
    if (refresh) refresh_tracked(w, nw);
    int begin, end;
    share((int)sb_.size() - 1, w, nw, begin, end);
    for (int k = begin + 1; k < end + 1; ++k) {
      if (capture) {  // the last substep's impulses, all of them (warm_start)
        BodyImpulse& d = impulse_change_[k];
        d.dv = sb_[k].v - d.v0;
        d.dw = sb_[k].w - d.w0;
      }
      integrate_velocity(k, h);
    }
  });
}

void ContactSolver::integrate_velocity(int k, double h) {
  SolverBody& b = sb_[k];
  if (b.inv_mass == 0) return;  // kinematic: keeps its velocity
  b.v += h * accel_[k];
  b.w += h * ang_accel_[k];
  if (gyro_[k] == 1) {
    // The world inertia of the body as turned so far in the step (its inverse in the impulses stays
    // the step's): with the step's, a body of unequal moments in contact turned its angular
    // momentum off |L| at the first order in dt (2.8% in 0.5 s for a ball with I = (4, 4, 7.5)
    // g m^2 spinning on a frictionless floor; 0.36% refreshed, 0.09% at 16 substeps).
    if (inertia_due_) {
      const int i = bodies_[k - 1];
      const Mat3 R = (b.dq * in_.state[i].q_WP).toRotationMatrix();
      I_W_[k] = R * in_.model[i].I_P.asDiagonal() * R.transpose();
    }
    b.w = midpoint_gyro(I_W_[k], b.w, b.w, h);
  } else if (gyro_[k] == 2) {
    gyro_w0_[k] = b.w;  // a tracked body's: after the warm start (see there)
  }
}

namespace {

template <int kStatic>
__attribute__((flatten)) inline void warm_start_constraint(const SweepConstraint& k,
                                                           const ContactConstraint& f, SolverBody& A,
                                                           SolverBody& B) {
  for (int j = 0; j < k.count; ++j) apply_normal<kStatic>(A, B, k, k.p[j], k.p[j].normal_impulse);
  apply_tangent<kStatic>(A, B, k, k.tangent_impulse[0], k.tangent_impulse[1]);
  if (k.rolling > 0) {
    const Vec3 twist = k.twist_impulse * k.n + f.rolling_impulse;
    if constexpr (kStatic != kStaticA) A.w -= A.inv_I * twist;
    if constexpr (kStatic != kStaticB) B.w += B.inv_I * twist;
  } else {
    if constexpr (kStatic != kStaticA) A.w -= k.twist_impulse * k.InA;
    if constexpr (kStatic != kStaticB) B.w += k.twist_impulse * k.InB;
  }
}

}  // namespace

// Per body, after the step's first substep. Within a step a constraint's Jacobian is fixed (its
// lever arms and the bodies' inverse inertia are the step's), so the velocity change that the
// accumulated impulses lambda give a body, M^-1 J^T lambda, summed over its constraints, is
// exactly what the last substep's warm start and sweeps added to it together (they applied
// lambda's last value and every change to it, through the same J): v - v0 at the substep's end,
// v0 its velocity before that warm start. Adding that per body is the sweep's result up to
// rounding (1e-16 of the velocities), for a pass over the bodies instead of the constraints (the
// large pyramid: 5,050 bodies against 15,000 manifolds, 2.2 KB a bundle of four). Not where a
// constraint's Jacobian moves within the step (a tracked point) or restitution clears impulses
// between substeps: there the sweep.
// Every body's velocities before the substep's contact impulses are kept first (BodyImpulse).
bool ContactSolver::warm_start() {
  const bool by_body = body_warm_ && warm_starts_++ > 0;
  on_workers([&](int w, int nw) {
    int begin, end;
    share((int)sb_.size() - 1, w, nw, begin, end);
    for (int k = begin + 1; k < end + 1; ++k) {
      SolverBody& b = sb_[k];
      BodyImpulse& d = impulse_change_[k];
      d.v0 = b.v;
      d.w0 = b.w;
      if (by_body) {
        b.v += d.dv;
        b.w += d.dw;
      }
    }
    if (by_body) return;
    if (nw > 1) pool_->barrier();  // every body's v0 kept before any impulse moves it
    by_colour(
        w, nw,
        [&](int begin, int end) {
          for (int n = begin; n < end; ++n) {
            const int i = scalar_[n];
            const SweepConstraint& k = sweep_[i];
            if (n + 2 < end) prefetch(sweep_[scalar_[n + 2]]);
            if (k.a == 0)
              warm_start_constraint<kStaticA>(k, cons_[i], sb_[0], sb_[k.b]);
            else if (k.b == 0)
              warm_start_constraint<kStaticB>(k, cons_[i], sb_[k.a], sb_[0]);
            else
              warm_start_constraint<kNoneStatic>(k, cons_[i], sb_[k.a], sb_[k.b]);
          }
        },
        [&](int begin, int end) {
          for (int i = begin; i < end; ++i) {
            wide::warm_start(bundles_[i], sb_.data());
          }
        });
    // A tracked body's gyroscopic term, with the substep's contact impulse in its midpoint: m = (w0 +
    // w')/2 must hold the whole substep's change of w, and the contact's, I^-1 (r x P), is of the
    // same order as the term's own (the contact's torque is what turns L). Taken before the
    // impulses (integrate_velocities), m misses I^-1 (r x P) / 2, and the term is off by
    // h/2 ((I^-1 tau) x I w + w x tau) relatively to first order in h; the warm start's impulses are
    // the last substep's, this one's to O(h), so the term taken after them is right to O(h^2).
    // Measured: the rattleback spun +5 rad/s reversed 17.5% late at substeps of 1/960 s (+7.8% at
    // 1/1920 s, +3.6% at 1/3840: first order) and reverses within 0.1% of the reference at all three
    // now (the one spun -5: -4.3% before, -3.0% to -2.6% now); a tippe top at 1/2400 s kept Jellett's
    // quantity to 1.1e-2 and now to 1.9e-4; a rolling coin's lean drifted 15 -> 21 degrees in 5 s and
    // holds now; a heavy top on a 1 um tip precessed 0.3% slow and is within 6e-5 of the slow root.
    // (Bodies that are not tracked keep the term before the impulses: their contact point does not
    // run over them, and the other demos keep their motion.) Per body in fixed shares, once every
    // colour is warm-started (a barrier).
    if (tracked_bodies_.empty()) return;
    if (nw > 1) pool_->barrier();
    share((int)tracked_bodies_.size(), w, nw, begin, end);
    for (int i = begin; i < end; ++i) {
      const int k = tracked_bodies_[i];
      if (gyro_[k] != 2) continue;
      SolverBody& b = sb_[k];
      b.w = midpoint_gyro(I_W_[k], gyro_w0_[k], b.w, h_);
    }
  });
  return by_body;
}

namespace {

struct SolveParams {
  double inv_h, max_push, slop, apart, slip_speed;
  int resting_passes;  ///< contacts.passes
  bool use_bias, first_iteration;
  double h;
  const TrackedContact* tracked;  ///< ContactSolver::tracked_ (ContactConstraint::track indexes it)
  const BodyImpulse* start;       ///< per solver body, its velocities before the substep's impulses
};

// Which side of a constraint is the static body (see apply_normal).
inline int static_side(const SweepConstraint& k) {
  return k.a == 0 ? kStaticA : (k.b == 0 ? kStaticB : kNoneStatic);
}

// One manifold's solve: normal passes, then friction, twist and rolling. kStatic names the side
// that is the static body (solver body 0), which is read (zero velocity, no displacement) but
// never written. The two bodies are worked on in local copies (registers, not a store and reload
// per impulse on Gauss-Seidel's serial chain) and written back at the end. Split into steps so
// that two manifolds with no body in common can be solved interleaved (see ContactSolver::solve).
// A body as a manifold's solve works on it: its velocities copied (the rest read in place).
struct LocalBody {
  Vec3 v, w;
  double inv_mass;
  const SolverBody& s;
  explicit LocalBody(const SolverBody& b) : v(b.v), w(b.w), inv_mass(b.inv_mass), s(b) {}
};

template <int kStatic>
struct ManifoldSolve {
  SweepConstraint& k;
  ContactConstraint& f;  ///< the full record: restitution, tracked point and rolling fields
  const SolveParams& q;
  LocalBody A, B;
  double sep[4];
  double total_normal = 0, twist_limit = 0;
  double total_normal_pass = 0, twist_pass = 0, change = 0, scale = 1e-300;
  int pass = 0;
  bool impact = false, done = false, had_impact = false, struck = false;

  static constexpr int kPasses = 32;
  static constexpr double kImpactTolerance = 1e-6, kRestingTolerance = 1e-4;

  ManifoldSolve(SweepConstraint& kk, ContactConstraint& ff, const SolveParams& qq,
                const std::vector<SolverBody>& sb)
      : k(kk), f(ff), q(qq), A(sb[kk.a]), B(sb[kk.b]) {
    const Vec3 dp = B.s.dp - A.s.dp;
    const Mat3& RA = A.s.dR;
    const Mat3& RB = B.s.dR;
    // Separation now of each point: each surface's centre of curvature moved with its body since
    // the manifold was computed. Positions do not change within a solve, so once per call.
    for (int j = 0; j < k.count; ++j)
      sep[j] = k.n.dot(dp + RB * k.p[j].cB - RA * k.p[j].cA) + k.p[j].adjusted_separation;
    const bool track_impact = q.use_bias && q.first_iteration && k.restitution > 0;
    // Non-penetration. One pass is Gauss-Seidel over the manifold's points; where one point's
    // impulse disturbs another (a box landing on a face: each corner's push turns the box) the
    // pass is repeated, alternating direction, up to kPasses times, until no impulse changes by
    // more than 1e-6 of the largest. An unconverged landing leaves the box tilted, and the tilt
    // grows bounce after bounce.
    if (track_impact) {
      // The normal velocity each point will hit with if it touches in this substep, taken before
      // any of the manifold's impulses act: from the gap s and the substep's start velocity and
      // approach acceleration, by energy, v_i^2 = v_0^2 + 2 |a| s. Restitution reverses it, so
      // the bounce leaves with the energy of the true impact whatever the moment of touching.
      for (int j = 0; j < k.count; ++j) {
        ConstraintPoint& p = f.p[j];
        const double s = sep[j];
        const double vn = normal_velocity(A, B, k.n, k.p[j]);
        if (s > 0) {
          const double accel = std::min(0.0, vn - p.vn_prev) * q.inv_h;
          p.impact_velocity = -std::sqrt(p.vn_prev * p.vn_prev - 2.0 * accel * s);
        } else {
          p.impact_velocity = vn;
        }
      }
    }
  }

  // The block solve: a manifold whose points all rest (the solve: every gap closed, each point
  // soft) or all touch (the relax: no gap beyond `apart`, each point rigid) is solved at once, to
  // the fixed point the repeated passes converge to. A pass updates point i by
  //   dl_i = -m_i ms (vn_i + b_i) - is l_i,  m_i = 1 / K_ii, ms = a2 a3, is = a3,
  // with l_i the accumulated impulse and vn_i the normal velocity, both as they are at the update.
  // At the fixed point of the passes dl_i = 0 with l_i = l0_i + x_i (x the change this sweep,
  // vn = vn0 + K x): 0 = -m_i ms (vn0_i + (K x)_i + b_i) - is (l0_i + x_i); divided by -m_i ms and
  // with is / ms = 1 / a2:  (K x)_i + (K_ii / a2) x_i = -(vn0_i + b_i) - (K_ii / a2) l0_i, that is
  //   (K + D) x = -(vn0 + b) - D l0,  D = diag(K_ii / a2),
  // K = J M^-1 J^T symmetric positive semi-definite and D > 0: positive definite, one solution.
  // (One point, count 1: x = -m ms (vn0 + b) - is l0, the pass itself.) The solution is accepted
  // if every accumulated impulse l0 + x stays >= 0 (the clamp inactive: then it is the passes'
  // limit exactly, which they reach only to their tolerance); else the passes run.
  // The relax has no softness (ms = 1, is = 0, D = 0) and K x = -(vn0 + b); a face on a face is
  // four points on three degrees of freedom and K is singular there. Any solution gives the same
  // velocities (they differ by impulses in the null space of J^T, which move nothing; for a
  // rectangle's corners (+1, -1, +1, -1), which changes neither the sum nor the twist limit), so
  // it takes x of (K + eps diag(K)) x = -(vn0 + b), eps = kBlockRegularisation: the least
  // diag(K)-weighted x, off the exact velocities by a relative eps.
  void block() {
    if (!k.block || k.track >= 0) return;
    const double* M = q.use_bias ? k.block_soft : k.block_rigid;
    const double d = q.use_bias ? k.soft.impulse_scale / k.soft.mass_scale : 0.0;
    double r[4];
    for (int j = 0; j < k.count; ++j) {
      const SweepPoint& p = k.p[j];
      const double s = sep[j];
      double bias = 0;
      if (q.use_bias) {
        if (s > 0) return;  // speculative: rigid, a row of its own kind (the passes)
        bias = std::max(k.soft.bias_rate * std::min(0.0, s + q.slop), -q.max_push);
      } else {
        if (s > q.apart) return;  // may only release (the passes)
        if (s > 0) bias = s * q.inv_h;
      }
      const double vn = (k.n.dot(B.v) + B.w.dot(p.rnB)) - (k.n.dot(A.v) + A.w.dot(p.rnA));
      r[j] = -(vn + bias) - (d / p.normal_mass) * p.normal_impulse;
    }
    double x[4], total[4];
    for (int i = 0; i < k.count; ++i) {
      const int row = i * (i + 1) / 2;
      double sum = 0;
      for (int j = 0; j < k.count; ++j) sum += M[j <= i ? row + j : j * (j + 1) / 2 + i] * r[j];
      x[i] = sum;
      total[i] = k.p[i].normal_impulse + sum;
      if (total[i] < 0) return;
    }
    for (int j = 0; j < k.count; ++j) {
      SweepPoint& p = k.p[j];
      p.normal_impulse = total[j];
      p.max_normal_impulse = std::max(p.max_normal_impulse, total[j]);
      total_normal += total[j];
      twist_limit += p.lever * total[j];
      apply_normal<kStatic>(A, B, k, p, x[j]);
    }
    done = true;
  }

  void start_pass() {
    total_normal_pass = 0;
    twist_pass = 0;
    change = 0;
    scale = 1e-300;
    impact = false;
  }

  void point(int jj) {
    // Symmetric Gauss-Seidel: odd passes run backwards, so no corner is always served first.
    const int j = (pass & 1) ? k.count - 1 - jj : jj;
    SweepPoint& p = k.p[j];
    const double s = sep[j];
    double bias = 0, mass_scale = 1, impulse_scale = 0;
    if (s > 0) {
      bias = s * q.inv_h;  // speculative: allow closing the gap within this substep, no more
    } else if (q.use_bias) {
      bias = std::max(k.soft.bias_rate * std::min(0.0, s + q.slop), -q.max_push);
      mass_scale = k.soft.mass_scale;
      impulse_scale = k.soft.impulse_scale;
    }
    // The new accumulated impulse, lambda_acc + lambda with lambda = c (vn + bias) - impulse_scale
    // lambda_acc, c = -m_eff mass_scale, is (lambda_acc - impulse_scale lambda_acc + c bias) + c vn:
    // all but c vn is made off Gauss-Seidel's chain (vn -> impulse -> velocities -> next vn).
    // A tracked point's workless target (sim/collision/tracked_contacts.cpp, track_turn).
    if (k.track >= 0) bias += k.n.dot(track_turn(q.tracked[k.track], f.p[j], A.w, B.w, q.h));
    const double c = -p.normal_mass * mass_scale;
    const double base = (p.normal_impulse - impulse_scale * p.normal_impulse) + c * bias;
    // vn = n.(vB - vA) + wB.(rB x n) - wA.(rA x n), each body's part summed on its own.
    const double vn = (k.n.dot(B.v) + B.w.dot(p.rnB)) - (k.n.dot(A.v) + A.w.dot(p.rnA));
    double total = std::max(base + c * vn, 0.0);
    double lambda;
    // Relax on a point still apart after this substep's move: the next substep's solve limits
    // its approach from its own gap; pushing here would slow a falling body before it touches
    // (and lose the energy restitution should return). Relax may only release such a point.
    // ("Apart" means by more than a thousandth of the slop: a face landing flat has corners
    // at +-1e-12 m by rounding, and releasing some of them but not others would tip it.)
    if (!q.use_bias && s > q.apart) total = std::min(total, p.normal_impulse);
    lambda = total - p.normal_impulse;
    p.normal_impulse = total;
    p.max_normal_impulse = std::max(p.max_normal_impulse, total);
    total_normal_pass += total;
    twist_pass += p.lever * total;
    impact = impact || (s > 0 && total > 0);
    // Struck: closing fast from apart, judged by the approach speed before the substep's contact
    // impulses (vn here carries those the sweep has applied so far: the large pyramid's rows,
    // pushed sideways within a sweep, closed their 0.01-0.1 mm side gaps at 0.5-0.7 m/s read
    // there, and took six to eleven "impacts" a run, each 1/30 s of extra sweeps).
    if (s > 0 && total > 0 && vn < -kImpactSpeed && !struck) {
      const BodyImpulse &A0 = q.start[k.a], &B0 = q.start[k.b];
      struck = (k.n.dot(B0.v0) + B0.w0.dot(p.rnB)) - (k.n.dot(A0.v0) + A0.w0.dot(p.rnA)) < -kImpactSpeed;
    }
    change = std::max(change, std::fabs(lambda));
    scale = std::max(scale, total);
    apply_normal<kStatic>(A, B, k, p, lambda);
  }

  void end_pass() {
    total_normal = total_normal_pass;
    twist_limit = twist_pass;
    // An impact (a point apart at the substep's start that pushes now) may take all kPasses;
    // resting contacts at most contacts.passes (default 8): with one pass a tower of twenty
    // cubes drifted 0.8 mm at the top in 10 s, with eight 0.01 mm; with 32 it cost three times as
    // much. (A face on a face is four points on three degrees of freedom: the passes share the
    // load out among them, converging by a factor 0.6-0.9 a pass. The large pyramid's resting
    // manifolds hit the cap in 43% of their solves, measured, and its drift is no worse with one.)
    // Converged when no impulse changed by more than a share of the largest: 1e-6 for a manifold
    // that has hit or can bounce (restitution needs the exact impact impulse: at 1e-4 a box
    // dropped flat with restitution 1 lost its height and tipped), 1e-4 for resting ones (warm
    // started, they are within that after a pass or two). Measured on the R3 scenes: the pile's
    // point updates fell from 1.95e8 to 1.05e8 (-46%), the tower's top drift rose from 1.1e-5 to
    // 3.2e-5 m (target 1e-4), its sink stayed 8.6 mm. Looser still (1e-3) let the tower drift 3.6e-4 m.
    had_impact = had_impact || impact;
    const double tolerance = (had_impact || k.restitution > 0) ? kImpactTolerance : kRestingTolerance;
    if (k.count == 1 || (!impact && pass + 1 >= q.resting_passes) || change <= tolerance * scale) done = true;
    if (++pass >= kPasses) done = true;
  }

  void finish(std::vector<SolverBody>& sb) {
    // No normal impulse and no friction, twist or rolling impulse: each of them would stay zero
    // (clamped to mu 0) and move nothing. (The sides of the large pyramid's rows, a gap apart:
    // a quarter of its manifolds.)
    if (total_normal == 0 && k.tangent_impulse[0] == 0 && k.tangent_impulse[1] == 0 && k.twist_impulse == 0 &&
        (k.rolling == 0 || f.rolling_impulse.isZero())) {
      write_back(sb);
      return;
    }
    const double limit = k.friction * total_normal;
    // Friction at the centre, the accumulated 2D impulse clamped to the disk of radius mu N.
    {
      // Tangent velocity at the centre: t_j.(vB + wB x fB - vA - wA x fA), the angular terms as
      // wB.(fB x t_j) - wA.(fA x t_j).
      const Vec3 dv = B.v - A.v;
      Eigen::Vector2d vt(k.t[0].dot(dv) + B.w.dot(k.fBt[0]) - A.w.dot(k.fAt[0]),
                         k.t[1].dot(dv) + B.w.dot(k.fBt[1]) - A.w.dot(k.fAt[1]));
      if (k.track >= 0) {
        const Vec3 turn = track_turn(q.tracked[k.track], f.p[0], A.w, B.w, q.h);
        vt += Eigen::Vector2d(k.t[0].dot(turn), k.t[1].dot(turn));
      }
      const Eigen::Vector2d old(k.tangent_impulse[0], k.tangent_impulse[1]);
      Eigen::Vector2d total = old - k.tangent_mass * vt;
      if (q.slip_speed > 0) {
        // Regularised Coulomb (contacts.slip_speed): below the slip speed v_s friction is a
        // damper, F = -c v with c = mu N / v_s, taken implicitly over the substep: the substep's
        // impulse is -c h v_end, v_end = vt + K d, so (M + c h 1) d = -M (c h vt + old), M = K^-1
        // (= tangent_mass); c h = mu lambda_N / v_s. As v_s -> 0 it becomes the sticking impulse.
        const double ch = limit / q.slip_speed;
        if (ch > 0) {
          const Eigen::Matrix2d A = k.tangent_mass + ch * Eigen::Matrix2d::Identity();
          total = old - A.inverse() * (k.tangent_mass * (ch * vt + old));
        } else {
          total.setZero();
        }
      }
      const double mag2 = total.squaredNorm();
      if (mag2 > limit * limit) total *= limit / std::sqrt(mag2);
      const Eigen::Vector2d d = total - old;
      k.tangent_impulse[0] = total.x();
      k.tangent_impulse[1] = total.y();
      apply_tangent<kStatic>(A, B, k, d.x(), d.y());
    }
    // Twist friction about the normal, limited by the pressure's moment arm over the patch.
    if (k.count > 1) {
      const double tl = k.friction * twist_limit;
      const double old = k.twist_impulse;
      const double total = std::clamp(old - k.twist_mass * k.n.dot(B.w - A.w), -tl, tl);
      k.twist_impulse = total;
      const double d = total - old;
      if constexpr (kStatic != kStaticA) A.w -= d * k.InA;
      if constexpr (kStatic != kStaticB) B.w += d * k.InB;
    }
    // Rolling resistance: a torque impulse against relative spin, at most rolling * lever * N. Below
    // the bound it stops the relative spin (K^-1 dw); at the bound it acts against the spin itself,
    // -rl dw / |dw| (the most dissipative torque of that size, as Coulomb friction against the
    // slip), not along the stopping impulse K^-1 dw, which for a body of unequal moments leans
    // toward its larger moments (4.6% less dissipation for a ball of moments 4, 4, 7.5 g m^2
    // spinning about no principal axis).
    if (k.rolling > 0) {
      const Vec3 dw = B.w - A.w;
      Vec3 total = f.rolling_impulse - f.rolling_mass * dw;
      const double rl = k.rolling * f.rolling_lever * total_normal;
      const double n2 = total.squaredNorm(), w2 = dw.squaredNorm();
      if (n2 > rl * rl) total = w2 > 0 ? Vec3(-rl / std::sqrt(w2) * dw) : Vec3(total * (rl / std::sqrt(n2)));
      const Vec3 d = total - f.rolling_impulse;
      f.rolling_impulse = total;
      if constexpr (kStatic != kStaticA) A.w -= A.s.inv_I * d;
      if constexpr (kStatic != kStaticB) B.w += B.s.inv_I * d;
    }
    write_back(sb);
  }

  void write_back(std::vector<SolverBody>& sb) const {
    if constexpr (kStatic != kStaticA) {
      sb[k.a].v = A.v;
      sb[k.a].w = A.w;
    }
    if constexpr (kStatic != kStaticB) {
      sb[k.b].v = B.v;
      sb[k.b].w = B.w;
    }
  }
};

// Flattened: GCC at -O2 inlines neither Eigen's 3x3 products nor the helpers above here, and the
// calls cost more than the arithmetic (the order of operations is the same either way).
// Returns whether the manifold was struck (see kImpactSpeed).
template <int kStatic>
__attribute__((flatten)) bool solve_one(SweepConstraint& k, ContactConstraint& f, const SolveParams& q,
                                        std::vector<SolverBody>& sb) {
  ManifoldSolve<kStatic> m(k, f, q, sb);
  m.block();
  while (!m.done) {
    m.start_pass();
    for (int jj = 0; jj < k.count; ++jj) m.point(jj);
    m.end_pass();
  }
  m.finish(sb);
  return m.struck;
}

// Two manifolds with no body in common (bar the static one, which is never written), each in
// exactly the operations and order of solve_one, their passes interleaved: Gauss-Seidel within a
// manifold is one long chain of dependent operations, and the processor runs two such chains
// side by side.
template <int kStatic0, int kStatic1>
__attribute__((flatten)) bool solve_two(SweepConstraint& k0, SweepConstraint& k1, ContactConstraint& f0,
                                        ContactConstraint& f1, const SolveParams& q,
                                        std::vector<SolverBody>& sb) {
  ManifoldSolve<kStatic0> m0(k0, f0, q, sb);
  ManifoldSolve<kStatic1> m1(k1, f1, q, sb);
  m0.block();
  m1.block();
  while (!m0.done && !m1.done) {
    m0.start_pass();
    m1.start_pass();
    const int n = std::max(k0.count, k1.count);
    for (int jj = 0; jj < n; ++jj) {
      if (jj < k0.count) m0.point(jj);
      if (jj < k1.count) m1.point(jj);
    }
    m0.end_pass();
    m1.end_pass();
  }
  while (!m0.done) {
    m0.start_pass();
    for (int jj = 0; jj < k0.count; ++jj) m0.point(jj);
    m0.end_pass();
  }
  while (!m1.done) {
    m1.start_pass();
    for (int jj = 0; jj < k1.count; ++jj) m1.point(jj);
    m1.end_pass();
  }
  m0.finish(sb);
  m1.finish(sb);
  return m0.struck || m1.struck;
}

template <int kStatic0>
bool solve_two_dispatch(SweepConstraint& k0, SweepConstraint& k1, ContactConstraint& f0,
                        ContactConstraint& f1, const SolveParams& q, std::vector<SolverBody>& sb) {
  switch (static_side(k1)) {
    case kStaticA:
      return solve_two<kStatic0, kStaticA>(k0, k1, f0, f1, q, sb);
    case kStaticB:
      return solve_two<kStatic0, kStaticB>(k0, k1, f0, f1, q, sb);
    default:
      return solve_two<kStatic0, kNoneStatic>(k0, k1, f0, f1, q, sb);
  }
}

}  // namespace

namespace {

bool solve_single(SweepConstraint& k, ContactConstraint& f, const SolveParams& q,
                  std::vector<SolverBody>& sb) {
  switch (static_side(k)) {
    case kStaticA:
      return solve_one<kStaticA>(k, f, q, sb);
    case kStaticB:
      return solve_one<kStaticB>(k, f, q, sb);
    default:
      return solve_one<kNoneStatic>(k, f, q, sb);
  }
}

bool solve_pair(SweepConstraint& k0, SweepConstraint& k1, ContactConstraint& f0, ContactConstraint& f1,
                const SolveParams& q, std::vector<SolverBody>& sb) {
  switch (static_side(k0)) {
    case kStaticA:
      return solve_two_dispatch<kStaticA>(k0, k1, f0, f1, q, sb);
    case kStaticB:
      return solve_two_dispatch<kStaticB>(k0, k1, f0, f1, q, sb);
    default:
      return solve_two_dispatch<kNoneStatic>(k0, k1, f0, f1, q, sb);
  }
}

}  // namespace

// Colour by colour; within a worker's share of a colour, two constraints at a time, interleaved
// (solve_two: they share no moving body, so this is exactly solving one after the other).
bool ContactSolver::solve(double h, bool use_bias, bool first_iteration) {
  const SolveParams q{1.0 / h,
                      in_.settings.max_push_out,
                      in_.settings.linear_slop,
                      1e-3 * in_.settings.linear_slop + 1e-12,
                      in_.settings.slip_speed,
                      in_.settings.passes,
                      use_bias,
                      first_iteration,
                      h,
                      tracked_.data(),
                      impulse_change_.data()};
  const wide::SolveParams wq{
      q.inv_h,
      q.max_push,
      q.slop,
      q.apart,
      {soft_.bias_rate, static_soft_.bias_rate},
      {soft_.mass_scale, static_soft_.mass_scale},
      {soft_.impulse_scale, static_soft_.impulse_scale},
      {soft_.impulse_scale / soft_.mass_scale, static_soft_.impulse_scale / static_soft_.mass_scale},
      q.resting_passes,
      use_bias,
      impulse_change_.data()};
  for (Flag& f : struck_) f.value = false;  // the pool may run everything as worker 0 of 1
  on_workers([&](int w, int nw) {
    bool struck = false;
    by_colour(
        w, nw,
        [&](int begin, int end) {
          int n = begin;
          for (; n + 1 < end; n += 2) {
            if (n + 3 < end) prefetch(sweep_[scalar_[n + 2]]), prefetch(sweep_[scalar_[n + 3]]);
            const int i = scalar_[n], i1 = scalar_[n + 1];
            struck |= solve_pair(sweep_[i], sweep_[i1], cons_[i], cons_[i1], q, sb_);
          }
          if (n < end) struck |= solve_single(sweep_[scalar_[n]], cons_[scalar_[n]], q, sb_);
        },
        [&](int begin, int end) {
          for (int i = begin; i < end; ++i) {
            struck |= wide::solve(bundles_[i], sb_.data(), wq);
          }
        });
    struck_[w].value = struck;
  });
  bool struck = false;
  for (int w = 0; w < workers_; ++w) struck = struck || struck_[w].value;
  return struck;
}

void ContactSolver::integrate_positions(double h) {
  on_workers([&](int w, int nw) {
    int begin, end;
    share((int)sb_.size() - 1, w, nw, begin, end);
    for (int k = begin + 1; k < end + 1; ++k) {
      SolverBody& b = sb_[k];
      b.dp += h * b.v;
      // World angular velocity: the rotation exp(h w / 2) multiplies from the left.
      b.dq = rotation_increment(b.w, h) * b.dq;
      if (need_dR_) b.dR = b.dq.toRotationMatrix();
    }
  });
  track_due_ = !tracked_.empty();
}

// The tracked points (sim/collision/tracked_contacts.hpp) found again after a substep's move, and made the
// constraints' anchors, with their bodies' world inertia of that orientation. Called before the
// next substep's velocity update, not at the move: the relax after the move then acts through the
// same constraint (anchors, inertia) as the solve before it, and only takes back the push-out.
// Done at the move (before the relax), it solved the new point's velocity jump, d.(w x r') h
// (track_turn), at once in the relax, the accumulated impulses carried it into the next
// substep's warm start, and that substep's solve took most of it back out: for Euler's disk at
// 20 degrees (n.(w x r') = 35 m/s^2 against g), the relax pushed 0.8 m g h and the solve was left
// with 0.2 m g h of accumulated normal impulse while its friction needed 0.26 m g h, and the
// Coulomb clamp (mu = 0.6 of the accumulated normal impulse) cut it. A clamped friction impulse
// lets the point slip at O(h) for the substep: O(h^2) per substep, O(h) over the run; the disk
// drifted off its steady motion by 9% in 5 s at h = 1/3840 s with friction (0.8% without), and
// is within 0.5% of it now (measured; tests/sim/scenarios/disks_test.cpp).
// A tracked body turns its contact point a good part of a radian per step (Euler's disk near its
// end, a tippe top): its world inertia, fixed for the step elsewhere, follows its orientation here,
// or the step's stale inertia makes an error of the first order in dt in its motion (a disk in
// steady rolling drifted off it, 36% in Omega^2 sin(alpha) after 1 s at 1/240 s, measured).
// Inside on_workers: the bodies' inertia in fixed shares, a barrier, then the points in fixed
// shares (each writes its own record and constraint, and reads its two bodies).
void ContactSolver::refresh_tracked(int w, int nw) {
  int begin, end;
  share((int)tracked_bodies_.size(), w, nw, begin, end);
  for (int j = begin; j < end; ++j) {
    const int k = tracked_bodies_[j];
    SolverBody& b = sb_[k];
    const int i = bodies_[k - 1];
    const BodyModel& m = in_.model[i];
    const Mat3 R = (b.dq * in_.state[i].q_WP).toRotationMatrix();
    b.inv_I = R * m.inv_I_P.asDiagonal() * R.transpose();
    if (gyro_[k]) I_W_[k] = R * m.I_P.asDiagonal() * R.transpose();
  }
  if (nw > 1) pool_->barrier();
  share((int)tracked_.size(), w, nw, begin, end);
  for (int j = begin; j < end; ++j) {
    TrackedContact& t = tracked_[j];
    ContactConstraint& k = cons_[t.con];
    const SolverBody& A = sb_[k.a];
    const SolverBody& B = sb_[k.b];
    if (!track_point(t, k, A, B)) continue;  // turned onto a face: keep the last point
    normal_terms(k.p[0], k.n, A, B);
    friction_terms(k, A, B);
    pack_sweep(t.con, false);
  }
}

// Restitution at the end of the substep in which the impact happens (Box3D applies it once after
// all substeps; then a body that hit early in the step rests on the surface for the remaining
// substeps and every bounce loses up to a step's travel: 0.5% of the height per bounce at 240 Hz,
// measured). Each bouncing point's normal velocity becomes -e times its impact velocity, solved
// for all of a manifold's bouncing points together (Gauss-Seidel to convergence: a box landing
// flat gets four equal impulses and no spin). The points' accumulated impulses are then cleared so
// that later substeps treat the separating points as fresh contacts instead of pulling the bounce
// back through the accumulated-impulse clamp.
void ContactSolver::restitution(double threshold) {
  if (!any_restitution_) return;
  on_workers([&](int w, int nw) {
    by_colour(
        w, nw,
        [&](int begin, int end) {
          for (int n = begin; n < end; ++n) {
            const int i = scalar_[n];
            if (sweep_[i].restitution > 0) restitution_one(sweep_[i], cons_[i], threshold);
          }
        },
        [](int, int) {});          // wide manifolds have no restitution
    if (nw > 1) pool_->barrier();  // every manifold has bounced
    // The next substep's start velocities, once every manifold has bounced: a later manifold's
    // bounce changes the velocity of a body this one shares (a row of balls), and a velocity taken
    // before it read as an acceleration over the substep and predicted a false impact speed (a
    // Newton's cradle then gained energy; measured).
    int begin, end;
    share((int)scalar_.size(), w, nw, begin, end);
    for (int n = begin; n < end; ++n) {
      const int i = scalar_[n];
      const SweepConstraint& k = sweep_[i];
      if (k.restitution == 0) continue;
      for (int j = 0; j < k.count; ++j)
        cons_[i].p[j].vn_prev = normal_velocity(sb_[k.a], sb_[k.b], k.n, k.p[j]);
    }
  });
}

void ContactSolver::restitution_one(SweepConstraint& k, ContactConstraint& f, double threshold) {
  const double slop = in_.settings.linear_slop + 1e-9;
  // Worked on in copies, written back for the moving sides only: the static body, shared by
  // every ground contact and read by other threads, is never written.
  SolverBody A = sb_[k.a];
  SolverBody B = sb_[k.b];
  double acc[4] = {0, 0, 0, 0};
  bool bounce[4] = {false, false, false, false};
  bool any = false;
  const Vec3 dp = B.dp - A.dp;
  const Mat3& RA = A.dR;
  const Mat3& RB = B.dR;
  // A manifold bounces when it pushed this substep; each of its points that touches now (gap
  // closed) bounces with it, pushed or not: a flat face landing is stopped by any three of its
  // four corners, but all four leave the floor together.
  bool pushed = false;
  for (int j = 0; j < k.count; ++j) {
    SweepPoint& p = k.p[j];
    bool& bounced = f.p[j].bounced;
    // A point that bounced and has come apart again may bounce again in the same step: in a
    // Newton's cradle with 1 mm gaps at 0.8 m/s, a ball is struck twice within 1/240 s, and
    // a second impact without restitution was inelastic (two struck balls then lost 29% of
    // the energy; measured).
    if (bounced && k.n.dot(dp + RB * p.cB - RA * p.cA) + p.adjusted_separation > slop) bounced = false;
    pushed = pushed || (p.normal_impulse > 0 && !bounced);
  }
  for (int j = 0; j < k.count && pushed; ++j) {
    const SweepPoint& p = k.p[j];
    const double s = k.n.dot(dp + RB * p.cB - RA * p.cA) + p.adjusted_separation;
    bounce[j] = !f.p[j].bounced && f.p[j].impact_velocity < -threshold && s <= slop;
    any = any || bounce[j];
  }
  if (!any) return;
  constexpr int kMaxIterations = 32;
  for (int it = 0; it < kMaxIterations; ++it) {
    double change = 0, scale = 0;
    for (int j = 0; j < k.count; ++j) {
      if (!bounce[j]) continue;
      const SweepPoint& p = k.p[j];
      const double vn = normal_velocity(A, B, k.n, p);
      const double total =
          std::max(acc[j] - p.normal_mass * (vn + k.restitution * f.p[j].impact_velocity), 0.0);
      apply_normal(A, B, k, p, total - acc[j]);
      change = std::max(change, std::fabs(total - acc[j]));
      scale = std::max(scale, total);
      acc[j] = total;
    }
    if (change <= 1e-12 * scale) break;
  }
  for (int j = 0; j < k.count; ++j) {
    if (!bounce[j]) continue;
    SweepPoint& p = k.p[j];
    p.max_normal_impulse = std::max(p.max_normal_impulse, p.normal_impulse + acc[j]);
    p.normal_impulse = 0;
    f.p[j].bounced = true;
  }
  if (k.a != 0) sb_[k.a].v = A.v, sb_[k.a].w = A.w;
  if (k.b != 0) sb_[k.b].v = B.v, sb_[k.b].w = B.w;
}

void ContactSolver::store_impulses(std::vector<Contact>& contacts) const {
  art_->store(contacts);
  on_workers([&](int w, int nw) {
    int begin, end;
    share((int)scalar_.size(), w, nw, begin, end);
    for (int n = begin; n < end; ++n) {
      const int i = scalar_[n];
      const SweepConstraint& k = sweep_[i];
      Contact& c = contacts[cons_[i].contact];
      for (int j = 0; j < k.count; ++j) {
        c.points[j].normal_impulse = k.p[j].normal_impulse;
      }
      c.friction_impulse_W = k.tangent_impulse[0] * k.t[0] + k.tangent_impulse[1] * k.t[1];
      c.twist_impulse = k.twist_impulse;
      c.rolling_impulse = cons_[i].rolling_impulse;
    }
    share((int)bundles_.size(), w, nw, begin, end);
    for (int i = begin; i < end; ++i) {
      const wide::Bundle& k = bundles_[i];
      for (int l = 0; l < wide::kLanes; ++l) {
        if (k.contact[l] < 0) continue;
        Contact& c = contacts[k.contact[l]];
        for (int j = 0; j < k.count[l]; ++j) c.points[j].normal_impulse = k.p[j].normal_impulse[l];
        const Vec3 n(k.n.x[l], k.n.y[l], k.n.z[l]), t0(k.t0.x[l], k.t0.y[l], k.t0.z[l]);
        const Vec3 t1 = n.cross(t0);  // as make_constraint's
        c.friction_impulse_W = k.tangent_impulse0[l] * t0 + k.tangent_impulse1[l] * t1;
        c.twist_impulse = k.twist_impulse[l];
        c.rolling_impulse.setZero();
      }
    }
  });
}

void ContactSolver::finish(const BodyModel* model, MotionState* state, std::vector<char>& touched_none) {
  for (int k = 1; k < (int)sb_.size(); ++k) touched_none[k] = 1;
  touched_none[0] = 0;
  for (int i : scalar_) {
    const SweepConstraint& k = sweep_[i];
    bool touched = false;
    for (int j = 0; j < k.count; ++j) touched = touched || k.p[j].max_normal_impulse > 0;
    if (touched) touched_none[k.a] = touched_none[k.b] = 0;
  }
  for (const wide::Bundle& k : bundles_)
    for (int l = 0; l < wide::kLanes; ++l) {
      if (k.touched[l]) touched_none[k.a[l]] = touched_none[k.b[l]] = 0;
    }
  art_->touched(touched_none);
  art_->finish(state);
  for (int k = 1; k < (int)sb_.size(); ++k) {
    const int i = bodies_[k - 1];
    if (model[i].inv_mass == 0 || touched_none[k]) continue;
    const SolverBody& b = sb_[k];
    MotionState& s = state[i];
    s.x_W += b.dp;
    s.q_WP = (b.dq * s.q_WP).normalized();
    s.v_W = b.v;
    s.w_P = s.q_WP.conjugate() * b.w;
  }
}

// The step's substeps (Box2D's solver stages), each stage timed into `clock`.
void ContactSolver::run_substeps(int& settle, StageClock& clock, Profile& profile) {
  const ContactSettings& cs = in_.settings;
  const double h = in_.dt / in_.substeps;
  for (int sub = 0; sub < in_.substeps; ++sub) {
    const bool art = !art_->empty();
    {
      StageClock::Scope t(clock, Stage::integrate_velocities);
      inertia_due_ = sub > 0;  // the first substep's is prepare's
      integrate_velocities(h);
      if (art) art_->integrate_velocities(h);
    }
    {
      StageClock::Scope t(clock, Stage::warm_start);
      if (warm_start()) ++profile.body_warm_starts;
      if (art) art_->warm_start(sb_);
    }
    // One more sweep each while the last impact settles (kImpactSettleTime), and one at once on
    // an impact in this substep's first sweeps.
    const int sweeps = cs.iterations + (settle > 0 ? 1 : 0);
    {
      StageClock::Scope t(clock, Stage::solve);
      bool struck = false;
      for (int it = 0; it < sweeps; ++it) {
        struck |= solve(h, true, it == 0);
        if (art) art_->solve(sb_, h, true);
      }
      profile.sweeps += sweeps;
      if (struck && settle == 0) {
        solve(h, true, false), ++profile.sweeps;
        if (art) art_->solve(sb_, h, true);
      }
      if (struck) {
        settle = (int)std::ceil(kImpactSettleTime / h - 1e-9) + 1;
        ++profile.impact_substeps;
      }
    }
    {
      StageClock::Scope t(clock, Stage::integrate_positions);
      integrate_positions(h);
      if (art) art_->integrate_positions(h, sb_);
    }
    {
      StageClock::Scope t(clock, Stage::relax);
      const int relax = cs.iterations + (settle > 0 ? 1 : 0);
      for (int it = 0; it < relax; ++it) {
        solve(h, false, false);
        if (art) art_->solve(sb_, h, false);
      }
      profile.sweeps += relax;
      if (settle > 0) --settle;
    }
    {
      StageClock::Scope t(clock, Stage::restitution);
      restitution(cs.restitution_threshold);
      if (art) art_->restitution(sb_, cs.restitution_threshold);
    }
  }
  for (Stage s : {Stage::integrate_velocities, Stage::warm_start, Stage::solve, Stage::integrate_positions,
                  Stage::relax, Stage::restitution})
    clock.ran(s);
}

}  // namespace simreel
