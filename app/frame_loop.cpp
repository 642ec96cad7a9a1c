#include "app/frame_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace simreel {

long step_at(double t, double dt, long total_steps) {
  return std::min((long)std::ceil(t / dt - 1e-9), total_steps);
}

FrameTarget plan_target(const FramePlan& plan, long k, double fps) {
  return {k, (double)k / fps, plan.frame_step[(size_t)k]};
}

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// A whole number >= 0, all of `s`; -1 if it is not one.
long whole(const std::string& s) {
  if (s.empty() || s.size() > 12 || s.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stol(s);
}

double real(const std::string& s, const std::string& item) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    throw std::invalid_argument("'" + item +
                                "' is not a frame number, a range A:B, a time like 2.5s or a share like 50%");
  return v;
}

}  // namespace

std::vector<FrameTarget> parse_frame_spec(const std::string& spec, const FramePlan& plan, double fps,
                                          double dt, double duration, bool plan_only) {
  const long n = (long)plan.frame_step.size();
  std::vector<FrameTarget> out;
  auto check = [&](long k, const std::string& item) {
    if (k < 0 || k >= n)
      throw std::invalid_argument("frame " + std::to_string(k) + " in '" + item +
                                  "' is outside the run (frames 0 to " + std::to_string(n - 1) + ")");
  };
  auto moment = [&](double t, const std::string& item) {
    if (t < -1e-12 || t > duration * (1 + 1e-12))
      throw std::invalid_argument("time " + item + " is outside the run (0 to " + std::to_string(duration) +
                                  " s)");
    t = std::clamp(t, 0.0, duration);
    // A time on a frame of the plan is that frame, so its picture and its name are the frame's.
    const double kf = t * fps;
    const long k = std::lround(kf);
    if (std::fabs(kf - (double)k) <= 1e-9 * std::max(1.0, kf) && k < n)
      out.push_back({k, t, plan.frame_step[(size_t)k]});
    else if (plan_only)
      out.push_back(plan_target(plan, std::min(n - 1, (long)std::ceil(kf)), fps));
    else
      out.push_back({-1, t, step_at(t, dt, plan.total_steps)});
  };
  size_t pos = 0;
  while (pos <= spec.size()) {
    const size_t comma = std::min(spec.find(',', pos), spec.size());
    const std::string item = trim(spec.substr(pos, comma - pos));
    pos = comma + 1;
    if (item.empty()) throw std::invalid_argument("empty item in frame spec '" + spec + "'");
    if (const size_t colon = item.find(':'); colon != std::string::npos) {
      const std::string a = trim(item.substr(0, colon)), b = trim(item.substr(colon + 1));
      const long lo = a.empty() ? 0 : whole(a), hi = b.empty() ? n - 1 : whole(b);
      if (lo < 0 || hi < 0) throw std::invalid_argument("'" + item + "' is not a range of frame numbers A:B");
      if (lo > hi) throw std::invalid_argument("range '" + item + "' is empty (A > B)");
      check(lo, item);
      check(hi, item);
      for (long k = lo; k <= hi; ++k) out.push_back(plan_target(plan, k, fps));
    } else if (item.back() == 's') {
      moment(real(item.substr(0, item.size() - 1), item), item);
    } else if (item.back() == '%') {
      const double p = real(item.substr(0, item.size() - 1), item);
      if (p < 0 || p > 100) throw std::invalid_argument("'" + item + "' is not between 0% and 100%");
      moment(duration * p / 100, item);
    } else {
      const long k = whole(item);
      if (k < 0) real(item, item);  // throws with the grammar
      if (k < 0)
        throw std::invalid_argument("'" + item + "' is not a frame number (times end in s: " + item + "s)");
      check(k, item);
      out.push_back(plan_target(plan, k, fps));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const FrameTarget& a, const FrameTarget& b) {
    return a.step != b.step ? a.step < b.step : a.time < b.time;
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const FrameTarget& a, const FrameTarget& b) {
                          return a.step == b.step && a.index == b.index && a.time == b.time;
                        }),
            out.end());
  return out;
}

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

std::vector<FrameTarget> FrameLoop::all_frames() const {
  std::vector<FrameTarget> out;
  for (size_t k = 0; k < plan_.frame_step.size(); ++k)
    if (plan_.frame_step[k] >= world_.steps()) out.push_back(plan_target(plan_, (long)k, fps_));
  return out;
}

std::vector<FrameTarget> FrameLoop::video_frames() const {
  std::vector<FrameTarget> out;
  for (size_t k = 0; k < video_.frame_step.size(); ++k)
    if (video_.frame_step[k] >= world_.steps()) out.push_back(plan_target(video_, (long)k, fps_));
  return out;
}

long FrameLoop::video_frame_at_step(long step) const {
  const auto it = std::lower_bound(video_.frame_step.begin(), video_.frame_step.end(), step);
  return it != video_.frame_step.end() && *it == step ? (long)(it - video_.frame_step.begin()) : -1;
}

void FrameLoop::advance_to(long step, const Hooks& hooks) {
  const std::atomic<int>* stop = hooks.stop;
  const size_t n = plan_.frame_step.size();
  for (;;) {
    // Frames of the plan at the current step: the drift is sampled there, whatever is drawn.
    while (next_sample_ < n && plan_.frame_step[next_sample_] <= world_.steps()) {
      if (plan_.frame_step[next_sample_] == world_.steps()) {
        world_.check_spin();
        drift_.sample(world_);
      }
      ++next_sample_;
    }
    if (world_.steps() >= step) return;
    const long until = next_sample_ < n ? std::min(step, plan_.frame_step[next_sample_]) : step;
    const auto t0 = std::chrono::steady_clock::now();
    while (world_.steps() < until) {
      if (stop && stop->load(std::memory_order_relaxed)) {
        interrupted_ = true;
        break;
      }
      world_.step();
      if (hooks.step) hooks.step(world_);
    }
    step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (interrupted_) return;
  }
}

long FrameLoop::run(const std::vector<FrameTarget>& targets, const Hooks& hooks, bool to_end) {
  long done = 0;
  if (hooks.step) hooks.step(world_);  // the state the run starts from
  for (const FrameTarget& t : targets) {
    if (t.step < world_.steps()) continue;  // before a resumed world's start
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
