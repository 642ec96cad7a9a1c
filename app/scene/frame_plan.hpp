// A scene's timeline: which physics steps and which frames a run has, the limits on their counts,
// and frame specs (`--frames`, a scene's test.frames) read against that plan. It is the scene's:
// loading checks test.frames against it and a variant's own timestep is readied by prepare_run;
// the runner (app/runner/frame_loop.hpp) only steps through it.
#pragma once
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

namespace simreel {

struct Scene;

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

}  // namespace simreel
