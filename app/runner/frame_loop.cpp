#include "app/runner/frame_loop.hpp"

#include <algorithm>
#include <chrono>

namespace simreel {

FrameLoop::FrameLoop(const Scene& scene, int threads)
    : FrameLoop(world_config(scene, threads), scene.bodies, scene.duration, scene.video.fps) {
  if (!scene.time.identity()) {
    const TimeMap map(scene.time, scene.duration);
    video_ = plan_video(map, scene.timestep, fps_);
    video_duration_ = map.video_duration();
  }
}

FrameLoop::FrameLoop(const WorldConfig& config, const std::vector<BodyDef>& bodies, double duration,
                     double fps)
    : world_(config, bodies),
      fps_(fps),
      plan_(plan_frames(duration, config.dt, fps)),
      video_(plan_),
      video_duration_(duration),
      drift_(world_) {}

namespace {
// The first frame of `plan` taken at or after `step` (steps never decrease with k), by bisection;
// plan.frames if none.
long first_at_or_after(const FramePlan& plan, long step) {
  long a = -1, b = plan.frames;  // frame a is before `step`; the answer is in (a, b]
  while (b - a > 1) {
    const long mid = a + (b - a) / 2;
    (plan.step(mid) >= step ? b : a) = mid;
  }
  return b;
}
}  // namespace

FrameTargets FrameLoop::all_frames() const {
  FrameTargets out;
  out.push_back_frames(plan_, first_at_or_after(plan_, world_.steps()), plan_.frames - 1);
  return out;
}

FrameTargets FrameLoop::video_frames() const {
  FrameTargets out;
  out.push_back_frames(video_, first_at_or_after(video_, world_.steps()), video_.frames - 1);
  return out;
}

long FrameLoop::video_frame_at_step(long step) const {
  const long k = first_at_or_after(video_, step);
  return k < video_.frames && video_.step(k) == step ? k : -1;
}

void FrameLoop::advance_to(long step, const Hooks& hooks) {
  const std::atomic<int>* stop = hooks.stop;
  const long n = plan_.frames;
  for (;;) {
    // Frames of the plan at the current step: the drift is sampled there, whatever is drawn.
    while (next_sample_ < n && plan_.step(next_sample_) <= world_.steps()) {
      if (plan_.step(next_sample_) == world_.steps()) {
        world_.check_spin();
        drift_.sample(world_);
      }
      ++next_sample_;
    }
    if (world_.steps() >= step) return;
    const long until = next_sample_ < n ? std::min(step, plan_.step(next_sample_)) : step;
    const auto t0 = std::chrono::steady_clock::now();
    while (world_.steps() < until) {
      if (stop && stop->load(std::memory_order_relaxed)) {
        interrupted_ = true;
        break;
      }
      world_.step();
      drift_.step(world_);
      if (hooks.step) hooks.step(world_);
    }
    step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (interrupted_) return;
  }
}

long FrameLoop::run(const FrameTargets& targets, const Hooks& hooks, bool to_end) {
  long done = 0;
  std::vector<long> samples;  // a target's sub-frame steps (motion blur)

  if (hooks.step) hooks.step(world_);  // the state the run starts from
  for (const FrameTarget& t : targets) {
    if (t.step < world_.steps()) continue;  // before a resumed world's start
    if (hooks.sample && hooks.sample_steps) {
      samples.clear();
      hooks.sample_steps(t, samples);
      for (const long s : samples) {
        if (s < world_.steps() || s >= t.step) continue;
        advance_to(s, hooks);
        if (interrupted_) return done;
        hooks.sample(t, world_);
      }
    }
    advance_to(t.step, hooks);
    if (interrupted_) return done;
    if (hooks.frame) hooks.frame(t, world_);
    ++done;
    if (hooks.progress) hooks.progress(done);
    if (hooks.stop && hooks.stop->load(std::memory_order_relaxed)) {
      interrupted_ = true;
      return done;
    }
  }
  if (to_end) {
    advance_to(plan_.total_steps, hooks);
    if (!interrupted_) drift_.sample(world_);  // the end, whether or not a frame falls there
  }
  return done;
}

}  // namespace simreel
