// The contact set's collide stage (contact_set.hpp; the pipeline is in world.cpp): the narrow
// phase on the broad phase's pairs, records kept or made afresh, the sleeping islands touched by
// something awake woken, and the bodies in contact found. Pairs with a static triangle mesh are in
// mesh_pairs.cpp, fast pairs' manifolds taken ahead in continuous.cpp.
#include "sim/world/contact_set.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "sim/base/pair_key.hpp"
#include "sim/base/worker_pool.hpp"
#include "sim/collision/narrow/mesh.hpp"

namespace simreel {

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
// and stay where they are while the pair sleeps: a sleeping pair costs nothing (no copy; the
// solver and the sleep stage never see it; the broad phase lists it apart, as dormant, and the
// passes run over the live pairs alone unless a dormant pair changed, a resting record is
// touched or something wakes). Both lists are rebuilt
// only in a step where a record enters or leaves resting_ (an island falls asleep or wakes, a
// pair leaves the broad phase). contacts_ and resting_ together, in key order, are the one list
// the sequential pass keeps (and the saved state holds).
void ContactSet::collide(const Step& in, Islands& islands, Profile& profile) {
  // The live pairs alone (those with a shape of an awake body) when the sleeping ones cannot take
  // part: no dormant pair changed, no resting record is touched, and nothing wakes. Otherwise the
  // pass runs over every pair, live and dormant, in key order, as one sequential pass would.
  if (!in.dormant_changed && build_jobs(in, islands, pairs_, true)) {
    run_jobs(in);
    bool wakes = false;
    for (const CollideJob& job : collide_jobs_)
      wakes = wakes ||
              (!job.keep && job.points > 0 && (islands.asleep(job.body_a) || islands.asleep(job.body_b)));
    if (!wakes) {
      finish(in, islands, profile);
      return;
    }
  }
  const std::vector<uint64_t>* keys = &pairs_;
  if (in.dormant && !in.dormant->empty()) {
    all_keys_.clear();
    std::set_union(pairs_.begin(), pairs_.end(), in.dormant->begin(), in.dormant->end(),
                   std::back_inserter(all_keys_));
    keys = &all_keys_;
  }
  build_jobs(in, islands, *keys, false);
  run_jobs(in);
  finish(in, islands, profile);
}

// Pass 1 over `keys`. live_only: the keys are the live pairs alone, and the pass gives up (false)
// where the dormant ones would matter: a pair with records in resting_, or one entering it.
bool ContactSet::build_jobs(const Step& in, Islands& islands, const std::vector<uint64_t>& keys,
                            bool live_only) {
  const ShapeTable& st = *in.shapes;
  // Static or asleep (resting_ holds the pairs of two such bodies); inert: static, asleep, or
  // kinematic at rest, neither moves nor wakes anything (Islands::inert).
  auto resting = [&](int i) { return in.model[i].is_static || islands.asleep(i); };
  auto inert = [&](int i) { return islands.inert(i, in.model[i], in.state[i]); };
  collide_jobs_.clear();
  size_t old = 0, rest = 0;
  int slots = 0;
  busy_ = 0;               // pairs collided or copied
  packed_ = true;          // every job fills its slots exactly
  resting_moves_ = false;  // a record enters or leaves resting_ this step
  for (uint64_t key : keys) {
    while (old < contacts_.size() && contacts_[old].key() < key) ++old;
    size_t old_end = old;
    while (old_end < contacts_.size() && contacts_[old_end].key() == key) ++old_end;
    size_t rest_end;
    if (live_only) {
      rest = std::lower_bound(resting_keys_.begin(), resting_keys_.end(), key) - resting_keys_.begin();
      if (rest < resting_keys_.size() && resting_keys_[rest] == key) return false;
      rest_end = rest;
    } else {
      // Resting records of a pair the broad phase no longer reports are dropped, as contacts_' are.
      for (; rest < resting_keys_.size() && resting_keys_[rest] < key; ++rest) resting_moves_ = true;
      rest_end = rest;
      while (rest_end < resting_keys_.size() && resting_keys_[rest_end] == key) ++rest_end;
    }
    const int a = pair_first(key), b = pair_second(key);
    const int body_a = in.extents->shape_body[a], body_b = in.extents->shape_body[b];
    CollideJob job;
    job.key = key;
    job.body_a = body_a;
    job.body_b = body_b;
    job.stored = rest_end > rest;
    job.prev = job.stored ? (int)rest : old_end > old ? (int)old : -1;
    job.prev_count = job.stored ? (int)(rest_end - rest) : (int)(old_end - old);
    // A pair that cannot move keeps its records as they were when it fell asleep: neither body
    // has moved since.
    job.keep = islands.sleeping() > 0 && inert(body_a) && inert(body_b);
    job.count = job.points = 0;
    job.seconds = 0;
    if (job.keep && job.stored) {
      job.mesh = false;  // (not looked at: the shape records are not touched)
      job.cap = 0;       // its records stay in resting_
      job.slot = -1;
      job.count = job.prev_count;
    } else {
      job.mesh = st[a].geom.kind == CollideKind::mesh || st[b].geom.kind == CollideKind::mesh;
      // Woken since (its records leave resting_), or fell asleep last step (they enter it).
      const bool enters = job.keep && resting(body_a) && resting(body_b);
      if (live_only && enters) return false;
      resting_moves_ = resting_moves_ || job.stored || enters;
      job.cap = std::max(job.mesh ? kMaxMeshManifolds : 1, job.prev_count);
      job.slot = slots;
      slots += job.cap;
      ++busy_;
      packed_ = packed_ && !job.mesh && !(job.keep && job.prev_count != 1);
    }
    collide_jobs_.push_back(job);
    rest = rest_end;
  }
  if (!live_only) resting_moves_ = resting_moves_ || rest < resting_keys_.size();
  contacts_next_.resize(slots);
  return true;
}

// Pass 2: the pairs not kept collided on the threads.
void ContactSet::run_jobs(const Step& in) {
  const int n = (int)collide_jobs_.size();
  collide_sums_.resize(in.threads);
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
          deepest = std::max(deepest, collide_job(in, job));
        }
      }
    }
    collide_sums_[w].value = deepest;
  };
  // Threads only for enough pairs to be worth a pool run (the result is the same either way).
  // (The pool may also run it as worker 0 of 1: sim/base/worker_pool.hpp.)
  constexpr int kMinParallelPairs = 64;
  for (Deepest& d : collide_sums_) d.value = 0;
  if (in.pool && busy_ >= kMinParallelPairs)
    in.pool->run(work);
  else
    work(0, 1);
  for (const Deepest& d : collide_sums_) stats_.max_penetration = std::max(stats_.max_penetration, d.value);
}

// Pass 3, in key order, and the lists afterwards.
void ContactSet::finish(const Step& in, Islands& islands, Profile& profile) {
  const ShapeTable& st = *in.shapes;
  auto resting = [&](int i) { return in.model[i].is_static || islands.asleep(i); };
  auto inert = [&](int i) { return islands.inert(i, in.model[i], in.state[i]); };
  bool resting_moves = resting_moves_, packed = packed_;
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
      stats_.max_penetration = std::max(stats_.max_penetration, collide_job(in, job));
      packed = packed && job.count == job.cap;
    }
    if (job.points <= 0) continue;
    points += job.points;
    // Something awake comes within reach of a sleeping body: its island wakes.
    if (islands.asleep(body_a)) islands.wake(body_a), woke = true;
    if (islands.asleep(body_b)) islands.wake(body_b), woke = true;
    in_contact_[body_a] = in_contact_[body_a] || !in.model[body_a].is_static;
    in_contact_[body_b] = in_contact_[body_b] || !in.model[body_b].is_static;
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
      if (!islands.asleep(c.body_a) && !in.model[c.body_a].is_static) in_contact_[c.body_a] = 1;
      if (!islands.asleep(c.body_b) && !in.model[c.body_b].is_static) in_contact_[c.body_b] = 1;
    }
  }
  stats_.contacts_max = std::max(stats_.contacts_max, points);
  profile.contact_points += points;
  contact_bodies_.clear();
  for (int i = 0; i < (int)in_contact_.size(); ++i)
    if (in_contact_[i]) contact_bodies_.push_back(i);
  if (in.timing) {
    // Which pair kinds the narrow phase's time goes to (profiling only: a pass over the pairs).
    for (const CollideJob& job : collide_jobs_) {
      if (job.keep) continue;  // (a kept pair was not collided; a woken one is not kept any more)
      const int ka = (int)st[pair_first(job.key)].geom.kind, kb = (int)st[pair_second(job.key)].geom.kind;
      const int lo = std::min(ka, kb), hi = std::max(ka, kb);
      ++profile.narrow_calls[lo][hi];
      profile.narrow_seconds[lo][hi] += job.seconds;
    }
  }
}

double ContactSet::collide_job(const Step& in, CollideJob& job) {
  Contact* out = &contacts_next_[job.slot];
  double deepest = 0;
  const auto t0 = in.timing ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  if (job.mesh) {
    job.count = collide_mesh_pair(in, job, out, job.points, deepest);
  } else {
    deepest = collide_pair(in, job, *out);
    job.count = 1;
    job.points = out->count;
  }
  if (in.timing) job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return deepest;
}

// One convex pair's narrow phase into c (overwritten); returns its deepest overlap (m, >= 0).
double ContactSet::collide_pair(const Step& in, const CollideJob& job, Contact& c) const {
  const ShapeTable& st = *in.shapes;
  const double spec = in.speculative_distance, dt = in.dt;
  const int a = pair_first(job.key), b = pair_second(job.key);
  const Contact* prev = prev_record(job);
  const ShapeRecord& A = st[a];
  const ShapeRecord& B = st[b];
  const MotionState& sa = in.state[A.body];
  const MotionState& sb = in.state[B.body];
  new_contact(st, c, a, b, prev);
  if (prev) c.cache = prev->cache;
  // How far the two can close this step, bounded: relative speed of their farthest points.
  const double reach_a = in.extents->shape_reach[a] * sa.w_P.norm();
  const double reach_b = in.extents->shape_reach[b] * sb.w_P.norm();
  const double closing = ((sa.v_W - sb.v_W).norm() + reach_a + reach_b) * dt;
  Manifold m;
  Vec3 offset[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  // World poses: the broad phase's for moving shapes (made from this same state).
  const Pose xa = in.pose(a, A), xb = in.pose(b, B);
  // A fast pair's speculative manifold is taken where it will touch (sim/world/continuous.cpp).
  const int n = fast_pair(in, a, b, closing)
                    ? collide_ahead(in, a, b, xa, xb, spec, closing, c.cache, m, offset)
                    : simreel::collide(A.geom, xa, B.geom, xb, spec + closing, c.cache, m);
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

// (Assigned whole: the slots are reused from step to step.)
void ContactSet::new_contact(const ShapeTable& shapes, Contact& c, int a, int b, const Contact* prev) {
  const ShapeRecord& A = shapes[a];
  const ShapeRecord& B = shapes[b];
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
