// Contact solver settings (scene key `simulation.contacts`; docs/contacts.md explains each
// and why its default was chosen).
#pragma once

namespace simreel {

// Automatic substeps (substeps: 0): at least kContactSubstepRate substeps per second, and more
// while a body in contact turns faster than kContactMaxSubstepAngle per substep, up to
// kContactMaxSubsteps a step.
constexpr double kContactSubstepRate = 960;       ///< 1/s: 4 substeps of the default 1/240 s step
constexpr double kContactMaxSubstepAngle = 0.05;  ///< rad
constexpr int kContactMaxSubsteps = 16;

// Impacts: a substep in which a point that was apart at its start is struck at more than
// kImpactSpeed gets one more solve sweep, and the substeps of the next kImpactSettleTime one more
// solve and relax sweep each (docs/contacts.md "Impacts"). Gauss-Seidel moves an impulse one contact
// per sweep: with one sweep, the R3 pile's top layers landing (5 m/s) pushed the layers below
// 2.9 mm into each other; with these, 0.91 mm, for 25 struck substeps in its 10 s (1/60 s of
// settling: 1.03 mm; two more sweeps instead of one: no better).
constexpr double kImpactSpeed = 0.5;              ///< m/s, normal approach speed
constexpr double kImpactSettleTime = 1.0 / 30.0;  ///< s

struct ContactSettings {
  int substeps = 0;                  ///< solver substeps per step; 0: automatic (see above)
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
  // Continuous collision (docs/continuous-collision.md): bodies moving more than half their
  // smallest width in a step, and bodies flagged `bullet`, are swept and stopped before they pass
  // through anything. Scene: simulation.contacts.continuous.
  bool continuous = true;
  // Sleeping (docs/sleeping.md): a group of touching bodies whose every point has moved
  // slower than sleep_speed for sleep_time stops being stepped until something wakes it.
  bool sleep = true;          ///< scene: simulation.sleep
  double sleep_speed = 0.01;  ///< m/s, |v| + |w| r (r: the body's farthest shape point)
  double sleep_time = 0.5;    ///< s
};

}  // namespace simreel
