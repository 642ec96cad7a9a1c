// Running a scene: conservation bookkeeping and the summary both commands share (the frame
// schedule is the scene's own: app/scene/frame_plan.hpp).
#pragma once
#include <string>
#include <vector>

#include <simreel/world.hpp>
#include "app/scene/scene.hpp"

namespace simreel {

// Energy (kinetic + gravitational) and angular momentum about the system's centre of mass,
// sampled along the run. Relative drift: max |E - E0| / max(|E0|, max KE) and max |L - L0| / |L0|.
class Drift {
 public:
  explicit Drift(const World& w);
  void sample(const World& w);
  double energy_rel() const;
  double momentum_rel() const;
  // J, the largest rise of total mechanical energy between two samples; rises within rounding
  // (1e-9 of the energy scale) count as none, so a scene that only loses energy reports 0.
  double energy_gained() const { return max_rise_ > 1e-9 * scale_ ? max_rise_ : 0.0; }
  double joint_gap() const { return max_gap_; }          ///< m, largest anchor gap of any joint
  double joint_angle_gap() const { return max_angle_; }  ///< rad, largest axis misalignment
  // Every step (FrameLoop): whether any joint has reached its limits yet (a limit that is never
  // reached takes no energy). Cheap: only joints with limits are read, and only until one is reached.
  void step(const World& w);
  bool limit_reached() const { return limit_reached_; }

 private:
  double E0_, scale_, max_dE_ = 0, max_dL_ = 0, prev_E_ = 0, max_rise_ = 0, max_gap_ = 0, max_angle_ = 0;
  Vec3 L0_;
  std::vector<int> limited_;  // joints with limits
  bool limit_reached_ = false;
};

WorldConfig world_config(const Scene& s, int threads);

// What the scene's physics conserves, so that the summary reports drift only for that: the angular
// momentum about the system's centre of mass when nothing outside pushes (uniform gravity exerts no
// torque about it; contacts and springs between moving bodies are internal), the energy (kinetic,
// gravitational and springs') when nothing takes or gives any (no contacts, friction, dashpots,
// motors, drag or applied forces). `why`: what breaks it, "" when conserved.
struct Conservation {
  bool energy = true, angular_momentum = true;
  std::string energy_why, angular_momentum_why;
};
// `drift`: what the run saw (a joint's limits break the energy only once reached); none: limits
// count as reached.
Conservation conservation(const Scene& scene, const World& world, const Drift* drift = nullptr);

// The summary of a run: text for people, one JSON object for scripts.
struct RunSummary {
  std::string scene;
  Integrator integrator;
  double timestep = 0, duration = 0;
  long steps = 0;
  int bodies = 0, dynamic_bodies = 0, frames = 0;
  double step_seconds = 0;  ///< wall time inside World::step only
  double energy_rel_drift = 0, momentum_rel_drift = 0;
  Conservation conserved;             ///< what the drifts are meaningful for
  bool contacts = false;              ///< the scene has colliding shapes
  int contacts_max = 0;               ///< most contact points in a step
  double max_penetration = 0;         ///< m, over the run
  int sleeping = 0;                   ///< bodies asleep at the end
  double energy_gained = 0;           ///< J, largest rise between two frames
  int joints = 0;                     ///< joints in the scene
  double joint_error_max = 0;         ///< m, largest gap between a joint's two anchors at a frame
  double joint_angle_error_max = 0;   ///< rad, largest angle between a joint's two axes at a frame
  std::vector<std::string> warnings;  ///< what went wrong or was odd in the run
  std::vector<std::string> notes;     ///< the scene's notes (already printed on stderr before the run)
  const Profile* profile = nullptr;   ///< set with --profile
  double render_seconds = -1, encode_seconds = -1;  ///< render command only
  std::string renderer;                             ///< render command only: GL backend, renderer, version
  std::string encoder;                              ///< render command only: the video encoder used, or ""
  std::string output;
};
// The fields every command fills the same way: scene, world counters, drift, warnings and notes.
RunSummary make_summary(const Scene& scene, const World& world, const Drift& drift, int frames,
                        double step_seconds);
std::string summary_text(const RunSummary& s);
std::string summary_json(const RunSummary& s);

}  // namespace simreel
