// The one frame loop. Every command that runs a scene (simulate, render, check, diff's renders)
// and the benchmarks drive the world through it: it owns the world, the frame plan and the drift
// figures, steps the physics through every step in order, and calls a hook at each frame that is
// wanted. Frames that are not wanted cost nothing but their steps: the physics runs through them.
#pragma once
#include <atomic>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"
#include <simreel/world.hpp>

namespace simreel {

// One moment at which a frame is taken.
struct FrameTarget {
  long index = -1;  ///< frame k of the plan (video time k / fps), or -1 for a time between plan frames
  double time = 0;  ///< s, the nominal time asked for (of the video, for frames of a video plan)
  long step = 0;    ///< the world's step count when it is taken: the first step whose time reaches `time`
};

// The step at which time t is shown: the first step whose time reaches t (the 1e-9 slack keeps
// exact multiples from gaining a step to rounding), at most the last step.
long step_at(double t, double dt, long total_steps);

// Frame k of the plan as a target.
FrameTarget plan_target(const FramePlan& plan, long k, double fps);

// Targets in the order they are taken (by step, then time), held as runs of consecutive frames of
// a plan and single targets: never one entry per frame, so all 1e7 frames of a plan are one run
// (as a list of FrameTargets they took 240 MB). Reads like a list of FrameTargets.
class FrameTargets {
 public:
  FrameTargets() = default;
  FrameTargets(std::initializer_list<FrameTarget> ts) : FrameTargets(std::vector<FrameTarget>(ts)) {}
  FrameTargets(const std::vector<FrameTarget>& ts);  ///< each a single target, in the order given
  // Frames first..last (inclusive) of `plan`; the plan is kept (one plan per FrameTargets).
  void push_back_frames(const FramePlan& plan, long first, long last);
  void push_back(const FrameTarget& t);
  void push_front(const FrameTarget& t);

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  FrameTarget operator[](size_t i) const;
  FrameTarget front() const { return (*this)[0]; }
  FrameTarget back() const { return (*this)[size_ - 1]; }

  class const_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = FrameTarget;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = FrameTarget;
    const_iterator() = default;
    FrameTarget operator*() const;
    const_iterator& operator++();
    const_iterator operator++(int) {
      const_iterator old = *this;
      ++*this;
      return old;
    }
    bool operator==(const const_iterator& o) const { return run_ == o.run_ && at_ == o.at_; }

   private:
    friend class FrameTargets;
    const FrameTargets* t_ = nullptr;
    size_t run_ = 0;
    long at_ = 0;  ///< offset in the run
  };
  const_iterator begin() const;
  const_iterator end() const;

 private:
  struct Run {
    long first = 0, count = 1;  ///< frames first .. first + count - 1 of the plan, if `frames`
    bool frames = false;
    FrameTarget single;  ///< else this one
  };
  FrameTarget at(const Run& r, long offset) const;
  std::vector<Run> runs_;
  FramePlan plan_;
  size_t size_ = 0;
};

// A frame spec: comma-separated items, each
//   N        frame N of the plan (t = N / fps)
//   A:B      frames A to B, both included; A defaults to 0, B to the last frame
//   Ts       the moment t = T seconds ("2.5s"), whether or not a frame of the plan falls there
//   P%       the moment P percent of the duration ("50%")
// Targets come back sorted by step, duplicates removed. With `plan_only` (a video or a numbered
// PNG sequence, whose frames fall at k / fps) a time takes the first frame of the plan at or
// after it. Throws std::invalid_argument with a message naming the item for anything else, or
// for a frame or time outside the run.
FrameTargets parse_frame_spec(const std::string& spec, const FramePlan& plan, double fps, double dt,
                              double duration, bool plan_only = false);

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
