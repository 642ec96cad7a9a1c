// Closed-form motion of a torque-free rigid body (the "free top"): body angular velocity from
// Jacobi's elliptic functions, and the intermediate-axis flip period. References: Landau &
// Lifshitz, Mechanics, 3rd ed., section 37; Abramowitz & Stegun 16.4 (sn, cn, dn by the
// arithmetic-geometric mean), 17.6 (K by the AGM); Carlson, Numer. Algorithms 10 (1995) (R_F).
// These are the references tests and benchmarks compare the integrators against.
#pragma once
#include <simreel/math.hpp>

namespace simreel {

double elliptic_K(double m);              ///< complete elliptic integral of the first kind, parameter m = k^2
double elliptic_F(double phi, double m);  ///< incomplete, any real phi
struct JacobiSnCnDn {
  double sn, cn, dn;
};
JacobiSnCnDn jacobi(double u, double m);  ///< 0 <= m < 1

// Torque-free body with principal moments I (strictly ascending) and initial body angular
// velocity w0 (principal frame). w(t) = (a cn, b sn, c dn)(s lambda t + tau0) up to the axis
// order, which swaps to (c dn, b sn, a cn) when the body rotates on the minor-axis side of the
// separatrix (L^2 < 2 E I2).
class FreeTop {
 public:
  FreeTop(const Vec3& I, const Vec3& w0);
  Vec3 angular_velocity(double t) const;  ///< rad/s, principal frame
  double flip_half_period() const;        ///< s, 2 K(m) / lambda: w2 goes from +max to -max
  double modulus_m() const { return m_; }
  double energy() const { return E_; }         ///< J
  double momentum_norm() const { return L_; }  ///< kg m^2/s

 private:
  Vec3 I_;
  bool swapped_ = false;
  double a_ = 0, b_ = 0, c_ = 0, lambda_ = 0, m_ = 0, K_ = 0, tau0_ = 0, s3_ = 1, E_ = 0, L_ = 0;
};

// Torque-free symmetric top (I1 = I2 = It, I3): the body-frame angular velocity precesses about
// the symmetry axis at (I3 - It) w3 / It, and the symmetry axis precesses about L in the world at
// |L| / It (Landau & Lifshitz section 33).
double symmetric_top_body_precession(double It, double I3, double w3);
double symmetric_top_space_precession(double It, double L_norm);

}  // namespace simreel
