// Time integrators: each advances a range of bodies by one fixed step h under a uniform
// acceleration g and each body's wrench (held constant over the step). All work in the principal
// frame P, where the inertia tensor is diagonal.
//
// | name       | order | conserves (torque free)                  | cost/step | use it for |
// |------------|-------|------------------------------------------|-----------|---------------------------------|
// | seed       | 1     | world angular velocity (wrongly: no      | lowest    | comparison with the article |
// |            |       | gyroscopic term, never precesses)        |           | | | euler_gyro | 1     |
// nothing exactly; implicit gyroscopic     | low       | contact-heavy scenes (later)    | |            | |
// term damps energy instead of exploding   |           |                                 | | rk4        | 4
// | nothing exactly; drift O(h^4)            | 4 evals   | smooth motion, general torques  | | splitting  | 2
// | world L exactly, |L| exactly, energy     | 5 sincos  | very long runs                  | |            |
// | error bounded (symplectic)               |           |                                 | | auto       | 4
// | per body: exact for isotropic bodies     | <= rk4    | default                         | |            |
// | without torque, rk4 otherwise            |           |                                 | Linear motion:
// seed and euler_gyro use semi-implicit Euler (v += h a; x += h v), as the article; the others the exact
// update for a constant acceleration (x += h v + h^2/2 a; v += h a).
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include "sim/state.hpp"

namespace simreel {

enum class Integrator { automatic, seed, euler_gyro, rk4, splitting };
const char* to_string(Integrator i);
std::optional<Integrator> integrator_from_name(std::string_view name);
const char* integrator_names();  ///< "auto, seed, euler_gyro, rk4, splitting"

// Largest rotation of the fast variables per (sub)step that `auto` accepts before it substeps,
// rad. Measured on a box at 1000 rad/s: 0.5 gives 2e-2 energy error over 10 s, 0.2 gives 2e-4, 0.1
// gives 7e-6. R1 at dt >= 1/60 (0.083 rad) takes single steps.
constexpr double kAutoMaxStepAngle = 0.1;
constexpr int kAutoMaxSubsteps = 4096;

// Advances bodies idx[0..n) by h. `wrench` may be null (no applied force or torque this step).
void integrate(Integrator method, const int* idx, int n, MotionState* state, const BodyModel* model,
               const Wrench* wrench, const Vec3& g, double h);

// Orientation increment for a constant body angular velocity w over h: exp(h w / 2) as a unit
// quaternion. Zero w gives the identity (the article's normalise-zero-vector NaN avoided).
Quat rotation_increment(const Vec3& w, double h);

}  // namespace simreel
