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
inline int sign(double x) {
  return (x > 0) - (x < 0);
}
}  // namespace

double Mechanism::Dof::target_rate(double qk) const {
  if (motor == 1) return speed;
  if (motor == 2) return std::clamp((position - qk) / time_constant, -speed, speed);
  return 0;
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
    o[3] = d.motor != 0 && !d.hold ? d.push * (d.target_rate(qk) - vk) : 1.0;
    o[4] = d.friction > 0 && !d.stick ? d.slide * vk : 1.0;
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
  solve_rows();
  vv += dv_;
  for (size_t d = 0; d < dofs.size(); ++d)
    if (!std::isnan(target[d])) v[dofs[d].iv] = target[d];
  // Rates an impulse moved (the rebounding coordinates' too): a coordinate that friction or the
  // motor held slips; a saturated motor or sliding friction takes the direction of the new rate.
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    const double vk = v[d.iv];
    if (d.motor != 0) {
      const double vt = d.target_rate(q[d.iq]);
      d.hold = vk == vt;
      d.push = d.hold ? 0 : sign(vt - vk);
    }
    if (d.friction > 0 && d.at_stop == 0) {
      d.stick = vk == 0;
      d.slide = sign(vk);
    }
  }
}

void Mechanism::apply_events(double* y, const double* g0, const double* g1, const Vec3& g, const Wrench* wr) {
  double* q = y;
  double* v = y + nq;
  bool impact = false;
  std::fill(vtarget_.begin(), vtarget_.end(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < dofs.size(); ++i) {
    Dof& d = dofs[i];
    const double* a = g0 + 5 * i;
    const double* b = g1 + 5 * i;
    auto hit = [&](int k) { return a[k] >= 0 && b[k] < 0; };
    if (hit(0) || hit(1)) {
      stop_impact(d, hit(0), q, v, vtarget_[i]);
      impact = true;
    }
    if (hit(2)) release(d, d.lambda < d.lower_bound() ? 1 : -1);
    if (hit(3)) {
      d.hold = true;
      d.push = 0;
      v[d.iv] = d.target_rate(q[d.iq]);
    }
    if (hit(4)) {
      d.stick = true;
      d.slide = 0;
      v[d.iv] = 0;
    }
  }
  if (impact) {
    for (size_t i = 0; i < dofs.size(); ++i)
      if (dofs[i].at_stop != 0 && std::isnan(vtarget_[i])) vtarget_[i] = 0;  // stays on its stop
    impulse(q, v, vtarget_);
  }
  settle_modes(y, g, wr);
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
      const double vt = d.target_rate(qk);
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
  if (impact) {
    for (size_t i = 0; i < dofs.size(); ++i)
      if (dofs[i].at_stop != 0 && std::isnan(vtarget_[i])) vtarget_[i] = 0;
    impulse(q, v, vtarget_);
  }
  settle_modes(y, g, wr);
}

void Mechanism::settle_modes(double* y, const Vec3& g, const Wrench* wr) {
  // Release the most violated held coordinate, then look again: a release changes the others'
  // holding forces. Each pass releases one, so this ends within the number of coordinates.
  for (size_t it = 0; it <= dofs.size(); ++it) {
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
      v[d.iv] = d.target_rate(q[d.iq]);
    }
  }
}

}  // namespace simreel
