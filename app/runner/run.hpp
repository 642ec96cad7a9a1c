// Running a scene: the frame schedule, conservation bookkeeping and the summary both commands share.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "app/scene/scene.hpp"
#include <simreel/world.hpp>

namespace simreel {

// Frame k shows simulation time k / fps; it is taken after the first step whose time reaches it
// (physics keeps its own fixed step). Frames run from t = 0 to the last k / fps <= duration.
// Computed, never tabulated: a plan of 1e7 frames is as small as one of ten (a table of them
// took 80 MB, and `duration: 1e7` 2.3 GB before the limits below).
struct FramePlan {
  long total_steps = 0;  ///< ceil(duration / dt)
  long frames = 0;       ///< floor(duration x fps) + 1
  double dt = 0;         ///< s
  double fps = 0;        ///< frames per second (of simulated time, or of video with sim_time)
  /// A video plan's (app/scene/scene_time.hpp): the simulated time (s) frame k shows, of its video time
  /// k / fps, and the step is the nearest; empty: frame k shows simulated time k / fps.
  std::function<double(double)> sim_time;
  long step(long k) const;  ///< step count at which frame k (0 <= k < frames) is taken
};
FramePlan plan_frames(double duration, double dt, double fps);

// Limits of one run, checked before anything is allocated or stepped.
constexpr double kMaxSteps = 1e9;   ///< physics steps (duration / timestep)
constexpr double kMaxFrames = 1e7;  ///< frames (duration x fps)

// Readies a scene's run after its overrides: throws UsageError-like std::invalid_argument naming
// the keys when the step or frame count is over the limits, and makes every frame fall exactly
// at k / fps: when 1/fps is not a whole number of steps, the timestep becomes the largest that
// divides the frame interval (never longer than asked), with a note in scene.notes saying so
// (at fps 25 and dt 1/240 frames used to fall 37.5-41.7 ms apart; a step longer than the frame
// interval repeated frames). A run that is legal but long (more than kLongSteps steps or
// kLongFrames frames, or an estimated kLongSeconds of physics) gets a note saying so, how long it
// may take and how to stop it. Returns nothing; notes go to scene.notes.
void prepare_run(Scene& scene);

constexpr double kLongSteps = 1e7, kLongFrames = 1e6, kLongSeconds = 300;
// Seconds of physics a run of `steps` steps of the scene's bodies may take on a typical machine:
// per step 1 us, plus per dynamic body 0.03 us alone (bench R2: 3.4e7 free body-steps/s) or
// 1.5 us where contacts are possible (R3: a settling pile of 1000 cubes, 1.6 us). A warning's
// order of magnitude, not a promise.
double estimate_physics_seconds(const Scene& scene, double steps);

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

 private:
  double E0_, scale_, max_dE_ = 0, max_dL_ = 0, prev_E_ = 0, max_rise_ = 0;
  Vec3 L0_;
};

WorldConfig world_config(const Scene& s, int threads);

// The summary of a run: text for people, one JSON object for scripts.
struct RunSummary {
  std::string scene;
  Integrator integrator;
  double timestep = 0, duration = 0;
  long steps = 0;
  int bodies = 0, dynamic_bodies = 0, frames = 0;
  double step_seconds = 0;  ///< wall time inside World::step only
  double energy_rel_drift = 0, momentum_rel_drift = 0;
  bool contacts = false;              ///< the scene has colliding shapes
  int contacts_max = 0;               ///< most contact points in a step
  double max_penetration = 0;         ///< m, over the run
  int sleeping = 0;                   ///< bodies asleep at the end
  double energy_gained = 0;           ///< J, largest rise between two frames
  std::vector<std::string> warnings;  ///< what went wrong or was odd in the run
  std::vector<std::string> notes;     ///< the scene's notes (already printed on stderr before the run)
  const Profile* profile = nullptr;   ///< set with --profile
  double render_seconds = -1, encode_seconds = -1;  ///< render command only
  std::string renderer;                             ///< render command only: GL backend, renderer, version
  std::string output;
};
// The fields every command fills the same way: scene, world counters, drift, warnings and notes.
RunSummary make_summary(const Scene& scene, const World& world, const Drift& drift, int frames,
                        double step_seconds);
std::string summary_text(const RunSummary& s);
std::string summary_json(const RunSummary& s);

}  // namespace simreel
