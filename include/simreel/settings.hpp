// The settings a World is built with: the step, gravity, the free-flight integrator, the contact
// solver's settings, ignored pairs and applied forces (scene keys under `simulation:`;
// docs/contacts.md and docs/integrators.md explain each and why its default was chosen).
#pragma once
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include <simreel/forces.hpp>
#include <simreel/joints.hpp>
#include <simreel/math.hpp>

namespace simreel {

// Free-flight integrators (docs/integrators.md: order, conservation, cost, use of each):
//   seed        1st order, no gyroscopic term: never precesses (kept for comparison)
//   euler_gyro  1st order, implicit gyroscopic term (Catto 2015, Bullet): stable, damps energy
//   rk4         4th order on (q, w_P), renormalised
//   splitting   2nd order symplectic (DLM 1997): world L and |L| exact, energy error bounded
//   automatic   the default: exact rotation for isotropic torque-free bodies, rk4 otherwise,
//               substeps for fast spinners
enum class Integrator { automatic, seed, euler_gyro, rk4, splitting };
const char* to_string(Integrator i);
std::optional<Integrator> integrator_from_name(std::string_view name);
const char* integrator_names();  ///< "auto, seed, euler_gyro, rk4, splitting"

// The contact solver (scene key `simulation.contacts`): Box2D v3's soft step in double precision.
struct ContactSettings {
  /// solver substeps per step; 0: automatic, at least 960 a second (4 of a 1/240 s step) and more,
  /// up to 16 a step, while a body in contact turns more than 0.05 rad a substep
  int substeps = 0;
  int iterations = 1;                ///< solve and relax iterations per substep
  int passes = 8;                    ///< most Gauss-Seidel passes over a resting manifold's points a sweep
  double contact_hertz = 120;        ///< Hz, stiffness of the soft contact (at most 1/4 of the substep rate)
  double damping_ratio = 10;         ///< dimensionless, of the soft contact
  double max_push_out = 3;           ///< m/s, fastest speed at which overlap is removed
  double restitution_threshold = 1;  ///< m/s, approach speeds below this do not bounce
  double speculative_distance = 0.02;  ///< m, contacts are created this far before touching
  double linear_slop = 0.0001;         ///< m, overlap left uncorrected (keeps resting contacts quiet)
  double rolling_resistance = 0;       ///< dimensionless (lever per unit radius), 0 = off
  /// m/s: sliding friction below this slip speed is viscous, mu N v / slip_speed, instead of sticking
  /// (the regularised Coulomb law of tippe-top models: a spinning contact patch never sticks); 0 = off
  double slip_speed = 0;
  /// Rolling without slip (docs/contacts.md, "Rolling contact"): a smooth shape (sphere,
  /// ellipsoid, a capsule's end, a cylinder's rim) touching a fixed flat surface at one point, not
  /// slipping, is stepped as the rolling constraint's exact equations of motion by an adaptive
  /// 5th-order integrator instead of the soft solver's substeps (which lose energy to the curving
  /// contact); false: the soft solver for every contact. Off by itself with rolling resistance or
  /// a slip speed (they are the soft solver's).
  bool rolling = true;
  double rolling_tolerance = 1e-10;  ///< dimensionless, local error per internal step (relative)
  // Continuous collision (docs/continuous-collision.md): bodies moving more than half their
  // smallest width in a step, and bodies flagged `bullet`, are swept and stopped before they pass
  // through anything. Scene: simulation.contacts.continuous.
  bool continuous = true;
  /// A body with at least this many colliding shapes enters the broad phase once, with a tree of
  /// its shapes inside (a compound: sim/collision/compound.hpp); 0: never. Speed only: the pairs
  /// found, and so every result, are the same whatever it is.
  int compound_shapes = 8;
  // Sleeping (docs/sleeping.md): a group of touching bodies whose every point has moved
  // slower than sleep_speed for sleep_time stops being stepped until something wakes it.
  bool sleep = true;          ///< scene: simulation.sleep
  double sleep_speed = 0.01;  ///< m/s, |v| + |w| r (r: the body's farthest shape point)
  double sleep_time = 0.5;    ///< s
};

// What a World is built with (World's constructor takes it with the bodies).
struct WorldConfig {
  double dt = 1.0 / 240.0;                        ///< s, fixed step
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);           ///< m/s^2
  Integrator integrator = Integrator::automatic;  ///< for bodies whose BodyDef names none
  int threads = 1;  ///< worker threads for the step's parallel stages (results identical whatever the count)
  /// Whether the workers may run a stage on the calling thread alone while the machine is too busy
  /// for them to meet (timing only, never results). Off in the thread-count tests, so that their
  /// runs are split among the threads whatever the load.
  bool thread_backoff = true;
  ContactSettings contacts;
  /// Pairs of body indices that never collide with each other (scene: simulation.ignore_pairs).
  std::vector<std::pair<int, int>> ignore_pairs;
  /// Applied forces (scene: forces), by body index; checked when the World is built (InputError).
  std::vector<ForceDef> forces;
  /// Joints between bodies (scene: joints), by body index; checked when the World is built.
  std::vector<JointDef> joints;
  JointSettings joint_settings;  ///< scene: simulation.joints
};

}  // namespace simreel
