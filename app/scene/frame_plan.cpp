#include "app/scene/frame_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "app/scene/scene.hpp"

namespace simreel {

namespace {
// A count as a long, saturated: plans are made before prepare_run refuses absurd counts (a
// scene's test.frames is checked at load), and a double over LONG_MAX must not become a long.
long saturated(double v) {
  return v >= 4e18 ? (long)4e18 : v > 0 ? (long)v : 0;
}
}  // namespace

FramePlan plan_frames(double duration, double dt, double fps) {
  FramePlan p;
  p.dt = dt;
  p.fps = fps;
  // The 1e-9 slack keeps exact multiples (20 s / (1/240)) from gaining a step to rounding.
  p.total_steps = saturated(std::ceil(duration / dt - 1e-9));
  p.frames = saturated(std::floor(duration * fps + 1e-9)) + 1;
  return p;
}

long FramePlan::step(long k) const {
  if (sim_time) return std::min(saturated(std::round(sim_time((double)k / fps) / dt)), total_steps);
  return std::min(saturated(std::ceil((double)k / fps / dt - 1e-9)), total_steps);
}

double estimate_physics_seconds(const Scene& s, double steps) {
  int dynamic = 0, colliding = 0;
  bool moving_collider = false;
  for (const BodyDef& b : s.bodies) {
    if (b.type == BodyType::dynamic) ++dynamic;
    for (const Collider& c : b.colliders)
      if (c.collide) {
        ++colliding;
        moving_collider = moving_collider || b.type != BodyType::static_body;
      }
  }
  const bool contacts = colliding >= 2 && moving_collider;
  return steps * (1e-6 + dynamic * (contacts ? 1.5e-6 : 0.03e-6));
}

namespace {

std::string count(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return std::string(b);
}

std::string span(double sec) {
  char b[48];
  if (sec < 120)
    std::snprintf(b, sizeof b, "%.2g s", sec);
  else if (sec < 7200)
    std::snprintf(b, sizeof b, "%.2g min", sec / 60);
  else if (sec < 2 * 86400)
    std::snprintf(b, sizeof b, "%.2g h", sec / 3600);
  else
    std::snprintf(b, sizeof b, "%.2g days", sec / 86400);
  return std::string(b);
}

void check_limits(const Scene& s) {
  const double steps = s.duration / s.timestep, frames = s.duration * s.video.fps;
  if (!(steps <= kMaxSteps))
    throw std::invalid_argument("simulation.duration / simulation.timestep asks for " + count(steps) +
                                " steps, over the limit of " + count(kMaxSteps));
  if (!(frames <= kMaxFrames))
    throw std::invalid_argument("simulation.duration x video.fps asks for " + count(frames) +
                                " frames, over the limit of " + count(kMaxFrames));
}

}  // namespace

void prepare_run(Scene& s) {
  check_limits(s);
  // Steps per frame interval: when 1/fps is a whole number of steps (to 1e-9), frames already
  // fall on the grid; otherwise shorten the step to the next whole number of steps per frame.
  const double interval = 1.0 / s.video.fps, per = interval / s.timestep;
  const double whole = std::round(per);
  if (!(whole >= 1 && std::fabs(per - whole) <= 1e-9 * per)) {
    const double n = std::ceil(per);
    const double dt = interval / n;
    char note[256];
    std::snprintf(
        note, sizeof note,
        "timestep %.6g s does not divide the frame interval 1/%g s%s: using %.6g s (%g steps a frame) so "
        "frame k falls exactly at t = k / fps",
        s.timestep, s.video.fps, per < 1 ? " (it is longer than the interval)" : "", dt, n);
    s.notes.push_back(note);
    s.timestep = dt;
    check_limits(s);  // a shorter step is more steps
  }
  prepare_time(s);  // app/scene/scene_time.hpp
  // Legal but long: say so before starting, with what it may take and how to stop it.
  const double steps = s.duration / s.timestep, frames = s.duration * s.video.fps;
  const double est = estimate_physics_seconds(s, steps);
  if (steps > kLongSteps || frames > kLongFrames || est > kLongSeconds) {
    int dynamic = 0;
    for (const BodyDef& b : s.bodies) dynamic += b.type == BodyType::dynamic;
    char note[512];
    std::snprintf(note, sizeof note,
                  "a long run: simulation.duration %g s / simulation.timestep %g s is %s steps of %d dynamic "
                  "%s, and %s frames at video.fps %g; the physics alone may take %s (a rough estimate "
                  "from bodies x steps), a full render about %s more at 10 ms a frame. Ctrl-C (or SIGTERM) "
                  "stops it early and keeps what is done: the CSV rows, a playable video of the frames drawn",
                  s.duration, s.timestep, count(steps).c_str(), dynamic, dynamic == 1 ? "body" : "bodies",
                  count(frames).c_str(), s.video.fps, span(est).c_str(), span(frames * 0.01).c_str());
    s.notes.push_back(note);
  }
}

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

}  // namespace simreel
