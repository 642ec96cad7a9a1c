// The simulated world: bodies built from BodyDefs, advanced by a fixed step, read and pushed by
// body index (0 .. body_count() - 1, in the order the bodies were given).
//
// Frames and units: include/simreel/math.hpp. A body's origin is the point its BodyDef's p_WB
// placed (the model's own origin); its centre of mass (`centroid`) is what moves freely. Its
// principal frame P has its origin at the centre of mass and its axes along the principal axes of
// inertia, moments ascending.
//
// step() runs the pipeline: applied forces, broad phase, narrow phase, the contact solver's
// substeps, free-flight integration, the NaN guard, continuous collision, sleeping (docs/step.md
// describes each stage). A World's state lives behind a private implementation, so
// that a program built on this header does not recompile when the engine's internals change.
#pragma once
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/contacts.hpp>
#include <simreel/error.hpp>
#include <simreel/math.hpp>
#include <simreel/profile.hpp>
#include <simreel/settings.hpp>

namespace simreel {

class WorldImpl;

class World {
 public:
  /// Validates every body (positive mass, valid inertia, finite, unit quaternion) and every applied
  /// force; throws InputError naming the body or force.
  World(const WorldConfig& config, std::vector<BodyDef> bodies);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// One fixed step of config().dt. Throws StateError naming the body and time if a value of the
  /// state stopped being finite.
  void step();
  double time() const;  ///< s, steps() * dt (no accumulated rounding)
  long steps() const;
  const WorldConfig& config() const;
  int body_count() const;
  int dynamic_count() const;
  BodyType type(int i) const;
  const BodyDef& def(int i) const;  ///< as given (colliders, name, start state)

  // ---- Mass properties (fixed when the world is built).
  double mass(int i) const;                    ///< kg (static and kinematic: their colliders' mass)
  const Vec3& local_centroid(int i) const;     ///< m, centre of mass in the body frame B
  const Vec3& principal_moments(int i) const;  ///< kg m^2, ascending
  const Quat& principal_axes(int i) const;     ///< q_BP: the principal frame P in the body frame B
  Mat3 inertia_world(int i) const;             ///< R I_local R^T, kg m^2, about the centroid
  Mat3 inverse_inertia_world(int i) const;     ///< R I_local^-1 R^T, 1/(kg m^2)

  // ---- Pose and motion.
  const Vec3& centroid(int i) const;                      ///< m, centre of mass, world
  Vec3 origin_position(int i) const;                      ///< m, the body origin, world
  void set_origin_position(int i, const Vec3& p_W);       ///< moves the body so its origin is at p_W
  Quat orientation(int i) const;                          ///< q_WB, body to world
  void set_orientation(int i, const Quat& q_WB);          ///< keeps the centroid, normalises
  Quat principal_orientation(int i) const;                ///< q_WP, principal frame to world
  Mat3 rotation(int i) const;                             ///< R_WB
  Mat3 inverse_rotation(int i) const;                     ///< R_BW
  Vec3 local_to_world(int i, const Vec3& p_B) const;      ///< point, m
  Vec3 world_to_local(int i, const Vec3& p_W) const;      ///< point, m
  Vec3 local_to_world_vec(int i, const Vec3& v_B) const;  ///< direction: rotation only
  Vec3 world_to_local_vec(int i, const Vec3& v_W) const;
  const Vec3& linear_velocity(int i) const;             ///< m/s, of the centroid, world
  void set_linear_velocity(int i, const Vec3& v_W);     ///< wakes the body
  Vec3 angular_velocity(int i) const;                   ///< rad/s, world
  void set_angular_velocity(int i, const Vec3& w_W);    ///< wakes the body
  Vec3 angular_velocity_body(int i) const;              ///< rad/s, in the body frame B
  const Vec3& angular_velocity_principal(int i) const;  ///< rad/s, in the principal frame P
  Vec3 angular_momentum(int i) const;                   ///< kg m^2/s about the centroid, world
  void normalize_orientation(int i);                    ///< re-orthonormalise through the quaternion

  // ---- Pushing bodies. Forces and torques act over the next step and are then cleared; impulses
  // act at once. Each wakes the body.
  void apply_force(int i, const Vec3& f_W, const Vec3& at_W);        ///< N at a world point, m
  void apply_force_local(int i, const Vec3& f_B, const Vec3& at_B);  ///< both in the body frame
  void apply_central_force(int i, const Vec3& f_W);                  ///< at the centroid, no torque
  void apply_torque(int i, const Vec3& tau_W);                       ///< N m, world
  void apply_impulse(int i, const Vec3& J_W, const Vec3& at_W);      ///< N s at a world point
  void apply_angular_impulse(int i, const Vec3& dL_W);               ///< N m s
  bool has_forces() const;                                           ///< the config's force list is not empty
  bool impulse_applied(int k) const;  ///< config().forces[k] (an impulse) has been applied

  // ---- Whole-world quantities (dynamic bodies only).
  double kinetic_energy() const;        ///< J
  double potential_energy() const;      ///< J, uniform gravity (zero at the world origin) + springs
  Vec3 total_momentum() const;          ///< kg m/s
  Vec3 total_angular_momentum() const;  ///< kg m^2/s about the system's centre of mass
  void check_state() const;             ///< throws StateError naming the body and time if not finite
  /// Bodies turning more than `max_angle` rad per step; each named once in warnings().
  void check_spin(double max_angle = 0.5);
  const std::vector<std::string>& warnings() const;

  // ---- Contacts.
  bool has_contacts() const;  ///< some pair of colliders can touch (else every contact stage is skipped)
  int substeps() const;       ///< contact solver substeps of the last step
  /// Appends every pair that touched in the last step (sleeping pairs included, as they were when
  /// they fell asleep) to `out`, in pair order; returns how many it appended.
  int contacts(std::vector<ContactData>& out) const;
  /// Appends the pairs body i touched in the last step, each with body i on side b: the normal
  /// points into body i and the forces are those on it. Returns how many it appended.
  int body_contacts(int i, std::vector<ContactData>& out) const;
  const ContactStats& contact_stats() const;

  // ---- Joints (config().joints, docs/joints.md). Coordinates are zero in the start pose.
  int joint_count() const;
  int find_joint(std::string_view name) const;  ///< index, or -1
  /// Coordinate k of joint j: rad (revolute; universal k = 0, 1; spherical: the rotation angle from
  /// the start pose) or m (prismatic).
  double joint_position(int j, int k = 0) const;
  double joint_speed(int j, int k = 0) const;  ///< its rate, rad/s or m/s (spherical: |relative w|)
  /// The generalised force that coordinate k of joint j's limits, motor and friction apply,
  /// N m or N, at the end of the last step (0 for a joint without them); spherical: the torque of
  /// its motor and friction about the child's axis k = 0, 1, 2.
  double joint_force(int j, int k = 0) const;
  /// The force (N) and torque (N m) that joint j's parent exerts on its child through the joint,
  /// at the anchor, world frame, at the end of the last step: what holds the joint together plus
  /// its spring, stops, motor and friction (the child exerts the opposite on the parent), from the
  /// mechanism's equations at its current state (a contact's push on the mechanism is not in it).
  void joint_reaction(int j, Vec3& force_W, Vec3& torque_W) const;
  /// The largest distance between the two anchor points of any joint, m (0 up to round-off: the
  /// mechanisms move in joint coordinates), and the largest angle between hinge or slider axes or
  /// by which a ball joint's swing or twist is past its stop, rad.
  double joint_gap() const;
  double joint_angular_gap() const;

  // ---- Sleeping: a sleeping body is not stepped; touching it, a force, an impulse or setting its
  // pose or velocity wakes it with the bodies it slept with.
  bool asleep(int i) const;
  int sleeping_count() const;
  void wake(int i);

  // ---- Save and restore the whole state between two steps: a resumed run equals a straight
  // one bit for bit. restore_state throws InputError for a file from another scene or version, or
  // a damaged one.
  void save_state(std::ostream& os) const;
  void restore_state(std::istream& is);
  uint64_t fingerprint() const;  ///< of the model: what a saved state must match

  void set_profiling(bool on);  ///< time each stage into profile()
  const Profile& profile() const;

  /// The private implementation (sim/world/world_impl.hpp): for simreel's own libraries and tests.
  WorldImpl& impl() { return *impl_; }
  const WorldImpl& impl() const { return *impl_; }

 private:
  std::unique_ptr<WorldImpl> impl_;
};

}  // namespace simreel
