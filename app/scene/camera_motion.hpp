// A camera that moves (the `camera:` block's `path:`, `orbit:` and `follow: { damping }`, and the
// shutter, `render.motion_blur`; scenes/README.md). Every camera here is a pure function of the
// simulated time, or of the physics steps up to it, never of which frames were drawn before: frame
// k of `render --frames A:B` (and of a render in chunks) is byte for byte frame k of a full render.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

// One key of a camera path: what the camera is at time t. A key gives any of the four channels;
// each channel runs through the keys that give it (CameraPath).
struct CameraKey {
  double t = 0;                               ///< s of simulated time
  std::optional<Vec3> position, look_at, up;  ///< m (up: a direction, any length)
  std::optional<double> fov;                  ///< degrees, vertical
};

// A keyframed camera (`camera.path`). Each channel (position, look_at, up, fov) is a C1 cubic
// Hermite in time through the keys that give it: it takes each key's value exactly at the key's
// time, holds the first key's value before it and the last key's after it, and eases into and out
// of those holds (zero velocity at the end keys, so the hold joins C1). The inner keys' velocities
// are those of the parabola through the key and its two neighbours (for uneven key spacing, the
// weighted mean of the two neighbouring chords' slopes): the non-uniform Catmull-Rom of a curve
// parameterised by time. (Centripetal Catmull-Rom would reparameterise by distance, and the camera
// would then no longer pass a key at the key's time.) A channel that no key gives keeps the camera
// block's value; `up` is interpolated as a vector (the renderer normalises it).
class CameraPath {
 public:
  CameraPath() = default;
  // `keys` sorted by t, times distinct (load_scene checks).
  explicit CameraPath(std::vector<CameraKey> keys);
  bool empty() const { return keys_.empty(); }
  const std::vector<CameraKey>& keys() const { return keys_; }
  // The channels the keys give at time t (s), over the values passed in; the others untouched.
  void apply(double t, Vec3& position, Vec3& look_at, Vec3& up, double& fov_deg) const;

 private:
  struct Track {  // one channel: times, values and velocities at its keys
    std::vector<double> t;
    std::vector<Vec3> v, m;
    Vec3 at(double time) const;
  };
  std::vector<CameraKey> keys_;
  Track position_, look_at_, up_, fov_;  // fov_: in x
};

// A camera circling a point or a body (`camera.orbit`) about the vertical (+z) axis, looking at
// the centre: at time t its eye is centre + (radius cos a, radius sin a, height) with
// a = start_angle + rate t.
struct CameraOrbit {
  Vec3 center = Vec3::Zero();  ///< m, the fixed centre when `body` is empty
  std::string body;            ///< "" or the body whose centre of mass is the centre, at every frame
  double radius = 0;           ///< m, horizontal distance of the eye from the centre, > 0
  double height = 0;           ///< m, of the eye above the centre
  double rate = 0;             ///< rad/s, counter-clockwise seen from above (negative: clockwise)
  double start_angle = 0;      ///< rad, from +x towards +y, at t = 0
  Vec3 eye(double t, const Vec3& centre) const;  ///< m, at time t (s)
};

// A critically damped follow (`camera.follow: { body, damping }`): a point that lags the body's
// centre of mass p(t) as x'' + 2 w x' + w^2 x = w^2 p with w = 1 / damping (no overshoot, the
// fastest such lag without one). Advanced at every physics step through the frame loop's step
// hook (app/view/scene_view.cpp), with p taken as linear between steps and the step solved in
// closed form: for a target moving at u, z = x - (p - 2u/w) obeys z'' + 2 w z' + w^2 z = 0, so
// z(h) = (z0 + (z0' + w z0) h) e^(-w h) and z'(h) = (z0' - w (z0' + w z0) h) e^(-w h) (exact for
// any step, stable whatever w h). Its state at a step is therefore a function of the body's
// trajectory up to that step alone: the same whichever frames are drawn. (A closed form over the
// whole trajectory would need every past state at each frame; the recursion is that closed form
// applied step by step.) A body moving at a constant velocity u is followed at a lag of 2 u / w
// once the start (camera at rest on the body) has died away, as (2/w + t) e^(-w t).
class DampedFollow {
 public:
  explicit DampedFollow(double damping) : w_(1 / damping) {}  ///< damping: s, > 0
  // The body's centre of mass `p` at physics step `step`, time `t` (s). The first call sets the
  // follow at rest on p (the state the run starts from); later ones advance it to a later step
  // (steps already seen are ignored, so a hook called twice at a step does no harm).
  void track(long step, double t, const Vec3& p);
  bool started() const { return started_; }
  const Vec3& position() const { return x_; }  ///< m
  const Vec3& velocity() const { return v_; }  ///< m/s
  // The whole state, for a render that resumes mid-clip.
  struct State {
    bool started = false;
    long step = 0;
    double t = 0;                            ///< s
    double x[3] = {}, v[3] = {}, p[3] = {};  ///< m, m/s, m
  };
  State state() const;
  void set_state(const State& s);

 private:
  double w_;  // 1/s
  bool started_ = false;
  long step_ = 0;                                                // of the last call
  double t_ = 0;                                                 // s, of the last call
  Vec3 x_ = Vec3::Zero(), v_ = Vec3::Zero(), p_ = Vec3::Zero();  // m, m/s, m (the last target)
};

// `render.motion_blur`: each frame averages `samples` images of states in its shutter interval,
// from `shutter` of the way back to the previous frame's step up to its own
// (app/view/motion_blur.hpp). samples 1: no blur.
struct MotionBlurSpec {
  int samples = 1;       ///< images averaged per frame, 1..64
  double shutter = 0.5;  ///< share of the frame interval the shutter is open, (0, 1] (0.5: 180 degrees)
  bool on() const { return samples > 1; }
};

}  // namespace simreel
