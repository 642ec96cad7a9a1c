#include "app/scene/scene_time.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "app/scene/frame_plan.hpp"
#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"

namespace simreel {

using namespace scene_yaml;

TimeMap::TimeMap(const TimeSpec& spec, double duration) : duration_(duration) {
  // Every moment where the rate changes: segment ends, holds, the end of the run.
  std::vector<double> marks = {duration};
  for (const TimeSegment& g : spec.segments)
    if (g.until < duration) marks.push_back(g.until);
  for (const TimeHold& h : spec.holds)  // (a hold after a shortened --duration is dropped)
    if (h.at <= duration) marks.push_back(h.at);
  std::sort(marks.begin(), marks.end());
  marks.erase(std::unique(marks.begin(), marks.end()), marks.end());
  auto speed_at = [&](double s) {
    for (const TimeSegment& g : spec.segments)
      if (s < g.until) return g.speed;
    return spec.speed;
  };
  double v = 0, s = 0;
  for (double m : marks) {
    if (m > s) {
      const double rate = speed_at(s);
      pieces_.push_back({v, v + (m - s) / rate, s, rate});
      v = pieces_.back().v1;
      s = m;
    }
    for (const TimeHold& h : spec.holds)
      if (h.at == m) {
        pieces_.push_back({v, v + h.seconds, s, 0.0});
        v = pieces_.back().v1;
      }
  }
}

double TimeMap::sim_time(double tau) const {
  if (pieces_.empty() || tau <= 0) return 0;
  // The last piece that starts at or before tau (a hold's start belongs to the hold).
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), tau,
                             [](double t, const Piece& p) { return t < p.v0; });
  const Piece& p = *(it - 1);
  return std::clamp(p.s0 + p.rate * (std::min(tau, p.v1) - p.v0), 0.0, duration_);
}

FramePlan plan_video(const TimeMap& map, double dt, double fps) {
  FramePlan p;
  const double duration = map.pieces().empty() ? 0 : map.sim_time(map.video_duration());
  p.total_steps = (long)std::ceil(duration / dt - 1e-9);
  p.frames = (long)std::floor(map.video_duration() * fps + 1e-9) + 1;
  p.dt = dt;
  p.fps = fps;
  p.sim_time = [map](double t) { return map.sim_time(t); };  // frame k: llround(sim_time(k / fps) / dt)
  return p;
}

void load_time(const YAML::Node& root, const std::string& path, Scene& s) {
  const YAML::Node t = root["time"];
  if (!t) return;
  const Ctx c = Ctx(path, "").child("time");
  if (!t.IsMap()) c.fail(t, "expected a mapping with speed, segments or hold, got " + show(t));
  check_keys(t, c, {"speed", "segments", "hold"});
  TimeSpec& ts = s.time;
  if (t["speed"]) ts.speed = positive(t["speed"], c.child("speed"));
  if (const YAML::Node segs = t["segments"]) {
    const Ctx sc = c.child("segments");
    if (!segs.IsSequence() || segs.size() == 0)
      sc.fail(segs, "expected a list of { until: T, speed: S }, got " + show(segs));
    for (size_t k = 0; k < segs.size(); ++k) {
      const Ctx e = sc.index(k);
      const YAML::Node n = segs[k];
      if (!n.IsMap()) e.fail(n, "expected { until: T, speed: S }, got " + show(n));
      check_keys(n, e, {"until", "speed"});
      if (!n["until"]) e.fail(n, "needs 'until' (s of simulated time where the segment ends)");
      if (!n["speed"]) e.fail(n, "needs 'speed' (simulated seconds per second of video)");
      TimeSegment g;
      g.until = positive(n["until"], e.child("until"));
      g.speed = positive(n["speed"], e.child("speed"));
      if (!ts.segments.empty() && g.until <= ts.segments.back().until)
        e.child("until").fail(n["until"], "must be after the previous segment's until (" +
                                              std::to_string(ts.segments.back().until) + " s)");
      if (g.until > s.duration * (1 + 1e-12))
        e.child("until").fail(n["until"], "is after the end of the run (simulation.duration " +
                                              std::to_string(s.duration) + " s)");
      ts.segments.push_back(g);
    }
  }
  if (const YAML::Node h = t["hold"]) {
    const Ctx hc = c.child("hold");
    const bool list = h.IsSequence();
    if (!list && !h.IsMap()) hc.fail(h, "expected { at: T, for: S } or a list of them, got " + show(h));
    const size_t n = list ? h.size() : 1;
    if (n == 0) hc.fail(h, "expected { at: T, for: S } or a list of them, got an empty list");
    for (size_t k = 0; k < n; ++k) {
      const YAML::Node e = list ? h[k] : h;
      const Ctx ec = list ? hc.index(k) : hc;
      if (!e.IsMap()) ec.fail(e, "expected { at: T, for: S }, got " + show(e));
      check_keys(e, ec, {"at", "for"});
      if (!e["at"]) ec.fail(e, "needs 'at' (s of simulated time to freeze)");
      if (!e["for"]) ec.fail(e, "needs 'for' (s of video to hold the frame)");
      TimeHold th;
      th.at = non_negative(e["at"], ec.child("at"));
      th.seconds = positive(e["for"], ec.child("for"));
      if (th.at > s.duration * (1 + 1e-12))
        ec.child("at").fail(e["at"], "is after the end of the run (simulation.duration " +
                                         std::to_string(s.duration) + " s)");
      for (const TimeHold& o : ts.holds)
        if (o.at == th.at)
          ec.child("at").fail(e["at"], "another hold is at the same moment: give one, longer");
      ts.holds.push_back(th);
    }
    std::sort(ts.holds.begin(), ts.holds.end(),
              [](const TimeHold& a, const TimeHold& b) { return a.at < b.at; });
  }
}

void prepare_time(Scene& s) {
  if (s.time.identity()) return;
  const TimeMap map(s.time, s.duration);
  const double frames = map.video_duration() * s.video.fps;
  if (!(frames <= kMaxFrames)) {
    char b[64];
    std::snprintf(b, sizeof b, "%.3g", frames);
    throw std::invalid_argument("time: the video plays " + std::to_string(map.video_duration()) +
                                " s, which at video.fps asks for " + b + " frames, over the limit");
  }
  // Speeds at which a frame is not a whole number of steps after the last.
  std::vector<double> told;
  for (const TimeMap::Piece& p : map.pieces()) {
    if (p.rate == 0 || std::find(told.begin(), told.end(), p.rate) != told.end()) continue;
    const double per = p.rate / (s.video.fps * s.timestep), whole = std::round(per);
    if (whole >= 1 && std::fabs(per - whole) <= 1e-9 * per) continue;
    told.push_back(p.rate);
    // The nearest speed at which a frame is a whole number of steps (at least one).
    const double even = std::max(1.0, std::round(per)) * s.video.fps * s.timestep;
    char note[300];
    std::snprintf(note, sizeof note,
                  "time: at speed %g a frame is %.3g physics steps after the last: frames show the nearest "
                  "step (within half a step, %.3g ms of simulated time); speed %.6g plays evenly",
                  p.rate, per, 0.5e3 * s.timestep, even);
    s.notes.push_back(note);
  }
}

}  // namespace simreel
