#include "sim/joints/articulation.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <simreel/error.hpp>

#include "sim/base/dormand_prince.hpp"
#include "sim/base/enum_names.hpp"
#include "sim/base/sincos.hpp"
#include "sim/dynamics/forces.hpp"

namespace simreel {

namespace {
template <class T>
const T* opt_ptr(const std::optional<T>& o) {
  return o ? &*o : nullptr;
}
constexpr EnumNames<JointType, 8> kJointTypes{
    {"revolute", "prismatic", "spherical", "fixed", "universal", "wheel", "distance", "pulley"}};
static_assert(kJointTypes.complete());
constexpr double kPi = std::numbers::pi;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

inline Quat joint_rotation(const Link& l, const double* q) {
  switch (l.kind) {
    case LinkJoint::revolute:
      return Quat(Eigen::AngleAxisd(q[0], l.axis_F));
    case LinkJoint::spherical:
      return Quat(q[0], q[1], q[2], q[3]).normalized();
    case LinkJoint::free:
      return Quat(q[3], q[4], q[5], q[6]).normalized();
    case LinkJoint::prismatic:
    case LinkJoint::fixed:
      break;
  }
  return Quat::Identity();
}

// dq/dt of one link's coordinates from its velocities: unit quaternions turn as q' = q (0, w) / 2
// with w in the rotated frame; a free root's position moves with its centre-of-mass velocity,
// given in the link frame.
inline void coordinate_rates(const Link& l, const double* q, const double* v, double* dq) {
  switch (l.kind) {
    case LinkJoint::revolute:
    case LinkJoint::prismatic:
      dq[0] = v[0];
      return;
    case LinkJoint::fixed:
      return;
    case LinkJoint::spherical:
    case LinkJoint::free: {
      const double* qq = l.kind == LinkJoint::free ? q + 3 : q;
      double* dd = l.kind == LinkJoint::free ? dq + 3 : dq;
      const double w = qq[0], x = qq[1], y = qq[2], z = qq[3];
      const double a = v[0], b = v[1], c = v[2];
      dd[0] = 0.5 * (-x * a - y * b - z * c);
      dd[1] = 0.5 * (w * a + y * c - z * b);
      dd[2] = 0.5 * (w * b + z * a - x * c);
      dd[3] = 0.5 * (w * c + x * b - y * a);
      if (l.kind == LinkJoint::free) {
        const Vec3 vW = Quat(w, x, y, z).normalized() * Vec3(v[3], v[4], v[5]);
        dq[0] = vW.x();
        dq[1] = vW.y();
        dq[2] = vW.z();
      }
      return;
    }
  }
}

void normalize_quaternions(const Mechanism& m, double* q) {
  for (const Link& l : m.links) {
    if (l.kind != LinkJoint::spherical && l.kind != LinkJoint::free) continue;
    double* qq = q + l.iq + (l.kind == LinkJoint::free ? 3 : 0);
    const double n = std::sqrt(qq[0] * qq[0] + qq[1] * qq[1] + qq[2] * qq[2] + qq[3] * qq[3]);
    for (int k = 0; k < 4; ++k) qq[k] /= n;
  }
}

}  // namespace

const char* to_string(JointType t) {
  return kJointTypes(t);
}
std::optional<JointType> joint_type_from_name(std::string_view name) {
  return kJointTypes.parse(name);
}
const char* joint_type_names() {
  return "revolute, prismatic, spherical, fixed, universal, wheel, distance, pulley";
}

// ------------------------------------------------------------------ one mechanism
void Mechanism::allocate() {
  work_.resize(links.size());
  for (size_t i = 0; i < links.size(); ++i) {
    const int n = links[i].nv;
    work_[i].U.resize(6, n);
    work_[i].Dinv.resize(n, n);
    work_[i].u.resize(n);
  }
  const size_t ny = (size_t)(nq + nv);
  y0_.assign(ny, 0);
  y1_.assign(ny, 0);
  ys_.assign(ny, 0);
  for (auto& k : k_) k.assign(ny, 0);
  tau_.assign(nv, 0);
  if (events_on()) {
    for (auto* e : {&g0_, &g1_, &ga_, &gc_}) e->assign(5 * dofs.size() + 3 * tethers.size(), 0);
    vtarget_.assign(dofs.size() + tethers.size(), 0);
  }
  kd_.assign(ny, 0);
  y_end_.assign(ny, 0);
  carry_k1_ = false;
  for (auto* x : {&span.y0, &span_y1_, &span_k7_, &span_out_}) x->assign(ny, 0);
  verlet.a.assign(nv, 0);
  verlet.x.assign(ny, 0);
  verlet.y.assign(ny, 0);
  verlet.y_start.assign(ny, 0);
  world_q_.assign(nq, 0);
  world_at_q_ = false;
  for (auto& c : span_rc_) c.assign(ny, 0);
  span.valid = false;
  for (const Link& l : links)
    if (l.parent < 0) {
      origin_ = l.p_pF;
      break;
    }
  out_q_.resize(links.size());
  out_x_.resize(links.size());
  out_v_.resize(links.size());
  ke_a_.resize(links.size());
  ke_b_.resize(links.size());
}

void Mechanism::kinematics(const double* q, bool world) {
  world_at_q_ = false;
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    Work& w = work_[i];
    // This link's frame in its parent's: T_pF * X_J(q) * T_cF^-1, from the products Link keeps.
    Mat3 R = l.R0;
    Vec3 t = l.t0;
    switch (l.kind) {
      case LinkJoint::revolute: {
        double s, c;
        sin_cos(q[l.iq], s, c);
        const double k = 1 - c;
        // Written out: Eigen leaves the 3x3 sums out of line at -O2.
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) R(i, j) = l.R0(i, j) + s * l.Rs(i, j) + k * l.Rk(i, j);
        for (int i = 0; i < 3; ++i) t[i] = l.t0[i] - s * l.ts[i] - k * l.tk[i];
        break;
      }
      case LinkJoint::prismatic:
        t += l.a_p * q[l.iq];
        break;
      case LinkJoint::fixed:
        break;
      case LinkJoint::spherical: {
        const double* qq = q + l.iq;
        R.noalias() =
            l.R_pF * Quat(qq[0], qq[1], qq[2], qq[3]).normalized().toRotationMatrix() * l.R_cF.transpose();
        t = l.p_pF - R * l.p_cF;
        break;
      }
      case LinkJoint::free: {
        const double* qq = q + l.iq;
        R = Quat(qq[3], qq[4], qq[5], qq[6]).normalized().toRotationMatrix();
        t = Vec3(qq[0], qq[1], qq[2]);
        break;
      }
    }
    w.E = R.transpose();
    w.r = t;
    if (!world) continue;
    if (l.parent < 0) {
      w.R_W = R;
      w.x_W = t;
    } else {
      const Work& p = work_[l.parent];
      w.R_W.noalias() = p.R_W * R;
      w.x_W = p.x_W + p.R_W * t;
    }
  }
}

void Mechanism::derivative(const double* y, double* dy, const Vec3& g, const Wrench* wr,
                           const MotionState* st) {
  (void)st;
  const double* q = y;
  const double* v = y + nq;
  double* dq = dy;
  double* dv = dy + nq;
  kinematics(q, !lean_);
  const size_t n = links.size();
  // Saturated motors and sliding friction: constant generalised forces while their mode lasts.
  for (const Dof& d : dofs) {
    double f = 0;
    if (d.motor != 0 && !d.hold) f += d.push * d.max_force;
    if (d.friction > 0 && !d.stick) f -= d.slide * d.friction;
    tau_[d.iv] = f;
  }
  // Pass 1, root to leaves: velocities, velocity-product accelerations, rigid-body inertias and
  // bias forces (Featherstone, Table 7.1).
  for (size_t i = 0; i < n; ++i) {
    const Link& l = links[i];
    Work& w = work_[i];
    coordinate_rates(l, q + l.iq, v + l.iv, dq + l.iq);
    Vec6 vJ;
    if (l.nv == 1)
      vJ = l.s1 * v[l.iv];  // the common case, without the dynamic-size products
    else if (l.nv > 0)
      vJ = l.S * Eigen::Map<const VecX6>(v + l.iv, l.nv);
    else
      vJ.setZero();
    if (l.parent < 0)
      w.vel = vJ;
    else
      transform_motion_add(w.E, w.r, work_[l.parent].vel.data(), vJ.data(), w.vel.data());
    cross_motion(w.vel.data(), vJ.data(), w.c.data());
    // The link's own inertia is diagonal in its frame (principal axes at the centre of mass).
    w.IA = l.M;
    const double* vel = w.vel.data();
    const double h[6] = {l.I_P[0] * vel[0], l.I_P[1] * vel[1], l.I_P[2] * vel[2],
                         l.mass * vel[3],   l.mass * vel[4],   l.mass * vel[5]};
    cross_force(vel, h, w.pA.data());
    if (wr && l.body >= 0 && !lean_) {
      const Wrench& f = wr[l.body];
      if (!f.tau_W.isZero(0)) w.pA.head<3>() -= w.R_W.transpose() * f.tau_W;
      if (!f.f_W.isZero(0)) w.pA.tail<3>() -= w.R_W.transpose() * f.f_W;
    }
  }
  if (!tethers.empty()) tether_springs();
  if (loop_springs_on) loop_springs();
  if (!loads.empty()) apply_loads();
  // Pass 2, leaves to root: articulated inertias and bias forces, each link's turned in place
  // into what its parent receives (Ia = IA - U D^-1 U^T, pa = pA + Ia c + U D^-1 u).
  for (size_t i = n; i-- > 0;) {
    const Link& l = links[i];
    Work& w = work_[i];
    Mat6& Ia = w.IA;
    Vec6& pa = w.pA;
    if (l.nv == 1) {
      w.U1 = mat6_vec(w.IA, l.s1);
      const double Dinv =
          1 / (l.s1.dot(w.U1) + l.armature);  // a rotor's inertia adds on its coordinate alone
      double u = -l.s1.dot(w.pA);
      if (l.stiffness != 0 || l.damping != 0) u += -l.stiffness * (q[l.iq] - l.rest) - l.damping * v[l.iv];
      if (l.dof_index >= 0) u += tau_[l.iv];
      w.Dinv1 = Dinv;
      w.u1 = u;
      // Locals, so that the compiler sees that Ia's entries and U's cannot alias (re-read from the
      // link's record, the update costs a sixth of a chain's evaluation).
      double U[6], UD[6];
      for (int k = 0; k < 6; ++k) U[k] = w.U1[k], UD[k] = Dinv * U[k];
      double* I = Ia.data();
      for (int c = 0; c < 6; ++c)
        for (int r = 0; r < 6; ++r) I[6 * c + r] -= UD[r] * U[c];
      const double f = Dinv * u;
      double* P = pa.data();
      for (int k = 0; k < 6; ++k) P[k] += U[k] * f;
    } else if (l.nv > 0) {
      w.U.noalias() = w.IA * l.S;
      const MatXX6 D = l.S.transpose() * w.U;
      w.Dinv = D.inverse();
      w.u = -l.S.transpose() * w.pA;
      if (l.kind == LinkJoint::spherical && (l.stiffness != 0 || l.damping != 0)) {
        // A ball joint's spring: the torque -k phi - c w (phi's gradient of k |phi|^2 / 2 along w
        // is phi itself: phi is the fixed vector of the rotation's Jacobian).
        const Vec3 phi = ball_rotation_vector(l, q);
        for (int k = 0; k < 3; ++k) w.u[k] -= l.stiffness * phi[k] + l.damping * v[l.iv + k];
      }
      if (l.dof_index >= 0)  // a ball joint's saturated motor and sliding friction
        for (int k = 0; k < l.nv; ++k) w.u[k] += tau_[l.iv + k];
      Ia.noalias() -= w.U * w.Dinv * w.U.transpose();
      pa += w.U * (w.Dinv * w.u);
    }
    if (l.parent >= 0) {
      add_mat6_vec(Ia, w.c, pa.data());
      Work& p = work_[l.parent];
      add_transform_inertia_back(w.E, w.r, Ia, p.IA);
      add_transform_force_back(w.E, w.r, pa.data(), p.pA.data());
    }
  }
  // Pass 3, root to leaves: accelerations. The world accelerates at -g, which puts gravity on
  // every link at once (Featherstone 5.3).
  Vec6 a_world;
  a_world << 0, 0, 0, -g.x(), -g.y(), -g.z();
  for (size_t i = 0; i < n; ++i) {
    const Link& l = links[i];
    Work& w = work_[i];
    Vec6 ap;
    transform_motion_add(w.E, w.r, l.parent < 0 ? a_world.data() : work_[l.parent].acc.data(), w.c.data(),
                         ap.data());
    if (l.nv == 1) {
      const double qdd = w.Dinv1 * (w.u1 - w.U1.dot(ap));
      dv[l.iv] = qdd;
      for (int k = 0; k < 6; ++k) w.acc[k] = ap[k] + l.s1[k] * qdd;
    } else if (l.nv > 0) {
      w.acc = ap;
      Eigen::Map<VecX6> qdd(dv + l.iv, l.nv);
      qdd = w.Dinv * (w.u - w.U.transpose() * ap);
      w.acc += l.S * qdd;
    } else {
      w.acc = ap;
    }
  }
  if (has_rows()) {
    constrain_accelerations(q, v, dv);
    for (Dof& d : dofs) d.force = d.lambda + tau_[d.iv];
  }
}

namespace {
// Packed symmetric 6x6 (the upper triangle by rows, 21 entries): kSym[r][c] is entry (r, c)'s slot.
// Articulated inertias are symmetric, so derivative_world keeps 21 of their 36 entries.
constexpr std::array<std::array<int, 6>, 6> kSym = [] {
  std::array<std::array<int, 6>, 6> t{};
  int k = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) t[r][c] = t[c][r] = k++;
  return t;
}();
inline void sym_vec(const double* __restrict I, const double* __restrict x, double* __restrict y) {
#pragma GCC unroll 6
  for (int r = 0; r < 6; ++r) {
    double s = 0;
#pragma GCC unroll 6
    for (int c = 0; c < 6; ++c) s += I[kSym[r][c]] * x[c];
    y[r] = s;
  }
}
}  // namespace

void Mechanism::derivative_world(const double* y, double* dy, const Vec3& g, const Wrench* wr) {
  const double* q = y;
  const double* v = y + nq;
  double* dq = dy;
  double* dv = dy + nq;
  kinematics(q, true);
  const size_t n = links.size();
  // No stops, motors or friction here (verlet_ok: no Dofs), so no generalised forces of modes.
  // Pass 1, root to leaves. Motion vectors are [w; v_O] (v_O: the velocity of the body point at
  // origin_), force vectors [n_O; f], all in world axes; s, the joint's motion subspace, moves
  // with its link, so the velocity-product term is v x s q' (Featherstone eq. 7.38).
  for (size_t i = 0; i < n; ++i) {
    const Link& l = links[i];
    Work& w = work_[i];
    const Mat3& R = w.R_W;
    const double c[3] = {w.x_W[0] - origin_[0], w.x_W[1] - origin_[1], w.x_W[2] - origin_[2]};
    double* vel = w.vel.data();
    if (l.nv == 1) {
      dq[l.iq] = v[l.iv];
      // s at the centre of mass in link axes, [a; b], carried to world axes about origin_:
      // [R a; R b + c x R a].
      const double* s = l.s1.data();
      double ra[3], rb[3];
      for (int k = 0; k < 3; ++k) {
        ra[k] = R(k, 0) * s[0] + R(k, 1) * s[1] + R(k, 2) * s[2];
        rb[k] = R(k, 0) * s[3] + R(k, 1) * s[4] + R(k, 2) * s[5];
      }
      double* sO = w.sO.data();
      sO[0] = ra[0], sO[1] = ra[1], sO[2] = ra[2];
      sO[3] = rb[0] + (c[1] * ra[2] - c[2] * ra[1]);
      sO[4] = rb[1] + (c[2] * ra[0] - c[0] * ra[2]);
      sO[5] = rb[2] + (c[0] * ra[1] - c[1] * ra[0]);
      const double qd = v[l.iv];
      double vJ[6];
      for (int k = 0; k < 6; ++k) vJ[k] = sO[k] * qd;
      if (l.parent < 0)
        for (int k = 0; k < 6; ++k) vel[k] = vJ[k];
      else
        for (int k = 0; k < 6; ++k) vel[k] = work_[l.parent].vel[k] + vJ[k];
      cross_motion(vel, vJ, w.c.data());
    } else {
      w.sO.setZero();
      w.c.setZero();
      if (l.parent < 0)
        w.vel.setZero();
      else
        w.vel = work_[l.parent].vel;
    }
    // The body's spatial inertia about origin_: [Ic + m (|c|^2 1 - c c^T), m [c]x; m [c]x^T, m 1]
    // with Ic = R diag(I_P) R^T (Featherstone eq. 2.63 with the shift of eq. 2.66).
    const double m = l.mass;
    double* I = w.Iw;
    double Ic[3][3];
    for (int r = 0; r < 3; ++r) {
      const double d0 = R(r, 0) * l.I_P[0], d1 = R(r, 1) * l.I_P[1], d2 = R(r, 2) * l.I_P[2];
      for (int k = r; k < 3; ++k) Ic[r][k] = Ic[k][r] = d0 * R(k, 0) + d1 * R(k, 1) + d2 * R(k, 2);
    }
    const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
#pragma GCC unroll 3
    for (int r = 0; r < 3; ++r)
#pragma GCC unroll 3
      for (int k = r; k < 3; ++k) I[kSym[r][k]] = Ic[r][k] + m * ((r == k ? cc : 0.0) - c[r] * c[k]);
    const double mc[3] = {m * c[0], m * c[1], m * c[2]};
    // Top right m [c]x (rows r, columns 3 + k); bottom right m 1.
    I[kSym[0][3]] = 0, I[kSym[0][4]] = -mc[2], I[kSym[0][5]] = mc[1];
    I[kSym[1][3]] = mc[2], I[kSym[1][4]] = 0, I[kSym[1][5]] = -mc[0];
    I[kSym[2][3]] = -mc[1], I[kSym[2][4]] = mc[0], I[kSym[2][5]] = 0;
    I[kSym[3][3]] = m, I[kSym[3][4]] = 0, I[kSym[3][5]] = 0;
    I[kSym[4][4]] = m, I[kSym[4][5]] = 0, I[kSym[5][5]] = m;
    // Bias force v x* h with h = I v = [Ic w + c x p; p], p = m (v_O + w x c) the momentum.
    const double pm[3] = {m * (vel[3] + (vel[1] * c[2] - vel[2] * c[1])),
                          m * (vel[4] + (vel[2] * c[0] - vel[0] * c[2])),
                          m * (vel[5] + (vel[0] * c[1] - vel[1] * c[0]))};
    double h[6];
    for (int r = 0; r < 3; ++r) h[r] = Ic[r][0] * vel[0] + Ic[r][1] * vel[1] + Ic[r][2] * vel[2];
    h[0] += c[1] * pm[2] - c[2] * pm[1];
    h[1] += c[2] * pm[0] - c[0] * pm[2];
    h[2] += c[0] * pm[1] - c[1] * pm[0];
    h[3] = pm[0], h[4] = pm[1], h[5] = pm[2];
    cross_force(vel, h, w.pA.data());
    if (wr && l.body >= 0 && !lean_) {
      // The external wrench's force acts at the centre of mass: about origin_, n_O = tau + c x f.
      const Wrench& f = wr[l.body];
      const Vec3 nO = f.tau_W + Vec3(c[0], c[1], c[2]).cross(f.f_W);
      w.pA.head<3>() -= nO;
      w.pA.tail<3>() -= f.f_W;
    }
  }
  // Pass 2, leaves to root: Ia = IA - U U^T / D and pa = pA + Ia c + U u / D, added to the
  // parent's as they are (same axes, same point).
  for (size_t i = n; i-- > 0;) {
    const Link& l = links[i];
    Work& w = work_[i];
    double* I = w.Iw;
    double* P = w.pA.data();
    if (l.nv == 1) {
      const double* s = w.sO.data();
      double U[6];
      sym_vec(I, s, U);
      const double Dinv = 1 / (s[0] * U[0] + s[1] * U[1] + s[2] * U[2] + s[3] * U[3] + s[4] * U[4] +
                               s[5] * U[5] + l.armature);
      double u = -(s[0] * P[0] + s[1] * P[1] + s[2] * P[2] + s[3] * P[3] + s[4] * P[4] + s[5] * P[5]);
      if (l.stiffness != 0 || l.damping != 0) u += -l.stiffness * (q[l.iq] - l.rest) - l.damping * v[l.iv];
      for (int k = 0; k < 6; ++k) w.U1[k] = U[k];
      w.Dinv1 = Dinv;
      w.u1 = u;
      if (l.parent < 0) continue;
      double UD[6];
      for (int k = 0; k < 6; ++k) UD[k] = Dinv * U[k];
#pragma GCC unroll 6
      for (int r = 0; r < 6; ++r)
#pragma GCC unroll 6
        for (int k = r; k < 6; ++k) I[kSym[r][k]] -= UD[r] * U[k];
      double Ic[6];
      sym_vec(I, w.c.data(), Ic);
      const double f = Dinv * u;
      for (int r = 0; r < 6; ++r) P[r] += U[r] * f + Ic[r];
    }
    if (l.parent < 0) continue;
    Work& p = work_[l.parent];
    for (int k = 0; k < 21; ++k) p.Iw[k] += I[k];
    double* pP = p.pA.data();
    for (int k = 0; k < 6; ++k) pP[k] += P[k];
  }
  // Pass 3, root to leaves: accelerations, the world's -g putting gravity on every link.
  const double a_world[6] = {0, 0, 0, -g.x(), -g.y(), -g.z()};
  for (size_t i = 0; i < n; ++i) {
    const Link& l = links[i];
    Work& w = work_[i];
    const double* ap0 = l.parent < 0 ? a_world : work_[l.parent].acc.data();
    double* acc = w.acc.data();
    if (l.nv == 1) {
      double ap[6];
      for (int k = 0; k < 6; ++k) ap[k] = ap0[k] + w.c[k];
      const double* U = w.U1.data();
      const double qdd =
          w.Dinv1 *
          (w.u1 - (U[0] * ap[0] + U[1] * ap[1] + U[2] * ap[2] + U[3] * ap[3] + U[4] * ap[4] + U[5] * ap[5]));
      dv[l.iv] = qdd;
      for (int k = 0; k < 6; ++k) acc[k] = ap[k] + w.sO[k] * qdd;
    } else {
      for (int k = 0; k < 6; ++k) acc[k] = ap0[k];
    }
  }
  // A Verlet step's last evaluation is at its end's coordinates (q1): write_bodies reads the
  // frame's poses from these kinematics.
  world_at_q_ = true;
  std::copy(q, q + nq, world_q_.begin());
}

double Mechanism::rk_step(double hs, const Vec3& g, const Wrench* wr, const MotionState* st, double tol) {
  const int ny = nq + nv;
  for (int s = 1; s < 7; ++s) {
    for (int j = 0; j < ny; ++j) {
      double acc = 0;
      for (int r = 0; r < s; ++r) acc += dopri::kA[s][r] * k_[r][j];
      ys_[j] = y0_[j] + hs * acc;
    }
    // Loads switch only at steps' ends (advance cuts steps there): a step's stages all see the
    // loads of its interior, read at its middle (its end may be an edge).
    time_ = t_step_ + 0.5 * hs;
    step_derivative(ys_.data(), k_[s].data(), g, wr, st);
  }
  // The 7th stage is evaluated at the 5th-order solution (its row of A is b): ys_ holds y1.
  double e2 = 0;
  for (int j = 0; j < ny; ++j) {
    double e = 0;
    for (int r = 0; r < 7; ++r) e += (dopri::kB[r] - dopri::kBstar[r]) * k_[r][j];
    e *= hs;
    y1_[j] = ys_[j];
    const double sc = tol * (1 + std::max(std::abs(y0_[j]), std::abs(y1_[j])));
    e2 += (e / sc) * (e / sc);
  }
  return std::sqrt(e2 / std::max(ny, 1));
}

void Mechanism::keep_span(double t0, double hs, const Vec3& g) {
  // Dormand-Prince's continuous extension (Hairer, Norsett & Wanner I, II.6, the coefficients of
  // their DOPRI5's dense output): y(t0 + th hs) = r0 + th (r1 + (1 - th) (r2 + th (r3 + (1 - th) r4))),
  // y0 and y1 at th = 0 and 1, slopes k1 and k7 there, 4th order in between.
  constexpr double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
                   d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
                   d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
  const int ny = nq + nv;
  for (int j = 0; j < ny; ++j) {
    const double dy = y1_[j] - y0_[j], r2 = hs * k_[0][j] - dy;
    span_rc_[0][j] = y0_[j];
    span_rc_[1][j] = dy;
    span_rc_[2][j] = r2;
    span_rc_[3][j] = dy - hs * k_[6][j] - r2;
    span_rc_[4][j] =
        hs * (d1 * k_[0][j] + d3 * k_[2][j] + d4 * k_[3][j] + d5 * k_[4][j] + d6 * k_[5][j] + d7 * k_[6][j]);
  }
  std::copy(y0_.begin(), y0_.end(), span.y0.begin());
  std::copy(y1_.begin(), y1_.end(), span_y1_.begin());
  std::copy(k_[6].begin(), k_[6].end(), span_k7_.begin());
  span.t0 = t0;
  span.len = hs;
  span.g = g;
  span.valid = true;
  span.retake = false;
}

void Mechanism::read_span(double t, double* y) const {
  const double th = (t - span.t0) / span.len, u = 1 - th;
  for (int j = 0; j < nq + nv; ++j)
    y[j] = span_rc_[0][j] +
           th * (span_rc_[1][j] + u * (span_rc_[2][j] + th * (span_rc_[3][j] + u * span_rc_[4][j])));
}

void Mechanism::retake_span(const Vec3& g, const Wrench* wr, const MotionState* st) {
  std::copy(span.y0.begin(), span.y0.end(), y0_.begin());
  time_ = t_step_ = span.t0;
  step_derivative(y0_.data(), k_[0].data(), g, wr, st);
  rk_step(span.len, g, wr, st, 1.0);
  keep_span(span.t0, span.len, g);
}

namespace {
// Two states equal to the bit (a derivative or a step taken at one holds at the other).
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), [](double x, double y) {
    return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
  });
}
// Some event function went from >= 0 at the step's start to < 0.
bool crossed(const std::vector<double>& g0, const std::vector<double>& g1) {
  for (size_t i = 0; i < g0.size(); ++i)
    if (g0[i] >= 0 && g1[i] < 0) return true;
  return false;
}
}  // namespace

void Mechanism::measure_rate(int pairs, const Vec3& g, const Wrench* wr, const MotionState* st) {
  const int ny = nq + nv;
  double* x = verlet.x.data();
  // A start with every coordinate and rate, alternating in sign: the fastest modes of chains
  // alternate from link to link, so the iteration starts near them.
  auto start = [&] {
    for (int j = 0; j < ny; ++j) x[j] = (j % 2 ? -1.0 : 1.0) * (1 + 0.01 * j);
  };
  if (!(verlet.rate > 0)) start();
  double size = 0;
  for (int j = 0; j < ny; ++j) size = std::max(size, std::abs(y0_[j]));
  // A perturbation of 1e-7 of the state's size: f's round-off (1e-16 relative) stays 1e-9 of the
  // difference, and the second-order term 1e-7 of it: the rate is wanted to a few percent.
  const double eps = 1e-7 * (1 + size);
  auto normalize = [&](double* z) {
    double n2 = 0;
    for (int j = 0; j < ny; ++j) n2 += z[j] * z[j];
    const double n = std::sqrt(n2);
    if (n > 0)
      for (int j = 0; j < ny; ++j) z[j] /= n;
    return n;
  };
  normalize(x);
  auto apply = [&]() {  // x <- J x / |J x|, returning |J x| (x unit)
    for (int j = 0; j < ny; ++j) ys_[j] = y0_[j] + eps * x[j];
    step_derivative(ys_.data(), k_[1].data(), g, wr, st);
    for (int j = 0; j < ny; ++j) x[j] = (k_[1][j] - k_[0][j]) / eps;
    return normalize(x);
  };
  double rate = 0;
  for (int p = 0; p < pairs; ++p) {
    const double before = rate;
    rate = std::sqrt(apply() * apply());
    if (p > 0 && std::abs(rate - before) <= kVerletConverged * rate) break;
  }
  if (!std::isfinite(rate) || !(rate > 0)) {  // no stiffness, damping or coupling: one step a frame
    rate = 0;
    start();
    normalize(x);
  }
  verlet.rate = rate;
}

void Mechanism::kinetic_energies(const double* a, const double* b, double& Ea, double& Eb) {
  Ea = Eb = 0;
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    const Work& w = work_[i];
    Vec6 ja = Vec6::Zero(), jb = Vec6::Zero();
    if (l.nv == 1) {
      ja = l.s1 * a[l.iv];
      jb = l.s1 * b[l.iv];
    } else if (l.nv > 0) {
      ja = l.S * Eigen::Map<const VecX6>(a + l.iv, l.nv);
      jb = l.S * Eigen::Map<const VecX6>(b + l.iv, l.nv);
    }
    if (l.parent < 0) {
      ke_a_[i] = ja;
      ke_b_[i] = jb;
    } else {
      transform_motion_add(w.E, w.r, ke_a_[l.parent].data(), ja.data(), ke_a_[i].data());
      transform_motion_add(w.E, w.r, ke_b_[l.parent].data(), jb.data(), ke_b_[i].data());
    }
    // Link frames are principal at the centre of mass: 2 T = I_P . w^2 + m |v|^2.
    const Vec6& A = ke_a_[i];
    const Vec6& B = ke_b_[i];
    for (int k = 0; k < 3; ++k) {
      Ea += l.I_P[k] * A[k] * A[k] + l.mass * A[k + 3] * A[k + 3];
      Eb += l.I_P[k] * B[k] * B[k] + l.mass * B[k + 3] * B[k + 3];
    }
  }
}

Mechanism::VerletFrame Mechanism::advance_verlet(double dt, const Vec3& g, const Wrench* wr,
                                                 const MotionState* st, const JointSettings& js) {
  const bool measured =
      verlet.rate > 0 || !std::all_of(verlet.x.begin(), verlet.x.end(), [](double z) { return z == 0; });
  // The frame's index, from the world's time: the measurement schedule is the same on a resumed run.
  const long frame = std::lround(frame_time / dt);
  const bool measure = js.substeps == 0 && (!measured || frame >= verlet.next);
  const bool carried = verlet.carry && !measure && lean_ && g == verlet.g && same_bits(y0_, verlet.y);
  verlet.carry = false;
  double* a = k_[0].data() + nq;
  if (carried) {
    std::copy(verlet.a.begin(), verlet.a.end(), a);
  } else {
    time_ = frame_time;
    step_derivative(y0_.data(), k_[0].data(), g, wr, st);
  }
  // The first measurement iterates from a fixed start until the rate holds within
  // kVerletConverged (the two fastest modes of a 20-link chain differ by 12%: 5 pairs, 0.6% low);
  // later ones refine it from the last vector, which the slow change of the configuration keeps
  // near the fastest mode.
  if (measure) {
    const double before = verlet.rate;
    measure_rate(measured ? 1 : 16, g, wr, st);
    const double change = before > 0 ? verlet.rate / before : 1;
    const bool steady = measured && change > 1 / 1.1 && change < 1.1;
    verlet.every = steady ? std::min(2 * verlet.every, kVerletEvery) : std::max(verlet.every / 2, 1);
    verlet.next = frame + verlet.every;
    verlet.growth = std::max(change, 1.0);
  }
  int n = js.substeps > 0 ? js.substeps
                          : std::max(1, (int)std::ceil(verlet.rate * verlet.growth * dt / kVerletReach));
  if (n > js.max_steps) {
    exceeded = true;
    return VerletFrame::failed;
  }
  std::copy(y0_.begin(), y0_.end(), verlet.y_start.begin());
  for (int s = 0; s < n; ++s) {
    const double hs = dt / n;
    const double* y = y0_.data();
    for (int j = 0; j < nv; ++j) {
      const double vh = y[nq + j] + 0.5 * hs * a[j];
      ys_[j] = y[j] + hs * vh;              // q1
      ys_[nq + j] = y[nq + j] + hs * a[j];  // the predicted rate
      y1_[nq + j] = vh;
    }
    t_step_ = frame_time + s * hs;
    time_ = t_step_ + hs;
    step_derivative(ys_.data(), k_[1].data(), g, wr, st);
    const double* a1 = k_[1].data() + nq;
    bool finite = true;
    double change = 0, vmax = 0;
    for (int j = 0; j < nv; ++j) {
      change = std::max(change, std::abs(a1[j] - a[j]));
      vmax = std::max(vmax, std::abs(y1_[nq + j]));
      y1_[j] = ys_[j];
      k_[2][j] = 0.5 * hs * (a1[j] - a[j]);  // the predictor's error, for the energy test
      y1_[nq + j] += 0.5 * hs * a1[j];
      finite = finite && std::isfinite(y1_[nq + j]) && std::isfinite(y1_[j]);
    }
    ++steps_taken;
    // Resolved if the predictor's error is within kVerletResolve of the largest rate, or else
    // carries at most kVerletEnergyShare of the kinetic energy: a fast mode in light links (a
    // heavy chain's) can carry the largest rates and almost none of the energy.
    bool resolved = 0.5 * hs * change <= kVerletResolve * vmax;
    if (!resolved && finite) {
      double Ee = 0, Ev = 0;
      kinetic_energies(k_[2].data(), y1_.data() + nq, Ee, Ev);
      resolved = Ee <= kVerletEnergyShare * Ev;
    }
    if (js.substeps == 0 && !resolved) {
      // Not resolved (or not finite): dopri5 takes the frame from its start, and the rate is
      // measured again at the next.
      std::copy(verlet.y_start.begin(), verlet.y_start.end(), y0_.begin());
      verlet.next = frame + 1;
      verlet.every = 1;
      ++verlet.unresolved;
      return VerletFrame::unresolved;
    }
    std::swap(y0_, y1_);
    std::swap(k_[0], k_[1]);
    a = k_[0].data() + nq;
    if (!finite) return VerletFrame::failed;
  }
  // Lean: a1 depends on the state and g alone, so the next frame starts from it unless the state
  // is changed from outside (the bits are compared there).
  if (lean_) {
    verlet.carry = true;
    verlet.g = g;
    std::copy(a, a + nv, verlet.a.begin());
    std::copy(y0_.begin(), y0_.end(), verlet.y.begin());
  }
  time_ = frame_time + dt;
  std::copy(y0_.begin(), y0_.begin() + nq, q.begin());
  std::copy(y0_.begin() + nq, y0_.end(), v.begin());
  return VerletFrame::done;
}

bool Mechanism::advance(double dt, const Vec3& g, const Wrench* wr, const MotionState* st,
                        const JointSettings& js) {
  std::copy(q.begin(), q.end(), y0_.begin());
  std::copy(v.begin(), v.end(), y0_.begin() + nq);
  if (!(h > 0)) h = dt;
  // Links' world poses enter an evaluation only through what acts in world terms (wrenches,
  // loads, loop and rope rows): without those, the evaluations of this step skip them.
  lean_ = !has_rows() && !loop_springs_on && loads.empty();
  if (wr)
    for (const Link& l : links)
      if (l.body >= 0 && !(wr[l.body].f_W.isZero(0) && wr[l.body].tau_W.isZero(0))) lean_ = false;
  struct Reset {
    bool& b;
    ~Reset() { b = false; }
  } reset{lean_};
  bool verlet_frame = false;  // taken by dopri5 because Verlet's steps did not resolve it
  if (js.integrator == JointIntegrator::verlet && verlet_ok()) {
    span.valid = false;
    carry_k1_ = false;
    const VerletFrame f = advance_verlet(dt, g, wr, st, js);
    if (f != VerletFrame::unresolved) return f == VerletFrame::done;
    verlet_frame = true;
  }
  const double tol = js.tolerance;
  const bool events_on = this->events_on();
  if (events_on && !started) {
    start_modes(y0_.data(), g, wr);
    started = true;
  }
  double t = 0;
  int steps = 0;
  // First same as last across frames: a lean evaluation depends on y and g alone, so the last
  // frame's final stage is this frame's first when neither changed since (one derivative in 7 of
  // a frame taken in one step). The comparison is of the bits: a state set from outside, restored
  // or woken differently evaluates afresh, with the same result it would have had.
  bool have_k1 = lean_ && carry_k1_ && g == g_end_ && same_bits(y0_, y_end_);
  carry_k1_ = false;
  // Lean, and coordinates whose rates are their derivatives (no quaternions to renormalise at the
  // frame): the last step runs past the frame's end (Span).
  const bool may_span = lean_ && nq == nv && !verlet_frame;
  if (span.valid) {
    const bool same = may_span && g == span.g && std::abs(frame_time - span.t_out) <= 1e-9 * dt &&
                      (span.retake || same_bits(y0_, span_out_));
    span.valid = false;
    if (same) {
      if (span.retake) retake_span(g, wr, st);
      const double t_end = frame_time + dt, t1 = span.t0 + span.len;
      if (t_end <= t1) {  // the frame ends within the step: read it there
        read_span(t_end, y0_.data());
        span.valid = true;
        span.t_out = t_end;
        std::copy(y0_.begin(), y0_.end(), span_out_.begin());
        time_ = t_end;
        std::copy(y0_.begin(), y0_.begin() + nq, q.begin());
        std::copy(y0_.begin() + nq, y0_.end(), v.begin());
        return true;
      }
      // On from the step's end, its last stage the next step's first.
      std::copy(span_y1_.begin(), span_y1_.end(), y0_.begin());
      std::copy(span_k7_.begin(), span_k7_.end(), k_[0].begin());
      have_k1 = true;
      t = t1 - frame_time;
    }
  }
  bool spanned = false;
  while (t < dt) {
    if (++steps > js.max_steps) {
      exceeded = true;
      return false;
    }
    bool last = h >= dt - t;
    double hs = last && !may_span ? dt - t : h;
    t_step_ = frame_time + t;
    // A load switching on or off ends the step at its edge: each side is smooth.
    bool cut = false;
    for (const Load& L : loads)
      for (double e : {L.f.from, L.f.to})
        if (e > t_step_ + 1e-12 * dt && e < t_step_ + hs - 1e-12 * dt) {
          hs = e - t_step_;
          last = false;
          cut = true;
        }
    if (!have_k1) {
      time_ = t_step_;
      step_derivative(y0_.data(), k_[0].data(), g, wr, st);
      if (events_on) event_values(y0_.data(), g0_.data());
    }
    have_k1 = true;
    const double err = rk_step(hs, g, wr, st, tol);
    if (!std::isfinite(err)) return false;
    const double fac = dopri::step_factor(err);
    if (err > 1) {
      h = hs * std::min(fac, 1.0);
      ++steps_rejected;
      continue;
    }
    if (last && may_span && hs > dt - t) {  // past the frame's end: kept, and the frame read from it
      keep_span(frame_time + t, hs, g);
      read_span(frame_time + dt, y0_.data());
      ++steps_taken;
      h = hs * fac;
      spanned = true;
      break;
    }
    bool event = false;
    if (events_on) {
      event_values(ys_.data(), g1_.data());
      if (crossed(g0_, g1_)) {
        // Locate the first crossing by re-taking the step (Illinois regula falsi on the step length
        // over the earliest-crossing function): the step ends just past it, by under 1e-12 of the
        // step, so the state there is as accurate as any accepted step's.
        event = true;
        const double h_full = hs;
        double a = 0, b = hs;
        int side = 0;
        double fa_scale = 1, fb_scale = 1;
        for (int it = 0; it < 100 && b - a > 1e-12 * h_full; ++it) {
          // The function whose linear crossing comes first, interpolated between a and b.
          double tc = b;
          for (size_t k = 0; k < g0_.size(); ++k) {
            if (!(g0_[k] >= 0 && g1_[k] < 0)) continue;
            const double fa = (a == 0 ? g0_[k] : ga_[k]) * fa_scale, fb = g1_[k] * fb_scale;
            const double c = a + (b - a) * fa / (fa - fb);
            tc = std::min(tc, c);
          }
          tc = std::clamp(tc, a + 1e-3 * (b - a), b - 1e-3 * (b - a));
          if (!std::isfinite(rk_step(tc, g, wr, st, tol))) return false;
          event_values(ys_.data(), gc_.data());
          if (crossed(g0_, gc_)) {
            b = tc;
            std::swap(g1_, gc_);
            fa_scale = side == -1 ? fa_scale * 0.5 : 1;  // Illinois: the kept end's value halves
            fb_scale = 1;
            side = -1;
          } else {
            a = tc;
            std::swap(ga_, gc_);
            fb_scale = side == 1 ? fb_scale * 0.5 : 1;
            fa_scale = 1;
            side = 1;
          }
        }
        if (side == 1) {  // the last trial was not the step kept
          if (!std::isfinite(rk_step(b, g, wr, st, tol))) return false;
          event_values(ys_.data(), g1_.data());
        }
        last = last && b == h_full;
        hs = b;
      }
    }
    t = last ? dt : t + hs;
    ++steps_taken;
    if (event) {
      apply_events(y1_.data(), g0_.data(), g1_.data(), g, wr);
      ++events;
    }
    if (projected()) {
      normalize_quaternions(*this, y1_.data());
      project_positions(y1_.data());
      // A coordinate that rebounded off its stop left the projection a hair past it (the loop's
      // rows move every coordinate by their round-off): back on it, so that its stop's event
      // function starts the next step at zero and a return within that step is seen (left past,
      // the return goes unseen and the coordinate runs through its stop).
      if (event) back_on_stops(y1_.data());
      project_velocities(y1_.data(), y1_.data() + nq);
    } else if (any_active()) {
      project_dofs(y1_.data());
    }
    if (!tethers.empty() && catch_stretched(y1_.data(), g, wr)) {
      project_velocities(y1_.data(), y1_.data() + nq);
      event = true;  // the state moved: no first-same-as-last, no step-size proposal from this one
    }
    std::swap(y0_, y1_);
    if (loop_tracked_on) {  // the tracked hinges' angles at the new state, for the next step's stages
      kinematics(y0_.data());
      track_loop_angles();
    }
    // First same as last: the 7th stage was evaluated at the new state, unless a projection or a
    // mode change moved it. (Quaternions drift off unit length by the tolerance only; they are
    // renormalised once the frame step is done.)
    have_k1 = !event && !cut && !projected() && !any_active();
    if (have_k1) {
      std::swap(k_[0], k_[6]);
      std::swap(g0_, g1_);
    }
    // A step cut short to land on the frame or an event does not set the next proposal.
    if (!event && !cut && (!last || hs >= h)) h = hs * fac;
  }
  if (spanned) {
    span.t_out = frame_time + dt;
    std::copy(y0_.begin(), y0_.end(), span_out_.begin());
  }
  // Quaternion coordinates are renormalised below, which would move the state off k_[0]'s.
  carry_k1_ = lean_ && have_k1 && nq == nv && !spanned;
  if (carry_k1_) {
    std::copy(y0_.begin(), y0_.end(), y_end_.begin());
    g_end_ = g;
  }
  normalize_quaternions(*this, y0_.data());
  time_ = frame_time + dt;
  if (events_on) derivative(y0_.data(), kd_.data(), g, wr, st);  // the forces read out at the frame
  std::copy(y0_.begin(), y0_.begin() + nq, q.begin());
  std::copy(y0_.begin() + nq, y0_.end(), v.begin());
  return true;
}

void Mechanism::link_velocities(const double* qq, const double* vv, std::vector<Vec6>& out) {
  kinematics(qq);
  out.resize(links.size());
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    Vec6 vJ = Vec6::Zero();
    if (l.nv > 0) vJ = l.S * Eigen::Map<const VecX6>(vv + l.iv, l.nv);
    out[i] = l.parent < 0 ? vJ : Vec6(transform_motion(work_[i].E, work_[i].r, out[l.parent]) + vJ);
  }
}

void Mechanism::write_bodies(MotionState* st) const {
  if (world_at_q_ && std::equal(q.begin(), q.end(), world_q_.begin())) {
    write_bodies_world(st);
    return;
  }
  // Poses by quaternion products (not the matrices of the derivative), so that a body's
  // orientation carries no rotation-matrix round trip.
  std::vector<Quat>& qW = out_q_;
  std::vector<Vec3>& xW = out_x_;
  std::vector<Vec6>& vel = out_v_;
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    const double* qq = q.data() + l.iq;
    Quat qpi;
    Vec3 t;
    if (l.kind == LinkJoint::revolute) {
      double sh, ch;
      sin_cos(0.5 * qq[0], sh, ch);
      qpi.coeffs() = ch * l.qh0.coeffs() + sh * l.qh1.coeffs();
      const double sq = 2 * sh * ch, kq = 2 * sh * sh;  // sin q, 1 - cos q
      t = l.t0 - sq * l.ts - kq * l.tk;
    } else if (l.kind == LinkJoint::free) {
      qpi = joint_rotation(l, qq);
      t = Vec3(qq[0], qq[1], qq[2]);
    } else {
      const Quat qJ = joint_rotation(l, qq);
      const Vec3 pJ = l.kind == LinkJoint::prismatic ? Vec3(l.axis_F * qq[0]) : Vec3::Zero();
      qpi = l.q_pF * qJ * l.q_cF.conjugate();
      t = l.p_pF + l.q_pF * (pJ - qJ * l.p_cF_F);
    }
    if (l.parent < 0) {
      qW[i] = qpi;
      xW[i] = t;
    } else {
      qW[i] = qW[l.parent] * qpi;
      xW[i] = xW[l.parent] + qW[l.parent] * t;
    }
    qW[i].normalize();
    // Velocity: v_i = X v_parent + S q' (the transform from the same pose).
    Vec6 vJ = Vec6::Zero();
    if (l.nv == 1)
      vJ = l.s1 * v[l.iv];
    else if (l.nv > 0)
      vJ = l.S * Eigen::Map<const VecX6>(v.data() + l.iv, l.nv);
    if (l.parent < 0)
      vel[i] = vJ;
    else
      transform_motion_add(qpi.conjugate().toRotationMatrix(), t, vel[l.parent].data(), vJ.data(),
                           vel[i].data());
    if (l.body < 0) continue;
    MotionState& s = st[l.body];
    s.q_WP = qW[i];
    s.x_W = xW[i];
    s.w_P = vel[i].head<3>();
    s.v_W = qW[i] * Vec3(vel[i].tail<3>());
  }
}

void Mechanism::write_bodies_world(MotionState* st) const {
  std::vector<Vec6>& vel = out_v_;
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    const Work& w = work_[i];
    // v_i = v_parent + s q' (world axes about origin_, as derivative_world).
    double* vi = vel[i].data();
    for (int k = 0; k < 6; ++k) vi[k] = l.parent < 0 ? 0.0 : vel[l.parent][k];
    if (l.nv == 1)
      for (int k = 0; k < 6; ++k) vi[k] += w.sO[k] * v[l.iv];
    if (l.body < 0) continue;
    MotionState& s = st[l.body];
    Quat qW(w.R_W);
    qW.normalize();
    if (qW.dot(s.q_WP) < 0) qW.coeffs() = -qW.coeffs();  // the sign the body had: no flip between frames
    s.q_WP = qW;
    s.x_W = w.x_W;
    const Vec3 wW(vi[0], vi[1], vi[2]), c = w.x_W - origin_;
    s.w_P = w.R_W.transpose() * wW;
    s.v_W = Vec3(vi[3], vi[4], vi[5]) + wW.cross(c);
  }
}

// ------------------------------------------------------------------ building the mechanisms
namespace {
// 'a', 'b', ...: the bodies of a mechanism, for messages.
std::string body_names(const Mechanism& m, const std::vector<BodyDef>& defs) {
  std::string out;
  for (const Link& l : m.links)
    if (l.body >= 0) out += (out.empty() ? "'" : ", '") + defs[l.body].name + "'";
  return out;
}
}  // namespace

void Articulations::build(const std::vector<JointDef>& joints, const JointSettings& settings,
                          const std::vector<BodyDef>& defs, const std::vector<BodyModel>& model,
                          std::vector<MotionState>& state, std::vector<std::string>& warnings,
                          const std::vector<std::pair<int, int>>& bonds) {
  joints_ = joints;
  settings_ = settings;
  const int nb = (int)defs.size();
  link_of_.assign(nb, {-1, -1});
  if (joints_.empty()) return;
  if (!(settings.tolerance > 0) || !(settings.tolerance < 1e-2))
    throw InputError("joints: tolerance must be a number in (0, 0.01)");
  if (settings.max_steps < 1) throw InputError("joints: max_steps must be at least 1");
  if (settings.substeps < 0) throw InputError("joints: substeps must be 0 (chosen) or more");
  auto name_of = [&](int j) { return "joint '" + joints_[j].name + "'"; };
  auto body_name = [&](int b) { return b < 0 ? std::string("world") : "'" + defs[b].name + "'"; };
  // The world, or a static body (which never moves): the tree's fixed base.
  auto fixed_base = [&](int b) { return b < 0 || model[b].is_static; };
  std::vector<int> parent_joint(nb, -1);  // per body: the joint it is the child of
  std::vector<int> loop_joints;           // joints that close a loop (constraints, not tree edges)
  std::vector<int> tether_joints;         // distance and pulley joints (rows, never tree edges)
  const int nj = (int)joints_.size();
  for (int j = 0; j < nj; ++j) {
    JointDef& d = joints_[j];
    if (d.name.empty()) d.name = "joint" + std::to_string(j);
    for (int k = 0; k < j; ++k)
      if (joints_[k].name == d.name) throw InputError(name_of(j) + ": the name is used by an earlier joint");
  }
  // The tree takes first the joints that only a tree edge can carry (a motor, friction, a wheel,
  // cone or twist stops, armature, a mimic's joints, a spring or limits on a joint without one
  // coordinate), then the rest, each group in file order: a loop is closed by a plain joint
  // wherever it has one, whichever joint the file wrote last. A scene whose loops were already
  // closed by plain joints gets the same tree as in file order.
  // A ball joint with a spring or stops (tree_only 2) is taken into the tree after those and before
  // the rest, and may close a loop that has no plain joint: its spring then acts between the two
  // bodies as a loop's hinge spring does, and its stops measure b's rotation relative to a's.
  std::vector<char> tree_only(nj, 0);
  for (int j = 0; j < nj; ++j) {
    const JointDef& d = joints_[j];
    const bool one_axis = d.type == JointType::revolute || d.type == JointType::prismatic;
    const bool ball = d.type == JointType::spherical;
    if (d.type == JointType::wheel || d.motor || d.motor2 || d.steering || d.friction != 0 ||
        (d.ball_limits && !ball) || d.armature != 0 || d.mimic || (d.spring && !one_axis && !ball) ||
        (d.limits && !one_axis))
      tree_only[j] = 1;
    else if (ball && (d.spring || d.ball_limits))
      tree_only[j] = 2;
    if (!d.mimic) continue;
    if (d.mimic->leader >= 0 && d.mimic->leader < nj) tree_only[d.mimic->leader] = 1;
    for (const auto& [l, c] : d.mimic->also)
      if (l >= 0 && l < nj) tree_only[l] = 1;
  }
  std::vector<int> order;
  for (int pass : {1, 2, 0})
    for (int j = 0; j < nj; ++j)
      if (tree_only[j] == pass) order.push_back(j);
  for (int j : order) {
    JointDef& d = joints_[j];
    if (d.child < -1 || d.child >= nb || d.parent < -1 || d.parent >= nb)
      throw InputError(name_of(j) + ": body index out of range");
    if (d.child == d.parent)
      throw InputError(name_of(j) + ": joins body " + body_name(d.child) + " to itself");
    if (fixed_base(d.parent) && fixed_base(d.child))
      throw InputError(name_of(j) + ": joins two bodies that cannot move (" + body_name(d.parent) + " and " +
                       body_name(d.child) + ")");
    const bool tether = d.type == JointType::distance || d.type == JointType::pulley;
    // Written the other way round: the moving body is the child, and its coordinate is its motion
    // relative to the fixed one. (A rope's length does not depend on the order.)
    if (!tether && fixed_base(d.child)) {
      std::swap(d.parent, d.child);
      // The parent's motion relative to the child about (along) the axis by q is the child's
      // about (along) the reversed axis by q: the coordinate keeps the meaning the joint gave it.
      if (d.type == JointType::revolute || d.type == JointType::prismatic) d.axis_W = -d.axis_W;
      // A ball joint's motor target turns the other way: minus the angular velocity, the inverse
      // rotation (whose rotation vector is minus the same axis-angle, in either body's axes).
      if (d.type == JointType::spherical && d.motor) {
        d.motor->angular_velocity = -d.motor->angular_velocity;
        d.motor->rotation = -d.motor->rotation;
      }
      // Its twist of the parent relative to the child is minus the child's (its quaternion's
      // vector part changes sign): the stops swap and change sign. Its swing, whole angle and
      // spring are the same either way.
      if (d.ball_limits) {
        BallLimits& B = *d.ball_limits;
        const double lower = B.twist_lower;
        B.twist_lower = -B.twist_upper;
        B.twist_upper = -lower;
      }
    }
    if ((d.child >= 0 && model[d.child].is_kinematic) || (d.parent >= 0 && model[d.parent].is_kinematic))
      throw InputError(name_of(j) + ": kinematic bodies cannot be jointed yet (body " +
                       body_name(d.child >= 0 && model[d.child].is_kinematic ? d.child : d.parent) + ")");
    if (tether) {
      validate_tether(d, defs, model);
      tether_joints.push_back(j);
      continue;
    }
    if (!all_finite(d.anchor_W)) throw InputError(name_of(j) + ": anchor must be finite");
    const bool wheel = d.type == JointType::wheel;
    const bool axial = d.type == JointType::revolute || d.type == JointType::prismatic ||
                       d.type == JointType::universal || wheel;
    if (axial) {
      if (!all_finite(d.axis_W) || d.axis_W.norm() < 1e-12)
        throw InputError(name_of(j) + ": axis must not be zero");
      d.axis_W.normalize();
    }
    if (d.type == JointType::universal || wheel) {
      if (!all_finite(d.axis2_W) || d.axis2_W.norm() < 1e-12)
        throw InputError(name_of(j) + ": axis2 must not be zero");
      d.axis2_W.normalize();
      if (std::abs(d.axis_W.dot(d.axis2_W)) > 1e-6)
        throw InputError(name_of(j) + ": axis2 must be perpendicular to axis");
    }
    if (d.spring) {
      if (d.type == JointType::fixed)
        throw InputError(name_of(j) + ": a spring needs a joint that moves (not " + to_string(d.type) + ")");
      if (!std::isfinite(d.spring->stiffness) || !std::isfinite(d.spring->damping) ||
          !std::isfinite(d.spring->rest) || d.spring->stiffness < 0 || d.spring->damping < 0)
        throw InputError(name_of(j) + ": spring stiffness and damping must be non-negative numbers");
    }
    const bool one_coordinate = d.type == JointType::revolute || d.type == JointType::prismatic ||
                                d.type == JointType::universal || wheel;
    if (d.limits) {
      const JointLimits& L = *d.limits;
      if (!one_coordinate)
        throw InputError(name_of(j) + ": a " + to_string(d.type) + " joint has no coordinate for limits");
      if (!std::isfinite(L.lower) || !std::isfinite(L.upper) || !(L.lower < L.upper))
        throw InputError(name_of(j) + ": limits must be finite with lower < upper");
      if (L.lower > 0 || L.upper < 0)
        throw InputError(name_of(j) +
                         ": joint coordinates are 0 in the start pose, so the limits must contain 0");
      if (!(L.restitution >= 0 && L.restitution <= 1))
        throw InputError(name_of(j) + ": limit restitution must be in [0, 1]");
    }
    if (d.ball_limits) {
      const BallLimits& B = *d.ball_limits;
      if (d.type != JointType::spherical)
        throw InputError(name_of(j) + ": cone and twist limits are a spherical joint's (not a " +
                         to_string(d.type) + " joint's)");
      const bool axial = B.cone != kInfinity || B.twist_lower != -kInfinity || B.twist_upper != kInfinity;
      if (axial && (!(d.axis_W.norm() > 1e-12) || !d.axis_W.allFinite()))
        throw InputError(name_of(j) + ": a ball joint's cone and twist need its axis (nonzero)");
      if (!(B.cone > 0) || (B.cone >= kPi && B.cone != kInfinity))
        throw InputError(name_of(j) + ": the cone's half angle must be in (0, pi) rad");
      if (!(B.angle > 0) || (B.angle >= kPi && B.angle != kInfinity))
        throw InputError(name_of(j) + ": a ball joint's largest rotation angle must be in (0, pi) rad");
      if (!(B.twist_lower <= 0 && B.twist_lower >= -kPi) && !(B.twist_lower == -kInfinity))
        throw InputError(name_of(j) + ": the twist's lower stop must be in [-pi, 0] rad");
      if (!(B.twist_upper >= 0 && B.twist_upper <= kPi) && !(B.twist_upper == kInfinity))
        throw InputError(name_of(j) + ": the twist's upper stop must be in [0, pi] rad");
      if (!(B.twist_lower < B.twist_upper))
        throw InputError(name_of(j) + ": the twist's stops must be in order (lower < upper)");
      if (!(B.restitution >= 0 && B.restitution <= 1))
        throw InputError(name_of(j) + ": limit restitution must be in [0, 1]");
    }
    if (d.armature != 0 &&
        (!(d.armature > 0) || !std::isfinite(d.armature) ||
         (d.type != JointType::revolute && d.type != JointType::prismatic && d.type != JointType::universal)))
      throw InputError(name_of(j) +
                       ": armature (rotor inertia) is a positive number on a revolute, prismatic or "
                       "universal joint");
    if (d.spring && d.type == JointType::spherical && d.spring->rest != 0)
      throw InputError(name_of(j) + ": a ball joint's spring rests at the start pose (rest 0)");
    if (d.motor && d.type != JointType::revolute && d.type != JointType::prismatic && !wheel &&
        d.type != JointType::universal && d.type != JointType::spherical)
      throw InputError(name_of(j) +
                       ": a motor needs a revolute, prismatic, universal, spherical or wheel joint (not " +
                       to_string(d.type) + ")");
    if (d.motor && d.type == JointType::spherical) {
      const JointMotor& M = *d.motor;
      if (!M.angular_velocity.allFinite() || !M.rotation.allFinite())
        throw InputError(name_of(j) + ": a ball joint motor's angular velocity and rotation must be finite");
      if (M.mode == JointMotor::Mode::position && !(M.rotation.norm() < kPi))
        throw InputError(name_of(j) +
                         ": a ball joint motor's rotation is a rotation vector under pi rad long (axis "
                         "times angle)");
    }
    if (d.motor2 && d.type != JointType::universal)
      throw InputError(name_of(j) + ": only a universal joint has a second motor (motor2)");
    for (const std::optional<JointMotor>* mo : {&d.motor, &d.motor2}) {
      if (!*mo) continue;
      const JointMotor& M = **mo;
      if (!(M.max_force > 0) || !std::isfinite(M.max_force))
        throw InputError(name_of(j) + ": a motor needs a positive, finite max force (torque)");
      if (M.mode == JointMotor::Mode::speed && !std::isfinite(M.speed))
        throw InputError(name_of(j) + ": the motor's speed must be finite");
      if (M.mode == JointMotor::Mode::position && (!std::isfinite(M.position) || !(M.speed > 0) ||
                                                   !(M.time_constant > 0) || !std::isfinite(M.time_constant)))
        throw InputError(
            name_of(j) +
            ": a position motor needs a finite position, a positive speed cap and a positive time constant");
    }
    if (d.steering) {
      const JointMotor& M = *d.steering;
      if (!wheel) throw InputError(name_of(j) + ": only a wheel joint steers");
      if (M.mode != JointMotor::Mode::position || !std::isfinite(M.position) || !(M.speed > 0) ||
          !(M.time_constant > 0) || !(M.max_force > 0) || !std::isfinite(M.max_force))
        throw InputError(
            name_of(j) +
            ": steering is a position motor: a finite angle, a positive speed cap, time constant "
            "and max torque");
    }
    if (d.friction != 0) {
      if (!one_coordinate && d.type != JointType::spherical)
        throw InputError(name_of(j) + ": a " + to_string(d.type) + " joint has no coordinate for friction");
      if (!(d.friction > 0) || !std::isfinite(d.friction))
        throw InputError(name_of(j) + ": friction must be a non-negative number");
    }
    // A joint whose child already has a parent, or whose parent descends from its child, closes
    // a loop: it becomes a constraint on the tree's coordinates instead of a tree edge.
    bool closes = parent_joint[d.child] >= 0;
    for (int x = d.parent; !closes && !fixed_base(x);
         x = parent_joint[x] >= 0 ? joints_[parent_joint[x]].parent : -1) {
      if (x == d.child) closes = true;
      if (parent_joint[x] < 0) break;
    }
    if (closes) {
      if (tree_only[j] == 1)
        throw InputError(
            name_of(j) +
            ": closes a loop but carries what only a tree joint can (a motor, friction, armature, a "
            "wheel, cone or twist stops, a mimic, or a spring or limits on a universal joint), and the "
            "tree takes such joints first: no plain joint of this loop can close it. Make one of the "
            "loop's joints plain (a spring on it, and limits on a revolute or prismatic joint, are "
            "allowed)");
      loop_joints.push_back(j);
      continue;
    }
    parent_joint[d.child] = j;
  }
  // Built in priority order above; the loops' rows and the tethers follow file order.
  std::sort(loop_joints.begin(), loop_joints.end());
  std::sort(tether_joints.begin(), tether_joints.end());
  // Children of each body, in joint order.
  std::vector<std::vector<int>> child_joints(nb);
  std::vector<int> base_joints;
  std::vector<char> is_loop(joints_.size(), 0);
  for (int j : loop_joints) is_loop[j] = 1;
  // A mimic: both coordinates one-coordinate tree joints, the leader not itself a follower.
  for (int j = 0; j < (int)joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (!d.mimic) continue;
    const int l = d.mimic->leader;
    auto one = [](const JointDef& x) {
      return x.type == JointType::revolute || x.type == JointType::prismatic;
    };
    if (!one(d))
      throw InputError(name_of(j) + ": only a revolute or prismatic joint can mimic another (not " +
                       to_string(d.type) + ")");
    if (l < 0 || l >= (int)joints_.size() || l == j)
      throw InputError(name_of(j) + ": mimics no other joint of the scene");
    if (!one(joints_[l]))
      throw InputError(name_of(j) + ": mimics " + name_of(l) +
                       ", which is not a revolute or prismatic joint");
    if (joints_[l].mimic)
      throw InputError(name_of(j) + ": mimics " + name_of(l) +
                       ", which mimics another itself (follow the first)");
    if (is_loop[j] || is_loop[l])
      throw InputError(name_of(j) + ": a mimic's joints must be tree joints; " + name_of(is_loop[j] ? j : l) +
                       " closes a loop");
    if (!std::isfinite(d.mimic->multiplier) || d.mimic->multiplier == 0)
      throw InputError(name_of(j) + ": the mimic's multiplier must be a finite, nonzero number");
    std::vector<int> leaders{l};
    for (const auto& [a, c] : d.mimic->also) {
      if (a < 0 || a >= (int)joints_.size() || a == j)
        throw InputError(name_of(j) + ": a further leader of its mimic is no other joint of the scene");
      if (std::find(leaders.begin(), leaders.end(), a) != leaders.end())
        throw InputError(name_of(j) + ": its mimic names " + name_of(a) + " twice");
      if (!one(joints_[a]))
        throw InputError(name_of(j) + ": its mimic names " + name_of(a) +
                         ", which is not a revolute or prismatic joint");
      if (joints_[a].mimic)
        throw InputError(name_of(j) + ": its mimic names " + name_of(a) + ", which mimics another itself");
      if (is_loop[a])
        throw InputError(name_of(j) + ": a mimic's joints must be tree joints; " + name_of(a) +
                         " closes a loop");
      if (!std::isfinite(c) || c == 0)
        throw InputError(name_of(j) + ": the mimic's multiplier for " + name_of(a) +
                         " must be a finite, nonzero number");
      leaders.push_back(a);
    }
    if (const auto& r = d.mimic->range; r && !(std::isfinite(r->first) && std::isfinite(r->second) &&
                                               r->first <= 0 && 0 <= r->second && r->first < r->second))
      throw InputError(name_of(j) +
                       ": the mimic's range must be two finite numbers, lower < upper, with 0 (the "
                       "start pose) between them");
  }
  // Mechanisms: bodies joined by any joint (loops included) move together; union-find over them.
  std::vector<int> group(nb);
  for (int b = 0; b < nb; ++b) group[b] = b;
  std::function<int(int)> root_of = [&](int b) { return group[b] == b ? b : group[b] = root_of(group[b]); };
  for (const JointDef& d : joints_) {
    // Every moving body a joint touches (a tether's may be either end, and its wheel) moves with
    // the others.
    int first = -1;
    for (int b : {d.parent, d.child, d.type == JointType::pulley ? d.wheel : -1}) {
      if (fixed_base(b)) continue;
      if (first < 0)
        first = b;
      else
        group[root_of(b)] = root_of(first);
    }
  }
  for (const auto& [a, b] : bonds)
    if (!fixed_base(a) && !fixed_base(b)) group[root_of(a)] = root_of(b);
  for (const JointDef& d : joints_)  // a mimic couples its joints' mechanisms
    if (d.mimic) {
      group[root_of(d.child)] = root_of(joints_[d.mimic->leader].child);
      for (const auto& [a, c] : d.mimic->also) group[root_of(d.child)] = root_of(joints_[a].child);
    }
  std::vector<int> mech_of_group(nb, -1);
  auto mechanism_for = [&](int body) {
    int& m = mech_of_group[root_of(body)];
    if (m < 0) {
      m = (int)mechanisms_.size();
      mechanisms_.emplace_back();
    }
    return m;
  };
  std::vector<char> is_tether(joints_.size(), 0);
  for (int j : tether_joints) is_tether[j] = 1;
  for (int j = 0; j < (int)joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (is_loop[j] || is_tether[j]) continue;
    if (fixed_base(d.parent))
      base_joints.push_back(j);
    else
      child_joints[d.parent].push_back(j);
  }
  joint_link_.assign(joints_.size(), {-1, -1});
  tether_of_.assign(joints_.size(), {-1, -1});
  sides_.assign(joints_.size(), Side{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  std::vector<char> done(nb, 0);

  auto P_pose = [&](int b, Quat& qWP, Vec3& xW) {
    if (b < 0 || model[b].is_static) {
      qWP = Quat::Identity();
      xW.setZero();
    } else {
      qWP = state[b].q_WP;
      xW = state[b].x_W;
    }
  };
  int building = -1;  // the mechanism add_body_link appends to
  auto add_body_link = [&](Mechanism& m, int body, int parent_link, LinkJoint kind) -> int {
    Link l;
    l.body = body;
    l.parent = parent_link;
    l.kind = kind;
    l.mass = model[body].mass;
    l.I_P = model[body].I_P;
    m.links.push_back(l);
    link_of_[body] = {building, (int)m.links.size() - 1};
    return (int)m.links.size() - 1;
  };
  // The links of joint j under parent link pl (-1: the base), then its child's subtree.
  std::function<void(Mechanism&, int, int)> add_joint = [&](Mechanism& m, int j, int pl) {
    const JointDef& d = joints_[j];
    Quat qWp, qWc;
    Vec3 xp, xc;
    P_pose(d.parent, qWp, xp);
    P_pose(d.child, qWc, xc);
    const Vec3 pp = qWp.conjugate() * (d.anchor_W - xp), pc = qWc.conjugate() * (d.anchor_W - xc);
    Side& sd = sides_[j];
    sd.p_p = d.parent >= 0 && !model[d.parent].is_static ? pp : d.anchor_W;
    sd.p_c = pc;
    sd.a_p = d.parent >= 0 && !model[d.parent].is_static ? Vec3(qWp.conjugate() * d.axis_W) : d.axis_W;
    sd.a_c = qWc.conjugate() * d.axis_W;
    const int pl_link = pl;
    auto place = [&](Link& l, bool parent_side, bool child_side) {
      if (parent_side) {
        l.q_pF = pl_link < 0 ? Quat::Identity() : qWp.conjugate();
        l.p_pF = pl_link < 0 ? d.anchor_W : pp;
      }
      if (child_side) {
        l.q_cF = qWc.conjugate();
        l.p_cF = pc;
      }
      l.R_pF = l.q_pF.toRotationMatrix();
      l.R_cF = l.q_cF.toRotationMatrix();
    };
    auto set_spring = [&](Link& l) {
      l.armature = d.armature;
      if (!d.spring) return;
      l.stiffness = d.spring->stiffness;
      l.damping = d.spring->damping;
      l.rest = d.spring->rest;
    };
    // A massless link inside a composite joint, its frame the joint frame at t = 0; its index.
    auto massless = [&](int parent, LinkJoint kind, const Vec3& axis, int dof, bool parent_side) {
      Link v;
      v.parent = parent;
      v.kind = kind;
      v.axis_F = axis;
      v.joint = j;
      v.dof = dof;
      place(v, parent_side, false);
      m.links.push_back(v);
      return (int)m.links.size() - 1;
    };
    int child_link = -1;
    switch (d.type) {
      case JointType::revolute:
      case JointType::prismatic:
      case JointType::spherical:
      case JointType::fixed: {
        const LinkJoint k = d.type == JointType::revolute    ? LinkJoint::revolute
                            : d.type == JointType::prismatic ? LinkJoint::prismatic
                            : d.type == JointType::spherical ? LinkJoint::spherical
                                                             : LinkJoint::fixed;
        child_link = add_body_link(m, d.child, pl, k);
        Link& l = m.links.back();
        l.axis_F = d.axis_W;
        l.joint = j;
        set_spring(l);
        place(l, true, true);
        joint_link_[j] = {building, child_link};
        break;
      }
      case JointType::wheel: {
        // A slider along the suspension axis and (when it steers) a hinge about it, on massless
        // links whose frames are the joint frame at t = 0; then the wheel's hinge about its axle.
        int prev = massless(pl, LinkJoint::prismatic, d.axis_W, 0, true);
        set_spring(m.links[prev]);
        joint_link_[j] = {building, prev};
        if (d.steering) prev = massless(prev, LinkJoint::revolute, d.axis_W, 1, false);
        child_link = add_body_link(m, d.child, prev, LinkJoint::revolute);
        Link& l = m.links.back();
        l.axis_F = d.axis2_W;
        l.joint = j;
        l.dof = d.steering ? 2 : 1;
        place(l, false, true);
        break;
      }
      case JointType::universal: {
        // Two hinges with a massless link between them, whose frame is the joint frame at t = 0.
        const int vl = massless(pl, LinkJoint::revolute, d.axis_W, 0, true);
        joint_link_[j] = {building, vl};
        child_link = add_body_link(m, d.child, vl, LinkJoint::revolute);
        Link& l = m.links.back();
        l.axis_F = d.axis2_W;
        l.joint = j;
        l.dof = 1;
        place(l, false, true);
        set_spring(m.links[vl]);
        set_spring(l);
        break;
      }
      case JointType::distance:
      case JointType::pulley:
        break;  // rows on the tree (build_tether), never tree edges
    }
    done[d.child] = 1;
    for (int cj : child_joints[d.child]) add_joint(m, cj, child_link);
  };
  auto finish = [&](Mechanism& m) {
    for (Link& l : m.links) {
      const Mat3& R = l.R_cF;
      const Vec3& p = l.p_cF;
      switch (l.kind) {
        case LinkJoint::revolute: {
          l.nq = l.nv = 1;
          const Vec3 a = R * l.axis_F;
          l.S.resize(6, 1);
          l.S << a, p.cross(a);
          break;
        }
        case LinkJoint::prismatic:
          l.nq = l.nv = 1;
          l.S.resize(6, 1);
          l.S << Vec3::Zero(), R * l.axis_F;
          break;
        case LinkJoint::spherical:
          l.nq = 4;
          l.nv = 3;
          l.S.resize(6, 3);
          for (int k = 0; k < 3; ++k) {
            const Vec3 a = R.col(k);
            l.S.col(k) << a, p.cross(a);
          }
          break;
        case LinkJoint::fixed:
          l.nq = l.nv = 0;
          l.S.resize(6, 0);
          break;
        case LinkJoint::free:
          l.nq = 7;
          l.nv = 6;
          l.S = Mat6::Identity();
          break;
      }
      if (l.nv == 1) l.s1 = l.S.col(0);
      l.M = spatial_inertia(l.mass, l.I_P);
      l.R0 = l.R_pF * l.R_cF.transpose();
      l.t0 = l.p_pF - l.R0 * l.p_cF;
      l.a_c = l.R_cF * l.axis_F;
      l.a_p = l.R_pF * l.axis_F;
      l.p_cF_F = l.q_cF.conjugate() * l.p_cF;
      if (l.kind == LinkJoint::revolute) {
        l.Rs = l.R0 * skew(l.a_c);
        l.Rk = l.Rs * skew(l.a_c);
        l.ts = l.Rs * l.p_cF;
        l.tk = l.Rk * l.p_cF;
        const Vec3& a = l.axis_F;
        l.qh0 = l.q_pF * l.q_cF.conjugate();
        l.qh1 = l.q_pF * Quat(0, a.x(), a.y(), a.z()) * l.q_cF.conjugate();
      }
      l.iq = m.nq;
      l.iv = m.nv;
      m.nq += l.nq;
      m.nv += l.nv;
    }
    // Limits, motors and friction: one Dof per coordinate that has any.
    for (size_t li = 0; li < m.links.size(); ++li) {
      Link& l = m.links[li];
      if (l.kind == LinkJoint::spherical && l.joint >= 0) {
        // A ball joint's motor and friction act on each of its three rates (child's axes).
        const JointDef& d = joints_[l.joint];
        if (!d.motor && !(d.friction > 0)) continue;
        l.dof_index = (int)m.dofs.size();
        for (int k = 0; k < 3; ++k) {
          Mechanism::Dof f;
          f.iq = l.iq;
          f.iv = l.iv + k;
          f.ball = k;
          f.joint = l.joint;
          if (d.motor) {
            const JointMotor& M = *d.motor;
            const bool speed = M.mode == JointMotor::Mode::speed;
            f.motor = speed ? 1 : 2;
            f.speed = speed ? M.angular_velocity[k] : M.speed;
            const double a = M.rotation.norm();
            f.target = a > 0 ? Quat(Eigen::AngleAxisd(a, M.rotation / a)) : Quat::Identity();
            f.time_constant = M.time_constant;
            f.max_force = M.max_force;
          }
          f.friction = d.friction;
          m.dofs.push_back(f);
        }
        continue;
      }
      if (l.nv != 1 || l.joint < 0) continue;
      const JointDef& d = joints_[l.joint];
      // Which of the joint's options act on this coordinate: all of them on a one-coordinate joint
      // (a universal's limits and friction on both, its motor on the first, motor2 on the
      // second); on a wheel, the stops on the suspension, the
      // steering motor on the steering hinge, the motor and friction on the axle.
      std::optional<JointLimits> limits = d.limits;
      const JointMotor* motor =
          d.type == JointType::universal && l.dof == 1 ? opt_ptr(d.motor2) : opt_ptr(d.motor);
      double friction = d.friction;
      if (d.type == JointType::wheel) {
        const bool suspension = l.dof == 0, axle = l.kind == LinkJoint::revolute && l.body >= 0;
        if (!suspension) limits.reset();
        motor = axle ? opt_ptr(d.motor) : suspension ? nullptr : opt_ptr(d.steering);
        if (!axle) friction = 0;
      }
      if (!limits && !motor && !(friction > 0)) continue;
      Mechanism::Dof f;
      f.iq = l.iq;
      f.iv = l.iv;
      f.joint = l.joint;
      if (limits) {
        f.has_lo = f.has_hi = true;
        f.lo = limits->lower;
        f.hi = limits->upper;
        f.restitution = limits->restitution;
      }
      if (motor) {
        f.motor = motor->mode == JointMotor::Mode::speed ? 1 : 2;
        f.speed = motor->speed;
        f.position = motor->position;
        f.time_constant = motor->time_constant;
        f.max_force = motor->max_force;
      }
      f.friction = friction;
      l.dof_index = (int)m.dofs.size();
      m.dofs.push_back(f);
    }
    m.q.assign(m.nq, 0);
    m.v.assign(m.nv, 0);
    for (const Link& l : m.links) {
      if (l.kind == LinkJoint::spherical) m.q[l.iq] = 1;
      if (l.kind == LinkJoint::free) {
        const MotionState& s = state[l.body];
        m.q[l.iq + 0] = s.x_W.x();
        m.q[l.iq + 1] = s.x_W.y();
        m.q[l.iq + 2] = s.x_W.z();
        m.q[l.iq + 3] = s.q_WP.w();
        m.q[l.iq + 4] = s.q_WP.x();
        m.q[l.iq + 5] = s.q_WP.y();
        m.q[l.iq + 6] = s.q_WP.z();
      }
    }
    m.allocate();
  };
  // Each mechanism's subtrees: those on a fixed base (joint order), then those rooted at a body
  // that floats freely; a mechanism holds several when loops join them.
  for (int j : base_joints) {
    building = mechanism_for(joints_[j].child);
    add_joint(mechanisms_[building], j, -1);
  }
  auto add_free_root = [&](int root) {
    building = mechanism_for(root);
    Mechanism& m = mechanisms_[building];
    const int rl = add_body_link(m, root, -1, LinkJoint::free);
    done[root] = 1;
    for (int cj : child_joints[root]) add_joint(m, cj, rl);
  };
  for (int j = 0; j < (int)joints_.size(); ++j) {
    const int root = joints_[j].parent;
    if (is_loop[j] || is_tether[j] || fixed_base(root) || parent_joint[root] >= 0 || done[root]) continue;
    add_free_root(root);
  }
  // Bodies held by tethers or bonds only float freely: each is the root of its own subtree.
  for (int j : tether_joints)
    for (int b : {joints_[j].parent, joints_[j].child})
      if (!fixed_base(b) && parent_joint[b] < 0 && !done[b]) add_free_root(b);
  for (const auto& [a, b] : bonds)
    for (int x : {a, b})
      if (!fixed_base(x) && parent_joint[x] < 0 && !done[x]) add_free_root(x);
  // A pulley's wheel turns on a revolute joint to the fixed base (checked here: the tree is known).
  for (int j : tether_joints) {
    const JointDef& d = joints_[j];
    if (d.type != JointType::pulley || d.wheel < 0) continue;
    const int wj = parent_joint[d.wheel];
    if (wj < 0 || joints_[wj].type != JointType::revolute || !fixed_base(joints_[wj].parent))
      throw InputError(name_of(j) + ": the wheel " + body_name(d.wheel) +
                       " must turn on a revolute joint to the world or a static body");
  }
  for (Mechanism& m : mechanisms_) finish(m);
  // Loop-closing joints: their anchors (and a hinge's axes) in the two links' frames.
  for (int j : loop_joints) {
    const JointDef& d = joints_[j];
    const auto [mi, lb] = link_of_[d.child];
    Mechanism& m = mechanisms_[mi];
    Mechanism::Loop L;
    L.joint = j;
    L.lb = lb;
    L.la = fixed_base(d.parent) ? -1 : link_of_[d.parent].second;
    Quat qa, qb;
    Vec3 xa, xb;
    P_pose(d.parent, qa, xa);
    P_pose(d.child, qb, xb);
    L.pa = qa.conjugate() * (d.anchor_W - xa);
    L.pb = qb.conjugate() * (d.anchor_W - xb);
    using K = Mechanism::Loop::Kind;
    L.kind = d.type == JointType::revolute    ? K::hinge
             : d.type == JointType::prismatic ? K::prismatic
             : d.type == JointType::fixed     ? K::fixed
             : d.type == JointType::universal ? K::universal
                                              : K::spherical;
    L.hinge = L.kind == K::hinge;
    const Vec3 a = qa.conjugate() * d.axis_W;
    if (L.kind == K::hinge || L.kind == K::prismatic) {
      L.t1 = a.unitOrthogonal();
      L.t2 = a.cross(L.t1);
    }
    if (L.kind == K::hinge) L.ab = qb.conjugate() * d.axis_W;
    L.aa = a;  // (its hinge, slide or first axis)
    if (L.kind == K::universal) L.ab = qb.conjugate() * d.axis2_W;
    L.R0 = (qa.conjugate() * qb).toRotationMatrix();
    L.q_a0 = qa;
    L.q_b0 = qb;
    L.axis_W0 = d.axis_W;
    if (d.spring) {
      L.stiffness = d.spring->stiffness;
      L.damping = d.spring->damping;
      L.rest = d.spring->rest;
      m.loop_springs_on = true;
    }
    L.tracked = L.kind == K::hinge && (d.spring || d.limits);
    m.loop_tracked_on = m.loop_tracked_on || L.tracked;
    m.loops.push_back(L);
    if (d.limits) {  // its stops: a slack rope on the hinge's angle (the slide) between them
      Mechanism::Tether t;
      t.joint = j;
      t.measure = L.kind == K::hinge ? Mechanism::Tether::Measure::hinge : Mechanism::Tether::Measure::slide;
      t.loop = (int)m.loops.size() - 1;
      t.has_lo = t.has_hi = true;
      t.lo = d.limits->lower;
      t.hi = d.limits->upper;
      t.restitution = d.limits->restitution;
      m.tethers.push_back(t);
      m.allocate();
    }
    m.loop_rows += L.rows();
    Side& sd = sides_[j];
    sd.p_p = L.la < 0 ? d.anchor_W : L.pa;
    sd.p_c = L.pb;
    sd.a_p = L.la < 0 ? d.axis_W : Vec3(qa.conjugate() * d.axis_W);
    sd.a_c = qb.conjugate() * d.axis_W;
    joint_link_[j] = {mi, -1 - (int)(m.loops.size() - 1)};  // negative: a loop's index
  }
  for (int j : tether_joints) build_tether(j, model, state);
  // A ball joint's stops: its swing and twist, each a slack rope between its bounds.
  for (int j = 0; j < (int)joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (!d.ball_limits) continue;
    const auto [mi, li] = joint_link_[j];
    Mechanism& m = mechanisms_[mi];
    const BallLimits& B = *d.ball_limits;
    Mechanism::Tether t;
    t.joint = j;
    if (is_loop[j])
      t.loop = -1 - li;  // joint_link_ holds a loop's index as -1 - index
    else
      t.link = li;
    t.axis = d.axis_W.norm() > 0 ? Vec3(d.axis_W.normalized())
                                 : Vec3::UnitZ();  // joint frame = world axes at t = 0
    t.restitution = B.restitution;
    if (std::isfinite(B.cone)) {
      t.measure = Mechanism::Tether::Measure::swing;
      t.has_hi = true;
      t.hi = B.cone;
      m.tethers.push_back(t);
    }
    if (std::isfinite(B.angle)) {
      t.measure = Mechanism::Tether::Measure::angle;
      t.has_hi = true;
      t.hi = B.angle;
      m.tethers.push_back(t);
    }
    if (std::isfinite(B.twist_lower) || std::isfinite(B.twist_upper)) {
      t.measure = Mechanism::Tether::Measure::twist;
      t.has_hi = std::isfinite(B.twist_upper);
      t.hi = t.has_hi ? B.twist_upper : 0.0;
      t.has_lo = std::isfinite(B.twist_lower);
      t.lo = t.has_lo ? B.twist_lower : 0.0;
      m.tethers.push_back(t);
    }
    m.allocate();
  }
  // Mimics: s = q_follower - multiplier q_leader held at 0, a rod's row; with a range, a rope slack
  // between its bounds.
  for (int j = 0; j < (int)joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (!d.mimic) continue;
    const auto [mi, li] = joint_link_[j];
    const auto [mi2, li2] = joint_link_[d.mimic->leader];
    Mechanism& m = mechanisms_[mi];
    Mechanism::Tether t;
    t.joint = j;
    t.measure = Mechanism::Tether::Measure::coupling;
    t.link = li;
    t.link2 = li2;
    t.ratio = d.mimic->multiplier;
    for (const auto& [a, c] : d.mimic->also) t.more.emplace_back(joint_link_[a].second, c);
    if (d.mimic->range) {
      t.has_lo = t.has_hi = true;
      t.lo = d.mimic->range->first;
      t.hi = d.mimic->range->second;
    } else {
      t.rod = true;
      t.has_hi = true;
      t.hi = 0;
    }
    (void)mi2;  // the same mechanism: the union above
    m.tethers.push_back(t);
    m.allocate();
  }
  // Row scratch for every mechanism: the contact rows use its mass matrix too.
  for (Mechanism& m : mechanisms_) m.allocate_loops();
  // Start velocities: the joint velocities whose body motion is closest to the given one in the
  // kinetic-energy metric (sum over links of (V - V0)^T M (V - V0)); this keeps the mechanism's
  // momentum along every joint freedom. A warning when the given motion was not a joint motion.
  for (Mechanism& m : mechanisms_) {
    const int n = (int)m.links.size();
    std::vector<Vec6> V0(n, Vec6::Zero());
    bool moving = false;
    for (int i = 0; i < n; ++i) {
      const Link& l = m.links[i];
      if (l.body < 0) continue;
      const MotionState& s = state[l.body];
      V0[i] << s.w_P, s.q_WP.conjugate() * s.v_W;
      moving = moving || !V0[i].isZero(0);
    }
    if (!moving) continue;
    Eigen::MatrixXd J(6 * n, m.nv);
    std::vector<Vec6> col;
    std::vector<double> e(m.nv, 0);
    for (int k = 0; k < m.nv; ++k) {
      std::fill(e.begin(), e.end(), 0.0);
      e[k] = 1;
      m.link_velocities(m.q.data(), e.data(), col);
      for (int i = 0; i < n; ++i) J.block<6, 1>(6 * i, k) = col[i];
    }
    Eigen::VectorXd W(6 * n), b(6 * n);
    for (int i = 0; i < n; ++i) {
      const Link& l = m.links[i];
      W.segment<3>(6 * i) = l.I_P;
      W.segment<3>(6 * i + 3).setConstant(l.mass);
      b.segment<6>(6 * i) = V0[i];
    }
    const Eigen::MatrixXd A = J.transpose() * W.asDiagonal() * J;
    const Eigen::VectorXd qd = A.ldlt().solve(J.transpose() * (W.asDiagonal() * b));
    for (int k = 0; k < m.nv; ++k) m.v[k] = qd[k];
    if (m.projected()) m.project_velocities(m.q.data(), m.v.data());
    const Eigen::VectorXd r = J * Eigen::Map<const Eigen::VectorXd>(m.v.data(), m.nv) - b;
    const double e_given = 0.5 * b.dot(W.asDiagonal() * b), e_lost = 0.5 * r.dot(W.asDiagonal() * r);
    if (e_lost > 1e-12 * std::max(e_given, 1e-300)) {
      std::ostringstream os;
      os << "joints: the start velocities of " << body_names(m, defs)
         << " are not all motions their joints allow; they were projected onto the joints' freedoms ("
         << e_lost << " J of " << e_given << " J of kinetic energy removed)";
      warnings.push_back(os.str());
    }
  }
  if (settings.integrator == JointIntegrator::verlet)
    for (const Mechanism& m : mechanisms_) {
      if (m.verlet_ok()) continue;
      std::ostringstream os;
      os << "joints: the mechanism of " << body_names(m, defs) << " has "
         << (!m.loops.empty()     ? "a closed loop"
             : !m.tethers.empty() ? "a rod or rope"
             : !m.dofs.empty()    ? "limits, a motor or friction"
             : m.loop_springs_on  ? "a loop spring"
                                  : "a ball or free joint")
         << ", which verlet does not take: it is integrated by dopri5";
      warnings.push_back(os.str());
    }
  for (Mechanism& m : mechanisms_) m.write_bodies(state.data());
}

void Articulations::validate_tether(JointDef& d, const std::vector<BodyDef>& defs,
                                    const std::vector<BodyModel>& model) const {
  const std::string name = "joint '" + d.name + "'";
  auto fixed_base = [&](int b) { return b < 0 || model[b].is_static; };
  const bool pulley = d.type == JointType::pulley;
  if (d.limits || d.motor || d.motor2 || d.friction != 0 || d.steering)
    throw InputError(name + ": a " + to_string(d.type) +
                     " joint takes no limits, motor, friction or steering (a rope's bounds are "
                     "min_length and max_length)");
  if (!all_finite(d.anchor_W) || !all_finite(d.anchor2_W))
    throw InputError(name + ": anchors must be finite");
  if (!(d.restitution >= 0 && d.restitution <= 1)) throw InputError(name + ": restitution must be in [0, 1]");
  if (!pulley) {
    const double L = (d.anchor2_W - d.anchor_W).norm();
    if (!(L > 1e-9))
      throw InputError(name +
                       ": the anchors coincide; a distance joint needs two distinct points (a ball joint is "
                       "'spherical')");
    if (d.min_length && (!std::isfinite(*d.min_length) || *d.min_length < 0 || *d.min_length > L + 1e-9))
      throw InputError(name + ": min_length must be in [0, the anchors' start distance " + std::to_string(L) +
                       " m]");
    if (d.max_length && (!std::isfinite(*d.max_length) || *d.max_length < L - 1e-9))
      throw InputError(name + ": max_length must be at least the anchors' start distance (" +
                       std::to_string(L) + " m)");
    if (d.min_length && d.max_length && !(*d.min_length < *d.max_length))
      throw InputError(name + ": min_length must be less than max_length");
    if (d.spring && (!std::isfinite(d.spring->stiffness) || !std::isfinite(d.spring->damping) ||
                     !std::isfinite(d.spring->rest) || d.spring->stiffness < 0 || d.spring->damping < 0 ||
                     d.spring->rest < 0))
      throw InputError(name + ": spring stiffness, damping and rest length must be non-negative numbers");
    return;
  }
  if (d.spring) throw InputError(name + ": a pulley carries no spring");
  if (d.min_length || d.max_length)
    throw InputError(name +
                     ": a pulley's rope keeps its start length; min_length and max_length are a distance "
                     "joint's");
  for (const Vec3& p : d.pulley_anchor_W)
    if (!all_finite(p)) throw InputError(name + ": pulley anchors must be finite");
  if (!((d.anchor_W - d.pulley_anchor_W[0]).norm() > 1e-9) ||
      !((d.anchor2_W - d.pulley_anchor_W[1]).norm() > 1e-9))
    throw InputError(name + ": each rope end must start away from its pulley anchor");
  if (!(d.ratio > 0) || !std::isfinite(d.ratio)) throw InputError(name + ": ratio must be a positive number");
  if (d.wheel >= 0) {
    if (d.wheel >= (int)defs.size()) throw InputError(name + ": wheel body index out of range");
    if (fixed_base(d.wheel) || model[d.wheel].is_kinematic)
      throw InputError(name + ": the wheel '" + defs[d.wheel].name + "' must be a dynamic body");
    if (d.wheel == d.parent || d.wheel == d.child)
      throw InputError(name + ": the wheel '" + defs[d.wheel].name + "' cannot also hang on the rope");
    if (d.ratio != 1) throw InputError(name + ": a rope over a wheel has ratio 1");
  }
}

void Articulations::build_tether(int j, const std::vector<BodyModel>& model,
                                 const std::vector<MotionState>& state) {
  const JointDef& d = joints_[j];
  auto moving = [&](int b) { return b >= 0 && !model[b].is_static; };
  const int mi = link_of_[moving(d.parent) ? d.parent : moving(d.child) ? d.child : d.wheel].first;
  Mechanism& m = mechanisms_[mi];
  // A body's point in its link's frame (its principal frame), or the world point for the base.
  auto end = [&](int b, const Vec3& p_W, int& link, Vec3& p) {
    if (!moving(b)) {
      link = -1;
      p = p_W;
      return;
    }
    link = link_of_[b].second;
    p = state[b].q_WP.conjugate() * (p_W - state[b].x_W);
  };
  std::vector<Mechanism::Tether> out;
  if (d.type == JointType::distance) {
    Mechanism::Tether t;
    end(d.parent, d.anchor_W, t.la[0], t.pa[0]);
    end(d.child, d.anchor2_W, t.lb[0], t.pb[0]);
    t.restitution = d.restitution;
    if (d.spring) {
      t.stiffness = d.spring->stiffness;
      t.damping = d.spring->damping;
      t.rest = d.spring->rest;
    }
    t.has_lo = d.min_length && *d.min_length > 0;
    t.lo = t.has_lo ? *d.min_length : 0.0;
    t.has_hi = d.max_length.has_value() || (!d.min_length && !d.spring);
    t.rod = !d.min_length && !d.max_length && !d.spring;
    out.push_back(t);
  } else if (d.wheel < 0) {
    Mechanism::Tether t;
    t.nseg = 2;
    t.la[0] = t.la[1] = -1;
    t.pa[0] = d.pulley_anchor_W[0];
    t.pa[1] = d.pulley_anchor_W[1];
    end(d.parent, d.anchor_W, t.lb[0], t.pb[0]);
    end(d.child, d.anchor2_W, t.lb[1], t.pb[1]);
    t.w[1] = d.ratio;
    t.has_hi = true;
    t.restitution = d.restitution;
    out.push_back(t);
  } else {
    // Over a wheel: each run is its own rope, wound on the wheel without slipping. The run leaving
    // the rim at g pays out at the rim's speed along it: L_k' = (a x (g - c)) . n_k theta', so
    // L_k - k_k theta keeps its start value, k_k the run's signed lever arm.
    const Link& wl = m.links[link_of_[d.wheel].second];
    const JointDef& wd = joints_[wl.joint];
    const Vec3 a = wl.R_pF * wl.axis_F, c = wd.anchor_W;
    for (int k = 0; k < 2; ++k) {
      Mechanism::Tether t;
      const int b = k == 0 ? d.parent : d.child;
      const Vec3 g = d.pulley_anchor_W[k], p = k == 0 ? d.anchor_W : d.anchor2_W;
      t.la[0] = -1;
      t.pa[0] = g;
      end(b, p, t.lb[0], t.pb[0]);
      const double lever = a.cross(g - c).dot((p - g).normalized());
      if (!(std::abs(lever) > 1e-9))
        throw InputError("joint '" + d.name + "': the rope's run from pulley anchor " + std::to_string(k) +
                         " does not turn the wheel (it leaves the rim along the axis or through the centre)");
      t.wheel_iq = wl.iq;
      t.wheel_iv = wl.iv;
      t.wheel_c = -lever;
      t.wheel_link = link_of_[d.wheel].second;
      t.wheel_point[0] = g;
      t.has_hi = true;
      t.restitution = d.restitution;
      out.push_back(t);
    }
  }
  tether_of_[j] = {mi, (int)m.tethers.size()};
  joint_link_[j] = {mi, std::numeric_limits<int>::min()};
  for (Mechanism::Tether& t : out) {
    t.joint = j;
    m.tethers.push_back(t);
    const double s = m.measure_tether((int)m.tethers.size() - 1);
    Mechanism::Tether& mt = m.tethers.back();
    if (mt.rod || (mt.has_hi && !d.max_length)) mt.hi = s;  // a rod's length, a rope's default bound
    if (mt.has_hi && d.max_length) mt.hi = std::max(*d.max_length, s);
  }
  m.allocate();  // event slots and impulse targets for the tethers
}

int Articulations::find(std::string_view name) const {
  for (int j = 0; j < (int)joints_.size(); ++j)
    if (joints_[j].name == name) return j;
  return -1;
}

bool Articulations::step_range(int begin, int end, double dt, const Vec3& g, const Wrench* wr,
                               MotionState* st) {
  bool ok = true;
  for (int k = begin; k < end; ++k) {
    Mechanism& m = mechanisms_[k];
    // The frame's end is the next frame's start (the World sets it each step anyway): a step
    // running past the frame is read on only in the frame that follows it (Mechanism::Span).
    struct Next {
      Mechanism& m;
      double dt;
      ~Next() { m.frame_time += dt; }
    } next{m, dt};
    if (m.asleep) continue;   // its bodies keep their poses, at rest
    if (m.contact_stepped) {  // the contact solver took this step (sim/joints/contact_rows.hpp)
      m.contact_stepped = false;
      bool finite = true;
      for (double x : m.q) finite = finite && std::isfinite(x);
      for (double x : m.v) finite = finite && std::isfinite(x);
      ok = finite && ok;
      continue;
    }
    ok = m.advance(dt, g, wr, st, settings_) && ok;
    m.write_bodies(st);
  }
  return ok;
}

void Articulations::add_loads(const std::vector<ForceDef>& forces, const std::vector<int>& which,
                              const std::vector<BodyDef>& defs, const std::vector<BodyModel>& model,
                              const std::vector<MotionState>& state) {
  for (int k : which) {
    const ForceDef& f = forces[k];
    Mechanism::Load L;
    L.f = f;
    const int a = f.body, b = f.kind == ForceKind::spring ? f.body_b : -1;
    if (!jointed(a))
      throw InputError("force " + std::to_string(k) + ": a spring from '" + defs[a].name +
                       "' to jointed body '" + defs[b].name +
                       "' is not supported yet (write it from the jointed body)");
    const auto [mi, la] = link_of_[a];
    L.link = la;
    L.f.body = 0;
    L.model[0] = model[a];
    if (b >= 0) {
      L.f.body_b = 1;
      L.model[1] = model[b];
      if (jointed(b)) {
        if (link_of_[b].first != mi)
          throw InputError("force " + std::to_string(k) + ": a spring between '" + defs[a].name + "' and '" +
                           defs[b].name + "', jointed in different mechanisms, is not supported yet");
        L.link_b = link_of_[b].second;
      } else if (model[b].is_static) {
        L.state_b = state[b];
      } else {
        throw InputError("force " + std::to_string(k) + ": a spring between jointed body '" + defs[a].name +
                         "' and '" + defs[b].name + "', which moves freely, is not supported yet");
      }
    }
    mechanisms_[mi].loads.push_back(L);
  }
}

void Articulations::apply_impulse(int body, const Vec3& P, const Vec3& at_W, const Vec3& L, MotionState* st) {
  const auto [mi, li] = link_of_[body];
  Mechanism& m = mechanisms_[mi];
  m.apply_impulse(li, at_W - st[body].x_W, P, L);
  m.write_bodies(st);
}

const Link& Articulations::coordinate_link(int j, int k, const Mechanism*& m) const {
  const auto [mi, li] = joint_link_[j];
  m = &mechanisms_[mi];
  const JointType t = joints_[j].type;
  return m->links[li + (t == JointType::universal || t == JointType::wheel ? k : 0)];
}

double Articulations::position(int j, int k) const {
  if (tether_of_[j].first >= 0) {
    // A distance joint's length; a pulley's run k (over a wheel: each run is its own tether).
    const auto [mi, t] = tether_of_[j];
    const Mechanism& m = mechanisms_[mi];
    if (joints_[j].type == JointType::distance) return m.tether_length(t);
    return m.tethers[t].nseg == 2 ? m.tether_length(t, k) : m.tether_length(t + k, 0);
  }
  if (joint_link_[j].second < 0)
    return mechanisms_[joint_link_[j].first].loop_angle(-1 - joint_link_[j].second);
  const Mechanism* m;
  const Link& l = coordinate_link(j, k, m);
  const double* q = m->q.data() + l.iq;
  switch (l.kind) {
    case LinkJoint::revolute:
    case LinkJoint::prismatic:
      return q[0];
    case LinkJoint::spherical:
      return 2 * std::atan2(Vec3(q[1], q[2], q[3]).norm(), std::abs(q[0]));
    case LinkJoint::fixed:
    case LinkJoint::free:
      break;
  }
  return 0;
}

double Articulations::speed(int j, int k) const {
  if (tether_of_[j].first >= 0) {
    const auto [mi, t] = tether_of_[j];
    const Mechanism& m = mechanisms_[mi];
    double r = 0;
    if (joints_[j].type == JointType::distance)
      m.tether_length(t, -1, &r);
    else if (m.tethers[t].nseg == 2)
      m.tether_length(t, k, &r);
    else
      m.tether_length(t + k, 0, &r);
    return r;
  }
  if (joint_link_[j].second < 0)
    return mechanisms_[joint_link_[j].first].loop_speed(-1 - joint_link_[j].second);
  const Mechanism* m;
  const Link& l = coordinate_link(j, k, m);
  const double* v = m->v.data() + l.iv;
  switch (l.kind) {
    case LinkJoint::revolute:
    case LinkJoint::prismatic:
      return v[0];
    case LinkJoint::spherical:
      return Vec3(v[0], v[1], v[2]).norm();
    case LinkJoint::fixed:
    case LinkJoint::free:
      break;
  }
  return 0;
}

double Articulations::force(int j, int k) const {
  if (tether_of_[j].first >= 0) {  // the row's force along the rope or rod (< 0 pulls), N
    const auto [mi, t] = tether_of_[j];
    const Mechanism& m = mechanisms_[mi];
    return m.tethers[m.tethers[t].nseg == 2 || joints_[j].type == JointType::distance ? t : t + k].lambda;
  }
  if (joint_link_[j].second < 0) return 0;
  const Mechanism* m;
  const Link& l = coordinate_link(j, k, m);
  if (l.dof_index < 0) return 0.0;
  // A ball joint's three: the torque of its motor and friction about the child's axis k.
  return m->dofs[l.dof_index + (l.kind == LinkJoint::spherical ? std::clamp(k, 0, 2) : 0)].force;
}

void Articulations::reaction(int j, const MotionState* st, const Vec3& g, Vec3& force_W,
                             Vec3& torque_W) const {
  if (tether_of_[j].first >= 0) {
    // The rope's pull on the child's end (the last run's), along the run, at the anchor; no torque.
    const auto [mi, t0] = tether_of_[j];
    Mechanism& m = const_cast<Mechanism&>(mechanisms_[mi]);  // scratch only
    Vec3 F, T;
    m.joint_wrench(0, g, F, T);  // evaluates the multipliers at q, v
    const int t = joints_[j].type == JointType::pulley && m.tethers[t0].nseg == 1 ? t0 + 1 : t0;
    const Mechanism::Tether& th = m.tethers[t];
    const int seg = th.nseg - 1;
    auto point = [&](int l, const Vec3& p) {
      if (l < 0) return p;
      const int b = m.links[l].body;
      return Vec3(st[b].x_W + st[b].q_WP * p);
    };
    const Vec3 d = point(th.lb[seg], th.pb[seg]) - point(th.la[seg], th.pa[seg]);
    const double f = th.lambda + m.tether_spring_force(th);
    force_W = d.norm() > 1e-12 ? Vec3((f * th.w[seg] / d.norm()) * d) : Vec3::Zero();
    torque_W.setZero();
    return;
  }
  const auto [mi, li] = joint_link_[j];
  Mechanism& m = const_cast<Mechanism&>(mechanisms_[mi]);  // scratch only; q and v are not changed
  Vec3 T;
  m.joint_wrench(li, g, force_W, T);
  if (li < 0) {  // a loop's force acts at its anchor
    torque_W = T;
    return;
  }
  // About the anchor: the child's anchor point now (the joint's two anchors coincide).
  const JointDef& d = joints_[j];
  const Vec3 anchor = st[d.child].x_W + st[d.child].q_WP * sides_[j].p_c;
  torque_W = T + (m.link_x(li) - anchor).cross(force_W);
}

double Articulations::spring_energy() const {
  double e = 0;
  for (const Mechanism& m : mechanisms_) {
    for (const Link& l : m.links) {
      if (l.stiffness != 0 && l.nq == 1) {
        const double x = m.q[l.iq] - l.rest;
        e += 0.5 * l.stiffness * x * x;
      }
      if (l.stiffness != 0 && l.kind == LinkJoint::spherical)
        e += 0.5 * l.stiffness * Mechanism::ball_rotation_vector(l, m.q.data()).squaredNorm();
    }
    for (int k = 0; k < (int)m.loops.size(); ++k)
      if (m.loops[k].stiffness != 0) {
        const double x = m.loop_angle(k) - m.loops[k].rest;
        e += 0.5 * m.loops[k].stiffness * x * x;
      }
    for (int t = 0; t < (int)m.tethers.size(); ++t)
      if (m.tethers[t].stiffness != 0) {
        const double x = m.tether_length(t) - m.tethers[t].rest;
        e += 0.5 * m.tethers[t].stiffness * x * x;
      }
  }
  return e;
}

double Articulations::armature_energy() const {
  double e = 0;
  for (const Mechanism& m : mechanisms_)
    for (const Link& l : m.links)
      if (l.armature != 0 && l.nv == 1) e += 0.5 * l.armature * m.v[l.iv] * m.v[l.iv];
  return e;
}

double Articulations::gap(const MotionState* st) const {
  double worst = 0;
  for (size_t j = 0; j < joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (tether_of_[j].first >= 0) {  // the length a rod or a taut rope keeps (from the mechanism's poses)
      const Mechanism& m = mechanisms_[tether_of_[j].first];
      for (int t = tether_of_[j].second; t < (int)m.tethers.size() && m.tethers[t].joint == (int)j; ++t)
        worst = std::max(worst, m.tether_gap(t));
      continue;
    }
    const Side& s = sides_[j];
    const bool moving_parent = d.parent >= 0 && jointed(d.parent);
    const Vec3 ap = moving_parent ? Vec3(st[d.parent].x_W + st[d.parent].q_WP * s.p_p) : s.p_p;
    const Vec3 ac = st[d.child].x_W + st[d.child].q_WP * s.p_c;
    if (d.type == JointType::prismatic || d.type == JointType::wheel) {
      // The slider's (suspension's) child anchor may move along the axis only.
      const Vec3 axis = moving_parent ? Vec3(st[d.parent].q_WP * s.a_p) : s.a_p;
      const Vec3 r = ac - ap;
      worst = std::max(worst, (r - axis * axis.dot(r)).norm());
    } else {
      worst = std::max(worst, (ac - ap).norm());
    }
    if (d.mimic && d.type == JointType::prismatic) worst = std::max(worst, coupling_gap((int)j));
  }
  return worst;
}

double Articulations::coupling_gap(int j) const {
  // A mimic's residual q - multiplier q_leader, in the follower's unit (rad or m).
  const Mechanism& m = mechanisms_[joint_link_[j].first];
  double worst = 0;
  for (int t = 0; t < (int)m.tethers.size(); ++t)
    if (m.tethers[t].joint == j && m.tethers[t].measure == Mechanism::Tether::Measure::coupling)
      worst = std::max(worst, m.tether_gap(t));
  return worst;
}

double Articulations::angular_gap(const MotionState* st) const {
  double worst = 0;
  for (size_t j = 0; j < joints_.size(); ++j) {
    const JointDef& d = joints_[j];
    if (d.ball_limits) {  // how far a ball joint's swing or twist is past its stop
      const Mechanism& m = mechanisms_[joint_link_[j].first];
      for (int t = 0; t < (int)m.tethers.size(); ++t)
        if (m.tethers[t].joint == (int)j) worst = std::max(worst, m.tether_gap(t));
      continue;
    }
    if (d.type != JointType::revolute && d.type != JointType::prismatic) continue;
    if (d.mimic && d.type == JointType::revolute) worst = std::max(worst, coupling_gap((int)j));
    const Side& s = sides_[j];
    const bool moving_parent = d.parent >= 0 && jointed(d.parent);
    const Vec3 a = moving_parent ? Vec3(st[d.parent].q_WP * s.a_p) : s.a_p;
    const Vec3 b = st[d.child].q_WP * s.a_c;
    worst = std::max(worst, std::atan2(a.cross(b).norm(), a.dot(b)));
  }
  return worst;
}

int Articulations::exceeded_joint() const {
  for (size_t mi = 0; mi < mechanisms_.size(); ++mi) {
    if (!mechanisms_[mi].exceeded) continue;
    for (size_t j = 0; j < joint_link_.size(); ++j)
      if (joint_link_[j].first == (int)mi) return (int)j;
  }
  return -1;
}

long Articulations::internal_steps() const {
  long n = 0;
  for (const Mechanism& m : mechanisms_) n += m.steps_taken;
  return n;
}

}  // namespace simreel
