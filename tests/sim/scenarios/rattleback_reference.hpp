// An independent reference for a rigid ellipsoid (or any body whose lower surface is an ellipsoid)
// rolling without slipping on the horizontal plane z = 0: the rattleback (celt) of Kane and
// Levinson (1982, "Realistic mathematical modeling of the rattleback", Int. J. Non-Linear
// Mechanics 17(3)) and Garcia and Hubbard (1988, "Spin reversal of the rattleback: theory and
// experiment", Proc. R. Soc. Lond. A 418). It shares nothing with simreel's contact code: the
// contact point is the ellipsoid's support point in the direction -n, and the contact force is
// eliminated from Newton-Euler by the no-slip constraint, giving an ODE in (q, w) integrated by
// classical RK4.
//
// Body frame B: origin at the ellipsoid's centre O, axes along its semi-axes (a, b, c); the centre
// of mass G at c_B; I_G the inertia about G in B. World: z up, gravity -g z.
// With r = G - P (P the contact point, on the plane), no slip says v_G = w x r, so
//   a_G = w' x r + w x r',            r' = w x r + R d(r_B)/dt,
// and with the contact force F = m (a_G - g):
//   I_W w' + w x I_W w = -r x F
//   => (I_W + m (|r|^2 1 - r r^T)) w' = -w x I_W w - m r x (w x r') + m r x g_vec.
// d(r_B)/dt = -dp_B/dt, p_B = support(-n_B) = -A n_B / sqrt(n_B^T A n_B), A = diag(a^2, b^2, c^2),
// n_B = R^T z, dn_B/dt = -w_B x n_B, dp/dd = A / s - (A d)(A d)^T / s^3 (s = sqrt(d^T A d)).
// r' depends on w only (not on w'), so the system is explicit.
//
// The state is (q_WB, w_W, x_G, y_G); z_G follows from the geometry (the body touches z = 0).
// Energy E = m |v_G|^2 / 2 + w^T I_W w / 2 + m g z_G is conserved (no slip does no work).
#pragma once
#include <Eigen/Dense>
#include <cmath>

namespace simreel::test {

struct RollingEllipsoid {
  using V3 = Eigen::Vector3d;
  using M3 = Eigen::Matrix3d;
  using Q = Eigen::Quaterniond;
  double m = 1.0;                   ///< kg
  V3 radii = V3(0.20, 0.03, 0.02);  ///< m, semi-axes a, b, c along B's x, y, z
  V3 c_B = V3(0, 0, -0.01);         ///< m, centre of mass from the ellipsoid's centre
  M3 I_B = M3::Identity();          ///< kg m^2, about the centre of mass, axes of B
  double g = 9.81;                  ///< m/s^2

  struct State {
    Q q = Q::Identity();  ///< body to world
    V3 w = V3::Zero();    ///< rad/s, world
    double x = 0, y = 0;  ///< m, centre of mass, horizontal
  };

  // Contact point P relative to the ellipsoid's centre, in B, for orientation R.
  V3 contact_B(const M3& R) const {
    const V3 n_B = R.transpose() * V3::UnitZ();
    const V3 A = radii.cwiseProduct(radii);
    const V3 An = A.cwiseProduct(n_B);
    return -An / std::sqrt(n_B.dot(An));
  }
  // r = G - P, world.
  V3 r_W(const M3& R) const { return R * (c_B - contact_B(R)); }
  // The centre of mass height and velocity the constraint gives.
  double z_G(const State& s) const { return r_W(s.q.normalized().toRotationMatrix()).z(); }
  V3 v_G(const State& s) const { return s.w.cross(r_W(s.q.normalized().toRotationMatrix())); }
  // The ellipsoid's centre O in the world.
  V3 centre_W(const State& s) const {
    const M3 R = s.q.normalized().toRotationMatrix();
    return V3(s.x, s.y, z_G(s)) - R * c_B;
  }

  double energy(const State& s) const {
    const M3 R = s.q.normalized().toRotationMatrix();
    const V3 r = r_W(R);
    const V3 v = s.w.cross(r);
    const M3 I_W = R * I_B * R.transpose();
    return 0.5 * m * v.squaredNorm() + 0.5 * s.w.dot(I_W * s.w) + m * g * r.z();
  }

  struct Deriv {
    Eigen::Vector4d dq;  ///< of (w, x, y, z) coefficients
    V3 dw;
    double dx, dy;
  };
  Deriv rate(const State& s) const {
    const Q q = s.q.normalized();
    const M3 R = q.toRotationMatrix();
    const V3 n_B = R.transpose() * V3::UnitZ();
    const V3 A = radii.cwiseProduct(radii);
    const V3 d = -n_B;  // support direction
    const V3 Ad = A.cwiseProduct(d);
    const double sn = std::sqrt(d.dot(Ad));
    const V3 p_B = Ad / sn;
    const M3 dp_dd = M3(A.asDiagonal()) / sn - Ad * Ad.transpose() / (sn * sn * sn);
    const V3 w_B = R.transpose() * s.w;
    const V3 dn_B = -w_B.cross(n_B);
    const V3 dp_B = dp_dd * (-dn_B);  // d = -n
    const V3 r = R * (c_B - p_B);
    const V3 dr = s.w.cross(r) - R * dp_B;
    const M3 I_W = R * I_B * R.transpose();
    const M3 K = I_W + m * (r.squaredNorm() * M3::Identity() - r * r.transpose());
    const V3 gv(0, 0, -g);
    const V3 rhs = -s.w.cross(I_W * s.w) - m * r.cross(s.w.cross(dr)) + m * r.cross(gv);
    Deriv out;
    out.dw = K.ldlt().solve(rhs);
    const V3 v = s.w.cross(r);
    out.dx = v.x();
    out.dy = v.y();
    // q' = 1/2 (0, w) q (w in the world).
    const Q wq(0, s.w.x(), s.w.y(), s.w.z());
    const Q dq = wq * s.q;
    out.dq = 0.5 * Eigen::Vector4d(dq.w(), dq.x(), dq.y(), dq.z());
    return out;
  }

  State add(const State& s, const Deriv& k, double h) const {
    State o;
    o.q = Q(s.q.w() + h * k.dq[0], s.q.x() + h * k.dq[1], s.q.y() + h * k.dq[2], s.q.z() + h * k.dq[3]);
    o.w = s.w + h * k.dw;
    o.x = s.x + h * k.dx;
    o.y = s.y + h * k.dy;
    return o;
  }

  // One classical RK4 step; the quaternion is renormalised after it (its drift is O(h^5)).
  State rk4(const State& s, double h) const {
    const Deriv k1 = rate(s);
    const Deriv k2 = rate(add(s, k1, h / 2));
    const Deriv k3 = rate(add(s, k2, h / 2));
    const Deriv k4 = rate(add(s, k3, h));
    State o;
    const Eigen::Vector4d dq = (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6;
    o.q = Q(s.q.w() + h * dq[0], s.q.x() + h * dq[1], s.q.y() + h * dq[2], s.q.z() + h * dq[3]).normalized();
    o.w = s.w + h / 6 * (k1.dw + 2 * k2.dw + 2 * k3.dw + k4.dw);
    o.x = s.x + h / 6 * (k1.dx + 2 * k2.dx + 2 * k3.dx + k4.dx);
    o.y = s.y + h / 6 * (k1.dy + 2 * k2.dy + 2 * k3.dy + k4.dy);
    return o;
  }
};

// The Kane-Levinson rattleback: m = 1 kg, semi-axes 0.20, 0.03, 0.02 m, centre of mass 0.01 m below
// the ellipsoid's centre, A, B, C = 2e-4, 1.6e-3, 1.7e-3 kg m^2, product of inertia D = -2e-5
// kg m^2 between the two horizontal axes (the tensor's (x, y) entry).
inline RollingEllipsoid kane_levinson(double D = -2e-5) {
  RollingEllipsoid e;
  e.I_B << 2e-4, D, 0, D, 1.6e-3, 0, 0, 0, 1.7e-3;
  return e;
}

}  // namespace simreel::test
