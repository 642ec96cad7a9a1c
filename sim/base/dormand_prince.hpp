// The Dormand-Prince RK5(4)7M pair (Dormand & Prince, "A family of embedded Runge-Kutta formulae",
// J. Comp. Appl. Math. 6 (1980)): seven stages, the 7th evaluated at the new state (first same as
// last); kB gives the 5th-order solution, kB - kBstar the error estimate's weights. The adaptive
// integrators of mechanisms (sim/joints/articulation.cpp) and of rolling bodies
// (sim/solver/rolling_contact.cpp) share it.
#pragma once
#include <algorithm>
#include <cmath>

namespace simreel::dopri {

constexpr double kC[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
constexpr double kA[7][6] = {{},
                             {1.0 / 5},
                             {3.0 / 40, 9.0 / 40},
                             {44.0 / 45, -56.0 / 15, 32.0 / 9},
                             {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
                             {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
                             {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
constexpr double kB[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
constexpr double kBstar[7] = {5179.0 / 57600, 0,       7571.0 / 16695, 393.0 / 640, -92097.0 / 339200,
                              187.0 / 2100,   1.0 / 40};

// Step-size factor from an error norm (1 = at tolerance): Hairer, Norsett & Wanner I, II.4, safety
// 0.9, growth within [0.2, 5].
inline double step_factor(double err) {
  return std::clamp(0.9 * std::pow(std::max(err, 1e-10), -0.2), 0.2, 5.0);
}

}  // namespace simreel::dopri
