// World's applied forces (applied_forces.hpp; the pipeline is in world.cpp): the `forces` stage,
// which hands the forces to the article's interface (apply_force, apply_impulse, ...: the same
// calls a program makes), and the bodies the forced RK4 takes from their integrator groups
// (docs/forces.md).
#include <algorithm>

#include "sim/world/world_impl.hpp"

namespace simreel {

namespace {
struct WorldSink {
  WorldImpl& w;
  const MotionState* state;
  void force(int i, const Vec3& f_W, const Vec3& at_W) { w.apply_force(i, f_W, at_W); }
  void central(int i, const Vec3& f_W) { w.apply_central_force(i, f_W); }
  void torque(int i, const Vec3& tau_W) { w.apply_torque(i, tau_W); }
  void impulse(const ForceDef& f) {
    const int i = f.body;
    const Vec3 v = f.frame == ForceFrame::body ? w.local_to_world_vec(i, f.vector) : f.vector;
    if (f.kind == ForceKind::impulse)
      w.apply_impulse(i, v, f.at_centroid ? state[i].x_W : w.local_to_world(i, f.at_B));
    else
      w.apply_angular_impulse(i, v);
  }
};
}  // namespace

void WorldImpl::init_forces() {
  std::vector<char> jointed(defs_.size(), 0);
  for (size_t i = 0; i < defs_.size(); ++i) jointed[i] = joints_.jointed((int)i) ? 1 : 0;
  forces_.init(cfg_.forces, defs_, model_, cfg_.integrator, jointed);
  // Continuous forces on jointed bodies are their mechanisms', evaluated inside their steps.
  if (!forces_.jointed().empty()) joints_.add_loads(cfg_.forces, forces_.jointed(), defs_, model_, state_);
  profile_.forces = forces_.count();
  profile_.forced_bodies = (int)forces_.forced().size();
  for (Group& g : groups_)
    g.bodies.erase(
        std::remove_if(g.bodies.begin(), g.bodies.end(), [&](int i) { return forces_.is_forced(i); }),
        g.bodies.end());
}

// Impulses that are due, then every continuous force at the step's start state, into the
// accumulators. An impulse with time T is applied once, at the start of the first step whose start
// time n dt reaches T (n dt >= T - 1e-9 dt): the velocity jumps at t = n dt, after the state at
// that time was reported. Returns false when there was nothing to do.
bool WorldImpl::stage_forces() {
  const double dt = cfg_.dt;
  WorldSink sink{*this, state_.data()};
  return forces_.apply(time(), (double)(steps_ + 1) * dt, dt, state_.data(), model_.data(), wrench_.data(),
                       sink);
}

}  // namespace simreel
