// What a World measured while it stepped: the time and run count of each pipeline stage (when
// profiling is on), what the integrate stage does with each body, and contact figures. The stages,
// in the order World::step runs them, are described in docs/step.md.
#pragma once

namespace simreel {

enum class Stage {
  forces,
  update_broad_phase,
  collide,
  roll,
  prepare_contacts,
  integrate_velocities,
  warm_start,
  solve,
  integrate_positions,
  relax,
  restitution,
  store_impulses,
  joints,
  integrate,
  check,
  continuous,
  sleep,
  clear,
  count
};
const char* to_string(Stage s);

struct Profile {
  double seconds[(int)Stage::count] = {};  ///< wall time spent per stage
  long runs[(int)Stage::count] = {};       ///< steps in which the stage did work
  long skipped[(int)Stage::count] = {};    ///< steps in which it had nothing to do
  long steps = 0;
  // What the integrate stage does with each body (fixed when the world is built):
  int static_bodies = 0;      ///< never visited
  int isotropic_bodies = 0;   ///< dynamic under `auto` with isotropic inertia: no gyroscopic work
  int gyroscopic_bodies = 0;  ///< dynamic, full rotational dynamics
  int kinematic_bodies = 0;   ///< moved at their given velocity
  int forced_bodies = 0;      ///< dynamic under auto/rk4 with forces: RK4 evaluating forces per stage
  int jointed_bodies = 0;     ///< dynamic bodies in mechanisms: moved by their joints' coordinates
  long joint_steps = 0;       ///< the mechanisms' internal integration steps, summed over steps
  int forces = 0;             ///< entries of the force list
  int shapes = 0;             ///< colliding shapes (planes included)
  long pairs = 0;             ///< candidate pairs from the broad phase, summed over steps
  long fat_box_moves = 0;     ///< shapes that left their fat box (a tree update and query each), summed
  long contact_points = 0;    ///< manifold points, summed over steps
  long solver_bodies = 0;     ///< bodies stepped by the contact solver, summed over steps
  long rolling_bodies = 0;    ///< bodies stepped as rolling on a fixed surface, summed over steps
  long sweeps = 0;            ///< the contact solver's solve and relax sweeps, summed over steps
  long impact_substeps = 0;   ///< substeps with an impact (one more sweep: kImpactSpeed)
  long body_warm_starts = 0;  ///< substeps warm-started per body (ContactSolver::warm_start)
  long pool_runs = 0;         ///< parallel stage runs handed to the worker pool (threads > 1)
  long pool_alone_runs = 0;  ///< of which run on the calling thread alone (sim/base/worker_pool.hpp back-off)
  long swept_bodies = 0;     ///< fast or bullet bodies swept by the continuous stage, summed over steps
  long toi_pairs = 0;        ///< shape pairs whose time of impact was computed, summed over steps
  long toi_hits = 0;         ///< swept bodies moved back to their time of impact, summed over steps
  // The narrow phase by pair kind [a][b], a <= b in narrow_kind_name's order: calls and wall time
  // (timed only with profiling on), summed over steps; which pairs a scene's collide time goes to.
  static constexpr int kNarrowKinds = 8;
  long narrow_calls[kNarrowKinds][kNarrowKinds] = {};
  double narrow_seconds[kNarrowKinds][kNarrowKinds] = {};
};
/// "plane", "sphere", "capsule", "cylinder", "ellipsoid", "box", "hull" (a moving mesh's convex
/// hull), "mesh" (a static mesh's triangles): the kinds of Profile::narrow_calls.
const char* narrow_kind_name(int k);

// What contact did over the run (simulate --json).
struct ContactStats {
  int contacts_max = 0;        ///< most manifold points in one step
  double max_penetration = 0;  ///< m, deepest overlap seen at the start of a step
};

}  // namespace simreel
