// Contact solver settings (scene key `simulation.contacts`; sim/README.md "Contacts" explains each
// and why its default was chosen).
#pragma once

namespace simreel {

// Automatic substeps (substeps: 0) keep every body in contact under this rotation per substep.
constexpr double kContactMaxSubstepAngle = 0.05;  ///< rad
constexpr int kContactMaxSubsteps = 16;

struct ContactSettings {
  int substeps = 0;           ///< solver substeps per step; 0: automatic (<= 1/240 s, more for fast spin)
  int iterations = 1;         ///< solve iterations per substep (and relax iterations)
  double contact_hertz = 30;  ///< Hz, stiffness of the soft contact constraint
  double damping_ratio = 10;  ///< dimensionless, of the soft contact constraint
  double max_push_out = 3;    ///< m/s, fastest speed at which overlap is removed
  double restitution_threshold = 1;    ///< m/s, approach speeds below this do not bounce
  double speculative_distance = 0.02;  ///< m, contacts are created this far before touching
  double linear_slop = 0.0005;         ///< m, overlap left uncorrected (keeps resting contacts quiet)
  double rolling_resistance = 0;       ///< dimensionless (m of lever per m of radius), 0 = off
};

}  // namespace simreel
