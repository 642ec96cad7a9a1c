// Stage "sleep": islands of touching bodies that have all been still for a while stop being
// stepped (sim/README.md "Sleeping"). Box2D v3 and Jolt do the same with a speed threshold and a
// time; here only bodies the contact solver stepped count time (a body in free flight keeps its
// exact integrator and never stops on its own, however slow), and the speed is that of the
// body's fastest point, |v| + |w| r.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/error.hpp"
#include "sim/shapes.hpp"
#include "sim/world.hpp"

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

bool World::inert(int i) const {
  if (model_[i].is_static || asleep_[i] >= 0) return true;
  return defs_[i].type == BodyType::kinematic && state_[i].v_W.isZero(0) && state_[i].w_P.isZero(0);
}

// A sleeping island is a list threaded through island_next_, from its id (its least body, itself
// a member) in ascending order: waking it visits its bodies only.
void World::wake(int i) {
  if ((size_t)i >= asleep_.size() || asleep_[i] < 0) return;
  for (int j = asleep_[i]; j >= 0;) {
    const int next = island_next_[j];
    asleep_[j] = -1;
    still_time_[j] = 0;
    island_next_[j] = -1;
    --sleeping_;
    j = next;
  }
  sleep_changed();
}

// After restore_state: the islands' lists from asleep_ (saved), and every shape's box made again.
void World::after_restore() {
  active_dirty_ = true;
  std::fill(frozen_.begin(), frozen_.end(), 0);
  broad_.reset();
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

void World::stage_sleep() {
  const double dt = cfg_.dt, speed = cfg_.contacts.sleep_speed;
  // 1. Still time: a body counts it while the solver stepped it and its fastest point is slow.
  for (int i : dynamic_) {
    if (asleep_[i] >= 0) continue;
    const MotionState& s = state_[i];
    const bool still = may_sleep_[i] && in_contact_[i] && s.v_W.norm() + reach_[i] * s.w_P.norm() < speed;
    still_time_[i] = still ? still_time_[i] + dt : 0.0;
  }
  // 2. Islands: union-find over the contacts between two awake dynamic bodies, the smaller root
  // kept (so an island's id, its least body index, does not depend on the contacts' order). A body
  // carried by a moving kinematic body is not still, whatever its own speed.
  for (int i : dynamic_) uf_[i] = i;
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
  for (int i : dynamic_)
    if (asleep_[i] < 0) island_min_[find(i)] = std::numeric_limits<double>::infinity();
  for (int i : dynamic_)
    if (asleep_[i] < 0) {
      const int r = find(i);
      island_min_[r] = std::min(island_min_[r], still_time_[i]);
    }
  // Members join their island's list in ascending order; its id, the least, comes first.
  const double t_sleep = std::max(cfg_.contacts.sleep_time, dt) - 1e-12;
  bool fell_asleep = false;
  for (int i : dynamic_) {
    if (asleep_[i] >= 0) continue;
    const int r = find(i);
    if (!(island_min_[r] >= t_sleep)) continue;
    asleep_[i] = r;
    island_next_[i] = -1;
    if (i != r) island_next_[island_tail_[r]] = i;
    island_tail_[r] = i;
    fell_asleep = true;
    state_[i].v_W.setZero();
    state_[i].w_P.setZero();
    in_contact_[i] = 0;
    ++sleeping_;
  }
  if (fell_asleep) sleep_changed();
}

}  // namespace simreel
