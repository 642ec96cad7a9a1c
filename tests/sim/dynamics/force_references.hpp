// References the forces tests and bench/forces_accuracy measure against.
#pragma once
#include <cmath>

#include <simreel/math.hpp>

namespace simreel::test {

// Where a sampled function crosses zero between two samples: the root in [t0, t1] of the cubic
// Hermite interpolant through (t0, s0, s0') and (t1, s1, s1') (error O(h^4), far below an
// integrator's at the steps used), found by bisection. Needs s0 < 0 <= s1.

inline double hermite_zero(double t0, double s0, double d0, double t1, double s1, double d1) {
  const double h = t1 - t0;
  auto p = [&](double u) {
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * s0 + (u3 - 2 * u2 + u) * h * d0 + (-2 * u3 + 3 * u2) * s1 +
           (u3 - u2) * h * d1;
  };
  double lo = 0, hi = 1;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (p(mid) < 0 ? lo : hi) = mid;
  }
  return t0 + 0.5 * (lo + hi) * h;
}

// Velocity at time t of a body (mass m, from rest) pushed by a body-frame force F along its x that
// turns it about z at the constant angular acceleration alpha (the thrust's own torque, started
// at rest): v(t) = F/m integral_0^t (cos th, sin th, 0) ds with th = alpha s^2 / 2, a Fresnel
// integral, by Simpson's rule on 200000 intervals (error O(h^4), far below the 1e-9 tested).
inline Vec3 offset_thrust_velocity(double F, double m, double alpha, double t) {
  const int n = 200000;
  double cx = 0, cy = 0;
  for (int j = 0; j <= n; ++j) {
    const double s = t * j / n, th = 0.5 * alpha * s * s;
    const double wgt = (j == 0 || j == n) ? 1 : (j % 2 ? 4 : 2);
    cx += wgt * std::cos(th);
    cy += wgt * std::sin(th);
  }
  return F / m * t / (3.0 * n) * Vec3(cx, cy, 0);
}

}  // namespace simreel::test
