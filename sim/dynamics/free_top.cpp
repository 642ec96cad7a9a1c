#include "sim/dynamics/free_top.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace simreel {

double elliptic_K(double m) {
  if (!(m >= 0 && m < 1)) throw std::domain_error("elliptic_K: parameter m must be in [0, 1)");
  double a = 1.0, b = std::sqrt(1.0 - m);
  for (int i = 0; i < 40 && std::fabs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return std::numbers::pi / (2.0 * a);
}

namespace {
// Carlson's symmetric integral R_F(x, y, z) by duplication (Carlson 1995, algorithm 1).
double carlson_rf(double x, double y, double z) {
  for (int i = 0; i < 100; ++i) {
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lam = sx * (sy + sz) + sy * sz;
    x = 0.25 * (x + lam), y = 0.25 * (y + lam), z = 0.25 * (z + lam);
    const double mu = (x + y + z) / 3.0;
    const double dx = 1 - x / mu, dy = 1 - y / mu, dz = 1 - z / mu;
    if (std::fmax(std::fabs(dx), std::fmax(std::fabs(dy), std::fabs(dz))) < 1e-4) {
      const double e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
      // Truncation error of this series ~ (1e-4)^6: far below double rounding.
      return (1 - e2 / 10 + e3 / 14 + e2 * e2 / 24 - 3 * e2 * e3 / 44) / std::sqrt(mu);
    }
  }
  return (x + y + z) / 3.0;  // not reached for valid input
}
}  // namespace

double elliptic_F(double phi, double m) {
  // F(phi + n pi) = F(phi) + 2 n K, and F on [-pi/2, pi/2] is sin(phi) R_F(cos^2, 1 - m sin^2, 1).
  const double n = std::round(phi / std::numbers::pi);
  const double psi = phi - n * std::numbers::pi;
  const double s = std::sin(psi), c = std::cos(psi);
  return 2.0 * n * elliptic_K(m) + s * carlson_rf(c * c, 1.0 - m * s * s, 1.0);
}

JacobiSnCnDn jacobi(double u, double m) {
  if (m < 1e-300) return {std::sin(u), std::cos(u), 1.0};
  // Descending Landen transformation via the AGM (A&S 16.4.3).
  double a[32], c[32];
  a[0] = 1.0;
  double b = std::sqrt(1.0 - m);
  c[0] = std::sqrt(m);
  int n = 0;
  while (n < 30 && std::fabs(c[n]) > 1e-16) {
    a[n + 1] = 0.5 * (a[n] + b);
    c[n + 1] = 0.5 * (a[n] - b);
    b = std::sqrt(a[n] * b);
    ++n;
  }
  double phi = std::ldexp(a[n] * u, n);
  for (int k = n; k > 0; --k) phi = 0.5 * (phi + std::asin(c[k] / a[k] * std::sin(phi)));
  const double sn = std::sin(phi), cn = std::cos(phi);
  return {sn, cn, std::sqrt(1.0 - m * sn * sn)};
}

FreeTop::FreeTop(const Vec3& I, const Vec3& w0) : I_(I) {
  if (!(I[0] < I[1] && I[1] < I[2])) throw std::domain_error("FreeTop needs strictly ascending moments");
  const double E2 = (I.array() * w0.array() * w0.array()).sum();              // 2E
  const double L2 = (I.array() * I.array() * w0.array() * w0.array()).sum();  // |L|^2
  E_ = 0.5 * E2;
  L_ = std::sqrt(L2);
  Vec3 J = I, u = w0;
  swapped_ = L2 < E2 * I[1];
  if (swapped_) {
    // Reverse the axis order. Euler's equations then run backwards in time, and the descending
    // moments flip the sign of lambda in the same formulas: the two cancel, tau = s3 lambda t + tau0.
    J = Vec3(I[2], I[1], I[0]);
    u = Vec3(w0[2], w0[1], w0[0]);
  }
  a_ = std::sqrt((E2 * J[2] - L2) / (J[0] * (J[2] - J[0])));
  b_ = std::sqrt((E2 * J[2] - L2) / (J[1] * (J[2] - J[1])));
  c_ = std::sqrt((L2 - E2 * J[0]) / (J[2] * (J[2] - J[0])));
  lambda_ = std::sqrt((J[2] - J[1]) * (L2 - E2 * J[0]) / (J[0] * J[1] * J[2]));
  m_ = (J[1] - J[0]) * (E2 * J[2] - L2) / ((J[2] - J[1]) * (L2 - E2 * J[0]));
  if (!(m_ >= 0 && m_ < 1)) throw std::domain_error("FreeTop: motion on the separatrix (infinite period)");
  K_ = elliptic_K(m_);
  s3_ = u[2] < 0 ? -1.0 : 1.0;
  const double phi0 = std::atan2(b_ > 0 ? u[1] / b_ : 0.0, a_ > 0 ? u[0] / a_ : 1.0);
  tau0_ = elliptic_F(phi0, m_);
}

Vec3 FreeTop::angular_velocity(double t) const {
  const JacobiSnCnDn j = jacobi(s3_ * lambda_ * t + tau0_, m_);
  const Vec3 u(a_ * j.cn, b_ * j.sn, s3_ * c_ * j.dn);
  return swapped_ ? Vec3(u[2], u[1], u[0]) : u;
}

double FreeTop::flip_half_period() const {
  return 2.0 * K_ / lambda_;
}

double symmetric_top_body_precession(double It, double I3, double w3) {
  return (I3 - It) * w3 / It;
}
double symmetric_top_space_precession(double It, double L_norm) {
  return L_norm / It;
}

}  // namespace simreel
