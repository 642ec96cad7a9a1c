// Stage "sleep": islands of touching bodies that have all been still for a while stop being
// stepped (docs/sleeping.md). Box2D v3 and Jolt do the same with a speed threshold and a
// time; here only bodies the contact solver stepped count time (a body in free flight keeps its
// exact integrator and never stops on its own, however slow), and the speed is that of the
// body's fastest point, |v| + |w| r.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/base/error.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/world/world.hpp"

namespace simreel {

void World::init_sleep() {
  const int n = (int)defs_.size();
  const ContactSettings& cs = cfg_.contacts;
  if (!(cs.sleep_speed >= 0) || !(cs.sleep_time >= 0) || !std::isfinite(cs.sleep_speed) ||
      !std::isfinite(cs.sleep_time))
    throw InputError("contacts: sleep_speed and sleep_time must be non-negative numbers");
  sleeping_ = 0;
  sleep_enabled_ = cs.sleep && collide_enabled_;
  if (!sleep_enabled_) return;
  may_sleep_.assign(n, 0);
  for (int i : dynamic_) may_sleep_[i] = 1;
  // Bodies under a continuous force (a spring, a thrust, drag) never sleep: the force may change
  // with time or with another body's motion without anything touching them.
  for (int i : involved_) may_sleep_[i] = 0;
  for (int i : forced_) may_sleep_[i] = 0;
  reach_.assign(n, 0.0);
  const ShapeTable& st = *shapes_;
  for (int k = 0; k < st.size(); ++k) {
    const ShapeRecord& r = st[k];
    reach_[r.body] = std::max(reach_[r.body], r.p_PC.norm() + r.geom.bounding_radius);
  }
  uf_.assign(n, 0);
  island_min_.assign(n, 0.0);
  island_next_.assign(n, -1);
  island_tail_.assign(n, -1);
}

bool World::kinematic_at_rest(int i) const {
  return defs_[i].type == BodyType::kinematic && state_[i].v_W.isZero(0) && state_[i].w_P.isZero(0);
}

// The bodies that move (dynamic and kinematic), all awake at the start, and each body's shapes
// (ShapeTable lists them body by body).
void World::init_awake() {
  const int n = (int)defs_.size();
  awake_bodies_.clear();
  for (int i = 0; i < n; ++i)
    if (!model_[i].is_static) awake_bodies_.push_back(i);
  awake_sorted_ = true;
  pending_freeze_.clear();
  const ShapeTable& st = *shapes_;
  shape_first_.assign(n + 1, 0);
  shape_body_.resize(st.size());
  for (int k = 0; k < st.size(); ++k) shape_first_[st[k].body + 1]++, shape_body_[k] = st[k].body;
  for (int b = 0; b < n; ++b) shape_first_[b + 1] += shape_first_[b];
}

// A sleeping island is a list threaded through island_next_, from its id (its least body, itself
// a member) in ascending order: waking it visits its bodies only, and they join awake_bodies_
// (sorted again before its next use).
void World::wake(int i) {
  if ((size_t)i >= asleep_.size() || asleep_[i] < 0) return;
  for (int j = asleep_[i]; j >= 0;) {
    const int next = island_next_[j];
    asleep_[j] = -1;
    still_time_[j] = 0;
    island_next_[j] = -1;
    --sleeping_;
    awake_bodies_.push_back(j);
    j = next;
  }
  awake_sorted_ = false;
}

// After restore_state: the awake list and the islands' lists from asleep_ (saved); the sleeping
// bodies' boxes made again at rest, and the broad phase started afresh.
void World::after_restore() {
  broad_.reset();
  awake_bodies_.clear();
  pending_freeze_.clear();
  for (int i = 0; i < (int)defs_.size(); ++i) {
    if (model_[i].is_static) continue;
    if (asleep_[i] < 0) {
      awake_bodies_.push_back(i);
      continue;
    }
    for (int k = shape_first_[i]; k < shape_first_[i + 1]; ++k)
      if (shape_moving_[k]) pending_freeze_.push_back(k);
    if (ccd_enabled_) x0_[i] = state_[i].x_W, q0_[i] = state_[i].q_WP;  // see save_start_poses
  }
  awake_sorted_ = true;
  if (!sleep_enabled_) return;
  for (int j : dynamic_) {
    island_next_[j] = -1;
    const int r = asleep_[j];
    if (r < 0) continue;
    // An island's id is its least body, itself asleep in it (so it comes first here).
    if (r > j || asleep_[r] != r)
      throw InputError("saved state is damaged (sleeping island of body '" + defs_[j].name + "')");
    if (j != r) island_next_[island_tail_[r]] = j;
    island_tail_[r] = j;
  }
}

// Visits the awake bodies and the step's contacts only (a sleeping pair's records are in resting_,
// which nothing here needs: both its sides are asleep or static): a world asleep costs nothing.
void World::stage_sleep() {
  const double dt = cfg_.dt, speed = cfg_.contacts.sleep_speed;
  if (!awake_sorted_) {
    std::sort(awake_bodies_.begin(), awake_bodies_.end());
    awake_sorted_ = true;
  }
  // 1. Still time: a body counts it while the solver stepped it and its fastest point is slow.
  for (int i : awake_bodies_) {
    if (model_[i].inv_mass == 0) continue;  // kinematic
    const MotionState& s = state_[i];
    const bool still = may_sleep_[i] && in_contact_[i] && s.v_W.norm() + reach_[i] * s.w_P.norm() < speed;
    still_time_[i] = still ? still_time_[i] + dt : 0.0;
  }
  // 2. Islands: union-find over the contacts between two awake dynamic bodies, the smaller root
  // kept (so an island's id, its least body index, does not depend on the contacts' order). A body
  // carried by a moving kinematic body is not still, whatever its own speed.
  for (int i : awake_bodies_) uf_[i] = i;
  auto find = [this](int i) {
    while (uf_[i] != i) i = uf_[i] = uf_[uf_[i]];
    return i;
  };
  auto awake_dynamic = [this](int i) { return asleep_[i] < 0 && model_[i].inv_mass > 0; };
  for (const Contact& c : contacts_) {
    if (c.count == 0) continue;
    const int a = c.body_a, b = c.body_b;
    const bool da = awake_dynamic(a), db = awake_dynamic(b);
    if (da && db) {
      const int ra = find(a), rb = find(b);
      if (ra < rb) uf_[rb] = ra;
      if (rb < ra) uf_[ra] = rb;
    } else if (da && !inert(b)) {
      still_time_[a] = 0;
    } else if (db && !inert(a)) {
      still_time_[b] = 0;
    }
  }
  // 3. An island sleeps when its least still body has been still for sleep_time.
  for (int i : awake_bodies_)
    if (model_[i].inv_mass > 0) island_min_[find(i)] = std::numeric_limits<double>::infinity();
  for (int i : awake_bodies_)
    if (model_[i].inv_mass > 0) {
      const int r = find(i);
      island_min_[r] = std::min(island_min_[r], still_time_[i]);
    }
  // Members join their island's list in ascending order; its id, the least, comes first. They
  // leave awake_bodies_, and their shapes get one box at rest in the next broad phase.
  const double t_sleep = std::max(cfg_.contacts.sleep_time, dt) - 1e-12;
  size_t kept = 0;
  for (size_t k = 0; k < awake_bodies_.size(); ++k) {
    const int i = awake_bodies_[k];
    const int r = model_[i].inv_mass > 0 ? find(i) : -1;
    if (r < 0 || !(island_min_[r] >= t_sleep)) {
      awake_bodies_[kept++] = i;
      continue;
    }
    asleep_[i] = r;
    island_next_[i] = -1;
    if (i != r) island_next_[island_tail_[r]] = i;
    island_tail_[r] = i;
    state_[i].v_W.setZero();
    state_[i].w_P.setZero();
    in_contact_[i] = 0;
    ++sleeping_;
    if (ccd_enabled_) x0_[i] = state_[i].x_W, q0_[i] = state_[i].q_WP;  // its sweeps' start while asleep
    for (int s = shape_first_[i]; s < shape_first_[i + 1]; ++s)
      if (shape_moving_[s]) pending_freeze_.push_back(s);
  }
  awake_bodies_.resize(kept);
}

}  // namespace simreel
