// Time integrators: each advances a range of bodies by one fixed step h under a uniform
// acceleration g and each body's wrench (held constant over the step). All work in the principal
// frame P, where the inertia tensor is diagonal. docs/integrators.md tabulates order, conservation,
// measured cost and use; in short:
//   seed        1st order, the article's scheme: no gyroscopic term, never precesses. Comparison.
//   euler_gyro  1st order, implicit gyroscopic term (Catto 2015, Bullet): stable, damps energy.
//   rk4         4th order on (q, w_P), renormalised; torque-free bodies four per vector.
//   splitting   2nd order symplectic (DLM 1997): world L and |L| exact, energy error bounded.
//   auto        the default: exact rotation for isotropic torque-free bodies, rk4 otherwise,
//               substeps for fast spinners.
// Linear motion: seed and euler_gyro use semi-implicit Euler (v += h a; x += h v), as the article;
// the others the exact update for a constant acceleration (x += h v + h^2/2 a; v += h a).
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include <simreel/settings.hpp>

#include "sim/dynamics/state.hpp"

namespace simreel {


// Largest rotation of the fast variables per (sub)step that `auto` accepts before it substeps,
// rad. Measured on a box at 1000 rad/s: 0.5 gives 2e-2 energy error over 10 s, 0.2 gives 2e-4, 0.1
// gives 7e-6. R1 at dt >= 1/60 (0.083 rad) takes single steps.
constexpr double kAutoMaxStepAngle = 0.1;
constexpr int kAutoMaxSubsteps = 4096;

// Advances bodies idx[0..n) by h. `wrench` may be null (no applied force or torque this step).
void integrate(Integrator method, const int* idx, int n, MotionState* state, const BodyModel* model,
               const Wrench* wrench, const Vec3& g, double h);

// Time derivative of one body's full state y = (x_W, v_W, q_WP (w, x, y, z), w_P), 13 doubles,
// under gravity g and the wrench w (dy: the same layout): x' = v, v' = g + f / m,
// q' = q (x) (0, w_P) / 2, w_P' = I^-1 (R^T tau - w_P x I w_P) (no gyroscopic term for isotropic
// bodies, where it vanishes). The forced RK4 of World evaluates it at every stage.
void state_derivative(const double* y, const BodyModel& m, const Wrench& w, const Vec3& g, double* dy);

// Orientation increment for a constant body angular velocity w over h: exp(h w / 2) as a unit
// quaternion. Zero w gives the identity (the article's normalise-zero-vector NaN avoided).
Quat rotation_increment(const Vec3& w, double h);

}  // namespace simreel
