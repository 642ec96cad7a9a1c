// Evaluating the applied forces (their records: include/simreel/forces.hpp) by a switch on the
// kind: no virtual call and no allocation per step. World::step evaluates them in its `forces`
// stage through apply_force / apply_torque / apply_impulse, and again at every stage of the
// free-flight RK4 (docs/forces.md), so that a force depending on the state or on time is
// integrated to fourth order.
#pragma once
#include <cmath>
#include <limits>
#include <vector>

#include <simreel/forces.hpp>

#include "sim/dynamics/state.hpp"

namespace simreel {

inline bool is_impulse(ForceKind k) {
  return k == ForceKind::impulse || k == ForceKind::angular_impulse;
}

// Checks indices and values against the bodies (throws InputError naming the entry): every body
// acted on is dynamic (a spring's second end may be any body), numbers finite, stiffness, damping
// and drag coefficients non-negative, from <= to.
void validate_forces(const std::vector<ForceDef>& forces, const std::vector<BodyModel>& models,
                     const std::vector<std::string>& names);

// The fraction of [t0, t1] inside the window [from, to): 1 or 0 away from the window's edges, the
// overlap in between (so a force switched on or off within a step delivers F x the overlap when
// it is held over the step).
inline double window_weight(const ForceDef& f, double t0, double t1) {
  if (f.from <= t0 && f.to >= t1) return 1.0;
  if (f.to <= t0 || f.from >= t1) return 0.0;
  return (std::min(f.to, t1) - std::max(f.from, t0)) / (t1 - t0);
}

// The body-to-world rotation of a state: q_WB = q_WP q_BP^-1.
inline Quat body_rotation(const MotionState& s, const BodyModel& m) {
  return s.q_WP * m.q_BP.conjugate();
}
// World position of a body point p_B (body frame, relative to the body origin):
// x_W + R_WB (p_B - c_B), since the origin is x_W - R_WB c_B.
inline Vec3 body_point_W(const MotionState& s, const BodyModel& m, const Vec3& p_B) {
  return s.x_W + body_rotation(s, m) * (p_B - m.c_B);
}
// Velocity of the material point at world position p_W: v + w x (p - x).
inline Vec3 point_velocity_W(const MotionState& s, const Vec3& p_W) {
  return s.v_W + (s.q_WP * s.w_P).cross(p_W - s.x_W);
}

// One continuous force (not an impulse) at the states `st`, scaled by `weight` (window_weight),
// handed to the sink as sink.force(i, f_W, at_W), sink.central(i, f_W) and sink.torque(i, tau_W).
// Only dynamic bodies (inv_mass > 0) receive anything.
template <class Sink>
inline void evaluate_force(const ForceDef& f, double weight, const MotionState* st, const BodyModel* mo,
                           Sink& sink) {
  if (weight == 0) return;
  const int i = f.body;
  const MotionState& s = st[i];
  const BodyModel& m = mo[i];
  switch (f.kind) {
    case ForceKind::force: {
      const Vec3 F = weight * (f.frame == ForceFrame::body ? Vec3(body_rotation(s, m) * f.vector) : f.vector);
      if (f.at_centroid)
        sink.central(i, F);
      else
        sink.force(i, F, body_point_W(s, m, f.at_B));
      break;
    }
    case ForceKind::torque:
      sink.torque(i,
                  weight * (f.frame == ForceFrame::body ? Vec3(body_rotation(s, m) * f.vector) : f.vector));
      break;
    case ForceKind::drag: {
      // F = -(c1 + c2 |v|) v: linear (Stokes) plus quadratic (Newton) drag on the centre of mass.
      const double speed = s.v_W.norm();
      sink.central(i, (-weight * (f.linear + f.quadratic * speed)) * s.v_W);
      break;
    }
    case ForceKind::spring: {
      // Hooke's law with a dashpot along the line (e.g. Witkin & Baraff, "Physically Based
      // Modeling", SIGGRAPH 2001 course, "Particle System Dynamics", damped spring):
      //   d = p_a - p_b, L = |d|, u = d / L,
      //   F_a = -(k (L - L0) + c u . (v_a - v_b)) u,  F_b = -F_a,
      // with p and v the world position and velocity of each end's material point. At L = 0 the
      // direction is undefined and no force acts.
      const Vec3 pa = f.at_centroid ? s.x_W : body_point_W(s, m, f.at_B);
      Vec3 pb = f.anchor_W, vb = Vec3::Zero();
      if (f.body_b >= 0) {
        const MotionState& sb = st[f.body_b];
        pb = f.at_b_centroid ? sb.x_W : body_point_W(sb, mo[f.body_b], f.at_b_B);
        vb = point_velocity_W(sb, pb);
      }
      const Vec3 d = pa - pb;
      const double L = d.norm();
      if (!(L > 0)) break;
      const Vec3 u = d / L;
      double mag = f.stiffness * (L - f.rest_length);
      if (f.damping != 0) mag += f.damping * u.dot(point_velocity_W(s, pa) - vb);
      const Vec3 Fa = (-weight * mag) * u;
      if (m.inv_mass > 0) {
        if (f.at_centroid)
          sink.central(i, Fa);
        else
          sink.force(i, Fa, pa);
      }
      if (f.body_b >= 0 && mo[f.body_b].inv_mass > 0) {
        if (f.at_b_centroid)
          sink.central(f.body_b, -Fa);
        else
          sink.force(f.body_b, -Fa, pb);
      }
      return;
    }
    case ForceKind::impulse:
    case ForceKind::angular_impulse:
      break;  // applied once by World, not a force
  }
}

// A sink that accumulates into wrenches by body index, with World::apply_force's arithmetic.
struct WrenchSink {
  Wrench* w;
  const MotionState* st;
  void force(int i, const Vec3& f_W, const Vec3& at_W) {
    w[i].f_W += f_W;
    w[i].tau_W += (at_W - st[i].x_W).cross(f_W);
  }
  void central(int i, const Vec3& f_W) { w[i].f_W += f_W; }
  void torque(int i, const Vec3& tau_W) { w[i].tau_W += tau_W; }
};

// A bound on how fast a force changes the motion of the bodies it acts on, 1/s, at the states
// `st` (the `auto` integrator substeps so that this times the step stays below
// kAutoMaxStepAngle): a spring's angular frequency sqrt(k / m_eff) with 1/m_eff = sum over its
// ends of 1/m + r^2/I_min (r the end's lever arm), plus its damping rate c / m_eff; drag's
// (linear + 2 quadratic |v|) / m, the derivative of its force in v per unit mass. Constant forces
// and torques: 0. Accumulated per body into rate2 (squared frequencies) and rate1 (rates).
void force_rates(const ForceDef& f, const MotionState* st, const BodyModel* mo, double* rate2, double* rate1);

}  // namespace simreel
