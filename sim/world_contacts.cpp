// World's contact stages (the pipeline is in world.cpp): broad phase, collide, the solver's
// substeps, and kinematic bodies.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include "sim/error.hpp"
#include "sim/task_pool.hpp"
#include "sim/world.hpp"

namespace simreel {

namespace {

struct StageTimer {
  bool on;
  double* acc;
  std::chrono::steady_clock::time_point t0;
  StageTimer(bool enabled, double* sink) : on(enabled), acc(sink) {
    if (on) t0 = std::chrono::steady_clock::now();
  }
  ~StageTimer() {
    if (on) *acc += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
};

}  // namespace

void World::init_contacts() {
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

bool World::shapes_may_touch(int a, int b) const {
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
// step is found before it does. (Flattened: GCC at -O2 calls Eigen's small products and the pose
// and bounds helpers here instead of inlining them.)
__attribute__((flatten)) void World::stage_broad_phase() {
  const ShapeTable& st = *shapes_;
  const double spec = cfg_.contacts.speculative_distance, dt = cfg_.dt;
  for (int i : sweep_shapes_) {
    if (!shape_moving_[i]) continue;
    const ShapeRecord& r = st[i];
    const MotionState& s = state_[r.body];
    poses_[i] = ShapeTable::world_pose(r, s);  // kept for collide: the state does not change between
    const Aabb b = ShapeTable::bounds(r.geom, poses_[i]);
    const double reach = (r.p_PC.norm() + r.geom.bounding_radius) * s.w_P.norm();
    const Vec3 m = Vec3::Constant(spec + (s.v_W.norm() + reach) * dt);
    boxes_[i] = Aabb{b.lo - m, b.hi + m};
  }
  broad_.update(
      boxes_, sweep_shapes_, plane_shapes_, plane_poses_, shape_moving_,
      [this](int a, int b) { return shapes_may_touch(a, b); }, pairs_);
  profile_.pairs += (long)pairs_.size();
}

// Narrow phase on each candidate pair; last step's contact for the same pair (found by a merge
// of the two sorted lists) gives its cache and its points' impulses by id. In three passes, so
// that the narrow phase, nearly all of the work, runs on every thread:
//   1. (serial) the merge: each pair's record slot in the new list, its last-step record, and
//      whether it is kept as it was (both sides inert: asleep, static or a resting kinematic);
//   2. (threads) collide() on each pair not kept, into its own slot: pairs are independent;
//   3. (serial, in key order) islands woken by a touch, and the bodies in contact. A pair kept in
//      pass 1 whose body has just woken is collided then, until no more islands wake.
void World::stage_collide() {
  collide_jobs_.clear();
  size_t old = 0;
  for (uint64_t key : pairs_) {
    while (old < contacts_.size() && contacts_[old].key() < key) ++old;
    const int prev = (old < contacts_.size() && contacts_[old].key() == key) ? (int)old : -1;
    const int a = (int)(key >> 32), b = (int)(key & 0xFFFFFFFFu);
    // A pair that cannot move keeps its contact as it was when it fell asleep: neither body has
    // moved since.
    const bool keep = sleeping_ > 0 && inert((*shapes_)[a].body) && inert((*shapes_)[b].body);
    if (keep && prev < 0) continue;
    collide_jobs_.push_back(CollideJob{key, prev, keep});
  }
  const int n = (int)collide_jobs_.size();
  contacts_next_.resize(n);
  collide_sums_.resize(cfg_.threads);
  // Blocks of pairs claimed from a shared counter (pairs cost from a sphere-plane formula to a
  // hull-hull clipping, so fixed shares would leave one thread waiting): which thread collides a
  // pair changes nothing, as each writes its own slot and the deepest overlap is a maximum.
  constexpr int kBlock = 32;
  std::atomic<int> next_block{0};
  auto work = [&](int w, int) {
    double deepest = 0;
    for (int begin; (begin = kBlock * next_block.fetch_add(1, std::memory_order_relaxed)) < n;) {
      const int end = std::min(n, begin + kBlock);
      for (int j = begin; j < end; ++j) {
        const CollideJob& job = collide_jobs_[j];
        if (job.keep)
          contacts_next_[j] = contacts_[job.prev];
        else
          deepest = std::max(deepest, collide_pair(job, contacts_next_[j]));
      }
    }
    collide_sums_[w].value = deepest;
  };
  // Threads only for enough pairs to be worth a pool run (the result is the same either way).
  // (The pool may also run it as worker 0 of 1: sim/task_pool.hpp.)
  constexpr int kMinParallelPairs = 64;
  for (ChunkSum& d : collide_sums_) d.value = 0;
  if (pool_ && n >= kMinParallelPairs)
    pool_->run(work);
  else
    work(0, 1);
  for (const ChunkSum& d : collide_sums_)
    contact_stats_.max_penetration = std::max(contact_stats_.max_penetration, d.value);

  std::fill(in_contact_.begin(), in_contact_.end(), 0);
  int points = 0;
  bool woke = false;
  auto touch = [&](const Contact& c) {
    if (c.count == 0) return;
    points += c.count;
    // Something awake comes within reach of a sleeping body: its island wakes.
    if (asleep_[c.body_a] >= 0) wake(c.body_a), woke = true;
    if (asleep_[c.body_b] >= 0) wake(c.body_b), woke = true;
    in_contact_[c.body_a] = in_contact_[c.body_a] || !model_[c.body_a].is_static;
    in_contact_[c.body_b] = in_contact_[c.body_b] || !model_[c.body_b].is_static;
  };
  for (int j = 0; j < n; ++j)
    if (!collide_jobs_[j].keep) touch(contacts_next_[j]);
  while (woke) {
    woke = false;
    for (int j = 0; j < n; ++j) {
      CollideJob& job = collide_jobs_[j];
      if (!job.keep || (inert(contacts_next_[j].body_a) && inert(contacts_next_[j].body_b))) continue;
      job.keep = false;
      contact_stats_.max_penetration =
          std::max(contact_stats_.max_penetration, collide_pair(job, contacts_next_[j]));
      touch(contacts_next_[j]);
    }
  }
  contacts_.swap(contacts_next_);
  contact_stats_.contacts_max = std::max(contact_stats_.contacts_max, points);
  profile_.contact_points += points;
  contact_bodies_.clear();
  for (int i = 0; i < (int)in_contact_.size(); ++i)
    if (in_contact_[i]) contact_bodies_.push_back(i);
}

// One pair's narrow phase into c (overwritten); returns its deepest overlap (m, >= 0). Reads only
// the state, the shapes, this step's poses and last step's contact list: pairs run in parallel.
double World::collide_pair(const CollideJob& job, Contact& c) const {
  const ShapeTable& st = *shapes_;
  const double spec = cfg_.contacts.speculative_distance, dt = cfg_.dt;
  const int a = (int)(job.key >> 32), b = (int)(job.key & 0xFFFFFFFFu);
  const Contact* prev = job.prev >= 0 ? &contacts_[job.prev] : nullptr;
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const MotionState& sa = state_[A.body];
  const MotionState& sb = state_[B.body];
  c = Contact{};
  c.shape_a = a;
  c.shape_b = b;
  c.body_a = A.body;
  c.body_b = B.body;
  c.friction = std::sqrt(A.friction * B.friction);
  c.restitution = std::max(A.restitution, B.restitution);
  if (prev) {
    c.cache = prev->cache;
    c.friction_impulse_W = prev->friction_impulse_W;
    c.twist_impulse = prev->twist_impulse;
    c.rolling_impulse = prev->rolling_impulse;
  }
  // How far the two can close this step, bounded: relative speed of their farthest points.
  const double reach_a = (A.p_PC.norm() + A.geom.bounding_radius) * sa.w_P.norm();
  const double reach_b = (B.p_PC.norm() + B.geom.bounding_radius) * sb.w_P.norm();
  const double closing = ((sa.v_W - sb.v_W).norm() + reach_a + reach_b) * dt;
  Manifold m;
  // World poses: the broad phase's for moving shapes (made from this same state).
  const Pose xa = shape_moving_[a] ? poses_[a] : ShapeTable::world_pose(A, sa);
  const Pose xb = shape_moving_[b] ? poses_[b] : ShapeTable::world_pose(B, sb);
  const int n = collide(A.geom, xa, B.geom, xb, spec + closing, c.cache, m);
  c.normal_W = m.normal_W;
  c.count = n;
  double deepest = 0;
  for (int j = 0; j < n; ++j) {
    ContactPoint& p = c.points[j];
    p.id = m.points[j].id;
    p.p_W = m.points[j].p_W;
    p.separation = m.points[j].separation;
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

// The soft step over the bodies in contact (sim/contact_solver.hpp), then their new state.
bool World::stage_solve_contacts() {
  double* sec = profile_.seconds;
  long* runs = profile_.runs;
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
  const double h = cfg_.dt / substeps_;
  {
    StageTimer t(profiling_, &sec[(int)Stage::prepare_contacts]);
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
  runs[(int)Stage::prepare_contacts]++;
  for (int sub = 0; sub < substeps_; ++sub) {
    {
      StageTimer t(profiling_, &sec[(int)Stage::integrate_velocities]);
      solver_.integrate_velocities(h);
    }
    {
      StageTimer t(profiling_, &sec[(int)Stage::warm_start]);
      solver_.warm_start();
    }
    // One more sweep each while the last impact settles (kImpactSettleTime), and one at once on
    // an impact in this substep's first sweeps.
    const int sweeps = cs.iterations + (settle_substeps_ > 0 ? 1 : 0);
    {
      StageTimer t(profiling_, &sec[(int)Stage::solve]);
      bool struck = false;
      for (int it = 0; it < sweeps; ++it) struck |= solver_.solve(h, true, it == 0);
      if (struck && settle_substeps_ == 0) solver_.solve(h, true, false);
      if (struck) {
        settle_substeps_ = (int)std::ceil(kImpactSettleTime / h - 1e-9) + 1;
        ++profile_.impact_substeps;
      }
    }
    {
      StageTimer t(profiling_, &sec[(int)Stage::integrate_positions]);
      solver_.integrate_positions(h);
    }
    {
      StageTimer t(profiling_, &sec[(int)Stage::relax]);
      const int relax = cs.iterations + (settle_substeps_ > 0 ? 1 : 0);
      for (int it = 0; it < relax; ++it) solver_.solve(h, false, false);
      if (settle_substeps_ > 0) --settle_substeps_;
    }
    {
      StageTimer t(profiling_, &sec[(int)Stage::restitution]);
      solver_.restitution(cs.restitution_threshold);
    }
  }
  for (Stage s : {Stage::integrate_velocities, Stage::warm_start, Stage::solve, Stage::integrate_positions,
                  Stage::relax})
    runs[(int)s]++;
  runs[(int)Stage::restitution]++;
  bool finite = true;
  {
    StageTimer t(profiling_, &sec[(int)Stage::store_impulses]);
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
        if (!in_contact_[i] && asleep_[i] < 0) free_[g].push_back(i);
    }
    profile_.solver_bodies += solved;
    if (pool_) profile_.pool_runs = pool_->runs(), profile_.pool_alone_runs = pool_->alone_runs();
  }
  runs[(int)Stage::store_impulses]++;
  return finite;
}

// Kinematic bodies move at their given velocity, exactly: x += h v, and a constant world angular
// velocity w turns the orientation by exp(h w / 2) (w_P is re-expressed so that w stays fixed).
void World::stage_kinematic() {
  const double h = cfg_.dt;
  for (int i : kinematic_) {
    MotionState& s = state_[i];
    const Vec3 w_W = s.q_WP * s.w_P;
    s.x_W += h * s.v_W;
    s.q_WP = (rotation_increment(w_W, h) * s.q_WP).normalized();
    s.w_P = s.q_WP.conjugate() * w_W;
  }
}

}  // namespace simreel
