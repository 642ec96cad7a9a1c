// The applied forces as a subsystem (their records: include/simreel/forces.hpp; their evaluation:
// sim/dynamics/forces.hpp; docs/forces.md). Owns the force list sorted by use (impulses once, the
// continuous forces every step), which bodies the forces read and which they move, which impulses
// were applied (saved state), and the forced RK4 with its buffers: the dynamic bodies under `auto`
// or `rk4` that a continuous force acts on are stepped here, every force evaluated again at every
// RK4 stage, instead of by their integrator group.
#pragma once
#include <vector>

#include <simreel/body.hpp>
#include <simreel/forces.hpp>

#include "sim/dynamics/forces.hpp"
#include "sim/dynamics/state.hpp"

namespace simreel {

class AppliedForces {
 public:
  // Checks the list against the bodies (InputError naming the entry) and sorts it by use.
  // `integrator`: the world's, for bodies whose BodyDef names none.
  // `jointed` (per body, may be empty): continuous forces on a jointed body are its mechanism's
  // (Articulations::add_loads): kept apart in jointed(), neither applied nor integrated here.
  void init(std::vector<ForceDef> forces, const std::vector<BodyDef>& defs,
            const std::vector<BodyModel>& model, Integrator integrator,
            const std::vector<char>& jointed = {});

  int count() const { return (int)forces_.size(); }
  const std::vector<ForceDef>& list() const { return forces_; }
  const std::vector<int>& continuous() const { return continuous_; }  ///< indices into list(): not impulses
  const std::vector<int>& jointed() const { return jointed_; }  ///< continuous forces the mechanisms take
  /// Dynamic auto/rk4 bodies under continuous forces, ascending: the forced RK4 steps them.
  const std::vector<int>& forced() const { return forced_; }
  bool is_forced(int i) const { return forced_slot_[i] >= 0; }
  const std::vector<int>& involved() const { return involved_; }  ///< every body a continuous force reads
  bool fired(int k) const { return fired_[k] != 0; }              ///< impulse k has been applied
  const std::vector<char>& fired_flags() const { return fired_; }
  void restore_fired(std::vector<char> fired) { fired_ = std::move(fired); }

  // The forces stage, over [t0, t1] (s): each impulse due at t0 (its time reached, within 1e-9 dt)
  // once, as sink.impulse(f); then every continuous force at the step's start states to
  // sink.force(i, F_W, at_W), sink.central(i, F_W) and sink.torque(i, tau_W), weighted by the part
  // of the step its window covers. `wrench`: what was applied from outside before the step (the
  // forced RK4 keeps it through its stages). Returns false when there was nothing to do.
  template <class Sink>
  bool apply(double t0, double t1, double dt, const MotionState* state, const BodyModel* model,
             const Wrench* wrench, Sink& sink) {
    bool did = false;
    for (int k : impulses_) {
      const ForceDef& f = forces_[k];
      if (fired_[k] || t0 < f.time - 1e-9 * dt) continue;
      fired_[k] = 1;
      did = true;
      sink.impulse(f);
    }
    if (continuous_.empty()) return did;
    for (int i : involved_) eval_state_[i] = state[i];
    for (size_t j = 0; j < forced_.size(); ++j) user_wrench_[j] = wrench[forced_[j]];
    for (int k : continuous_) {
      const ForceDef& f = forces_[k];
      evaluate_force(f, window_weight(f, t0, t1), state, model, sink);
    }
    return true;
  }

  // The forced bodies that touched nothing this step (in_contact 0, or none in contact at all),
  // integrated together from t0 to t1 by classical RK4; false if a non-finite value appeared.
  bool integrate(double t0, double t1, double dt, const Vec3& gravity, MotionState* state,
                 const BodyModel* model, const char* in_contact, bool some_in_contact);

 private:
  void rk4(double a, double b, const Vec3& gravity, MotionState* state, const BodyModel* model);

  std::vector<ForceDef> forces_;
  std::vector<int> continuous_;  ///< indices into forces_: everything but impulses
  std::vector<int> jointed_;
  std::vector<int> impulses_;              ///< indices into forces_: impulses, in list order
  std::vector<char> fired_;                ///< per force: an impulse already applied (saved state)
  std::vector<int> forced_;                ///< dynamic auto/rk4 bodies under continuous forces, ascending
  std::vector<int> forced_slot_;           ///< per body: its index in forced_, or -1
  std::vector<char> forced_auto_;          ///< per forced_ entry: integrator auto (substeps)
  std::vector<int> involved_;              ///< every body a continuous force reads, ascending
  std::vector<int> forced_now_;            ///< forced_ bodies not in contact this step
  std::vector<MotionState> eval_state_;    ///< per body: the state the forces are evaluated at
  std::vector<Wrench> stage_wrench_;       ///< per body: forces at an RK4 stage
  std::vector<Wrench> user_wrench_;        ///< per forced_ entry: apply_* calls from outside this step
  std::vector<double> rate1_, rate2_;      ///< per body: force rates (force_rates)
  std::vector<double> y0_, ys_, k_, acc_;  ///< RK4 buffers, 13 doubles per forced_ entry
  std::vector<double> cuts_;               ///< window edges within this step
};

}  // namespace simreel
