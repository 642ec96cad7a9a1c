// The simulated world: bodies as plain arrays reached by index, advanced by a fixed step.
//
// World::step() is the pipeline (Box2D v3's b2World_Step, Box3D's solver stages), each stage an
// entry of `Stage`, timed into Profile when profiling is on and counted as skipped when it had
// nothing to do:
//   forces               the scene's forces (sim/dynamics/forces.hpp) into the accumulators at the step's
//                        start, through apply_force / apply_torque; impulses due applied once
//                        (skipped when there are none; gravity is applied inside integration)
//   update_broad_phase   world boxes of the awake colliding shapes, dynamic tree -> candidate pairs
//   collide              narrow phase on each pair -> manifolds matched to last step's by feature
//                        id (warm-start impulses carried over): the contact set (contact_set.hpp)
//   prepare_contacts     solver bodies (world frame, fresh R I^-1 R^T) and constraints for the
//                        bodies in contact this step
//   per substep: integrate_velocities, warm_start, solve, integrate_positions, relax
//   restitution, store_impulses, then the solved bodies' motion is written back
//   integrate            the free-flight integrators over the dynamic bodies touching nothing this
//                        step (static bodies are never visited), kinematic bodies at their velocity;
//                        bodies under forces with `auto` or `rk4` by one RK4 over all of them that
//                        evaluates the forces again at every stage (docs/forces.md)
//   check                NaN/inf guard over the new state; stops the run naming the body and time
//   clear                zero the force/torque accumulators (skipped unless something was applied)
//   derived              world inverse inertia for consumers that need it every step
// A scene without colliding shapes skips every contact stage and pays nothing for them.
// Thread count never changes results: free-flight bodies are split into fixed contiguous chunks
// and each body is advanced independently; the narrow phase writes each pair into its own slot;
// the contact solver goes colour by colour through a colouring of its constraints that depends on
// the contact list alone (sim/solver/constraint_graph.hpp, docs/threads.md).
#pragma once
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/world.hpp>

#include "sim/base/stage_clock.hpp"
#include "sim/collision/body_extents.hpp"
#include "sim/collision/broad_phase.hpp"
#include "sim/collision/compound.hpp"
#include "sim/collision/contact.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/collision/time_of_impact.hpp"
#include "sim/dynamics/forces.hpp"
#include "sim/dynamics/integrators.hpp"
#include "sim/dynamics/state.hpp"
#include "sim/joints/articulation.hpp"
#include "sim/solver/contact_settings.hpp"
#include "sim/solver/contact_solver.hpp"
#include "sim/solver/rolling_contact.hpp"
#include "sim/world/applied_forces.hpp"
#include "sim/world/contact_set.hpp"
#include "sim/world/continuous.hpp"
#include "sim/world/islands.hpp"

namespace simreel {

class WorkerPool;

class WorldImpl {
 public:
  // Validates every body (positive mass, valid inertia, finite, unit quaternion); throws InputError.
  WorldImpl(const WorldConfig& config, std::vector<BodyDef> bodies);
  ~WorldImpl();
  WorldImpl(const WorldImpl&) = delete;
  WorldImpl& operator=(const WorldImpl&) = delete;

  void step();
  double time() const { return (double)steps_ * cfg_.dt; }  ///< s, steps * dt (no accumulated rounding)
  long steps() const { return steps_; }
  const WorldConfig& config() const { return cfg_; }
  int body_count() const { return (int)defs_.size(); }
  int dynamic_count() const { return (int)dynamic_.size(); }
  BodyType type(int i) const { return defs_[i].type; }
  const BodyDef& def(int i) const { return defs_[i]; }
  const BodyModel& model(int i) const { return model_[i]; }
  const MotionState& state(int i) const { return state_[i]; }

  // ---- The article's RigidBody interface, by body index (docs/bodies.md maps the names).
  const Vec3& local_centroid(int i) const { return model_[i].c_B; }  ///< m, body frame
  const Vec3& centroid(int i) const { return state_[i].x_W; }        ///< m, world
  Vec3 origin_position(int i) const;                                 ///< UpdatePositionFromGlobalCentroid
  void set_origin_position(int i, const Vec3& p_W);                  ///< UpdateGlobalCentroidFromPosition
  Quat orientation(int i) const;                                     ///< q_WB, body to world
  void set_orientation(int i, const Quat& q_WB);                     ///< keeps the centroid, normalises
  Mat3 rotation(int i) const { return orientation(i).toRotationMatrix(); }  ///< R_WB
  Mat3 inverse_rotation(int i) const { return rotation(i).transpose(); }    ///< R_BW
  Vec3 local_to_world(int i, const Vec3& p_B) const;                        ///< point, m
  Vec3 world_to_local(int i, const Vec3& p_W) const;                        ///< point, m
  Vec3 local_to_world_vec(int i, const Vec3& v_B) const;                    ///< direction: rotation only
  Vec3 world_to_local_vec(int i, const Vec3& v_W) const;
  const Vec3& linear_velocity(int i) const { return state_[i].v_W; }  ///< m/s, of the centroid
  void set_linear_velocity(int i, const Vec3& v_W) {
    require_unjointed(i, "set its velocity");
    wake(i);
    state_[i].v_W = v_W;
  }
  Vec3 angular_velocity(int i) const { return state_[i].q_WP * state_[i].w_P; }  ///< rad/s, world
  void set_angular_velocity(int i, const Vec3& w_W);
  Vec3 angular_momentum(int i) const;       ///< kg m^2/s about the centroid, world
  Mat3 inverse_inertia_world(int i) const;  ///< R I_local^-1 R^T, 1/(kg m^2) (article erratum fixed)
  Mat3 inertia_world(int i) const;          ///< R I_local R^T, kg m^2, about the centroid
  // Force f_W (N) at world point at_W (m): torque (at - centroid) x f about the centroid.
  void apply_force(int i, const Vec3& f_W, const Vec3& at_W);
  void apply_force_local(int i, const Vec3& f_B, const Vec3& at_B);  ///< both in the body frame
  void apply_central_force(int i, const Vec3& f_W);                  ///< at the centroid, no torque
  void apply_torque(int i, const Vec3& tau_W);                       ///< N m, world
  void apply_impulse(int i, const Vec3& J_W, const Vec3& at_W);      ///< N s at a world point, instant
  void apply_angular_impulse(int i, const Vec3& dL_W);               ///< N m s, instant
  void normalize_orientation(int i);  ///< UpdateOrientation: re-orthonormalise via the quaternion

  // ---- Whole-world quantities (dynamic bodies only).
  double kinetic_energy() const;  ///< J
  double potential_energy()
      const;                    ///< J, uniform gravity (zero at the world origin) + springs' k (L - L0)^2 / 2
  Vec3 total_momentum() const;  ///< kg m/s
  Vec3 total_angular_momentum() const;  ///< kg m^2/s about the system's centre of mass
  // Throws StateError naming the body and time if any state value is not finite.
  void check_state() const;
  // Bodies whose spin |w| dt exceeds `max_angle` rad per step; each named once in warnings().
  void check_spin(double max_angle = 0.5);
  const std::vector<std::string>& warnings() const { return warnings_; }

  // ---- Save and restore (sim/world/snapshot.hpp): the whole state between two steps. restore_state
  // throws InputError for a file from another scene or version, or a damaged one.
  void save_state(std::ostream& os) const;
  void restore_state(std::istream& is);
  uint64_t fingerprint() const;  ///< of the model: what a saved state must match

  // ---- Contacts.
  const ShapeTable& shapes() const { return *shapes_; }
  /// The records that may act this step (at least one side awake, or kinematic), by (shape a,
  /// shape b); a pair with a static triangle mesh may have several, consecutive.
  const std::vector<Contact>& contacts() const { return contacts_.active(); }
  /// The records of pairs whose two sides are asleep or static, by (shape a, shape b): kept as
  /// they were when the pair fell asleep, untouched until a side wakes (ContactSet::collide).
  const std::vector<Contact>& resting_contacts() const { return contacts_.resting(); }
  /// f(const Contact&) for the records of both lists, merged in key order (the one list the
  /// sequential pass keeps; what a saved state holds).
  template <class F>
  void for_each_contact(F&& f) const {
    contacts_.for_each(std::forward<F>(f));
  }
  const ContactStats& contact_stats() const { return contacts_.stats(); }
  bool has_contacts() const { return collide_enabled_; }  ///< false: contact stages always skipped
  int substeps() const { return substeps_; }              ///< contact solver substeps per step (resolved)
  const ContactSolver& contact_solver() const { return solver_; }  ///< the last step's (tests)

  // ---- Sleeping (islands.hpp): a sleeping body is not stepped; touching it, a force,
  // an impulse or setting its pose or velocity wakes it with the bodies it slept with.
  bool asleep(int i) const { return islands_.asleep(i); }
  int sleeping_count() const { return islands_.sleeping(); }
  void wake(int i) { islands_.wake(i); }

  // ---- Joints (sim/joints/articulation.hpp): mechanisms in joint coordinates.
  const Articulations& joints() const { return joints_; }
  bool jointed(int i) const { return joints_.jointed(i); }

  // ---- Applied forces (config().forces).
  bool has_forces() const { return !cfg_.forces.empty(); }
  bool impulse_applied(int k) const { return forces_.fired(k); }  ///< force k (an impulse) was applied

  void set_profiling(bool on) { clock_.set_timing(on); }
  const Profile& profile() const { return profile_; }

 private:
  bool stage_integrate_and_check();  ///< false if a non-finite value appeared
  void init_forces();
  bool stage_forces();  ///< false: nothing to do this step
  void init_contacts();
  bool bodies_may_touch(int a, int b) const;   ///< not one body, not both static, not ignored
  bool shapes_may_touch(int a, int b) const;   ///< their bodies may, and their filters allow
  bool proxies_may_touch(int a, int b) const;  ///< broad-phase entries: shapes, then compounds
  void make_shape_box(int i);                  ///< poses_, margins_ and boxes_ of shape i this step
  void stage_broad_phase();
  void place_compound(int c);     ///< compound c's box this step, from its body's state
  const Aabb& member_box(int k);  ///< compound shape k's pose, margin and box this step, made once
  // The broad phase's pairs with compounds replaced by their shapes' pairs whose boxes overlap (for
  // a plane: reach its side), merged in key order.
  void expand_compounds(std::vector<uint64_t>& pairs);
  void after_restore(std::vector<double> still,
                     std::vector<int> asleep);  ///< caches of the broad phase and the islands
  ContactSet::Step collide_step() const;        ///< what the collide stage reads of the world this step
  void refresh_free_lists();
  bool stage_solve_contacts();  ///< false if a non-finite value appeared
  void stage_kinematic();
  void init_sleep();
  void stage_sleep();
  void init_continuous();
  bool stage_continuous();  ///< false: nothing was fast
  /// static, asleep, or kinematic at rest: neither moves nor wakes (Islands::inert)
  bool inert(int i) const { return islands_.inert(i, model_[i], state_[i]); }
  void stage_clear();
  void init_joints();
  bool stage_joints();  ///< false if a mechanism's state stopped being finite
  // Jointed bodies move with their mechanism's coordinates: a pose or velocity set on one alone
  // would be overwritten by the next step (InputError naming the body and `what`).
  void require_unjointed(int i, const char* what) const;
  template <typename F>
  void for_each_chunk(F& f);
  Wrench& wrench(int i);

  WorldConfig cfg_;
  std::vector<BodyDef> defs_;
  std::vector<BodyModel> model_;
  std::vector<MotionState> state_;
  std::vector<Wrench> wrench_;
  std::vector<int> dynamic_;            ///< indices of dynamic bodies, ascending
  std::vector<int> unjointed_dynamic_;  ///< the dynamic bodies no joint holds (with joints only)
  std::vector<int> solver_bodies_;      ///< this step's bodies in contact that the free solver steps
  std::vector<int> kinematic_;          ///< indices of kinematic bodies, ascending
  struct Group {
    Integrator method;
    std::vector<int> bodies;  ///< ascending
  };
  std::vector<Group> groups_;    ///< dynamic bodies by integrator, in order of first use
  struct alignas(64) ChunkSum {  // one cache line per thread
    double value = 0;
  };
  std::vector<ChunkSum> chunk_sum_;
  std::vector<char> spin_warned_;
  std::vector<std::string> warnings_;
  bool wrench_dirty_ = false;
  long steps_ = 0;
  Profile profile_;
  StageClock clock_{profile_};  ///< times and counts the stages into profile_
  std::unique_ptr<WorkerPool> pool_;

  // ---- Applied forces (sim/dynamics/forces.hpp, forces_stage.cpp).
  AppliedForces forces_;

  // ---- Joints (sim/joints/articulation.hpp): the mechanisms and their coordinates.
  Articulations joints_;
  std::vector<std::pair<int, int>> joint_bonds_;  ///< each mechanism's bodies, paired (one island)

  // ---- Contact data (sim/collision/shape_table.hpp, broad_phase.hpp, contact.hpp, contact_solver.hpp).
  std::unique_ptr<ShapeTable> shapes_;
  BodyExtents extents_;  ///< shape ranges, reaches and widths (built with shapes_)
  bool collide_enabled_ = false;
  std::vector<int> sweep_shapes_, plane_shapes_;  ///< non-plane and plane colliding shapes
  std::vector<Pose> plane_poses_;
  std::vector<char> shape_moving_;  ///< per shape: its body is not static
  std::vector<Aabb> boxes_;         ///< per shape, this step
  std::vector<double> margins_;     ///< per shape: m, how far boxes_ reach past the shape
  std::vector<Vec3> drift_;         ///< per shape: m, v dt at this step's start (fat boxes' lead)
  // Per moving shape in a pair this step, its world pose, made once by the broad phase for the
  // narrow phase (pose_step_: broad_step_ when made). Only those: among 100,000 falling boxes with
  // no pair, writing every shape's pose was 96 bytes a body-step streamed to memory for nothing.
  std::vector<Pose> poses_;
  std::vector<long> pose_step_;
  // Compound bodies (sim/collision/compound.hpp). The broad phase's entries are the shapes not in
  // a compound (by shape index) and the compounds (shape count + compound index); boxes_, drift_
  // and proxy_moving_ have a slot for each. A compound's shapes get margins_ and boxes_
  // only where a pair needs them (member_box), stamped with the broad phase's step.
  CompoundProxies compounds_;
  std::vector<int> sweep_proxies_;  ///< the broad phase's entries that are not planes
  std::vector<char> proxy_moving_;  ///< per entry: its body is not static
  std::vector<long> box_step_;      ///< per shape: broad_step_ when member_box made its box
  std::vector<long> placed_step_;   ///< per compound: broad_step_ when placed
  long broad_step_ = 0;
  std::vector<uint64_t> expanded_, merged_pairs_, dormant_expanded_;
  std::vector<std::pair<int, int>> ignore_;  ///< body pairs, (lo, hi), sorted
  BroadPhase broad_;
  std::vector<int> active_shapes_;  ///< this step: moving shapes of awake bodies, then those to freeze
  int settle_substeps_ = 0;         ///< substeps left with one more sweep after an impact (saved state)

  // ---- Islands and sleeping (islands.hpp).
  Islands islands_;
  std::vector<int> fell_asleep_;  ///< bodies that fell asleep this step (scratch)

  // ---- The contact set (contact_set.hpp): candidate pairs, the narrow phase, the kept records,
  // the bodies in contact (saved state: the records and the statistics).
  ContactSet contacts_;

  // ---- The contact solver's step (sim/solver/contact_solver.hpp), and the bodies it leaves to the
  // free-flight integrators.
  std::vector<int> solver_index_;    ///< per body, this step (0: not in the solver)
  RollingContacts rolling_;          ///< bodies rolling on a fixed surface (sim/solver/rolling_contact.hpp)
  std::vector<char> rolled_;         ///< per body: rolled this step (not the solver's)
  std::vector<int> rolled_list_;     ///< the bodies that rolled this step, ascending
  std::vector<char> roll_excluded_;  ///< per body: may not roll (jointed)
  std::vector<char> touched_none_;   ///< per solver body: received no impulse this step
  int substeps_ = 1;                 ///< contact solver substeps this step
  int base_substeps_ = 1;            ///< the least (settings, or 1/240 s substeps)
  std::vector<std::vector<int>> free_;  ///< per group: its bodies not in contact this step
  ContactSolver solver_;

  // ---- Continuous collision (continuous.hpp): start poses and sweeps; nothing a saved state needs.
  ContinuousCollision ccd_;
};

}  // namespace simreel
