#include "sim/world/islands.hpp"

#include <algorithm>
#include <limits>

#include <simreel/error.hpp>

namespace simreel {

void Islands::reset(const std::vector<BodyModel>& model) {
  const int n = (int)model.size();
  enabled_ = false;
  asleep_.assign(n, -1);
  still_time_.assign(n, 0.0);
  sleeping_ = 0;
  awake_.clear();
  for (int i = 0; i < n; ++i)
    if (!model[i].is_static) awake_.push_back(i);
  awake_sorted_ = true;
  pending_freeze_.clear();
}

void Islands::enable(std::vector<char> may_sleep) {
  const int n = (int)may_sleep.size();
  enabled_ = true;
  may_sleep_ = std::move(may_sleep);
  uf_.assign(n, 0);
  island_min_.assign(n, 0.0);
  island_next_.assign(n, -1);
  island_tail_.assign(n, -1);
}

void Islands::sort_awake() {
  if (!awake_sorted_) {
    std::sort(awake_.begin(), awake_.end());
    awake_sorted_ = true;
  }
}

void Islands::wake(int i) {
  if ((size_t)i >= asleep_.size() || asleep_[i] < 0) return;
  for (int j = asleep_[i]; j >= 0;) {
    const int next = island_next_[j];
    asleep_[j] = -1;
    still_time_[j] = 0;
    island_next_[j] = -1;
    --sleeping_;
    awake_.push_back(j);
    j = next;
  }
  awake_sorted_ = false;
}

// Visits the awake bodies and the step's contacts only (a sleeping pair's records are kept apart,
// and nothing here needs them: both its sides are asleep or static): a world asleep costs nothing.
void Islands::step(const Step& in, std::vector<int>& fell_asleep) {
  const BodyModel* model = in.model;
  MotionState* state = in.state;
  sort_awake();
  // 1. Still time: a body counts it while the solver stepped it and its fastest point is slow.
  for (int i : awake_) {
    if (model[i].inv_mass == 0) continue;  // kinematic
    const MotionState& s = state[i];
    const bool still =
        may_sleep_[i] && in.in_contact[i] && s.v_W.norm() + in.extents->reach[i] * s.w_P.norm() < in.speed;
    still_time_[i] = still ? still_time_[i] + in.dt : 0.0;
  }
  // 2. Islands: union-find over the contacts between two awake dynamic bodies, the smaller root
  // kept (so an island's id, its least body index, does not depend on the contacts' order). A body
  // carried by a moving kinematic body is not still, whatever its own speed.
  for (int i : awake_) uf_[i] = i;
  auto find = [this](int i) {
    while (uf_[i] != i) i = uf_[i] = uf_[uf_[i]];
    return i;
  };
  auto awake_dynamic = [&](int i) { return asleep_[i] < 0 && model[i].inv_mass > 0; };
  for (const Contact& c : *in.contacts) {
    if (c.count == 0) continue;
    const int a = c.body_a, b = c.body_b;
    const bool da = awake_dynamic(a), db = awake_dynamic(b);
    if (da && db) {
      const int ra = find(a), rb = find(b);
      if (ra < rb) uf_[rb] = ra;
      if (rb < ra) uf_[ra] = rb;
    } else if (da && !inert(b, model[b], state[b])) {
      still_time_[a] = 0;
    } else if (db && !inert(a, model[a], state[a])) {
      still_time_[b] = 0;
    }
  }
  if (in.bonds)
    for (const auto& [a, b] : *in.bonds)
      if (awake_dynamic(a) && awake_dynamic(b)) {
        const int ra = find(a), rb = find(b);
        if (ra < rb) uf_[rb] = ra;
        if (rb < ra) uf_[ra] = rb;
      }
  // 3. An island sleeps when its least still body has been still for sleep_time.
  for (int i : awake_)
    if (model[i].inv_mass > 0) island_min_[find(i)] = std::numeric_limits<double>::infinity();
  for (int i : awake_)
    if (model[i].inv_mass > 0) {
      const int r = find(i);
      island_min_[r] = std::min(island_min_[r], still_time_[i]);
    }
  // Members join their island's list in ascending order; its id, the least, comes first. They
  // leave the awake list, and their shapes get one box at rest in the next broad phase.
  const double t_sleep = std::max(in.sleep_time, in.dt) - 1e-12;
  const std::vector<int>& first = in.extents->shape_begin;
  size_t kept = 0;
  for (size_t k = 0; k < awake_.size(); ++k) {
    const int i = awake_[k];
    const int r = model[i].inv_mass > 0 ? find(i) : -1;
    if (r < 0 || !(island_min_[r] >= t_sleep)) {
      awake_[kept++] = i;
      continue;
    }
    asleep_[i] = r;
    island_next_[i] = -1;
    if (i != r) island_next_[island_tail_[r]] = i;
    island_tail_[r] = i;
    state[i].v_W.setZero();
    state[i].w_P.setZero();
    in.in_contact[i] = 0;
    ++sleeping_;
    fell_asleep.push_back(i);
    for (int s = first[i]; s < first[i + 1]; ++s)
      if ((*in.shape_moving)[s]) pending_freeze_.push_back(s);
  }
  awake_.resize(kept);
}

void Islands::restore(std::vector<double> still, std::vector<int> asleep, const std::vector<BodyModel>& model,
                      const std::vector<std::string>& names, const BodyExtents& extents,
                      const std::vector<char>& shape_moving) {
  still_time_ = std::move(still);
  asleep_ = std::move(asleep);
  sleeping_ = 0;
  awake_.clear();
  pending_freeze_.clear();
  for (int i = 0; i < (int)model.size(); ++i) {
    sleeping_ += asleep_[i] >= 0;
    if (model[i].is_static) continue;
    if (asleep_[i] < 0) {
      awake_.push_back(i);
      continue;
    }
    for (int k = extents.shape_begin[i]; k < extents.shape_begin[i + 1]; ++k)
      if (shape_moving[k]) pending_freeze_.push_back(k);
  }
  awake_sorted_ = true;
  if (!enabled_) return;
  for (int j = 0; j < (int)model.size(); ++j) {
    if (!(model[j].inv_mass > 0)) continue;  // dynamic bodies only
    island_next_[j] = -1;
    const int r = asleep_[j];
    if (r < 0) continue;
    // An island's id is its least body, itself asleep in it (so it comes first here).
    if (r > j || asleep_[r] != r)
      throw InputError("saved state is damaged (sleeping island of body '" + names[j] + "')");
    if (j != r) island_next_[island_tail_[r]] = j;
    island_tail_[r] = j;
  }
}

}  // namespace simreel
