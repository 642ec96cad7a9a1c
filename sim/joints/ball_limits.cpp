// A ball joint's stops (BallLimits; articulation.hpp, Mechanism::Tether with Measure swing,
// twist or angle): the angles whose bounds the tether rows keep, and their first two time derivatives.
//
// The joint's coordinate is the child's rotation R relative to the parent (joint frames), with
// R' = R [w]x, w the relative angular velocity in the child's joint frame (the link's velocities).
// About the unit axis a (the same vector in both frames at t = 0), R = R_swing R_twist:
//   swing  theta = angle(a, c), c = R a: the tilt of the child's axis. With u = a x c,
//          theta' = n . W (n = u / |u|, W = R w the relative angular velocity in the parent's
//          frame) and theta'' = n' . W + n . R w', n' = (u' - n (n . u')) / |u|, u' = a x (W x c).
//   twist  psi = 2 atan2(a . v, s) for the unit quaternion (s, v) of R with s >= 0. From
//          q' = q (0, w) / 2: s' = -v . w / 2, v' = (s w + v x w) / 2, so
//          psi' = J . w, J = (s^2 a + s a x v + x v) / (s^2 + x^2), x = a . v, and on the stop
//          (J . w = 0) psi'' = J . w'.
//   angle  phi = 2 atan2(|v|, s), the whole rotation's: phi' = u . w with u = v / |v| (the
//          rotation's axis, the same in both frames), phi'' = u . w' + u' . w,
//          u' = (v' - u (u . v')) / |v|.
// All are singular only where they are not used: the swing's and the angle's rates at 0 (their
// stops are never at 0), the twist at a swing of pi.
#include <cmath>

#include "sim/joints/articulation.hpp"

namespace simreel {

namespace {

double swing_angle(const Vec3& a, const Mat3& R) {
  const Vec3 c = R * a;
  return std::atan2(a.cross(c).norm(), a.dot(c));
}

Quat unit_quaternion(const Mat3& R) {
  Quat q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return q;
}

double twist_angle(const Vec3& a, const Mat3& R) {
  const Quat q = unit_quaternion(R);
  return 2 * std::atan2(a.dot(q.vec()), q.w());
}

// d/dt of the swing or twist for relative rate w (child joint frame) and, with wd, its second
// derivative (wd = w').
double swing_derivative(const Vec3& a, const Mat3& R, const Vec3& w, const Vec3* wd) {
  const Vec3 c = R * a, u = a.cross(c), W = R * w;
  const double s = u.norm();
  if (s < 1e-12) return 0;
  const Vec3 n = u / s;
  if (!wd) return n.dot(W);
  const Vec3 du = a.cross(W.cross(c));
  const Vec3 dn = (du - n * n.dot(du)) / s;
  return dn.dot(W) + n.dot(R * *wd);
}

double twist_derivative(const Vec3& a, const Mat3& R, const Vec3& w, const Vec3* wd) {
  const Quat q = unit_quaternion(R);
  const double s = q.w();
  const Vec3 v = q.vec();
  const double x = a.dot(v), D = s * s + x * x;
  if (D < 1e-24) return 0;
  const Vec3 J = (s * s * a + s * a.cross(v) + x * v) / D;
  if (!wd) return J.dot(w);
  // The second derivative is asked for only on the stop, where the twist's rate J . w is 0, and
  // there J' . w vanishes: the rotations R exp(t w) with J . w = 0 keep the twist exactly.
  return J.dot(*wd);
}

double rotation_angle(const Mat3& R) {
  const Quat q = unit_quaternion(R);
  return 2 * std::atan2(q.vec().norm(), q.w());
}

double rotation_angle_derivative(const Mat3& R, const Vec3& w, const Vec3* wd) {
  const Quat q = unit_quaternion(R);
  const Vec3 v = q.vec();
  const double n = v.norm();
  if (n < 1e-12) return 0;
  const Vec3 u = v / n;
  if (!wd) return u.dot(w);
  const Vec3 dv = 0.5 * (q.w() * w + v.cross(w));
  return u.dot(*wd) + ((dv - u * u.dot(dv)) / n).dot(w);
}

using Measure = Mechanism::Tether::Measure;

double measure_angle(const Mechanism::Tether& t, const Mat3& R) {
  switch (t.measure) {
    case Measure::swing:
      return swing_angle(t.axis, R);
    case Measure::twist:
      return twist_angle(t.axis, R);
    default:
      return rotation_angle(R);
  }
}

double measure_derivative(const Mechanism::Tether& t, const Mat3& R, const Vec3& w, const Vec3* wd) {
  switch (t.measure) {
    case Measure::swing:
      return swing_derivative(t.axis, R, w, wd);
    case Measure::twist:
      return twist_derivative(t.axis, R, w, wd);
    default:
      return rotation_angle_derivative(R, w, wd);
  }
}

}  // namespace

// A ball joint that closes a loop: its joint frame is the world's axes at the start, so b's
// rotation relative to a's in it is (R_a R_a0^T)^T (R_b R_b0^T), and the relative rate in b's joint
// frame is R_b0 (w_b - R_b^T R_a w_a) from the link-frame rates, whose derivative is
// R_b0 (alpha_b - R_ba alpha_a + w_b x R_ba w_a) with R_ba = R_b^T R_a (the tree's formula below
// with the loop's two links in place of a link and its parent).
Mat3 Mechanism::loop_ball_rotation(const Loop& L, const Mat3& Ra, const Mat3& Rb) {
  return L.q_a0.toRotationMatrix() * Ra.transpose() * Rb * L.q_b0.conjugate().toRotationMatrix();
}

double Mechanism::ball_angle(const Tether& t) const {
  if (t.loop >= 0) {
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    return measure_angle(t, loop_ball_rotation(L, Ra, work_[L.lb].R_W));
  }
  // R from the link's transform: E^T = R_pF R R_cF^T (kinematics).
  const Link& l = links[t.link];
  const Mat3 R = l.R_pF.transpose() * work_[t.link].E.transpose() * l.R_cF;
  return measure_angle(t, R);
}

namespace {
// The relative angular velocity of a ball joint's child, in its joint frame, from link velocities.
Vec3 relative_rate(const Link& l, const Mat3& E, const std::vector<Vec6>& V, int link) {
  Vec3 w = V[link].head<3>();
  if (l.parent >= 0) w -= E * V[l.parent].head<3>();
  return l.R_cF.transpose() * w;
}
}  // namespace

double Mechanism::ball_rate(const Tether& t, const std::vector<Vec6>& V) const {
  if (t.loop >= 0) {
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Mat3& Rb = work_[L.lb].R_W;
    Vec3 wl = V[L.lb].head<3>();
    if (L.la >= 0) wl -= Rb.transpose() * (Ra * V[L.la].head<3>());
    return measure_derivative(t, loop_ball_rotation(L, Ra, Rb), L.q_b0 * wl, nullptr);
  }
  const Link& l = links[t.link];
  const Mat3& E = work_[t.link].E;
  const Mat3 R = l.R_pF.transpose() * E.transpose() * l.R_cF;
  const Vec3 w = relative_rate(l, E, V, t.link);
  return measure_derivative(t, R, w, nullptr);
}

double Mechanism::ball_acceleration(const Tether& t, const std::vector<Vec6>& V,
                                    const std::vector<Vec6>& A) const {
  if (t.loop >= 0) {
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
    const Mat3& Rb = work_[L.lb].R_W;
    Vec3 wl = V[L.lb].head<3>(), al = A[L.lb].head<3>();
    if (L.la >= 0) {
      const Mat3 Rba = Rb.transpose() * Ra;
      const Vec3 wa = Rba * V[L.la].head<3>();
      wl -= wa;
      al += V[L.lb].head<3>().cross(wa) - Rba * A[L.la].head<3>();
    }
    const Vec3 wd = L.q_b0 * al;
    return measure_derivative(t, loop_ball_rotation(L, Ra, Rb), L.q_b0 * wl, &wd);
  }
  const Link& l = links[t.link];
  const Mat3& E = work_[t.link].E;
  const Mat3 R = l.R_pF.transpose() * E.transpose() * l.R_cF;
  const Vec3 w = relative_rate(l, E, V, t.link);
  // The link's angular acceleration is E alpha_p + R_cF w' + omega x R_cF w (Featherstone's
  // a = X a_p + S q'' + v x S q'), so w' = R_cF^T (alpha - E alpha_p - omega x R_cF w).
  Vec3 al = A[t.link].head<3>() - V[t.link].head<3>().cross(l.R_cF * w);
  if (l.parent >= 0) al -= E * A[l.parent].head<3>();
  const Vec3 wd = l.R_cF.transpose() * al;
  return measure_derivative(t, R, w, &wd);
}

double Mechanism::ball_readout(const Tether& t, double* rate) const {
  if (t.loop >= 0) {  // from the written poses of the loop's two links
    const Loop& L = loops[t.loop];
    const Mat3 Ra = L.la < 0 ? Mat3::Identity() : out_q_[L.la].toRotationMatrix();
    const Mat3 Rb = out_q_[L.lb].toRotationMatrix();
    const Mat3 R = loop_ball_rotation(L, Ra, Rb);
    if (rate) {
      Vec3 wl = out_v_[L.lb].head<3>();
      if (L.la >= 0) wl -= Rb.transpose() * (Ra * out_v_[L.la].head<3>());
      *rate = measure_derivative(t, R, L.q_b0 * wl, nullptr);
    }
    return measure_angle(t, R);
  }
  // From the written poses: the link's and its parent's world rotations (the base's: identity).
  const Link& l = links[t.link];
  const Mat3 Rc = out_q_[t.link].toRotationMatrix();
  const Mat3 Rp = l.parent < 0 ? Mat3::Identity() : out_q_[l.parent].toRotationMatrix();
  const Mat3 Rrel = Rp.transpose() * Rc;
  const Mat3 R = l.R_pF.transpose() * Rrel * l.R_cF;
  if (rate) {
    Vec3 w = out_v_[t.link].head<3>();
    if (l.parent >= 0) w -= Rrel.transpose() * out_v_[l.parent].head<3>();
    *rate = measure_derivative(t, R, l.R_cF.transpose() * w, nullptr);
  }
  return measure_angle(t, R);
}

Vec3 rotation_vector(Quat r) {
  r.normalize();
  if (r.w() < 0) r.coeffs() = -r.coeffs();
  const double sn = r.vec().norm();
  // angle = 2 atan2(|v|, s); near 0 the ratio angle / |v| tends to 2 / s.
  return sn < 1e-300 ? Vec3::Zero() : Vec3((2 * std::atan2(sn, r.w()) / sn) * r.vec());
}

Vec3 Mechanism::ball_rotation_vector(const Link& l, const double* q) {
  return rotation_vector(Quat(q[l.iq], q[l.iq + 1], q[l.iq + 2], q[l.iq + 3]));
}

}  // namespace simreel
