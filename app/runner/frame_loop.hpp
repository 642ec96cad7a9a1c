// The one frame loop. Every command that runs a scene (simulate, render, check, diff's renders)
// and the benchmarks drive the world through it: it owns the world, the frame plan and the drift
// figures, steps the physics through every step in order, and calls a hook at each frame that is
// wanted. Frames that are not wanted cost nothing but their steps: the physics runs through them.
#pragma once
#include <atomic>
#include <functional>
#include <vector>

#include <simreel/world.hpp>
#include "app/runner/run.hpp"
#include "app/scene/frame_plan.hpp"
#include "app/scene/scene.hpp"

namespace simreel {

class FrameLoop {
 public:
  // The world as the scene describes it, `threads` integration threads. A scene with a `time:`
  // block gets a video plan apart from its simulation plan (app/scene/scene_time.hpp).
  FrameLoop(const Scene& scene, int threads);
  // For programs without a scene file (the benchmarks): the same loop over bodies built in code.
  FrameLoop(const WorldConfig& config, const std::vector<BodyDef>& bodies, double duration, double fps);

  World& world() { return world_; }
  const World& world() const { return world_; }
  /// Frame k of the simulation plan is simulated time k / fps: where drift is sampled, what
  /// simulate writes and check's times name.
  const FramePlan& plan() const { return plan_; }
  /// Frame k of the video (video time k / fps) shows step video_plan().step(k): the
  /// simulation plan itself unless the scene's `time:` remaps playback.
  const FramePlan& video_plan() const { return video_; }
  double video_duration() const { return video_duration_; }  ///< s
  // The first frame of the video that shows step `step`, or -1 if none does.
  long video_frame_at_step(long step) const;
  const Drift& drift() const { return drift_; }
  double fps() const { return fps_; }
  double step_seconds() const { return step_seconds_; }  ///< s of wall time inside World::step
  bool interrupted() const { return interrupted_; }

  // After the world's state was replaced (a resumed run): drift is measured from here.
  void state_restored() { drift_ = Drift(world_); }

  // Every frame of the simulation plan from the world's current step on (a resumed world starts
  // late): what simulate writes.
  FrameTargets all_frames() const;
  // Every frame of the video plan from the world's current step on: what render draws.
  FrameTargets video_frames() const;

  struct Hooks {
    std::function<void(const FrameTarget&, const World&)> frame;  ///< at each target, in order
    std::function<void(long done)> progress;                      ///< after each target
    /// At every physics step the loop runs through, drawn or not (and once at the state it
    /// starts from): what a trail's history is recorded from (app/view/overlays.hpp), so it depends on
    /// the steps alone, never on which frames are drawn.
    std::function<void(const World&)> step;
    /// Sub-frame states (motion blur, app/view/motion_blur.hpp): before each target, `sample_steps`
    /// names steps before it (ascending) and `sample` is called at each on the way, after that
    /// step's `step` hook; steps the world is already past (a resumed world's start) are skipped.
    /// The physics is the same with or without them.
    std::function<void(const FrameTarget&, std::vector<long>&)> sample_steps;
    std::function<void(const FrameTarget&, const World&)> sample;
    const std::atomic<int>* stop = nullptr;  ///< checked between steps: non-zero ends the run early
  };
  // Steps from the world's current step through `targets` (sorted by step, from parse_frame_spec or
  // all_frames), calling the hooks at each. At every frame of the plan passed on the way the drift
  // is sampled and the spin checked, whichever targets are drawn, so the figures of a run do not
  // depend on which frames a command wants. With `to_end` the physics goes on to the duration's
  // last step after the last target (and samples there). Returns the targets delivered: fewer
  // than asked only if stopped.
  long run(const FrameTargets& targets, const Hooks& hooks, bool to_end);
  // Steps on to `step` (the hooks' step and stop only; drift sampled on the way as in run()):
  // how the worlds of a scene's variants are kept at the frame the main loop shows.
  void advance_to(long step, const Hooks& hooks);

 private:
  World world_;
  double fps_;
  FramePlan plan_, video_;
  double video_duration_ = 0;
  Drift drift_;
  long next_sample_ = 0;  ///< the next frame of the plan at which drift is sampled
  double step_seconds_ = 0;
  bool interrupted_ = false;
};

}  // namespace simreel
