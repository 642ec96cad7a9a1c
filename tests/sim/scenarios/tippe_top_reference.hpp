// An independent reference for the tippe top: the eccentric-sphere model
// of Ueda, Sasaki and Watanabe (2005) and of Cohen (1977), integrated as an ODE. It shares nothing
// with simreel's contact code: no collision, no solver, no World, only Eigen's vectors.
//
// The body: a sphere of radius R whose centre of mass G lies a = alpha R from the sphere's centre
// O, on the symmetry axis e3 (a unit vector fixed in the body, pointing from G through O toward
// the stem: G = O - a e3). Moments of inertia about G: I1 across the axis, I3 along it. It touches
// the horizontal plane z = 0 at P = O - R z (O stays at height R: a holonomic constraint whose
// normal force N >= 0 is solved for at every evaluation). The contact slides: the friction force
// is F = -mu N u with u = v_P / max(|v_P|, eps) (Coulomb above the slip speed eps, viscous below
// it, continuous: the "modified Coulomb law" Ueda et al. use, vanishing at v_P = 0).
// Newton-Euler about G in the world frame:
//   m dv/dt = N z + F - m g z,    dL/dt = (P - G) x (N z + F),    w = I_W^-1 L,  I_W = R I_B R^T,
//   dq/dt = 1/2 (0, w) q,
// and N from d^2(O_z)/dt^2 = 0: dv_z/dt + a z.(dw/dt x e3 + w x (w x e3)) = 0, linear in N because
// dw/dt = I_W^-1 (tau - w x L) and F are. The state is integrated by the Dormand-Prince 5(4) pair
// (Dormand and Prince 1980; Hairer, Norsett and Wanner, Solving ODEs I, table 5.2) with local
// error control to a tolerance of 1e-11; the quaternion is renormalised after each step.
//
// Jellett's quantity lambda = L . (G - P) is conserved exactly by this model whatever the friction
// law (the forces act at P, so their torque about G is perpendicular to G - P, and for a body
// symmetric about e3, L . d(G - P)/dt = -a L . (w x e3) = 0): the reference checks itself on it.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <simreel/math.hpp>

namespace simreel::test {

struct TippeTop {
  double m = 0.02;     ///< kg
  double R = 0.02;     ///< m, sphere radius
  double alpha = 0.3;  ///< offset of the centre of mass from the sphere's centre, / R
  double I1 = 0;       ///< kg m^2, about an axis across the symmetry axis through G
  double I3 = 0;       ///< kg m^2, about the symmetry axis
  double mu = 0.3;     ///< sliding friction coefficient
  double g = 9.81;     ///< m/s^2
  double eps = 1e-3;   ///< m/s, slip speed below which friction is viscous (regularisation)
  double a() const { return alpha * R; }
};

// State: G (3), v of G (3), q body to world (w, x, y, z), L about G in the world frame (3).
using TippeState = std::array<double, 13>;

struct TippeSample {
  double t = 0;
  double theta = 0;    ///< rad, angle between e3 and the vertical (0: stem up, pi: on the stem)
  double jellett = 0;  ///< kg m^3/s, L . (G - P)
  double energy = 0;   ///< J, kinetic + potential (m g z_G)
  double normal = 0;   ///< N, the plane's normal force
  double slip = 0;     ///< m/s, |v_P|
};

class TippeTopOde {
 public:
  explicit TippeTopOde(const TippeTop& p) : p_(p) {}

  // Starts with the sphere on the plane, e3 tilted by theta0 about the world x axis, spinning at n0
  // about e3, its centre of mass at rest.
  TippeState initial(double theta0, double n0) const {
    const Quat q(Eigen::AngleAxisd(theta0, Vec3::UnitX()));
    const Vec3 e3 = q * Vec3::UnitZ();
    const Vec3 G = Vec3(0, 0, p_.R) - p_.a() * e3;
    const Vec3 L = p_.I3 * n0 * e3;  // w = n0 e3 is a principal axis: L = I3 w
    return {G.x(), G.y(), G.z(), 0, 0, 0, q.w(), q.x(), q.y(), q.z(), L.x(), L.y(), L.z()};
  }

  // Everything derived from a state: forces, angular velocity, and the derivative.
  struct Eval {
    Vec3 e3, w, r, vP;
    double N = 0;
    TippeState dy{};
  };
  Eval eval(const TippeState& y) const {
    Eval e;
    const Quat q(y[6], y[7], y[8], y[9]);
    const Mat3 Rm = q.normalized().toRotationMatrix();
    const Vec3 Ib(p_.I1, p_.I1, p_.I3);
    const Mat3 Iinv = Rm * Ib.cwiseInverse().asDiagonal() * Rm.transpose();
    const Vec3 v(y[3], y[4], y[5]);
    const Vec3 L(y[10], y[11], y[12]);
    const Vec3 z = Vec3::UnitZ();
    e.e3 = Rm.col(2);
    e.w = Iinv * L;
    e.r = p_.a() * e.e3 - p_.R * z;  // P - G
    e.vP = v + e.w.cross(e.r);
    Vec3 vh = e.vP - e.vP.dot(z) * z;
    const Vec3 u = vh / std::max(vh.norm(), p_.eps);
    const Vec3 f = z - p_.mu * u;  // contact force per unit normal force
    const Vec3 A1 = Iinv * e.r.cross(f);
    const Vec3 A0 = -(Iinv * e.w.cross(L));
    const double lhs = 1.0 / p_.m + p_.a() * z.dot(A1.cross(e.e3));
    const double rhs = p_.g - p_.a() * z.dot(A0.cross(e.e3) + e.w.cross(e.w.cross(e.e3)));
    e.N = rhs / lhs;
    const Vec3 acc = e.N * f / p_.m - p_.g * z;
    const Quat dq = Quat(0, e.w.x(), e.w.y(), e.w.z()) * q;
    const Vec3 dL = e.r.cross(e.N * f);
    e.dy = {v.x(),        v.y(),        v.z(),        acc.x(), acc.y(), acc.z(), 0.5 * dq.w(),
            0.5 * dq.x(), 0.5 * dq.y(), 0.5 * dq.z(), dL.x(),  dL.y(),  dL.z()};
    return e;
  }

  TippeSample sample(double t, const TippeState& y) const {
    const Eval e = eval(y);
    TippeSample s;
    s.t = t;
    s.theta = std::acos(std::clamp(e.e3.z(), -1.0, 1.0));
    const Vec3 L(y[10], y[11], y[12]);
    s.jellett = L.dot(-e.r);
    const Vec3 v(y[3], y[4], y[5]);
    s.energy = 0.5 * p_.m * v.squaredNorm() + 0.5 * e.w.dot(L) + p_.m * p_.g * y[2];
    s.normal = e.N;
    s.slip = e.vP.norm();
    return s;
  }

  // Integrates from y at t = 0 to t_end, returning a sample every `every` seconds (steps end
  // exactly on the sample times). `steps` counts accepted steps.
  std::vector<TippeSample> run(TippeState y, double t_end, double every, double tol = 1e-11,
                               long* steps = nullptr) const {
    std::vector<TippeSample> out{sample(0, y)};
    double t = 0, h = 1e-5, next = every;
    long accepted = 0;
    while (t < t_end - 1e-12) {
      const double target = std::min(next, t_end);
      const double hh = std::min(h, target - t);
      const bool clipped = hh < h;
      TippeState y1;
      double err = 0;
      dp45(y, hh, y1, err, tol);
      if (err <= 1.0) {
        t += hh;
        y = y1;
        normalise(y);
        ++accepted;
        if (std::fabs(t - target) < 1e-12) {
          t = target;
          out.push_back(sample(t, y));
          next += every;
        }
      }
      // Standard step-size control for a 5th-order pair: safety 0.9, exponent 1/5, growth <= 5.
      const double fac = err > 0 ? 0.9 * std::pow(err, -0.2) : 5.0;
      const double h_new = hh * std::clamp(fac, 0.2, 5.0);
      // A step cut short to land on a sample time does not shrink the next one.
      h = (err <= 1.0 && clipped) ? std::max(h, h_new) : h_new;
    }
    if (steps) *steps = accepted;
    return out;
  }

 private:
  static void normalise(TippeState& y) {
    const double n = std::sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9]);
    for (int i = 6; i < 10; ++i) y[i] /= n;
  }

  // One Dormand-Prince 5(4) step of size h; err is the scaled error norm (<= 1: accept).
  void dp45(const TippeState& y, double h, TippeState& y5, double& err, double tol) const {
    static constexpr double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
    static constexpr double A[7][6] = {
        {0, 0, 0, 0, 0, 0},
        {1.0 / 5, 0, 0, 0, 0, 0},
        {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
        {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
        {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
        {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
        {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
    // Fifth-order weights (the last row of A, FSAL) minus the embedded fourth-order ones.
    static constexpr double E[7] = {71.0 / 57600,      0,          -71.0 / 16695, 71.0 / 1920,
                                    -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
    (void)c;  // autonomous system: the stage times are not needed
    std::array<TippeState, 7> k;
    k[0] = eval(y).dy;
    for (int s = 1; s < 7; ++s) {
      TippeState ys = y;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < 13; ++i) ys[i] += h * A[s][j] * k[j][i];
      if (s == 6) y5 = ys;
      k[s] = eval(ys).dy;
    }
    // Error scaled per component by tol (absolute) plus tol times its magnitude, with a floor
    // per kind of variable so that tiny components (a velocity near zero) do not demand more than
    // the others: positions by R, velocities by R n, the quaternion by 1, L by I3 n (n = 100/s).
    const double sx = p_.R, sv = p_.R * 100, sL = p_.I3 * 100;
    double e2 = 0;
    for (int i = 0; i < 13; ++i) {
      double d = 0;
      for (int j = 0; j < 7; ++j) d += E[j] * k[j][i];
      d *= h;
      const double floor = i < 3 ? sx : (i < 6 ? sv : (i < 10 ? 1.0 : sL));
      const double sc = tol * (floor + std::max(std::fabs(y[i]), std::fabs(y5[i])));
      e2 += (d / sc) * (d / sc);
    }
    err = std::sqrt(e2 / 13);
  }

  TippeTop p_;
};

}  // namespace simreel::test
