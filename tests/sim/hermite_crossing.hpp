// Where a sampled function crosses zero between two samples: the root in [t0, t1] of the cubic
// Hermite interpolant through (t0, s0, s0') and (t1, s1, s1') (error O(h^4), far below an
// integrator's at the steps used), found by bisection. Needs s0 < 0 <= s1. Shared by the forces
// tests and bench/forces_accuracy.
#pragma once

namespace simreel::test {

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

}  // namespace simreel::test
