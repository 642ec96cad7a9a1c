// World's contact stages (the pipeline is in world.cpp): broad phase, collide, the solver's
// substeps, and kinematic bodies.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

#include "sim/collision/narrow/mesh.hpp"
#include <simreel/error.hpp>
#include "sim/base/worker_pool.hpp"
#include "sim/world/world_impl.hpp"
#include "sim/base/pair_key.hpp"

namespace simreel {

void WorldImpl::init_contacts() {
  const int n = (int)defs_.size();
  const ContactSettings& cs = cfg_.contacts;
  if (cs.substeps < 0 || cs.iterations < 1 || cs.passes < 1)
    throw InputError(
        "contacts: substeps must be at least 1 (or 0: automatic), iterations and passes at least 1");
  // Automatic: substeps of at most 1/960 s.
  base_substeps_ =
      cs.substeps > 0 ? cs.substeps : std::max(1, (int)std::ceil(cfg_.dt * kContactSubstepRate - 1e-9));
  substeps_ = base_substeps_;
  if (!(cs.contact_hertz >= 0) || !(cs.damping_ratio >= 0) || !(cs.max_push_out >= 0) ||
      !(cs.restitution_threshold >= 0) || !(cs.speculative_distance >= 0) || !(cs.linear_slop >= 0) ||
      !(cs.rolling_resistance >= 0) || !(cs.slip_speed >= 0))
    throw InputError("contacts: settings must be non-negative numbers");
  std::vector<std::string> notes;
  shapes_ = std::make_unique<ShapeTable>(defs_, model_, notes);
  extents_.build(*shapes_, n);
  for (std::string& s : notes) warnings_.push_back(std::move(s));
  for (const auto& [a, b] : cfg_.ignore_pairs) {
    if (a < 0 || b < 0 || a >= n || b >= n) throw InputError("ignore_pairs: body index out of range");
    ignore_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(ignore_.begin(), ignore_.end());
  const ShapeTable& st = *shapes_;
  profile_.shapes = st.size();
  shape_moving_.assign(st.size(), 0);
  boxes_.assign(st.size(), Aabb{});
  poses_.assign(st.size(), Pose{});
  bool any_moving = false;
  for (int i = 0; i < st.size(); ++i) {
    const ShapeRecord& r = st[i];
    // A shape that belongs to no group or collides with no group never touches anything.
    if (r.group == 0 || r.mask == 0) continue;
    shape_moving_[i] = !model_[r.body].is_static;
    if (r.geom.kind == CollideKind::plane) {
      plane_shapes_.push_back(i);
      plane_poses_.push_back(ShapeTable::world_pose(r, state_[r.body]));
    } else {
      sweep_shapes_.push_back(i);
      any_moving = any_moving || shape_moving_[i];
      if (!shape_moving_[i]) {
        Aabb b = ShapeTable::bounds(r.geom, ShapeTable::world_pose(r, state_[r.body]));
        const Vec3 m = Vec3::Constant(cs.speculative_distance);
        boxes_[i] = Aabb{b.lo - m, b.hi + m};
      }
    }
  }
  collide_enabled_ = any_moving && (sweep_shapes_.size() + plane_shapes_.size() >= 2);
  in_contact_.assign(n, 0);
  solver_index_.assign(n, 0);
  free_.resize(groups_.size());
  if (!collide_enabled_) return;
  // Bodies overlapping at the start: a warning naming the pair and the depth.
  stage_broad_phase();
  stage_collide();
  for (const Contact& c : contacts_) {
    double depth = 0;
    for (int j = 0; j < c.count; ++j) depth = std::max(depth, -c.points[j].separation);
    if (depth > cs.linear_slop) {
      std::ostringstream os;
      os << "bodies '" << defs_[c.body_a].name << "' and '" << defs_[c.body_b].name << "' overlap by "
         << depth << " m at the start; contacts will push them apart (at most " << cs.max_push_out << " m/s)";
      warnings_.push_back(os.str());
    }
  }
  contact_stats_ = ContactStats{};
  profile_.pairs = profile_.contact_points = 0;
}

bool WorldImpl::shapes_may_touch(int a, int b) const {
  const ShapeRecord& A = (*shapes_)[a];
  const ShapeRecord& B = (*shapes_)[b];
  if (A.body == B.body) return false;
  if (model_[A.body].inv_mass == 0 && model_[B.body].inv_mass == 0) return false;
  if (!filters_allow(A, B)) return false;
  if (!ignore_.empty()) {
    const std::pair<int, int> p(std::min(A.body, B.body), std::max(A.body, B.body));
    if (std::binary_search(ignore_.begin(), ignore_.end(), p)) return false;
  }
  return true;
}

// World boxes of the moving shapes, grown by the speculative distance and by the farthest any
// point of the shape can travel this step (|v| + |w| r) dt, so a pair that can touch within the
// step is found before it does. Only the active shapes are looked at: those of awake bodies, and
// once those of a body that fell asleep (its box then has no motion margin: a function of its
// pose alone, as a resumed run computes it). Static and sleeping shapes cost nothing.
// (Flattened: GCC at -O2 calls Eigen's small products and the pose and bounds helpers here
// instead of inlining them.)
__attribute__((flatten)) void WorldImpl::stage_broad_phase() {
  const ShapeTable& st = *shapes_;
  const double spec = cfg_.contacts.speculative_distance, dt = cfg_.dt;
  active_shapes_.clear();
  for (int b : islands_.awake_bodies())
    for (int i = extents_.shape_begin[b]; i < extents_.shape_begin[b + 1]; ++i)
      if (shape_moving_[i]) active_shapes_.push_back(i);  // (planes are static)
  // A body that fell asleep: its box at rest (v = w = 0 now), then nothing until it wakes.
  std::vector<int>& freeze = islands_.pending_freeze();
  active_shapes_.insert(active_shapes_.end(), freeze.begin(), freeze.end());
  freeze.clear();
  for (int i : active_shapes_) {
    const ShapeRecord& r = st[i];
    const MotionState& s = state_[r.body];
    poses_[i] = ShapeTable::world_pose(r, s);  // kept for collide: the state does not change between
    const Aabb b = ShapeTable::bounds(r.geom, poses_[i]);
    const double reach = extents_.shape_reach[i] * s.w_P.norm();
    const Vec3 m = Vec3::Constant(spec + (s.v_W.norm() + reach) * dt);
    boxes_[i] = Aabb{b.lo - m, b.hi + m};
  }
  broad_.update(
      boxes_, active_shapes_, sweep_shapes_, plane_shapes_, plane_poses_, shape_moving_,
      [this](int a, int b) { return shapes_may_touch(a, b); }, pairs_);
  profile_.pairs += (long)pairs_.size();
}

// Narrow phase on each candidate pair; last step's records of the same pair (found by a merge of
// the sorted lists) give its cache and its points' impulses by id. In three passes, so that the
// narrow phase, nearly all of the work, runs on every thread, with the results of one sequential
// pass in key order:
//   1. (serial) the merge: each pair's slots in the new list (one, or kMaxMeshManifolds for a pair
//      with a static triangle mesh), its last-step records, and whether they are kept as they
//      were (both sides inert: asleep, static or a resting kinematic);
//   2. (threads) each pair not kept collided into its own slots (collide_job): pairs are
//      independent; kept records copied, unless they rest in resting_;
//   3. (serial, in key order) the touches: a pair with points wakes the islands of its sleeping
//      bodies and puts its bodies in contact. A pair kept in pass 1 whose body was woken by a pair
//      before it in key order is collided here, where the sequential pass would have collided it
//      (a pair after the one that woke it; one before it keeps its records, as there). Then the
//      records are packed (a mesh pair leaves unused slots).
// Records of a pair whose two sides are asleep or static live in resting_, apart from contacts_,
// and stay where they are while the pair sleeps: a sleeping pair costs its key in the merge and
// nothing else (no copy; the solver and the sleep stage never see it). Both lists are rebuilt
// only in a step where a record enters or leaves resting_ (an island falls asleep or wakes, a
// pair leaves the broad phase). contacts_ and resting_ together, in key order, are the one list
// the sequential pass keeps (and the saved state holds).
void WorldImpl::stage_collide() {
  const ShapeTable& st = *shapes_;
  collide_jobs_.clear();
  size_t old = 0, rest = 0;
  int slots = 0, busy = 0;     // busy: pairs collided or copied
  bool packed = true;          // every job fills its slots exactly
  bool resting_moves = false;  // a record enters or leaves resting_ this step
  for (uint64_t key : pairs_) {
    while (old < contacts_.size() && contacts_[old].key() < key) ++old;
    size_t old_end = old;
    while (old_end < contacts_.size() && contacts_[old_end].key() == key) ++old_end;
    // Resting records of a pair the broad phase no longer reports are dropped, as contacts_' are.
    for (; rest < resting_keys_.size() && resting_keys_[rest] < key; ++rest) resting_moves = true;
    size_t rest_end = rest;
    while (rest_end < resting_keys_.size() && resting_keys_[rest_end] == key) ++rest_end;
    const int a = pair_first(key), b = pair_second(key);
    const int body_a = extents_.shape_body[a], body_b = extents_.shape_body[b];
    CollideJob job;
    job.key = key;
    job.body_a = body_a;
    job.body_b = body_b;
    job.stored = rest_end > rest;
    job.prev = job.stored ? (int)rest : old_end > old ? (int)old : -1;
    job.prev_count = job.stored ? (int)(rest_end - rest) : (int)(old_end - old);
    // A pair that cannot move keeps its records as they were when it fell asleep: neither body
    // has moved since.
    job.keep = islands_.sleeping() > 0 && inert(body_a) && inert(body_b);
    job.count = job.points = 0;
    if (job.keep && job.stored) {
      job.mesh = false;  // (not looked at: the shape records are not touched)
      job.cap = 0;       // its records stay in resting_
      job.slot = -1;
      job.count = job.prev_count;
    } else {
      job.mesh = st[a].geom.kind == CollideKind::mesh || st[b].geom.kind == CollideKind::mesh;
      // Woken since (its records leave resting_), or fell asleep last step (they enter it).
      resting_moves = resting_moves || job.stored || (job.keep && resting(body_a) && resting(body_b));
      job.cap = std::max(job.mesh ? kMaxMeshManifolds : 1, job.prev_count);
      job.slot = slots;
      slots += job.cap;
      ++busy;
      packed = packed && !job.mesh && !(job.keep && job.prev_count != 1);
    }
    collide_jobs_.push_back(job);
    rest = rest_end;
  }
  resting_moves = resting_moves || rest < resting_keys_.size();
  const int n = (int)collide_jobs_.size();
  contacts_next_.resize(slots);
  collide_sums_.resize(cfg_.threads);
  // Blocks of pairs claimed from a shared counter (pairs cost from a sphere-plane formula to a
  // hull-hull clipping, so fixed shares would leave one thread waiting): which thread collides a
  // pair changes nothing, as each writes its own slots and the deepest overlap is a maximum.
  constexpr int kBlock = 32;
  std::atomic<int> next_block{0};
  auto work = [&](int w, int) {
    double deepest = 0;
    for (int begin; (begin = kBlock * next_block.fetch_add(1, std::memory_order_relaxed)) < n;) {
      const int end = std::min(n, begin + kBlock);
      for (int j = begin; j < end; ++j) {
        CollideJob& job = collide_jobs_[j];
        if (job.keep) {
          if (job.stored) continue;
          for (int k = 0; k < job.prev_count; ++k) contacts_next_[job.slot + k] = contacts_[job.prev + k];
          job.count = job.prev_count;
        } else {
          deepest = std::max(deepest, collide_job(job));
        }
      }
    }
    collide_sums_[w].value = deepest;
  };
  // Threads only for enough pairs to be worth a pool run (the result is the same either way).
  // (The pool may also run it as worker 0 of 1: sim/base/worker_pool.hpp.)
  constexpr int kMinParallelPairs = 64;
  for (ChunkSum& d : collide_sums_) d.value = 0;
  if (pool_ && busy >= kMinParallelPairs)
    pool_->run(work);
  else
    work(0, 1);
  for (const ChunkSum& d : collide_sums_)
    contact_stats_.max_penetration = std::max(contact_stats_.max_penetration, d.value);

  std::fill(in_contact_.begin(), in_contact_.end(), 0);
  int points = 0;
  bool woke = false;
  for (CollideJob& job : collide_jobs_) {
    const int body_a = job.body_a, body_b = job.body_b;
    if (job.keep) {
      // (Only a wake in this pass can end a kept pair's rest.)
      if (!woke || (inert(body_a) && inert(body_b))) continue;
      // Woken by a pair before this one: collided now, as the sequential pass would.
      job.keep = false;
      if (job.stored) {
        // Slots after all others (the records are then packed by the rebuild below).
        job.mesh = st[pair_first(job.key)].geom.kind == CollideKind::mesh ||
                   st[(int)(job.key & 0xFFFFFFFFu)].geom.kind == CollideKind::mesh;
        job.cap = std::max(job.mesh ? kMaxMeshManifolds : 1, job.prev_count);
        job.slot = (int)contacts_next_.size();
        contacts_next_.resize(contacts_next_.size() + job.cap);
        resting_moves = true;
      }
      contact_stats_.max_penetration = std::max(contact_stats_.max_penetration, collide_job(job));
      packed = packed && job.count == job.cap;
    }
    if (job.points <= 0) continue;
    points += job.points;
    // Something awake comes within reach of a sleeping body: its island wakes.
    if (islands_.asleep(body_a)) wake(body_a), woke = true;
    if (islands_.asleep(body_b)) wake(body_b), woke = true;
    in_contact_[body_a] = in_contact_[body_a] || !model_[body_a].is_static;
    in_contact_[body_b] = in_contact_[body_b] || !model_[body_b].is_static;
  }
  // A resting pair woken by a pair after it in key order keeps its records, which leave resting_.
  if (woke && !resting_moves)
    for (const CollideJob& job : collide_jobs_)
      if (job.keep && job.stored && !(resting(job.body_a) && resting(job.body_b))) {
        resting_moves = true;
        break;
      }
  if (resting_moves) {
    // Both lists afresh, each in key order: a pair's records go to resting_ if both its bodies
    // are asleep or static now, else to contacts_ (last step's contacts_ is no longer read).
    contacts_.clear();
    resting_next_.clear();
    resting_keys_next_.clear();
    for (const CollideJob& job : collide_jobs_) {
      const Contact* from = job.keep && job.stored ? &resting_[job.prev] : &contacts_next_[job.slot];
      if (resting(job.body_a) && resting(job.body_b)) {
        resting_next_.insert(resting_next_.end(), from, from + job.count);
        resting_keys_next_.insert(resting_keys_next_.end(), job.count, job.key);
      } else {
        contacts_.insert(contacts_.end(), from, from + job.count);
      }
    }
    resting_.swap(resting_next_);
    resting_keys_.swap(resting_keys_next_);
  } else {
    if (!packed) {
      // Records after a job's unused slots move up, in order.
      int to = 0;
      for (const CollideJob& job : collide_jobs_) {
        if (job.keep && job.stored) continue;
        for (int k = 0; k < job.count; ++k, ++to)
          if (to != job.slot + k) contacts_next_[to] = contacts_next_[job.slot + k];
      }
      contacts_next_.resize(to);
    }
    contacts_.swap(contacts_next_);
  }
  if (woke) {
    // Contacts kept for bodies that slept until now (earlier in key order) are theirs again.
    for (const Contact& c : contacts_) {
      if (c.count == 0) continue;
      if (!islands_.asleep(c.body_a) && !model_[c.body_a].is_static) in_contact_[c.body_a] = 1;
      if (!islands_.asleep(c.body_b) && !model_[c.body_b].is_static) in_contact_[c.body_b] = 1;
    }
  }
  contact_stats_.contacts_max = std::max(contact_stats_.contacts_max, points);
  profile_.contact_points += points;
  contact_bodies_.clear();
  for (int i = 0; i < (int)in_contact_.size(); ++i)
    if (in_contact_[i]) contact_bodies_.push_back(i);
}

double WorldImpl::collide_job(CollideJob& job) {
  Contact* out = &contacts_next_[job.slot];
  double deepest = 0;
  if (job.mesh) {
    job.count = collide_mesh_pair(job, out, job.points, deepest);
  } else {
    deepest = collide_pair(job, *out);
    job.count = 1;
    job.points = out->count;
  }
  return deepest;
}

// One convex pair's narrow phase into c (overwritten); returns its deepest overlap (m, >= 0).
double WorldImpl::collide_pair(const CollideJob& job, Contact& c) const {
  const ShapeTable& st = *shapes_;
  const double spec = cfg_.contacts.speculative_distance, dt = cfg_.dt;
  const int a = pair_first(job.key), b = pair_second(job.key);
  const Contact* prev = prev_record(job);
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const MotionState& sa = state_[A.body];
  const MotionState& sb = state_[B.body];
  new_contact(c, a, b, prev);
  if (prev) c.cache = prev->cache;
  // How far the two can close this step, bounded: relative speed of their farthest points.
  const double reach_a = extents_.shape_reach[a] * sa.w_P.norm();
  const double reach_b = extents_.shape_reach[b] * sb.w_P.norm();
  const double closing = ((sa.v_W - sb.v_W).norm() + reach_a + reach_b) * dt;
  Manifold m;
  Vec3 offset[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  // World poses: the broad phase's for moving shapes (made from this same state).
  const Pose xa = shape_moving_[a] ? poses_[a] : ShapeTable::world_pose(A, sa);
  const Pose xb = shape_moving_[b] ? poses_[b] : ShapeTable::world_pose(B, sb);
  // A fast pair's speculative manifold is taken where it will touch (sim/world/continuous.cpp).
  const int n = fast_pair(a, b, closing) ? collide_ahead(a, b, xa, xb, spec, closing, c.cache, m, offset)
                                         : collide(A.geom, xa, B.geom, xb, spec + closing, c.cache, m);
  c.normal_W = m.normal_W;
  c.count = n;
  double deepest = 0;
  for (int j = 0; j < n; ++j) {
    ContactPoint& p = c.points[j];
    p.id = m.points[j].id;
    p.p_W = m.points[j].p_W;
    p.separation = m.points[j].separation;
    p.offset_W = offset[j];
    if (prev) {
      for (int k = 0; k < prev->count; ++k)
        if (prev->points[k].id == p.id) {
          p.normal_impulse = prev->points[k].normal_impulse;
          break;
        }
    }
    deepest = std::max(deepest, -p.separation);
  }
  return deepest;
}

// The soft step over the bodies in contact (sim/solver/contact_solver.hpp), then their new state.
bool WorldImpl::stage_solve_contacts() {
  const ContactSettings& cs = cfg_.contacts;
  // Automatic substeps: at least base_substeps_ (substeps of <= 1/240 s), more while a body in
  // contact turns fast, so that none turns more than kContactMaxSubstepAngle per substep (the
  // solver's rotation and lever arms are first order in that angle: a top spinning at 54 rad/s
  // precessed 3.4% slow with one 1/240 s substep, 0.35% with four, measured). A function of the
  // state only, so runs stay deterministic and a resumed run takes the same substeps.
  substeps_ = base_substeps_;
  if (cfg_.contacts.substeps == 0) {
    double w_max = 0;
    for (int i : contact_bodies_) w_max = std::max(w_max, state_[i].w_P.norm());
    const double need = std::ceil(w_max * cfg_.dt / kContactMaxSubstepAngle - 1e-9);
    substeps_ = std::max(substeps_, (int)std::min(need, (double)kContactMaxSubsteps));
  }
  {
    StageClock::Scope t(clock_, Stage::prepare_contacts);
    SolverInput in;
    in.model = model_.data();
    in.state = state_.data();
    in.wrench = wrench_dirty_ ? wrench_.data() : nullptr;
    in.gravity = cfg_.gravity;
    in.dt = cfg_.dt;
    in.substeps = substeps_;
    in.shapes = shapes_.get();
    in.settings = cs;
    in.pool = pool_.get();
    solver_.prepare(in, contact_bodies_, contacts_, solver_index_);
  }
  clock_.ran(Stage::prepare_contacts);
  solver_.run_substeps(settle_substeps_, clock_, profile_);
  bool finite = true;
  {
    StageClock::Scope t(clock_, Stage::store_impulses);
    solver_.store_impulses(contacts_);
    touched_none_.resize(contact_bodies_.size() + 1);
    solver_.finish(model_.data(), state_.data(), touched_none_);
    // Bodies that received no impulse after all (they only came within the speculative distance)
    // go back to the free-flight integrators, which are exact for them.
    double sum = 0;
    int solved = 0;
    for (size_t k = 0; k < contact_bodies_.size(); ++k) {
      const int i = contact_bodies_[k];
      solver_index_[i] = 0;
      if (touched_none_[k + 1]) {
        in_contact_[i] = 0;
        continue;
      }
      ++solved;
      const MotionState& s = state_[i];
      sum += s.q_WP.w() + s.x_W.x() + s.x_W.y() + s.x_W.z() + s.v_W.x() + s.w_P.x();
    }
    finite = std::isfinite(sum);
    for (size_t g = 0; g < groups_.size(); ++g) {
      free_[g].clear();
      for (int i : groups_[g].bodies)
        if (!in_contact_[i] && !islands_.asleep(i)) free_[g].push_back(i);
    }
    profile_.solver_bodies += solved;
    if (pool_) profile_.pool_runs = pool_->runs(), profile_.pool_alone_runs = pool_->alone_runs();
  }
  clock_.ran(Stage::store_impulses);
  return finite;
}

// Kinematic bodies move at their given velocity, exactly: x += h v, and a constant world angular
// velocity w turns the orientation by exp(h w / 2) (w_P is re-expressed so that w stays fixed).
void WorldImpl::stage_kinematic() {
  const double h = cfg_.dt;
  for (int i : kinematic_) {
    MotionState& s = state_[i];
    const Vec3 w_W = s.q_WP * s.w_P;
    s.x_W += h * s.v_W;
    s.q_WP = (rotation_increment(w_W, h) * s.q_WP).normalized();
    s.w_P = s.q_WP.conjugate() * w_W;
  }
}

// (Assigned whole: the slots are reused from step to step.)
void WorldImpl::new_contact(Contact& c, int a, int b, const Contact* prev) const {
  const ShapeRecord& A = (*shapes_)[a];
  const ShapeRecord& B = (*shapes_)[b];
  c = Contact{};
  c.shape_a = a;
  c.shape_b = b;
  c.body_a = A.body;
  c.body_b = B.body;
  c.friction = std::sqrt(A.friction * B.friction);
  c.restitution = std::max(A.restitution, B.restitution);
  if (prev) {
    c.friction_impulse_W = prev->friction_impulse_W;
    c.twist_impulse = prev->twist_impulse;
    c.rolling_impulse = prev->rolling_impulse;
  }
}

}  // namespace simreel
