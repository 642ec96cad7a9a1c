// Playback time apart from the physics (the scene's `time:` block, scenes/README.md): slow motion,
// segments with their own speed and holds (freeze frames). The physics keeps its fixed step; the
// video samples simulated times f(video time) on the step grid.
//
// Why on the grid: a frame shows the state of a step the physics really took, the state
// `simulate --csv` reports and `check` compares, never a state made for the picture. Integrating
// a copy of the world from the last step to the exact time f(t) would keep the trajectory's grid
// too, but the frame would then show a state computed with a shorter step, a different
// approximation than any step of the run (and for contacts a different solve). The cost of the
// grid is a jitter of at most half a step of simulated time where speed / fps is not a whole
// number of steps; prepare_time() says so in a note, with the speed that plays evenly.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace simreel {

struct Scene;

struct TimeSegment {
  double until = 0;  ///< s of simulated time: the segment runs from the previous one's end to here
  double speed = 1;  ///< simulated seconds per second of video (0.25: four times slower)
};
struct TimeHold {
  double at = 0;       ///< s of simulated time: the frozen moment
  double seconds = 0;  ///< s of video the frame is held (`for`)
};
struct TimeSpec {
  double speed = 1;                   ///< simulated seconds per second of video outside the segments
  std::vector<TimeSegment> segments;  ///< by `until`, ascending
  std::vector<TimeHold> holds;        ///< by `at`, ascending
  bool identity() const { return speed == 1 && segments.empty() && holds.empty(); }
};

// The playback map: video time tau -> simulated time f(tau), piecewise linear, continuous and
// non-decreasing, from f(0) = 0 to f(video_duration()) = duration.
class TimeMap {
 public:
  struct Piece {
    double v0, v1;  ///< s of video
    double s0;      ///< s simulated at v0
    double rate;    ///< simulated s per video s; 0 for a hold
  };
  TimeMap(const TimeSpec& spec, double duration);
  double video_duration() const { return pieces_.empty() ? 0 : pieces_.back().v1; }
  double sim_time(double video_t) const;  ///< f, clamped to [0, duration]
  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  std::vector<Piece> pieces_;
  double duration_;
};

// Reads the top-level `time:` into s.time; throws InputError "FILE:LINE:COL: KEY: what".
void load_time(const YAML::Node& root, const std::string& path, Scene& s);

// After the run's overrides (--fps, --timestep, --duration): refuses a video of more frames than
// kMaxFrames (std::invalid_argument) and notes speeds at which frames do not fall a whole number
// of steps apart (they show the nearest step: a jitter of up to half a step).
void prepare_time(Scene& s);

// The frame plan of the video: frame k (video time k / fps) shows the step nearest f(k / fps)
// (step(k)), for k = 0 .. the last k / fps <= video_duration.
struct FramePlan;
FramePlan plan_video(const TimeMap& map, double dt, double fps);

}  // namespace simreel
