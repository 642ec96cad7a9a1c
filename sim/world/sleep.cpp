// World's sleep stage: which bodies may sleep, the stage over the islands (islands.hpp), and the
// islands' caches after a restore.
#include <cmath>

#include <simreel/error.hpp>
#include "sim/world/world_impl.hpp"

namespace simreel {

void WorldImpl::init_sleep() {
  const int n = (int)defs_.size();
  const ContactSettings& cs = cfg_.contacts;
  if (!(cs.sleep_speed >= 0) || !(cs.sleep_time >= 0) || !std::isfinite(cs.sleep_speed) ||
      !std::isfinite(cs.sleep_time))
    throw InputError("contacts: sleep_speed and sleep_time must be non-negative numbers");
  if (!(cs.sleep && collide_enabled_)) return;
  std::vector<char> may_sleep(n, 0);
  for (int i : dynamic_) may_sleep[i] = 1;
  // Bodies under a continuous force (a spring, a thrust, drag) never sleep: the force may change
  // with time or with another body's motion without anything touching them.
  for (int i : forces_.involved()) may_sleep[i] = 0;
  for (int i : forces_.forced()) may_sleep[i] = 0;
  for (int k : forces_.jointed()) {  // and the mechanisms under them
    const ForceDef& f = forces_.list()[k];
    for (int b : {f.body, f.kind == ForceKind::spring ? f.body_b : -1})
      if (b >= 0) may_sleep[b] = 0;
  }
  // A mechanism sleeps and wakes whole: its bodies are bonded into one island. One with a motor
  // never sleeps (a motor may start it from rest).
  joint_bonds_.clear();
  for (const Mechanism& m : joints_.mechanisms()) {
    bool motor = false;
    for (const Mechanism::Dof& d : m.dofs) motor = motor || d.motor != 0;
    if (motor)
      for (const Link& l : m.links)
        if (l.body >= 0) may_sleep[l.body] = 0;
    int first = -1;
    for (const Link& l : m.links) {
      if (l.body < 0) continue;
      if (first < 0)
        first = l.body;
      else
        joint_bonds_.emplace_back(first, l.body);
    }
  }
  islands_.enable(std::move(may_sleep));
}

void WorldImpl::stage_sleep() {
  Islands::Step in;
  in.dt = cfg_.dt;
  in.speed = cfg_.contacts.sleep_speed;
  in.sleep_time = cfg_.contacts.sleep_time;
  in.model = model_.data();
  in.state = state_.data();
  in.in_contact = contacts_.in_contact();
  in.contacts = &contacts_.active();
  in.extents = &extents_;
  in.shape_moving = &shape_moving_;
  in.bonds = &joint_bonds_;
  // A mechanism any of whose bodies the contact solver stepped was stepped whole: all its bodies
  // count still time (a pendulum resting its bob on the floor rests its rod too).
  char* in_contact = contacts_.in_contact();
  for (const Mechanism& m : joints_.mechanisms()) {
    bool any = false;
    for (const Link& l : m.links) any = any || (l.body >= 0 && in_contact[l.body]);
    if (any)
      for (const Link& l : m.links)
        if (l.body >= 0) in_contact[l.body] = 1;
  }
  fell_asleep_.clear();
  islands_.step(in, fell_asleep_);
  // A mechanism that fell asleep stops with its bodies: its joint velocities are zero too.
  for (int i : fell_asleep_) {
    const auto [mi, li] = joints_.link_of(i);
    if (mi < 0) continue;
    Mechanism& m = joints_.mechanisms()[mi];
    std::fill(m.v.begin(), m.v.end(), 0.0);
  }
  // A sleeping body's sweeps start where it fell asleep (continuous.hpp, save_start_poses).
  if (ccd_.enabled())
    for (int i : fell_asleep_) ccd_.save_start_pose(i, state_[i]);
}

// After restore_state: the islands from the saved still times and ids (the awake list, the
// islands' lists, the sleeping bodies' boxes made again at rest), the broad phase started afresh.
void WorldImpl::after_restore(std::vector<double> still, std::vector<int> asleep) {
  broad_.reset();
  std::vector<std::string> names;
  for (const BodyDef& d : defs_) names.push_back(d.name);
  islands_.restore(std::move(still), std::move(asleep), model_, names, extents_, shape_moving_);
  if (ccd_.enabled())
    for (int i = 0; i < (int)defs_.size(); ++i)
      if (!model_[i].is_static && islands_.asleep(i)) ccd_.save_start_pose(i, state_[i]);
}

}  // namespace simreel
