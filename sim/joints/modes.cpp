// Limits, motors and Coulomb friction on one-coordinate joints (articulation.hpp, Mechanism::Dof):
// a hybrid system of smooth modes and events.
//
// Within a mode the right-hand side is smooth: a saturated motor or sliding friction is a constant
// generalised force, and a held coordinate (resting on a stop, held at the motor's rate, stuck) is
// a constraint row q''_k = a* whose multiplier is the holding force. Smoothness is what lets the
// 5th-order integrator keep its order: a sign(q') inside the right-hand side would put a kink in
// every step that straddles a zero and cost the error controller hundreds of rejected steps. The
// modes change only at events, each the zero of an event function (positive while the mode
// holds), which advance() locates by re-taking the step to the crossing:
//   a free coordinate reaches a stop        q - lower, upper - q
//   a held coordinate's force leaves its    lambda - lower bound, upper bound - lambda
//     bounds (stop: pushes only; motor: +-max_force; friction: +-friction; summed when held
//     together)
//   a saturated motor reaches its target    push (target(q) - q')
//   sliding friction's rate reaches zero    slide q'
// Reaching a stop is an impact (Newton's restitution on the coordinate): impulses through the mass
// matrix set q'_k = -e q'_k on that coordinate while the loops and the coordinates already on
// stops keep their rates; the other rates change as the mechanism's inertia dictates (Featherstone,
// ch. 11: the impulsive equations M dq' = G^T Lambda). Finite forces (motors, friction) take no
// part in an impact: a coordinate they held slips when the impulse moves it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/joints/articulation.hpp"

namespace simreel {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// A rebound slower than this (rad/s, m/s) rests on the stop: without it a bouncing coordinate with
// restitution below 1 would take infinitely many impacts in a finite time (Zeno). 1e-6 rad/s is
// 1e-8 rad of travel in a 1/100 s bounce at g-level accelerations: far under any figure shown.
constexpr double kRestRate = 1e-6;
// A rope whose ends start within this of its bound (m) starts there: a max length written to a
// few digits of the start distance.
constexpr double kStartSlack = 1e-9;
// A slack rope is caught this far (relative to 1 + its bound, m) past its bound: far under the
// event location's own resolution, far over round-off.
constexpr double kRopeSlack = 1e-12;
// A rebounding rope is put this far (relative to 1 + its bound) inside its event function's
// offset: a few times project_positions' own resolution (1e-14).
constexpr double kRebound = 3e-14;
// The slack past a bound (rad or m) at which a rope's event function reads zero.
inline double rope_slack(double bound) {
  return kRopeSlack * (1 + std::abs(bound));
}
inline int sign(double x) {
  return (x > 0) - (x < 0);
}
}  // namespace

namespace {
// A ball joint's position motor: the rotation vector e still to go, in the child's axes (E = Q^-1
// Q_t, the target seen from the current pose), and the target angular velocity e / time_constant
// with its length capped at `speed`.
Vec3 ball_error(const Mechanism::Dof& d, const double* q) {
  const Quat Q = Quat(q[d.iq], q[d.iq + 1], q[d.iq + 2], q[d.iq + 3]).normalized();
  return rotation_vector(Q.conjugate() * d.target);  // the shorter way round
}
Vec3 ball_target(const Mechanism::Dof& d, const Vec3& e) {
  const double n = e.norm();
  return n > d.speed * d.time_constant ? Vec3(d.speed / n * e) : Vec3(e / d.time_constant);
}
}  // namespace

double Mechanism::Dof::target_rate(const double* q) const {
  if (motor == 1) return speed;
  if (motor != 2) return 0;
  if (ball < 0) return std::clamp((position - q[iq]) / time_constant, -speed, speed);
  return ball_target(*this, ball_error(*this, q))[ball];
}

double Mechanism::Dof::target_acceleration(const double* q, const double* v) const {
  if (motor != 2) return 0;
  if (ball < 0)  // (position - q) / time_constant moves at -q' / time_constant until it is capped
    return std::abs(position - q[iq]) < speed * time_constant ? -v[iv] / time_constant : 0.0;
  // E = R^T R_t turns as E' = -[w] E, so e' = -J_l(e)^-1 w with J_l SO(3)'s left Jacobian,
  // J_l^-1(e) = 1 - [e]/2 + (1/t^2 - (1 + cos t) / (2 t sin t)) [e]^2, t = |e| (Barfoot, "State
  // Estimation for Robotics", 2017, eq. 7.77). Held at w = e / time_constant (parallel to e), this
  // is -w and e decays as exp(-t / time_constant) along a fixed axis.
  const Vec3 e = ball_error(*this, q);
  const Vec3 w(v[iv - ball], v[iv - ball + 1], v[iv - ball + 2]);
  const double t = e.norm();
  // The bracket's series below 1e-4 rad: 1/12 + t^2/720 (the closed form cancels to round-off).
  const double c =
      t < 1e-4 ? 1.0 / 12 + t * t / 720 : 1 / (t * t) - (1 + std::cos(t)) / (2 * t * std::sin(t));
  const Vec3 ew = e.cross(w);
  const Vec3 de = -(w - 0.5 * ew + c * e.cross(ew));
  if (t <= speed * time_constant) return de[ball] / time_constant;
  const Vec3 u = e / t;  // capped: speed u, u turning as (1 - u u^T) e' / |e|
  return (speed / t * (de - u * u.dot(de)))[ball];
}

double Mechanism::Dof::lower_bound() const {
  double b = at_stop > 0 ? -kInf : 0.0;
  if (hold) b -= max_force;
  if (stick) b -= friction;
  return b;
}

double Mechanism::Dof::upper_bound() const {
  double b = at_stop < 0 ? kInf : 0.0;
  if (hold) b += max_force;
  if (stick) b += friction;
  return b;
}

void Mechanism::event_values(const double* y, double* out) const {
  const double* q = y;
  const double* v = y + nq;
  for (size_t i = 0; i < dofs.size(); ++i) {
    const Dof& d = dofs[i];
    double* o = out + 5 * i;
    const double qk = q[d.iq], vk = v[d.iv];
    o[0] = d.has_lo && d.at_stop == 0 ? qk - d.lo : 1.0;
    o[1] = d.has_hi && d.at_stop == 0 ? d.hi - qk : 1.0;
    o[2] = d.active() ? std::min(d.lambda - d.lower_bound(), d.upper_bound() - d.lambda) : 1.0;
    o[3] = d.motor != 0 && !d.hold ? d.push * (d.target_rate(q) - vk) : 1.0;
    o[4] = d.friction > 0 && !d.stick ? d.slide * vk : 1.0;
  }
  // A slack rope reaching a bound; a taut rope's force changing sign (it would push: it goes
  // slack). The kinematics are y's (its derivative was just evaluated).
  double* o = out + 5 * dofs.size();
  for (const Tether& t : tethers) {
    const bool rope = !t.rod;
    const double s = rope && t.taut == 0 ? tether_position(t, q) : 0.0;
    // Offset by kRopeSlack: a rope let go at its bound is there only to round-off, and a function
    // starting a hair under zero would never be seen to cross it.
    o[0] = rope && t.taut == 0 && t.has_hi ? t.hi + rope_slack(t.hi) - s : 1.0;
    o[1] = rope && t.taut == 0 && t.has_lo ? s - t.lo + rope_slack(t.lo) : 1.0;
    o[2] = rope && t.taut != 0 ? (t.taut > 0 ? -t.lambda : t.lambda) : 1.0;
    o += 3;
  }
}

namespace {
// A held coordinate whose holding force would leave its bounds lets go; dir is the way it now
// accelerates (+1: its force wanted to be under the lower bound).
void release(Mechanism::Dof& d, int dir) {
  if ((d.at_stop < 0 && dir > 0) || (d.at_stop > 0 && dir < 0)) d.at_stop = 0;
  if (d.hold) {
    d.hold = false;
    d.push = -dir;  // the rate runs away from the target: the motor pushes back
  }
  if (d.stick) {
    d.stick = false;
    d.slide = dir;
  }
}

// Reaching a stop: the coordinate onto it exactly, and its rate after the impact.
void stop_impact(Mechanism::Dof& d, bool lower, double* q, const double* v, double& target) {
  q[d.iq] = lower ? d.lo : d.hi;
  double out = -d.restitution * v[d.iv];
  if (std::abs(out) < kRestRate) {
    out = 0;
    d.at_stop = lower ? -1 : 1;
    if (d.friction > 0) {
      d.stick = true;
      d.slide = 0;
    }
  }
  target = out;
}
}  // namespace

void Mechanism::impulse(const double* q, double* v, const std::vector<double>& target) {
  kinematics(q);
  loop_jacobian(true);
  Eigen::Map<Eigen::VectorXd> vv(v, nv);
  rhs_.noalias() = -(G_ * vv);
  for (size_t d = 0; d < dofs.size(); ++d)
    if (!std::isnan(target[d])) rhs_(loop_rows + (int)d) += target[d];
  for (size_t t = 0; t < tethers.size(); ++t)
    if (!std::isnan(target[dofs.size() + t])) rhs_(tether_row((int)t)) += target[dofs.size() + t];
  solve_rows();
  vv += dv_;
  for (size_t d = 0; d < dofs.size(); ++d)
    if (!std::isnan(target[d])) v[dofs[d].iv] = target[d];
  // Rates an impulse moved (the rebounding coordinates' too): a coordinate that friction or the
  // motor held slips; a saturated motor or sliding friction takes the direction of the new rate.
  refresh_rate_modes(q, v);
}

void Mechanism::refresh_rate_modes(const double* q, const double* v) {
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    const double vk = v[d.iv];
    if (d.motor != 0) {
      const double vt = d.target_rate(q);
      d.hold = vk == vt;
      d.push = d.hold ? 0 : sign(vt - vk);
    }
    if (d.friction > 0 && d.at_stop == 0) {
      d.stick = vk == 0;
      d.slide = sign(vk);
    }
  }
}

double Mechanism::rope_impact(int ti, int bound, const double* q, const double* v) {
  Tether& t = tethers[ti];
  link_velocities(q, v, V_);
  const double rate = tether_rate(t, V_, t.wheel_iv >= 0 ? v[t.wheel_iv] : 0.0);
  double out = -t.restitution * rate;
  if (std::abs(out) < kRestRate) {
    out = 0;
    t.taut = bound;
  }
  return out;
}

void Mechanism::apply_events(double* y, const double* g0, const double* g1, const Vec3& g, const Wrench* wr) {
  double* q = y;
  double* v = y + nq;
  bool impact = false;
  std::fill(vtarget_.begin(), vtarget_.end(), std::numeric_limits<double>::quiet_NaN());
  const size_t D = dofs.size();
  bool caught = false;
  std::vector<int>& rebound = rebound_;
  rebound.assign(tethers.size(), 0);
  for (size_t i = 0; i < tethers.size(); ++i) {
    const double* a = g0 + 5 * D + 3 * i;
    const double* b = g1 + 5 * D + 3 * i;
    auto hit = [&](int k) { return a[k] >= 0 && b[k] < 0; };
    if (hit(0) || hit(1)) {
      vtarget_[D + i] = rope_impact((int)i, hit(0) ? 1 : -1, q, v);
      impact = true;
      caught = caught || tethers[i].taut != 0;
      if (tethers[i].taut == 0) rebound[i] = hit(0) ? 1 : -1;
    }
    if (hit(2)) tethers[i].taut = 0;
  }
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    const double* a = g0 + 5 * i;
    const double* b = g1 + 5 * i;
    auto hit = [&](int k) { return a[k] >= 0 && b[k] < 0; };
    d.rebounded = 0;
    if (hit(0) || hit(1)) {
      stop_impact(d, hit(0), q, v, vtarget_[i]);
      impact = true;
      if (d.at_stop == 0) d.rebounded = hit(0) ? -1 : 1;
    }
    if (hit(2)) release(d, d.lambda < d.lower_bound() ? 1 : -1);
    if (hit(3)) {
      d.hold = true;
      d.push = 0;
      v[d.iv] = d.target_rate(q);
    }
    if (hit(4)) {
      d.stick = true;
      d.slide = 0;
      v[d.iv] = 0;
    }
  }
  if (impact) {
    keep_held_rows();
    impulse(q, v, vtarget_);
  }
  // A rope caught past its bound (by the event's resolution, or by a contact substep's travel)
  // is put on it before anything may let it go again: a rope let go there must start slack. One
  // that rebounds is put just inside its event function's offset, so that the function starts
  // its next step above zero and the rope's return is seen: left where the event was located (a
  // hair past, the function at -6e-17), a return within one step goes unseen. Just inside, by
  // kRebound: a rope put a distance d from where it was, under an acceleration a toward the
  // bound, returns at sqrt(2 a d) however slowly it left, so the bounces would never fall under
  // kRestRate (d = kRopeSlack would give 7.8e-6 m/s at a = 15 m/s^2; d = kRebound gives 9e-7).
  bool rebounds = false;
  for (size_t i = 0; i < tethers.size(); ++i) {
    if (!rebound[i]) continue;
    Tether& t = tethers[i];
    const double bound = rebound[i] > 0 ? t.hi : t.lo;
    t.taut = rebound[i];
    t.aim = bound + rebound[i] * (1 - kRebound / kRopeSlack) * rope_slack(bound);
    rebounds = true;
  }
  if (caught || rebounds) project_positions(q);
  for (size_t i = 0; i < tethers.size(); ++i)
    if (rebound[i]) tethers[i].taut = 0, tethers[i].aim = NAN;
  settle_modes(y, g, wr);
}

bool Mechanism::catch_stretched(double* y, const Vec3& g, const Wrench* wr) {
  double* q = y;
  double* v = y + nq;
  bool any = false;
  std::fill(vtarget_.begin(), vtarget_.end(), std::numeric_limits<double>::quiet_NaN());
  link_velocities(q, v, V_);  // the kinematics at q too
  for (size_t i = 0; i < tethers.size(); ++i) {
    Tether& t = tethers[i];
    if (t.rod || t.taut != 0) continue;
    // Past the event functions' own offset (where an event leaves a rope it caught), and moving
    // further out: one coming back in is seen by its event function once inside again.
    const double s = tether_position(t, q);
    const int bound = t.has_hi && s > t.hi + 2 * rope_slack(t.hi)   ? 1
                      : t.has_lo && s < t.lo - 2 * rope_slack(t.lo) ? -1
                                                                    : 0;
    if (bound == 0) continue;
    const double rate = tether_rate(t, V_, t.wheel_iv >= 0 ? v[t.wheel_iv] : 0.0);
    if (bound * rate <= 0) continue;
    any = true;
    vtarget_[dofs.size() + i] = rope_impact((int)i, bound, q, v);
  }
  if (!any) return false;
  keep_held_rows();
  impulse(q, v, vtarget_);
  // Every caught rope back on its bound; one that rebounds leaves it slack.
  std::vector<int>& rebound = rebound_;
  rebound.assign(tethers.size(), 0);
  for (size_t i = 0; i < tethers.size(); ++i) {
    const double vt = vtarget_[dofs.size() + i];
    if (!std::isnan(vt) && tethers[i].taut == 0) {
      rebound[i] = 1;
      tethers[i].taut = vt < 0 ? 1 : -1;
    }
  }
  project_positions(q);
  for (size_t i = 0; i < tethers.size(); ++i)
    if (rebound[i]) tethers[i].taut = 0;
  settle_modes(y, g, wr);
  return true;
}

bool Mechanism::catch_past_stops(double* y, const Vec3& g, const Wrench* wr) {
  double* q = y;
  double* v = y + nq;
  bool any = false;
  std::fill(vtarget_.begin(), vtarget_.end(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    if (d.at_stop != 0) continue;
    const double qk = q[d.iq], vk = v[d.iv];
    const bool lower = d.has_lo && qk < d.lo && vk < 0, upper = d.has_hi && qk > d.hi && vk > 0;
    if (!lower && !upper) continue;
    stop_impact(d, lower, q, v, vtarget_[i]);
    any = true;
  }
  if (!any) return false;
  keep_held_rows();
  impulse(q, v, vtarget_);
  settle_modes(y, g, wr);
  return true;
}

void Mechanism::back_on_stops(double* q) const {
  for (const Dof& d : dofs) {
    double& x = q[d.iq];
    if (d.rebounded > 0 && x > d.hi && x - d.hi < rope_slack(d.hi)) x = d.hi;
    if (d.rebounded < 0 && x < d.lo && d.lo - x < rope_slack(d.lo)) x = d.lo;
  }
}

void Mechanism::keep_held_rows() {
  // Coordinates on their stops stay there, rods and taut ropes keep their lengths.
  for (size_t i = 0; i < dofs.size(); ++i)
    if (dofs[i].at_stop != 0 && std::isnan(vtarget_[i])) vtarget_[i] = 0;
  for (size_t i = 0; i < tethers.size(); ++i)
    if (tethers[i].active() && std::isnan(vtarget_[dofs.size() + i])) vtarget_[dofs.size() + i] = 0;
}

void Mechanism::start_modes(double* y, const Vec3& g, const Wrench* wr) {
  double* q = y;
  double* v = y + nq;
  bool impact = false;
  std::fill(vtarget_.begin(), vtarget_.end(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    const double qk = q[d.iq], vk = v[d.iv];
    d.at_stop = 0;
    d.hold = d.stick = false;
    d.push = d.slide = 0;
    if (d.motor != 0) {
      const double vt = d.target_rate(q);
      d.hold = vk == vt;
      d.push = d.hold ? 0 : sign(vt - vk);
    }
    if (d.friction > 0) {
      d.stick = vk == 0;
      d.slide = sign(vk);
    }
    // Starting on a stop (a limit at 0): resting on it, or hitting it at once.
    const bool lower = d.has_lo && qk <= d.lo && vk <= 0, upper = d.has_hi && qk >= d.hi && vk >= 0;
    if (lower || upper) {
      if (vk == 0) {
        d.at_stop = lower ? -1 : 1;
      } else {
        stop_impact(d, lower, q, v, vtarget_[i]);
        impact = true;
      }
    }
  }
  // A rope starting at a bound (its default max length is the start distance): taut, or
  // hitting it at once when its ends move apart (together).
  if (!tethers.empty()) link_velocities(q, v, V_);  // the kinematics at q too
  for (size_t i = 0; i < tethers.size(); ++i) {
    Tether& t = tethers[i];
    if (t.rod) continue;
    t.taut = 0;
    const double s = tether_position(t, q);
    const double rate = tether_rate(t, V_, t.wheel_iv >= 0 ? v[t.wheel_iv] : 0.0);
    const int bound = t.has_hi && s >= t.hi - kStartSlack && rate >= 0   ? 1
                      : t.has_lo && s <= t.lo + kStartSlack && rate <= 0 ? -1
                                                                         : 0;
    if (bound == 0) continue;
    if (rate == 0) {
      t.taut = bound;
    } else {
      vtarget_[dofs.size() + i] = rope_impact((int)i, bound, q, v);
      impact = true;
    }
  }
  if (impact) {
    keep_held_rows();
    impulse(q, v, vtarget_);
  }
  settle_modes(y, g, wr);
}

void Mechanism::settle_modes(double* y, const Vec3& g, const Wrench* wr) {
  // Release the most violated held coordinate, then look again: a release changes the others'
  // holding forces. Each pass releases one, so this ends within the number of coordinates.
  for (size_t it = 0; it <= dofs.size() + tethers.size(); ++it) {
    derivative(y, kd_.data(), g, wr, nullptr);
    int worst = -1, dir = 0;
    double by = 0;
    for (size_t i = 0; i < dofs.size(); ++i) {
      const Dof& d = dofs[i];
      if (!d.active()) continue;
      const double lo = d.lower_bound(), hi = d.upper_bound();
      const double slack = 1e-12 * (1 + std::abs(d.lambda));
      if (lo - d.lambda > slack && lo - d.lambda > by) {
        worst = (int)i;
        by = lo - d.lambda;
        dir = 1;
      }
      if (d.lambda - hi > slack && d.lambda - hi > by) {
        worst = (int)i;
        by = d.lambda - hi;
        dir = -1;
      }
    }
    // A taut rope pushing (or a rope at its min length pulling) goes slack.
    int worst_tether = -1;
    for (size_t i = 0; i < tethers.size(); ++i) {
      const Tether& t = tethers[i];
      if (t.rod || t.taut == 0) continue;
      const double out = t.taut > 0 ? t.lambda : -t.lambda;  // > 0: the wrong way
      if (out > 1e-12 * (1 + std::abs(t.lambda)) && out > by) {
        worst_tether = (int)i;
        by = out;
      }
    }
    if (worst_tether >= 0) {
      tethers[worst_tether].taut = 0;
      continue;
    }
    if (worst < 0) return;
    release(dofs[worst], dir);
  }
}

void Mechanism::project_dofs(double* y) {
  double* q = y;
  double* v = y + nq;
  for (const Dof& d : dofs) {
    if (d.at_stop != 0) {
      q[d.iq] = d.at_stop < 0 ? d.lo : d.hi;
      v[d.iv] = 0;
    } else if (d.stick) {
      v[d.iv] = 0;
    } else if (d.hold) {
      v[d.iv] = d.target_rate(q);
    }
  }
}

}  // namespace simreel
