// The simulated world: bodies as plain arrays reached by index, advanced by a fixed step.
//
// World::step() is the pipeline, each stage timed into Profile when profiling is on:
//   1. forces     user force fields into the accumulators (skipped: none exist yet; gravity is a
//                 uniform acceleration applied inside integration, so it costs no pass)
//   2. integrate  the selected integrator over the dynamic bodies (static bodies are never visited)
//   4. check      NaN/inf guard over the new state; stops the run naming the body and time (run in
//                 the same pass over each thread's bodies as 2, while they are in its cache)
//   3. clear      zero the force/torque accumulators (skipped unless something was applied)
//   5. derived    world inverse inertia for consumers that need it every step (skipped unless
//                 requested; contacts will)
// Thread count never changes results: bodies are split into fixed contiguous chunks and each body
// is advanced independently.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/body.hpp"
#include "sim/contact_settings.hpp"
#include "sim/integrators.hpp"
#include "sim/state.hpp"

namespace simreel {

struct WorldConfig {
  double dt = 1.0 / 240.0;               ///< s, fixed step
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< m/s^2
  Integrator integrator = Integrator::automatic;
  int threads = 1;  ///< worker threads for integration (results identical)
  ContactSettings contacts;
  /// Pairs of body indices that never collide with each other (scene: simulation.ignore_pairs).
  std::vector<std::pair<int, int>> ignore_pairs;
};

// A non-finite value appeared in the state.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Stage { forces, integrate, clear, check, derived, count };
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
};

class WorkerPool;

class World {
 public:
  // Validates every body (positive mass, valid inertia, finite, unit quaternion); throws InputError.
  World(const WorldConfig& config, std::vector<BodyDef> bodies);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  void step();
  double time() const { return (double)steps_ * cfg_.dt; }  ///< s, steps * dt (no accumulated rounding)
  long steps() const { return steps_; }
  const WorldConfig& config() const { return cfg_; }
  int body_count() const { return (int)defs_.size(); }
  int dynamic_count() const { return (int)dynamic_.size(); }
  const BodyDef& def(int i) const { return defs_[i]; }
  const BodyModel& model(int i) const { return model_[i]; }
  const MotionState& state(int i) const { return state_[i]; }

  // ---- The article's RigidBody interface, by body index (sim/README.md maps the names).
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
  void set_linear_velocity(int i, const Vec3& v_W) { state_[i].v_W = v_W; }
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
  double kinetic_energy() const;        ///< J
  double potential_energy() const;      ///< J, uniform gravity, zero at the world origin
  Vec3 total_momentum() const;          ///< kg m/s
  Vec3 total_angular_momentum() const;  ///< kg m^2/s about the system's centre of mass
  // Throws StateError naming the body and time if any state value is not finite.
  void check_state() const;
  // Bodies whose spin |w| dt exceeds `max_angle` rad per step; each named once in warnings().
  void check_spin(double max_angle = 0.5);
  const std::vector<std::string>& warnings() const { return warnings_; }

  void set_profiling(bool on) { profiling_ = on; }
  const Profile& profile() const { return profile_; }
  // Ask for the world inverse inertia to be refreshed every step (stage 5).
  void keep_world_inertia(bool on) { keep_derived_ = on; }
  const Mat3& cached_inverse_inertia_world(int i) const { return inv_I_W_[i]; }

 private:
  bool stage_integrate_and_check();  ///< false if a non-finite value appeared
  void stage_clear();
  template <typename F>
  void for_each_chunk(F& f);
  void stage_derived();
  Wrench& wrench(int i);

  WorldConfig cfg_;
  std::vector<BodyDef> defs_;
  std::vector<BodyModel> model_;
  std::vector<MotionState> state_;
  std::vector<Wrench> wrench_;
  std::vector<Mat3> inv_I_W_;
  std::vector<int> dynamic_;  ///< indices of dynamic bodies, ascending
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
  bool keep_derived_ = false;
  bool profiling_ = false;
  long steps_ = 0;
  Profile profile_;
  std::unique_ptr<WorkerPool> pool_;
};

}  // namespace simreel
