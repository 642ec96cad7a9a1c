#include "app/runner/frame_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace simreel {

long step_at(double t, double dt, long total_steps) {
  return std::min((long)std::ceil(t / dt - 1e-9), total_steps);
}

FrameTarget plan_target(const FramePlan& plan, long k, double fps) {
  return {k, (double)k / fps, plan.step(k)};
}

FrameTargets::FrameTargets(const std::vector<FrameTarget>& ts) {
  for (const FrameTarget& t : ts) push_back(t);
}

void FrameTargets::push_back_frames(const FramePlan& plan, long first, long last) {
  if (last < first) return;
  plan_ = plan;
  Run r;
  r.first = first;
  r.count = last - first + 1;
  r.frames = true;
  runs_.push_back(r);
  size_ += (size_t)r.count;
}

void FrameTargets::push_back(const FrameTarget& t) {
  Run r;
  r.single = t;
  runs_.push_back(r);
  ++size_;
}

void FrameTargets::push_front(const FrameTarget& t) {
  Run r;
  r.single = t;
  runs_.insert(runs_.begin(), r);
  ++size_;
}

FrameTarget FrameTargets::at(const Run& r, long offset) const {
  return r.frames ? plan_target(plan_, r.first + offset, plan_.fps) : r.single;
}

FrameTarget FrameTargets::operator[](size_t i) const {
  for (const Run& r : runs_) {
    if (i < (size_t)r.count) return at(r, (long)i);
    i -= (size_t)r.count;
  }
  throw std::out_of_range("frame target " + std::to_string(i) + " of " + std::to_string(size_));
}

FrameTargets::const_iterator FrameTargets::begin() const {
  const_iterator it;
  it.t_ = this;
  return it;
}
FrameTargets::const_iterator FrameTargets::end() const {
  const_iterator it;
  it.t_ = this;
  it.run_ = runs_.size();
  return it;
}
FrameTarget FrameTargets::const_iterator::operator*() const {
  return t_->at(t_->runs_[run_], at_);
}
FrameTargets::const_iterator& FrameTargets::const_iterator::operator++() {
  if (++at_ >= t_->runs_[run_].count) {
    ++run_;
    at_ = 0;
  }
  return *this;
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

FrameTargets parse_frame_spec(const std::string& spec, const FramePlan& plan, double fps, double dt,
                              double duration, bool plan_only) {
  const long n = plan.frames;
  // Frames of the plan as ranges (first, last), moments between them as single targets.
  std::vector<std::pair<long, long>> ranges;
  std::vector<FrameTarget> moments;
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
      ranges.emplace_back(k, k);
    else if (plan_only)
      ranges.emplace_back(std::min(n - 1, (long)std::ceil(kf)), std::min(n - 1, (long)std::ceil(kf)));
    else
      moments.push_back({-1, t, step_at(t, dt, plan.total_steps)});
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
      ranges.emplace_back(lo, hi);
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
      ranges.emplace_back(k, k);
    }
  }
  // Sorted by step, then time, duplicates merged: the ranges joined where they overlap or touch
  // (frame k's step and time never decrease with k), the moments sorted, then each moment put
  // between the frames it falls between, splitting a range if it falls inside one.
  std::sort(ranges.begin(), ranges.end());
  std::vector<std::pair<long, long>> joined;
  for (const auto& r : ranges)
    if (!joined.empty() && r.first <= joined.back().second + 1)
      joined.back().second = std::max(joined.back().second, r.second);
    else
      joined.push_back(r);
  auto before = [](const FrameTarget& a, const FrameTarget& b) {
    return a.step != b.step ? a.step < b.step : a.time < b.time;
  };
  std::sort(moments.begin(), moments.end(), before);
  moments.erase(std::unique(moments.begin(), moments.end(),
                            [](const FrameTarget& a, const FrameTarget& b) {
                              return a.step == b.step && a.time == b.time;
                            }),
                moments.end());
  FrameTargets out;
  size_t m = 0;
  for (auto [lo, hi] : joined) {
    while (lo <= hi) {
      if (m < moments.size() && before(moments[m], plan_target(plan, lo, fps))) {
        out.push_back(moments[m++]);
        continue;
      }
      // The frames from lo up to the next moment (or to hi): the first frame after the moment,
      // by bisection over lo..hi + 1.
      long end = hi + 1;
      if (m < moments.size()) {
        long a = lo, b = hi + 1;  // frame a is before the moment; the answer is in (a, b]
        while (b - a > 1) {
          const long mid = a + (b - a) / 2;
          (before(moments[m], plan_target(plan, mid, fps)) ? b : a) = mid;
        }
        end = b;
      }
      out.push_back_frames(plan, lo, end - 1);
      lo = end;
    }
  }
  while (m < moments.size()) out.push_back(moments[m++]);
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
      if (hooks.step) hooks.step(world_);
    }
    step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (interrupted_) return;
  }
}

long FrameLoop::run(const FrameTargets& targets, const Hooks& hooks, bool to_end) {
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
