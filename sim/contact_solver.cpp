#include "sim/contact_solver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/integrators.hpp"

namespace simreel {

Softness make_softness(double hertz, double zeta, double h) {
  if (hertz == 0) return Softness{0, 1, 0};
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double a1 = 2.0 * zeta + h * omega;
  const double a2 = h * omega * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return Softness{omega / a1, a2 * a3, a3};
}

namespace {

// A unit vector perpendicular to n, chosen from n alone (deterministic): n x e, with e the world
// axis least aligned with n.
Vec3 perpendicular(const Vec3& n) {
  const Vec3 a = n.cwiseAbs();
  const Vec3 e =
      (a.x() <= a.y() && a.x() <= a.z()) ? Vec3::UnitX() : (a.y() <= a.z() ? Vec3::UnitY() : Vec3::UnitZ());
  return n.cross(e).normalized();
}

// Inverse effective mass of an impulse along d at anchors rA, rB:
//   1/m_A + 1/m_B + (rA x d) . I_A^-1 (rA x d) + (rB x d) . I_B^-1 (rB x d).
inline double inverse_effective_mass(const SolverBody& A, const SolverBody& B, const Vec3& rA, const Vec3& rB,
                                     const Vec3& d) {
  const Vec3 ra = rA.cross(d), rb = rB.cross(d);
  return A.inv_mass + B.inv_mass + ra.dot(A.inv_I * ra) + rb.dot(B.inv_I * rb);
}

inline void apply(SolverBody& A, SolverBody& B, const Vec3& rA, const Vec3& rB, const Vec3& P) {
  A.v -= A.inv_mass * P;
  A.w -= A.inv_I * rA.cross(P);
  B.v += B.inv_mass * P;
  B.w += B.inv_I * rB.cross(P);
}

inline Vec3 relative_velocity(const SolverBody& A, const SolverBody& B, const Vec3& rA, const Vec3& rB) {
  return B.v + B.w.cross(rB) - A.v - A.w.cross(rA);
}

}  // namespace

void ContactSolver::prepare(const SolverInput& in, const std::vector<int>& bodies,
                            const std::vector<Contact>& contacts, std::vector<int>& solver_index) {
  in_ = in;
  bodies_ = bodies;
  const int nb = (int)bodies.size() + 1;
  sb_.assign(nb, SolverBody{});
  I_W_.assign(nb, Mat3::Zero());
  gyro_.assign(nb, 0);
  accel_.assign(nb, Vec3::Zero());
  ang_accel_.assign(nb, Vec3::Zero());
  for (int k = 1; k < nb; ++k) {
    const int i = bodies[k - 1];
    solver_index[i] = k;
    const BodyModel& m = in.model[i];
    const MotionState& s = in.state[i];
    const Mat3 R = s.q_WP.toRotationMatrix();
    SolverBody& b = sb_[k];
    b.v = s.v_W;
    b.w = R * s.w_P;
    b.inv_mass = m.inv_mass;
    b.inv_I = R * m.inv_I_P.asDiagonal() * R.transpose();
    if (m.inv_mass > 0) {
      I_W_[k] = R * m.I_P.asDiagonal() * R.transpose();
      gyro_[k] = !m.isotropic;
      accel_[k] = in.gravity;
      if (in.wrench) {
        accel_[k] += m.inv_mass * in.wrench[i].f_W;
        ang_accel_[k] = b.inv_I * in.wrench[i].tau_W;
      }
    }
  }
  const ContactSettings& cs = in.settings;
  const double h = in.dt / cs.substeps;
  // Stiffer than the substep can resolve is pointless and rings: at most a quarter of its rate.
  const double hertz = std::min(cs.contact_hertz, 0.25 / h);
  soft_ = make_softness(hertz, cs.damping_ratio, h);
  static_soft_ = make_softness(2.0 * hertz, cs.damping_ratio, h);

  cons_.clear();
  for (int ci = 0; ci < (int)contacts.size(); ++ci) {
    const Contact& c = contacts[ci];
    if (c.count == 0) continue;
    ContactConstraint k;
    k.a = solver_index[c.body_a];
    k.b = solver_index[c.body_b];
    if (k.a == 0 && k.b == 0) continue;  // nothing in this pair moves under impulses
    k.contact = ci;
    k.n = c.normal_W;
    k.t[0] = perpendicular(k.n);
    k.t[1] = k.n.cross(k.t[0]);
    k.friction = c.friction;
    k.restitution = c.restitution;
    k.rolling = cs.rolling_resistance;
    k.count = c.count;
    const SolverBody& A = sb_[k.a];
    const SolverBody& B = sb_[k.b];
    k.soft = (A.inv_mass == 0 || B.inv_mass == 0) ? static_soft_ : soft_;
    const Vec3 xA = in.state[c.body_a].x_W, xB = in.state[c.body_b].x_W;
    double lever = 0;
    for (int j = 0; j < c.count; ++j) {
      const ContactPoint& cp = c.points[j];
      ConstraintPoint& p = k.p[j];
      p.rA = cp.p_W - xA;
      p.rB = cp.p_W - xB;
      p.adjusted_separation = cp.separation - k.n.dot(p.rB - p.rA);
      const double kn = inverse_effective_mass(A, B, p.rA, p.rB, k.n);
      p.normal_mass = kn > 0 ? 1.0 / kn : 0.0;
      for (int t = 0; t < 2; ++t) {
        const double kt = inverse_effective_mass(A, B, p.rA, p.rB, k.t[t]);
        p.tangent_mass[t] = kt > 0 ? 1.0 / kt : 0.0;
        p.tangent_impulse[t] = k.t[t].dot(cp.tangent_impulse_W);
      }
      p.normal_impulse = cp.normal_impulse;
      p.max_normal_impulse = 0;
      p.relative_velocity = k.n.dot(relative_velocity(A, B, p.rA, p.rB));
      lever = std::max(lever, std::max(p.rA.norm() * (A.inv_mass > 0), p.rB.norm() * (B.inv_mass > 0)));
    }
    if (k.rolling > 0) {
      const Mat3 Kr = A.inv_I + B.inv_I;
      k.rolling_mass = std::fabs(Kr.determinant()) > 0 ? Mat3(Kr.inverse()) : Mat3::Zero();
      k.rolling_impulse_limit = lever;
    }
    cons_.push_back(k);
  }
}

void ContactSolver::integrate_velocities(double h) {
  for (int k = 1; k < (int)sb_.size(); ++k) {
    SolverBody& b = sb_[k];
    if (b.inv_mass == 0) continue;  // kinematic: keeps its velocity
    b.v += h * accel_[k];
    b.w += h * ang_accel_[k];
    if (gyro_[k]) {
      // Implicit gyroscopic term, one Newton step on f(w') = I (w' - w) + h w' x I w' from w' = w
      // (Catto, "Numerical methods", GDC 2015): J = I + h (skew(w) I - skew(I w)), w' = w - J^-1 f(w).
      const Mat3& I = I_W_[k];
      const Vec3 Iw = I * b.w;
      const Vec3 f = h * b.w.cross(Iw);
      const Mat3 J = I + h * (skew(b.w) * I - skew(Iw));
      b.w -= J.inverse() * f;
    }
  }
}

void ContactSolver::warm_start() {
  for (ContactConstraint& k : cons_) {
    SolverBody& A = sb_[k.a];
    SolverBody& B = sb_[k.b];
    for (int j = 0; j < k.count; ++j) {
      const ConstraintPoint& p = k.p[j];
      const Vec3 P = p.normal_impulse * k.n + p.tangent_impulse[0] * k.t[0] + p.tangent_impulse[1] * k.t[1];
      apply(A, B, p.rA, p.rB, P);
    }
    if (k.rolling > 0) {
      A.w -= A.inv_I * k.rolling_impulse;
      B.w += B.inv_I * k.rolling_impulse;
    }
    sb_[0] = SolverBody{};  // the static body never moves, whatever was applied to it
  }
}

void ContactSolver::solve(double h, bool use_bias) {
  const double inv_h = 1.0 / h;
  const double max_push = in_.settings.max_push_out;
  const double slop = in_.settings.linear_slop;
  for (ContactConstraint& k : cons_) {
    SolverBody& A = sb_[k.a];
    SolverBody& B = sb_[k.b];
    const Vec3 dp = B.dp - A.dp;
    double total_normal = 0;
    // Non-penetration.
    for (int j = 0; j < k.count; ++j) {
      ConstraintPoint& p = k.p[j];
      // Separation now: the anchors moved with their bodies since the manifold was computed.
      const Vec3 d = dp + (B.dq * p.rB - A.dq * p.rA);
      const double s = k.n.dot(d) + p.adjusted_separation;
      double bias = 0, mass_scale = 1, impulse_scale = 0;
      if (s > 0) {
        bias = s * inv_h;  // speculative: allow closing the gap within this substep, no more
      } else if (use_bias) {
        bias = std::max(k.soft.bias_rate * std::min(0.0, s + slop), -max_push);
        mass_scale = k.soft.mass_scale;
        impulse_scale = k.soft.impulse_scale;
      }
      const double vn = k.n.dot(relative_velocity(A, B, p.rA, p.rB));
      // The fastest approach seen before an impulse acts is the impact speed that restitution
      // reverses: it includes the gravity gained within the step before touching, which exactly
      // offsets (to first order in h) the travel lost by stopping at the surface mid-substep.
      if (use_bias) p.relative_velocity = std::min(p.relative_velocity, vn);
      double lambda = -p.normal_mass * mass_scale * (vn + bias) - impulse_scale * p.normal_impulse;
      const double total = std::max(p.normal_impulse + lambda, 0.0);
      lambda = total - p.normal_impulse;
      p.normal_impulse = total;
      p.max_normal_impulse = std::max(p.max_normal_impulse, lambda);
      total_normal += total;
      apply(A, B, p.rA, p.rB, lambda * k.n);
    }
    // Friction: both tangent directions, the accumulated impulse clamped to the disk of radius
    // mu lambda_n (an isotropic Coulomb cone, per point).
    for (int j = 0; j < k.count; ++j) {
      ConstraintPoint& p = k.p[j];
      const Vec3 vr = relative_velocity(A, B, p.rA, p.rB);
      double t0 = p.tangent_impulse[0] - p.tangent_mass[0] * k.t[0].dot(vr);
      double t1 = p.tangent_impulse[1] - p.tangent_mass[1] * k.t[1].dot(vr);
      const double limit = k.friction * p.normal_impulse;
      const double mag2 = t0 * t0 + t1 * t1;
      if (mag2 > limit * limit) {
        const double s = limit / std::sqrt(mag2);
        t0 *= s;
        t1 *= s;
      }
      const Vec3 P = (t0 - p.tangent_impulse[0]) * k.t[0] + (t1 - p.tangent_impulse[1]) * k.t[1];
      p.tangent_impulse[0] = t0;
      p.tangent_impulse[1] = t1;
      apply(A, B, p.rA, p.rB, P);
    }
    // Rolling resistance: a torque impulse against relative spin, at most rolling * lever * N.
    if (k.rolling > 0) {
      const Vec3 dw = B.w - A.w;
      Vec3 total = k.rolling_impulse - k.rolling_mass * dw;
      const double limit = k.rolling * k.rolling_impulse_limit * total_normal;
      const double n2 = total.squaredNorm();
      if (n2 > limit * limit) total *= limit / std::sqrt(n2);
      const Vec3 d = total - k.rolling_impulse;
      k.rolling_impulse = total;
      A.w -= A.inv_I * d;
      B.w += B.inv_I * d;
    }
    sb_[0] = SolverBody{};
  }
}

void ContactSolver::integrate_positions(double h) {
  for (int k = 1; k < (int)sb_.size(); ++k) {
    SolverBody& b = sb_[k];
    b.dp += h * b.v;
    // World angular velocity: the rotation exp(h w / 2) multiplies from the left.
    b.dq = rotation_increment(b.w, h) * b.dq;
  }
}

// Restitution at the end of the substep in which the impact happens (Box3D applies it once after
// all substeps; then a body that hit early in the step rests on the surface for the remaining
// substeps and every bounce loses up to a step's travel: 0.5% of the height per bounce at 240 Hz,
// measured). The point's normal velocity becomes -e times its impact speed; its accumulated
// impulse is then cleared so that later substeps treat the separating point as a fresh contact
// instead of pulling the bounce back through the accumulated-impulse clamp.
void ContactSolver::restitution(double threshold) {
  for (ContactConstraint& k : cons_) {
    if (k.restitution == 0) continue;
    SolverBody& A = sb_[k.a];
    SolverBody& B = sb_[k.b];
    for (int j = 0; j < k.count; ++j) {
      ConstraintPoint& p = k.p[j];
      if (p.bounced || p.relative_velocity > -threshold || p.normal_impulse == 0) continue;
      const double vn = k.n.dot(relative_velocity(A, B, p.rA, p.rB));
      const double lambda = std::max(-p.normal_mass * (vn + k.restitution * p.relative_velocity), 0.0);
      apply(A, B, p.rA, p.rB, lambda * k.n);
      p.max_normal_impulse = std::max(p.max_normal_impulse, p.normal_impulse + lambda);
      p.normal_impulse = 0;
      p.bounced = true;
    }
    sb_[0] = SolverBody{};
  }
}

void ContactSolver::store_impulses(std::vector<Contact>& contacts) const {
  for (const ContactConstraint& k : cons_) {
    Contact& c = contacts[k.contact];
    for (int j = 0; j < k.count; ++j) {
      const ConstraintPoint& p = k.p[j];
      c.points[j].normal_impulse = p.normal_impulse;
      c.points[j].tangent_impulse_W = p.tangent_impulse[0] * k.t[0] + p.tangent_impulse[1] * k.t[1];
      c.points[j].max_normal_impulse = p.max_normal_impulse;
    }
  }
}

void ContactSolver::finish(const BodyModel* model, MotionState* state) const {
  for (int k = 1; k < (int)sb_.size(); ++k) {
    const int i = bodies_[k - 1];
    if (model[i].inv_mass == 0) continue;
    const SolverBody& b = sb_[k];
    MotionState& s = state[i];
    s.x_W += b.dp;
    s.q_WP = (b.dq * s.q_WP).normalized();
    s.v_W = b.v;
    s.w_P = s.q_WP.conjugate() * b.w;
  }
}

}  // namespace simreel
