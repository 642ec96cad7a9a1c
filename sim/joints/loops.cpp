// Closed loops on a mechanism's tree coordinates (articulation.hpp, Mechanism::Loop).
//
// The tree's equations M q'' = tau - C gain constraint forces G^T lambda, with G the rows'
// Jacobian: the accelerations that keep the rows, G q'' + G' q' = 0, are
//   q'' = q''_0 + M^-1 G^T lambda,   (G M^-1 G^T) lambda = -(G q''_0 + G' q')
// where q''_0 is the tree's own (ABA) and G q''_0 + G' q' is read directly as the rows'
// acceleration under q''_0 (the anchors' classical accelerations): no derivative of G is formed.
// The rows' matrix G M^-1 G^T is solved with a diagonal shift of 1e-12 of its largest entry, so
// redundant rows (a planar loop's out-of-plane rows: zero rows of G) are harmless: their
// multipliers meet only zero columns of M^-1 G^T. The index-1 form lets round-off and the integrator's
// error drift off the rows, so after every internal step positions are Newton-projected back and
// velocities projected in the mass metric (Hairer, Lubich & Roche, "The Numerical Solution of
// Differential-Algebraic Systems by Runge-Kutta Methods", 1989, ch. 7).
#include "sim/joints/articulation.hpp"

#include "sim/dynamics/forces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace simreel {

namespace {
// A body point's velocity and classical acceleration, world frame, from the link's spatial
// velocity V = [w; v0] and acceleration A = [alpha; a0] (link frame, at its origin):
// v = v0 + w x p,  a = a0 + alpha x p + w x v  (Featherstone 2.11: classical = spatial + w x v).
inline Vec3 point_velocity(const Vec6& V, const Vec3& p) {
  return V.tail<3>() + V.head<3>().cross(p);
}
inline Vec3 point_acceleration(const Vec6& V, const Vec6& A, const Vec3& p) {
  return A.tail<3>() + A.head<3>().cross(p) + V.head<3>().cross(point_velocity(V, p));
}
}  // namespace

void Mechanism::allocate_loops() {
  const int nr = loop_rows + (int)dofs.size() + (int)tethers.size();
  M_.setZero(nv, nv);
  G_.setZero(nr, nv);
  Y_.setZero(nv, nr);
  A_.setZero(nr, nr);
  rows_.setZero(nr);
  lambda_.setZero(nr);
  dv_.setZero(nv);
  rhs_.setZero(nr);
  V_.assign(links.size(), Vec6::Zero());
  Acc_.assign(links.size(), Vec6::Zero());
}

namespace {
// vee((R - R^T) / 2): the rotation vector of a small rotation R (sin(angle) times its axis).
inline Vec3 small_rotation(const Mat3& R) {
  return 0.5 * Vec3(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
}
}  // namespace

void Mechanism::loop_position_rows(double* out) const {
  using K = Loop::Kind;
  int r = 0;
  for (const Loop& L : loops) {
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Vec3 xa = L.la < 0 ? Vec3::Zero() : work_[L.la].x_W;
    const Work& b = work_[L.lb];
    const Vec3 gap = (b.x_W + b.R_W * L.pb) - (xa + Ra * L.pa);
    if (L.kind == K::prismatic) {  // only across the axis: the anchors slide along it
      out[r++] = (Ra * L.t1).dot(gap);
      out[r++] = (Ra * L.t2).dot(gap);
    } else {
      out[r++] = gap.x();
      out[r++] = gap.y();
      out[r++] = gap.z();
    }
    switch (L.kind) {
      case K::spherical:
        break;
      case K::hinge: {
        // Rows whose rates are t1 . (w_b - w_a) and t2 . (w_b - w_a) at zero (velocity rows below):
        // d/dt (t . a_b) = (w_b - w_a) . (a x t), and a x t1 = t2, a x t2 = -t1.
        const Vec3 a_b = b.R_W * L.ab, t1 = Ra * L.t1, t2 = Ra * L.t2;
        out[r++] = -t2.dot(a_b);
        out[r++] = t1.dot(a_b);
        break;
      }
      case K::prismatic:
      case K::fixed: {
        // b's rotation relative to a's since the start, as a small rotation in a's axes: its rate
        // is R_a^T (w_b - w_a) at zero.
        const Vec3 e = small_rotation(Ra.transpose() * b.R_W * L.R0.transpose());
        out[r++] = e.x();
        out[r++] = e.y();
        out[r++] = e.z();
        break;
      }
      case K::universal:  // the two axes stay perpendicular
        out[r++] = (Ra * L.aa).dot(b.R_W * L.ab);
        break;
    }
  }
}

void Mechanism::loop_velocity_rows(const std::vector<Vec6>& V, double* out) const {
  using K = Loop::Kind;
  int r = 0;
  for (const Loop& L : loops) {
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Vec3 va = L.la < 0 ? Vec3::Zero() : Vec3(Ra * point_velocity(V[L.la], L.pa));
    const Vec3 vb = work_[L.lb].R_W * point_velocity(V[L.lb], L.pb);
    const Vec3 dv = vb - va;
    const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * V[L.la].head<3>());
    const Vec3 dw = work_[L.lb].R_W * V[L.lb].head<3>() - wa;
    if (L.kind == K::prismatic) {
      // d/dt (t . g) with t turning with a: t . g' + (w_a x t) . g (g runs along the axis).
      const Vec3 xa = L.la < 0 ? Vec3::Zero() : work_[L.la].x_W;
      const Vec3 gap = (work_[L.lb].x_W + work_[L.lb].R_W * L.pb) - (xa + Ra * L.pa);
      for (const Vec3& tl : {L.t1, L.t2}) {
        const Vec3 t = Ra * tl;
        out[r++] = t.dot(dv) + wa.cross(t).dot(gap);
      }
    } else {
      out[r++] = dv.x();
      out[r++] = dv.y();
      out[r++] = dv.z();
    }
    switch (L.kind) {
      case K::spherical:
        break;
      case K::hinge:
        out[r++] = (Ra * L.t1).dot(dw);
        out[r++] = (Ra * L.t2).dot(dw);
        break;
      case K::prismatic:
      case K::fixed: {
        const Vec3 e = Ra.transpose() * dw;
        out[r++] = e.x();
        out[r++] = e.y();
        out[r++] = e.z();
        break;
      }
      case K::universal: {
        // d/dt (A . B) = (B x A) . (w_b - w_a), A = axis fixed in a, B = axis2 fixed in b.
        const Vec3 A = Ra * L.aa, B = work_[L.lb].R_W * L.ab;
        out[r++] = B.cross(A).dot(dw);
        break;
      }
    }
  }
}

void Mechanism::loop_acceleration_rows(const std::vector<Vec6>& V, const std::vector<Vec6>& A,
                                       double* out) const {
  using K = Loop::Kind;
  int r = 0;
  for (const Loop& L : loops) {
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Mat3& Rb = work_[L.lb].R_W;
    const Vec3 aa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * point_acceleration(V[L.la], A[L.la], L.pa));
    const Vec3 ab = Rb * point_acceleration(V[L.lb], A[L.lb], L.pb);
    const Vec3 da = ab - aa;
    const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * V[L.la].head<3>());
    const Vec3 ala = L.la < 0 ? Vec3::Zero() : Vec3(Ra * A[L.la].head<3>());
    const Vec3 wb = Rb * V[L.lb].head<3>();
    const Vec3 dw = wb - wa;
    const Vec3 dal = Rb * A[L.lb].head<3>() - ala;
    if (L.kind == K::prismatic) {
      // d2/dt2 (t . g) = t . g'' + 2 (w_a x t) . g' + (al_a x t + w_a x (w_a x t)) . g.
      const Vec3 xa = L.la < 0 ? Vec3::Zero() : work_[L.la].x_W;
      const Vec3 gap = (work_[L.lb].x_W + Rb * L.pb) - (xa + Ra * L.pa);
      const Vec3 va = L.la < 0 ? Vec3::Zero() : Vec3(Ra * point_velocity(V[L.la], L.pa));
      const Vec3 dv = Rb * point_velocity(V[L.lb], L.pb) - va;
      for (const Vec3& tl : {L.t1, L.t2}) {
        const Vec3 t = Ra * tl, wt = wa.cross(t);
        out[r++] = t.dot(da) + 2 * wt.dot(dv) + (ala.cross(t) + wa.cross(wt)).dot(gap);
      }
    } else {
      out[r++] = da.x();
      out[r++] = da.y();
      out[r++] = da.z();
    }
    // d/dt [t . (w_b - w_a)] with t turning with a: t . (al_b - al_a) + (w_a x t) . (w_b - w_a).
    auto turning_with_a = [&](const Vec3& t) { return t.dot(dal) + wa.cross(t).dot(dw); };
    switch (L.kind) {
      case K::spherical:
        break;
      case K::hinge:
        out[r++] = turning_with_a(Ra * L.t1);
        out[r++] = turning_with_a(Ra * L.t2);
        break;
      case K::prismatic:
      case K::fixed:
        for (int k = 0; k < 3; ++k) out[r++] = turning_with_a(Ra.col(k));
        break;
      case K::universal: {
        // d/dt [(B x A) . dw] = (B x A) . dal + ((w_b x B) x A + B x (w_a x A)) . dw.
        const Vec3 Aw = Ra * L.aa, B = Rb * L.ab;
        out[r++] = B.cross(Aw).dot(dal) + (wb.cross(B).cross(Aw) + B.cross(wa.cross(Aw))).dot(dw);
        break;
      }
    }
  }
}

// A one-coordinate link's rate and acceleration (a mimic's coupling row reads them): the joint's
// relative motion V_i - X_i V_p = s q', and A_i - X_i A_p = s q'' + V_i x s q' (Featherstone 7.1).
double Mechanism::coordinate_rate(int i, const std::vector<Vec6>& V) const {
  const Link& l = links[i];
  Vec6 d = V[i];
  if (l.parent >= 0) d -= transform_motion(work_[i].E, work_[i].r, V[l.parent]);
  return l.s1.dot(d) / l.s1.squaredNorm();
}

double Mechanism::coordinate_acceleration(int i, const std::vector<Vec6>& V,
                                          const std::vector<Vec6>& A) const {
  const Link& l = links[i];
  Vec6 d = A[i] - cross_motion(V[i], l.s1 * coordinate_rate(i, V));
  if (l.parent >= 0) d -= transform_motion(work_[i].E, work_[i].r, A[l.parent]);
  return l.s1.dot(d) / l.s1.squaredNorm();
}

// A tether's length s = sum_k w_k |d_k| (+ c theta), d_k = x_b - x_a. Its rates are the
// projections of the ends' relative motion on n_k = d_k / |d_k|:
//   s'  = sum w_k n_k . d_k'
//   s'' = sum w_k [n_k . d_k'' + (|d_k'|^2 - (n_k . d_k')^2) / |d_k|]
// (the second term: n_k turns as the segment swings). A segment shorter than 1e-12 m has no
// direction and adds nothing.
double Mechanism::tether_position(const Tether& t, const double* q) const {
  if (t.measure == Tether::Measure::coupling) {
    double s = q[links[t.link].iq] - t.ratio * q[links[t.link2].iq];
    for (const auto& [l, r] : t.more) s -= r * q[links[l].iq];
    return s;
  }
  if (t.measure == Tether::Measure::hinge) return hinge_angle(loops[t.loop]);
  if (t.measure == Tether::Measure::slide) return slide_position(loops[t.loop]);
  if (t.measure != Tether::Measure::length) return ball_angle(t);
  double s = 0;
  for (int k = 0; k < t.nseg; ++k)
    s += t.w[k] * (point_W(t.lb[k], t.pb[k]) - point_W(t.la[k], t.pa[k])).norm();
  if (t.wheel_iq >= 0) s += t.wheel_c * q[t.wheel_iq];
  return s;
}

double Mechanism::tether_rate(const Tether& t, const std::vector<Vec6>& V, double wheel_rate) const {
  if (t.measure == Tether::Measure::coupling) {
    double r = coordinate_rate(t.link, V) - t.ratio * coordinate_rate(t.link2, V);
    for (const auto& [l, c] : t.more) r -= c * coordinate_rate(l, V);
    return r;
  }
  if (t.measure == Tether::Measure::hinge) return hinge_rate(loops[t.loop], V);
  if (t.measure == Tether::Measure::slide) return slide_rate(loops[t.loop], V);
  if (t.measure != Tether::Measure::length) return ball_rate(t, V);
  double r = t.wheel_iv >= 0 ? t.wheel_c * wheel_rate : 0.0;
  for (int k = 0; k < t.nseg; ++k) {
    const Vec3 d = point_W(t.lb[k], t.pb[k]) - point_W(t.la[k], t.pa[k]);
    const double L = d.norm();
    if (L < 1e-12) continue;
    const Vec3 vb =
        t.lb[k] < 0 ? Vec3::Zero() : Vec3(work_[t.lb[k]].R_W * point_velocity(V[t.lb[k]], t.pb[k]));
    const Vec3 va =
        t.la[k] < 0 ? Vec3::Zero() : Vec3(work_[t.la[k]].R_W * point_velocity(V[t.la[k]], t.pa[k]));
    r += t.w[k] * d.dot(vb - va) / L;
  }
  return r;
}

double Mechanism::tether_acceleration(const Tether& t, const std::vector<Vec6>& V, const std::vector<Vec6>& A,
                                      double wheel_acc) const {
  if (t.measure == Tether::Measure::coupling) {
    double a = coordinate_acceleration(t.link, V, A) - t.ratio * coordinate_acceleration(t.link2, V, A);
    for (const auto& [l, c] : t.more) a -= c * coordinate_acceleration(l, V, A);
    return a;
  }
  if (t.measure == Tether::Measure::hinge) return hinge_acceleration(loops[t.loop], V, A);
  if (t.measure == Tether::Measure::slide) return slide_acceleration(loops[t.loop], V, A);
  if (t.measure != Tether::Measure::length) return ball_acceleration(t, V, A);
  double r = t.wheel_iv >= 0 ? t.wheel_c * wheel_acc : 0.0;
  for (int k = 0; k < t.nseg; ++k) {
    const Vec3 d = point_W(t.lb[k], t.pb[k]) - point_W(t.la[k], t.pa[k]);
    const double L = d.norm();
    if (L < 1e-12) continue;
    const Vec3 n = d / L;
    Vec3 dv = Vec3::Zero(), da = Vec3::Zero();
    if (t.lb[k] >= 0) {
      const Mat3& R = work_[t.lb[k]].R_W;
      dv += R * point_velocity(V[t.lb[k]], t.pb[k]);
      da += R * point_acceleration(V[t.lb[k]], A[t.lb[k]], t.pb[k]);
    }
    if (t.la[k] >= 0) {
      const Mat3& R = work_[t.la[k]].R_W;
      dv -= R * point_velocity(V[t.la[k]], t.pa[k]);
      da -= R * point_acceleration(V[t.la[k]], A[t.la[k]], t.pa[k]);
    }
    const double nv = n.dot(dv);
    r += t.w[k] * (n.dot(da) + (dv.squaredNorm() - nv * nv) / L);
  }
  return r;
}

namespace {
// A force F (world) at a link's point p (link frame) as a spatial force in the link frame about
// its origin, subtracted from f: what the ABA's bias forces and joint_wrench's sums take.
inline void subtract_point_force(const Mat3& R, const Vec3& p, const Vec3& F_W, Vec6& f) {
  const Vec3 F = R.transpose() * F_W;
  f.head<3>() -= p.cross(F);
  f.tail<3>() -= F;
}
}  // namespace

namespace {
// The value of principal + 2 pi k nearest `near`.
double unwrap_near(double principal, double near) {
  return principal + 2 * std::numbers::pi * std::round((near - principal) / (2 * std::numbers::pi));
}
}  // namespace

double Mechanism::hinge_angle(const Loop& L) const {
  // b's turn since the start relative to a's, about the start axis (as loop_angle reads it).
  const Quat qa = L.la < 0 ? Quat::Identity() : Quat(work_[L.la].R_W);
  const Quat rel = (qa * L.q_a0.conjugate()).conjugate() * (Quat(work_[L.lb].R_W) * L.q_b0.conjugate());
  return unwrap_near(2 * std::atan2(rel.vec().dot(L.axis_W0), rel.w()), L.angle);
}

void Mechanism::track_loop_angles() {
  for (Loop& L : loops)
    if (L.tracked) L.angle = hinge_angle(L);
}

// The hinge's axis is fixed in a: x' = (w_b - w_a) . n, n = R_a n_a, and
// x'' = (alpha_b - alpha_a) . n + (w_b - w_a) . (w_a x n), world angular accelerations being
// R alpha_link (the link-frame spatial acceleration's angular part).
double Mechanism::hinge_rate(const Loop& L, const std::vector<Vec6>& V) const {
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  const Vec3 n = Ra * L.aa;
  const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * V[L.la].head<3>());
  return (work_[L.lb].R_W * V[L.lb].head<3>() - wa).dot(n);
}

double Mechanism::hinge_acceleration(const Loop& L, const std::vector<Vec6>& V,
                                     const std::vector<Vec6>& A) const {
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  const Mat3& Rb = work_[L.lb].R_W;
  const Vec3 n = Ra * L.aa;
  const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * V[L.la].head<3>());
  const Vec3 aa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * A[L.la].head<3>());
  return (Rb * A[L.lb].head<3>() - aa).dot(n) + (Rb * V[L.lb].head<3>() - wa).dot(wa.cross(n));
}

// The slide is s = n . g with n = R_a aa (fixed in a) and g = P_b - P_a, a's anchor a point of a:
// s' = n' . g + n . g', s'' = n'' . g + 2 n' . g' + n . g'', with n' = w_a x n and
// n'' = alpha_a x n + w_a x (w_a x n). The rows keep g along n, so n' . g in the rate is round-off;
// in the second derivative n'' . g + 2 n' . g' is a point's centripetal acceleration along a
// turning axis (s |w_a|^2 in a plane): a stop held without it lets the assembly lose 1e-2 of its
// energy in 2 s.
double Mechanism::slide_position(const Loop& L) const {
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  return (Ra * L.aa).dot(point_W(L.lb, L.pb) - point_W(L.la, L.pa));
}

double Mechanism::slide_rate(const Loop& L, const std::vector<Vec6>& V) const {
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  const Vec3 n = Ra * L.aa, g = point_W(L.lb, L.pb) - point_W(L.la, L.pa);
  Vec3 dg = work_[L.lb].R_W * point_velocity(V[L.lb], L.pb);
  Vec3 dn = Vec3::Zero();
  if (L.la >= 0) {
    dg -= Ra * point_velocity(V[L.la], L.pa);
    dn = (Ra * V[L.la].head<3>()).cross(n);
  }
  return dn.dot(g) + n.dot(dg);
}

double Mechanism::slide_acceleration(const Loop& L, const std::vector<Vec6>& V,
                                     const std::vector<Vec6>& A) const {
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  const Mat3& Rb = work_[L.lb].R_W;
  const Vec3 n = Ra * L.aa, g = point_W(L.lb, L.pb) - point_W(L.la, L.pa);
  Vec3 dg = Rb * point_velocity(V[L.lb], L.pb), ddg = Rb * point_acceleration(V[L.lb], A[L.lb], L.pb);
  Vec3 dn = Vec3::Zero(), ddn = Vec3::Zero();
  if (L.la >= 0) {
    dg -= Ra * point_velocity(V[L.la], L.pa);
    ddg -= Ra * point_acceleration(V[L.la], A[L.la], L.pa);
    const Vec3 wa = Ra * V[L.la].head<3>(), ala = Ra * A[L.la].head<3>();
    dn = wa.cross(n);
    ddn = ala.cross(n) + wa.cross(dn);
  }
  return ddn.dot(g) + 2 * dn.dot(dg) + n.dot(ddg);
}

void Mechanism::loop_springs(std::vector<Vec6>* f) {
  for (const Loop& L : loops) {
    if (L.stiffness == 0 && L.damping == 0) continue;
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Mat3& Rb = work_[L.lb].R_W;
    const Vec3 axis_W = Ra * L.aa;  // fixed in a
    const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(Ra * work_[L.la].vel.head<3>());
    const Vec3 wb = Rb * work_[L.lb].vel.head<3>();
    Vec6& fb = f ? (*f)[L.lb] : work_[L.lb].pA;
    Vec6* fa = L.la < 0 ? nullptr : f ? &(*f)[L.la] : &work_[L.la].pA;
    if (L.kind == Loop::Kind::hinge) {
      // The angle, continuous past +-pi (a crank's linkage may turn its coupler all the way
      // round); its rate about the axis a carries. The torque's power is the spring's
      // -k (x - rest) x' - c x'^2 exactly: the rows hold the turn about the axis.
      const double angle = hinge_angle(L);
      const double tau = -L.stiffness * (angle - L.rest) - L.damping * (wb - wa).dot(axis_W);
      fb.head<3>() -= Rb.transpose() * (tau * axis_W);
      if (fa) fa->head<3>() += Ra.transpose() * (tau * axis_W);
    } else if (L.kind == Loop::Kind::spherical) {
      // A ball joint's spring: k |phi|^2 / 2 with phi the rotation vector of b's turn relative to
      // a's since the start, in a's axes (D = (R_a^T R_b) (R_a0^T R_b0)^T). Turning b by dt w_b
      // turns D by dt R_a^T w_b on the left, and phi is the fixed vector of D's rotation, so the
      // potential's rate is k phi . R_a^T w_b: the torque on b is -k R_a phi (on a its opposite),
      // with the dashpot -c (w_b - w_a), as on a ball joint in the tree.
      const Quat qa = L.la < 0 ? Quat::Identity() : Quat(Ra);
      const Vec3 phi = rotation_vector(qa.conjugate() * Quat(Rb) * (L.q_a0.conjugate() * L.q_b0).conjugate());
      const Vec3 T = -L.stiffness * (Ra * phi) - L.damping * (wb - wa);
      fb.head<3>() -= Rb.transpose() * T;
      if (fa) fa->head<3>() += Ra.transpose() * T;
    } else {
      // The slide along the axis, and both forces at b's anchor: a's point there moves with a,
      // so the force pair's power is the spring's along the slide's rate (which includes the
      // axis's turning with a).
      const Vec3 xa = L.la < 0 ? Vec3::Zero() : work_[L.la].x_W;
      const Vec3 P = work_[L.lb].x_W + Rb * L.pb;
      const Vec3 gap = P - (xa + Ra * L.pa);
      const Vec3 pa_local = Ra.transpose() * (P - xa);
      const Vec3 vb = Rb * point_velocity(work_[L.lb].vel, L.pb);
      const Vec3 va = L.la < 0 ? Vec3::Zero() : Vec3(Ra * point_velocity(work_[L.la].vel, pa_local));
      const double F = -L.stiffness * (axis_W.dot(gap) - L.rest) - L.damping * axis_W.dot(vb - va);
      subtract_point_force(Rb, L.pb, F * axis_W, fb);
      if (fa) subtract_point_force(Ra, pa_local, -F * axis_W, *fa);
    }
  }
}

double Mechanism::tether_spring_force(const Tether& t) const {
  if (t.stiffness == 0 && t.damping == 0) return 0;
  // Spring tethers are distance joints: one segment, no wheel.
  const Vec3 d = point_W(t.lb[0], t.pb[0]) - point_W(t.la[0], t.pa[0]);
  const double L = d.norm();
  Vec3 dv = Vec3::Zero();
  if (t.lb[0] >= 0) dv += work_[t.lb[0]].R_W * point_velocity(work_[t.lb[0]].vel, t.pb[0]);
  if (t.la[0] >= 0) dv -= work_[t.la[0]].R_W * point_velocity(work_[t.la[0]].vel, t.pa[0]);
  const double rate = L > 1e-12 ? d.dot(dv) / L : 0.0;
  return -t.stiffness * (L - t.rest) - t.damping * rate;  // > 0 pushes the ends apart
}

void Mechanism::tether_springs() {
  for (const Tether& t : tethers) {
    if (t.stiffness == 0 && t.damping == 0) continue;
    const Vec3 d = point_W(t.lb[0], t.pb[0]) - point_W(t.la[0], t.pa[0]);
    const double L = d.norm();
    if (L < 1e-12) continue;
    const Vec3 F = (tether_spring_force(t) / L) * d;
    // A force on a link enters the ABA as minus its bias force.
    if (t.lb[0] >= 0) subtract_point_force(work_[t.lb[0]].R_W, t.pb[0], F, work_[t.lb[0]].pA);
    if (t.la[0] >= 0) subtract_point_force(work_[t.la[0]].R_W, t.pa[0], -F, work_[t.la[0]].pA);
  }
}

namespace {
// Forces from evaluate_force onto links' bias forces: body 0 is link a, body 1 link b (-1: none).
struct LinkLoadSink {
  Vec6* pa;  ///< link a's spatial force to subtract from
  Vec6* pb;  ///< link b's, or null
  const MotionState* st;
  Vec6* of(int i) const { return i == 0 ? pa : pb; }
  void force(int i, const Vec3& f_W, const Vec3& at_W) {
    Vec6* p = of(i);
    if (!p) return;
    const Mat3 R = st[i].q_WP.toRotationMatrix();
    subtract_point_force(R, R.transpose() * (at_W - st[i].x_W), f_W, *p);
  }
  void central(int i, const Vec3& f_W) {
    if (Vec6* p = of(i)) p->tail<3>() -= st[i].q_WP.conjugate() * f_W;
  }
  void torque(int i, const Vec3& tau_W) {
    if (Vec6* p = of(i)) p->head<3>() -= st[i].q_WP.conjugate() * tau_W;
  }
};
}  // namespace

void Mechanism::apply_loads(std::vector<Vec6>* f) {
  MotionState st[2];
  for (const Load& L : loads) {
    if (!(L.f.from <= time_ && time_ < L.f.to)) continue;
    // The bodies' states from the links' poses and velocities (link frame = principal frame).
    auto state_of = [&](int l, MotionState& s) {
      const Work& w = work_[l];
      s.x_W = w.x_W;
      s.q_WP = Quat(w.R_W);
      s.w_P = w.vel.head<3>();
      s.v_W = w.R_W * w.vel.tail<3>();
    };
    state_of(L.link, st[0]);
    if (L.link_b >= 0)
      state_of(L.link_b, st[1]);
    else
      st[1] = L.state_b;
    auto target = [&](int l) { return f ? &(*f)[l] : &work_[l].pA; };
    LinkLoadSink sink{target(L.link), L.link_b >= 0 ? target(L.link_b) : nullptr, st};
    evaluate_force(L.f, 1.0, st, L.model, sink);
  }
}

void Mechanism::tether_loads(const Tether& t, double force, std::vector<Vec6>& f) const {
  // A loop hinge's stop: a torque about the axis on its two links, external to the tree as the
  // loop's own rows are. A ball joint's stop acts between the joint's own two links, a coupling
  // along its joints' own axes (as a motor): what the joints transmit.
  if (t.measure == Tether::Measure::hinge) {
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Vec3 T = force * (Ra * L.aa);  // on b; -T on a
    f[L.lb].head<3>() -= work_[L.lb].R_W.transpose() * T;
    if (L.la >= 0) f[L.la].head<3>() += Ra.transpose() * T;
    return;
  }
  // A loop slider's stop: a force along the axis at b's anchor, and its opposite on a at the same
  // point (a's point there, which moves with a: the pair's virtual work is the slide's).
  if (t.measure == Tether::Measure::slide) {
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Vec3 F = force * (Ra * L.aa), P = point_W(L.lb, L.pb);  // on b; -F on a
    subtract_point_force(work_[L.lb].R_W, L.pb, F, f[L.lb]);
    if (L.la >= 0) subtract_point_force(Ra, Ra.transpose() * (P - work_[L.la].x_W), -F, f[L.la]);
    return;
  }
  if (t.measure != Tether::Measure::length) return;
  for (int k = 0; k < t.nseg; ++k) {
    const Vec3 d = point_W(t.lb[k], t.pb[k]) - point_W(t.la[k], t.pa[k]);
    const double L = d.norm();
    if (L < 1e-12) continue;
    const Vec3 F = (force * t.w[k] / L) * d;  // on b's end; -F on a's
    if (t.lb[k] >= 0) subtract_point_force(work_[t.lb[k]].R_W, t.pb[k], F, f[t.lb[k]]);
    if (t.la[k] >= 0) subtract_point_force(work_[t.la[k]].R_W, t.pa[k], -F, f[t.la[k]]);
    // A pulley's run pulls its wheel where it leaves the rim (the fixed base holds the rest).
    if (t.wheel_link >= 0) {
      const Work& w = work_[t.wheel_link];
      subtract_point_force(w.R_W, w.R_W.transpose() * (t.wheel_point[k] - w.x_W), -F, f[t.wheel_link]);
    }
  }
}

// Composite-rigid-body algorithm (Featherstone, Table 6.2): each link's composite inertia, then
// M_ij = S_i^T X^T ... Ic_j S_j walking from each link to the root.
void Mechanism::mass_matrix() {
  const int n = (int)links.size();
  for (int i = 0; i < n; ++i) work_[i].Ic = spatial_inertia(links[i].mass, links[i].I_P);
  for (int i = n; i-- > 0;)
    if (links[i].parent >= 0)
      add_transform_inertia_back(work_[i].E, work_[i].r, work_[i].Ic, work_[links[i].parent].Ic);
  M_.setZero();
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    for (int c = 0; c < l.nv; ++c) {
      Vec6 F = work_[i].Ic * l.S.col(c);
      for (int c2 = 0; c2 < l.nv; ++c2) M_(l.iv + c2, l.iv + c) = l.S.col(c2).dot(F);
      if (l.nv == 1) M_(l.iv, l.iv) += l.armature;
      for (int j = i; links[j].parent >= 0;) {
        F = transform_force_back(work_[j].E, work_[j].r, F);
        j = links[j].parent;
        const Link& lj = links[j];
        for (int c2 = 0; c2 < lj.nv; ++c2) {
          M_(lj.iv + c2, l.iv + c) = lj.S.col(c2).dot(F);
          M_(l.iv + c, lj.iv + c2) = M_(lj.iv + c2, l.iv + c);
        }
      }
    }
  }
}

void Mechanism::unit_velocities(int k, std::vector<Vec6>& V) const {
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    Vec6 vJ = Vec6::Zero();
    if (k >= l.iv && k < l.iv + l.nv) vJ = l.S.col(k - l.iv);
    V[i] = l.parent < 0 ? vJ : Vec6(transform_motion(work_[i].E, work_[i].r, V[l.parent]) + vJ);
  }
}

void Mechanism::loop_jacobian(bool impulse_rows) {
  const int D = (int)dofs.size(), T = (int)tethers.size();
  bool tether_rows = false;
  auto tether_is_row = [&](int t) {
    if (ropes_free_ && !tethers[t].rod) return false;
    return impulse_rows ? !std::isnan(vtarget_[D + t]) : tethers[t].active();
  };
  if (T > 0) {
    G_.bottomRows(T).setZero();
    for (int t = 0; t < T; ++t) tether_rows = tether_rows || tether_is_row(t);
  }
  if (loop_rows > 0 || tether_rows)
    for (int k = 0; k < nv; ++k) {
      unit_velocities(k, V_);
      if (loop_rows > 0) {
        loop_velocity_rows(V_, rows_.data());
        G_.col(k).head(loop_rows) = rows_.head(loop_rows);
      }
      for (int t = 0; t < T; ++t)
        if (tether_is_row(t))
          G_(tether_row(t), k) = tether_rate(tethers[t], V_, k == tethers[t].wheel_iv ? 1.0 : 0.0);
    }
  for (size_t d = 0; d < dofs.size(); ++d) {
    const bool row = impulse_rows ? !std::isnan(vtarget_[d]) : dofs[d].active();
    G_.row(loop_rows + (int)d).setZero();
    if (row) G_(loop_rows + (int)d, dofs[d].iv) = 1;
  }
  mass_matrix();
  llt_.compute(M_);
  Y_ = G_.transpose();
  llt_.solveInPlace(Y_);
  A_.noalias() = G_ * Y_;
  // Rows of coordinates that are not held (and of slack ropes) are zero: a unit diagonal gives them
  // zero multipliers exactly (their right-hand sides are zero).
  for (int r = loop_rows; r < loop_rows + D + T; ++r)
    if (G_.row(r).isZero(0)) A_(r, r) = 1;
  if (loop_rows > 0 || T > 0) A_.diagonal().array() += 1e-12 * std::max(A_.diagonal().maxCoeff(), 1e-300);
  llt_rows_.compute(A_);
}

void Mechanism::solve_rows() {
  lambda_ = rhs_;
  llt_rows_.solveInPlace(lambda_);
  dv_.noalias() = Y_ * lambda_;
}

void Mechanism::constrain_accelerations(const double* q, const double* v, double* qdd) {
  const bool held = any_active();
  if (loops.empty() && !held) {
    for (Dof& d : dofs) d.lambda = 0;
    for (Tether& t : tethers) t.lambda = 0;
    return;
  }
  bool tether_rows = false;
  for (const Tether& t : tethers) tether_rows = tether_rows || t.active();
  if (!loops.empty() || tether_rows) {
    // True link accelerations under the tree's q'' (the ABA's include the base's fictitious -g).
    for (size_t i = 0; i < links.size(); ++i) {
      const Link& l = links[i];
      const Work& w = work_[i];
      Vec6 a = l.parent < 0 ? Vec6::Zero() : transform_motion(w.E, w.r, Acc_[l.parent]);
      a += w.c;
      if (l.nv > 0) a += l.S * Eigen::Map<const VecX6>(qdd + l.iv, l.nv);
      Acc_[i] = a;
      V_[i] = w.vel;
    }
    if (!loops.empty()) {
      loop_acceleration_rows(V_, Acc_, rows_.data());
      rhs_.head(loop_rows) = -rows_.head(loop_rows);
    }
  }
  for (size_t t = 0; t < tethers.size(); ++t) {
    const Tether& T = tethers[t];
    rhs_(tether_row((int)t)) =
        T.active() ? -tether_acceleration(T, V_, Acc_, T.wheel_iv >= 0 ? qdd[T.wheel_iv] : 0.0) : 0.0;
  }
  // A held coordinate's row: q''_k = a*, the rate its mode keeps (a position motor's target rate
  // changes with q; every other held rate is constant).
  for (size_t d = 0; d < dofs.size(); ++d) {
    const Dof& f = dofs[d];
    double r = 0;
    if (f.active()) {
      const double a = f.at_stop == 0 && f.hold ? f.target_acceleration(q, v) : 0.0;
      r = a - qdd[f.iv];
    }
    rhs_(loop_rows + (int)d) = r;
  }
  loop_jacobian();  // overwrites V_ and rows_
  solve_rows();
  for (int k = 0; k < nv; ++k) qdd[k] += dv_[k];
  for (size_t d = 0; d < dofs.size(); ++d)
    dofs[d].lambda = dofs[d].active() ? lambda_(loop_rows + (int)d) : 0.0;
  for (size_t t = 0; t < tethers.size(); ++t)
    tethers[t].lambda = tethers[t].active() ? lambda_(tether_row((int)t)) : 0.0;
}

void Mechanism::displace(double* q, const double* dv) const {
  for (const Link& l : links) {
    double* qq = q + l.iq;
    const double* d = dv + l.iv;
    switch (l.kind) {
      case LinkJoint::revolute:
      case LinkJoint::prismatic:
        qq[0] += d[0];
        break;
      case LinkJoint::fixed:
        break;
      case LinkJoint::spherical:
      case LinkJoint::free: {
        // The rotation vector's exact increment q (x) exp(d / 2), then the position by R v.
        const int o = l.kind == LinkJoint::free ? 3 : 0;
        const Quat q0(qq[o], qq[o + 1], qq[o + 2], qq[o + 3]);
        const Vec3 w(d[0], d[1], d[2]);
        const double ang = w.norm();
        const Quat dq = ang > 0 ? Quat(Eigen::AngleAxisd(ang, w / ang)) : Quat::Identity();
        if (l.kind == LinkJoint::free) {
          const Vec3 dx = q0.normalized() * Vec3(d[3], d[4], d[5]);
          qq[0] += dx.x();
          qq[1] += dx.y();
          qq[2] += dx.z();
        }
        const Quat q1 = (q0 * dq).normalized();
        qq[o] = q1.w();
        qq[o + 1] = q1.x();
        qq[o + 2] = q1.y();
        qq[o + 3] = q1.z();
        break;
      }
    }
  }
}

void Mechanism::project_positions(double* q) {
  // Newton's method on C(q) = 0 with the minimum-mass-norm step; converges quadratically from the
  // integrator's error (1e-10 and below) in one or two iterations.
  for (int it = 0; it < 8; ++it) {
    kinematics(q);
    loop_position_rows(rows_.data());
    // A coordinate on a stop is held there; any other held coordinate keeps its value.
    for (size_t d = 0; d < dofs.size(); ++d) {
      const Dof& f = dofs[d];
      rows_(loop_rows + (int)d) = f.at_stop < 0 ? q[f.iq] - f.lo : f.at_stop > 0 ? q[f.iq] - f.hi : 0.0;
    }
    // A rod at its length, a taut rope at its bound.
    for (size_t t = 0; t < tethers.size(); ++t) {
      const Tether& T = tethers[t];
      const double at = !std::isnan(T.aim) ? T.aim : T.taut < 0 ? T.lo : T.hi;
      rows_(tether_row((int)t)) = T.active() ? tether_position(T, q) - at : 0.0;
    }
    if (rows_.lpNorm<Eigen::Infinity>() < 1e-14) return;
    rhs_ = -rows_;
    loop_jacobian();
    solve_rows();
    displace(q, dv_.data());
  }
}

void Mechanism::project_velocities(const double* q, double* v) {
  kinematics(q);
  loop_jacobian();
  Eigen::Map<Eigen::VectorXd> vv(v, nv);
  rhs_.noalias() = -(G_ * vv);
  for (size_t d = 0; d < dofs.size(); ++d) {
    const Dof& f = dofs[d];
    if (f.active()) rhs_(loop_rows + (int)d) += f.at_stop != 0 || f.stick ? 0.0 : f.target_rate(q);
  }
  solve_rows();
  vv += dv_;
}

double Mechanism::loop_angle(int k) const {
  const Loop& L = loops[k];
  const Quat qa = L.la < 0 ? Quat::Identity() : out_q_[L.la];
  const Quat qb = out_q_[L.lb];
  // Each link's rotation since the start, then b's relative to a's, about the start axis.
  const Quat ra = qa * L.q_a0.conjugate(), rb = qb * L.q_b0.conjugate();
  const Quat rel = ra.conjugate() * rb;
  if (L.kind == Loop::Kind::prismatic) {  // the slide along the axis (fixed in a) since the start
    const Vec3 xa = L.la < 0 ? Vec3::Zero() : out_x_[L.la];
    const Vec3 gap = (out_x_[L.lb] + qb * L.pb) - (xa + qa * L.pa);
    return (qa * L.aa).dot(gap);
  }
  if (!L.hinge) return 2 * std::atan2(rel.vec().norm(), std::abs(rel.w()));
  const double a = 2 * std::atan2(rel.vec().dot(L.axis_W0), rel.w());
  return L.tracked ? unwrap_near(a, L.angle) : a;
}

double Mechanism::loop_speed(int k) const {
  const Loop& L = loops[k];
  const Vec3 wa = L.la < 0 ? Vec3::Zero() : Vec3(out_q_[L.la] * out_v_[L.la].head<3>());
  const Vec3 wb = out_q_[L.lb] * out_v_[L.lb].head<3>();
  const Quat qa = L.la < 0 ? Quat::Identity() : out_q_[L.la];
  if (L.kind == Loop::Kind::prismatic) {
    const Quat qb = out_q_[L.lb];
    const Vec3 va = L.la < 0 ? Vec3::Zero() : Vec3(qa * point_velocity(out_v_[L.la], L.pa));
    const Vec3 vb = qb * point_velocity(out_v_[L.lb], L.pb);
    return (qa * L.aa).dot(vb - va);  // the slide's rate (the axis's own turning moves no anchor along it)
  }
  if (!L.hinge) return (wb - wa).norm();
  return (wb - wa).dot(qa * L.aa);
}

}  // namespace simreel

namespace simreel {

double Mechanism::tether_length(int ti, int seg, double* rate) const {
  const Tether& t = tethers[ti];
  if (t.measure == Tether::Measure::coupling) {
    const Link &f = links[t.link], &l = links[t.link2];
    double s = q[f.iq] - t.ratio * q[l.iq], r = v[f.iv] - t.ratio * v[l.iv];
    for (const auto& [k, c] : t.more) s -= c * q[links[k].iq], r -= c * v[links[k].iv];
    if (rate) *rate = r;
    return s;
  }
  if (t.measure == Tether::Measure::hinge || t.measure == Tether::Measure::slide) {
    if (rate) *rate = loop_speed(t.loop);
    return loop_angle(t.loop);
  }
  if (t.measure != Tether::Measure::length) return ball_readout(t, rate);
  auto point = [&](int l, const Vec3& p) { return l < 0 ? p : Vec3(out_x_[l] + out_q_[l] * p); };
  auto velocity = [&](int l, const Vec3& p) {
    return l < 0 ? Vec3::Zero() : Vec3(out_q_[l] * point_velocity(out_v_[l], p));
  };
  double s = 0, r = 0;
  for (int k = 0; k < t.nseg; ++k) {
    if (seg >= 0 && k != seg) continue;
    const Vec3 d = point(t.lb[k], t.pb[k]) - point(t.la[k], t.pa[k]);
    const double L = d.norm();
    const double w = seg >= 0 ? 1.0 : t.w[k];
    s += w * L;
    if (L > 1e-12) r += w * d.dot(velocity(t.lb[k], t.pb[k]) - velocity(t.la[k], t.pa[k])) / L;
  }
  if (seg < 0 && t.wheel_iq >= 0) {
    s += t.wheel_c * q[t.wheel_iq];
    r += t.wheel_c * v[t.wheel_iv];
  }
  if (rate) *rate = r;
  return s;
}

double Mechanism::tether_gap(int ti) const {
  const Tether& t = tethers[ti];
  const double s = tether_length(ti);
  if (t.rod) return std::abs(s - t.hi);
  double g = 0;
  if (t.has_hi) g = std::max(g, s - t.hi);
  if (t.has_lo) g = std::max(g, t.lo - s);
  return g;
}

}  // namespace simreel

namespace simreel {
double Mechanism::measure_tether(int t) {
  kinematics(q.data());
  return tether_position(tethers[t], q.data());
}
}  // namespace simreel
