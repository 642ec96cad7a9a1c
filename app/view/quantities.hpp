// The values of HUD fields and plot quantities (app/scene/scene_overlays.hpp, HudField): a quantity
// of the world's present state, an expression over them, or a value measured over the physics steps
// (a joint's period, mean(q), period(q), last_zero(q), first_contact). Measured values are recorded
// by StepMeters through FrameLoop::Hooks::step, so they are functions of the steps before a frame,
// the same in a partial render or a chunk as in the full one; nothing here allocates per step or
// per frame once the meters are set up.
#pragma once
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include <simreel/contacts.hpp>
#include <simreel/world.hpp>
#include "app/scene/scene_overlays.hpp"

namespace simreel {

// What is measured over the steps.
//
// `{NAME.period}` (and period(q) of a joint's angle): the most recent full period of a joint
// coordinate. At each step the coordinate's rate is read (World::joint_speed); where it changes sign
// between two steps the coordinate has turned, and the turning time is interpolated linearly between
// the two steps (s_a > 0 >= s_b: t_a + h s_a / (s_a - s_b); a step at exactly 0 followed by motion
// counts, so a release from rest is a turning point at t = 0). The period is the time between the
// latest turning point and the one before it in the same direction (maximum to maximum, minimum to
// minimum): it updates every half swing, and is NaN (the HUD prints an em dash) until two turns in
// one direction have been seen. Resolution: linear interpolation puts each turn within
// |q'''| h^2 / (8 |q''|) of the true one (h the physics step); at a pendulum's turn
// q''' = -w0^2 cos(theta) q' vanishes, so the error is at most w0^2 h^3 / 8 per turn
// (w0^2 = m g d / I_pivot) and w0^2 h^3 / 4 on a period: 1.8e-7 s for w0^2 = 10 / s^2 at 1/240 s.
//
// period(q) of any other quantity: its rate is not known, so a turn is where q's step-to-step
// difference changes sign, placed at the vertex of the parabola through the three samples around it
// (error O(h^2 q''' / q'')); the first turn is the first extremum after the start.
// mean(q): the time average since t = 0 (trapezoids over the steps); mean(q, T) over the last T s
// (the average since the start until T s have passed). last_zero(q): the latest time q changed sign,
// interpolated linearly between two steps. first_contact(...): when the body (or the pair, or any
// two bodies) first touched, within a physics step: the start of the step whose end first reports
// the contact (the solver sees a meeting in the step after the one it happens in, or in it;
// bodies touching at t = 0 read 0).
class StepMeters {
 public:
  // E0, L0: what {E_drift} and {L_drift} inside a measured value's argument compare against.
  void set_reference(double E0, const Vec3& L0) { E0_ = E0, L0_ = L0; }
  // Measures every period and measured value that field f (an expression: its terms) reads; a
  // value already measured is shared. dt: the physics step (s), for mean(q, T)'s window.
  void track(const HudField& f, double dt);
  bool empty() const { return joints_.empty() && meters_.empty(); }
  // FrameLoop::Hooks::step: every physics step in order (a step seen twice is skipped).
  void record(const World& w);
  // s, the latest full period of joint j's coordinate k; NaN until measured (or not tracked).
  double period(int joint, int coord) const;
  // The measured value a meter field names (HudField::is_meter); NaN until known (or not tracked).
  double value(const HudField& meter) const;
  // The turning times seen so far (for tests): +1 the coordinate's maxima, -1 its minima.
  const std::vector<double>& turns(int joint, int coord, int direction) const;
  // What record() has gathered, for a render that resumes mid-clip (app/view/view_state.hpp).
  void save(std::ostream& os) const;
  void restore(std::istream& is);

 private:
  struct JointMeter {
    int joint = -1, coord = 0;
    long last_step = -1;
    double t = 0, s = 0;           // the previous step's time and rate
    std::vector<double> up, down;  // turning times at maxima (rate + to -) and at minima
    double period = std::numeric_limits<double>::quiet_NaN();
  };
  struct Meter {
    HudField spec;  // name, terms[0] (the argument), window, body, body2; source: its identity
    long last_step = -1;
    double t1 = 0, q1 = 0, t0 = 0, q0 = 0;  // the previous two steps' times and values
    int samples = 0;                        // steps seen (up to 2 counted)
    int trend = 0;                          // period_of: the sign of q's last non-zero change
    double integral = 0;                    // mean: the integral of q since t = 0
    std::vector<double> ring_t, ring_i;     // mean(q, T): times and integrals of the last steps
    size_t head = 0, count = 0;
    double last_up = std::numeric_limits<double>::quiet_NaN(), last_down = last_up;
    double value = std::numeric_limits<double>::quiet_NaN();
  };
  void record(Meter& m, const World& w);
  std::vector<JointMeter> joints_;
  std::vector<Meter> meters_;
  std::vector<ContactData> scratch_;  // first_contact's read-out, capacity kept
  double E0_ = 0;
  Vec3 L0_ = Vec3::Zero();
};

// The value of a scalar field (a quantity with a component, |...|, a scene scalar, a body's number,
// a joint's number, an expression or a measured value) at the world's present state: periods and
// measured values from `meters` (NaN without), {frame} the frame's number, {video_t} frame / fps
// (fps 0: the simulated time).
double quantity_value(const HudField& f, const World& w, long frame, double E0, const Vec3& L0,
                      double fps = 0, const StepMeters* meters = nullptr);

// A HUD line with its fields filled from the world; `out` keeps its storage. A value not known yet
// (NaN) prints as an em dash; a whole vector as (x, y, z), the format applied to each.
void format_hud_line(const HudLine& line, const World& w, long frame, double E0, const Vec3& L0,
                     std::string& out, double fps = 0, const StepMeters* meters = nullptr);

}  // namespace simreel
