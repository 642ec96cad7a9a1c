#include "sim/world/world_impl.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "sim/base/enum_names.hpp"
#include "sim/base/worker_pool.hpp"

namespace simreel {

namespace {
constexpr EnumNames<Stage, (std::size_t)Stage::count> kStages{
    {"forces", "update_broad_phase", "collide", "roll", "prepare_contacts", "integrate_velocities",
     "warm_start", "solve", "integrate_positions", "relax", "restitution", "store_impulses", "joints",
     "integrate", "check", "continuous", "sleep", "clear"}};
static_assert(kStages.complete());
}  // namespace

const char* to_string(Stage s) {
  return kStages(s);
}

namespace {

std::string body_label(const std::vector<BodyDef>& defs, int i) {
  return "body " + std::to_string(i) + " ('" + defs[i].name + "')";
}

}  // namespace

WorldImpl::WorldImpl(const WorldConfig& config, std::vector<BodyDef> bodies)
    : cfg_(config), defs_(std::move(bodies)) {
  if (!(cfg_.dt > 0) || !std::isfinite(cfg_.dt)) throw InputError("timestep must be a positive number");
  if (!all_finite(cfg_.gravity)) throw InputError("gravity must be finite");
  if (cfg_.threads < 1) throw InputError("threads must be at least 1");
  const int n = (int)defs_.size();
  model_.resize(n);
  state_.resize(n);
  wrench_.resize(n);
  spin_warned_.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    const BodyDef& d = defs_[i];
    BodyModel& m = model_[i];
    MotionState& s = state_[i];
    if (!all_finite(d.p_WB) || !all_finite(d.v_W) || !all_finite(d.w_W) || !d.q_WB.coeffs().allFinite())
      throw InputError(body_label(defs_, i) + ": initial state is not finite");
    if (std::fabs(d.q_WB.norm() - 1.0) > 1e-6)
      throw InputError(body_label(defs_, i) + ": orientation quaternion is not unit length (norm " +
                       std::to_string(d.q_WB.norm()) + ")");
    if (d.colliders.empty() && !d.mass_override && d.type != BodyType::static_body)
      throw InputError(body_label(defs_, i) + " has no colliders (and no stated mass properties)");
    m.is_static = d.type == BodyType::static_body;
    m.is_kinematic = d.type == BodyType::kinematic;
    // Planes have no mass, nor have a static body's meshes (triangle meshes, sim/geometry/trimesh.hpp); a
    // static body made of those only is massless (it never moves).
    std::vector<Collider> massive;
    for (const Collider& c : d.colliders)
      if (c.shape != ShapeKind::plane &&
          !(m.is_static && c.shape == ShapeKind::mesh && c.props_C.mass == 0) &&
          !(!c.collide && c.props_C.mass == 0))  // drawn only (an imported link's visual shape)
        massive.push_back(c);
    // Stated mass properties weigh a body with no massive collider (an imported link that has an
    // inertial and nothing that collides).
    const bool weighed = !massive.empty() || (d.mass_override && !m.is_static);
    if (!weighed && !m.is_static)
      throw InputError(body_label(defs_, i) +
                       (d.colliders.empty() ? ": a moving body needs colliders or stated mass properties"
                                            : ": a plane collider needs a static body"));
    const MassProperties mp = !weighed          ? MassProperties{}
                              : d.mass_override ? *d.mass_override
                                                : compose(massive);
    if (weighed) {
      if (!d.mass_override)
        for (size_t k = 0; k < d.colliders.size(); ++k)
          if (d.colliders[k].shape != ShapeKind::plane && d.colliders[k].props_C.mass == 0 &&
              d.colliders[k].props_C.inertia.hasNaN() &&
              !(m.is_static && d.colliders[k].shape == ShapeKind::mesh))
            throw InputError(body_label(defs_, i) + ": collider " + std::to_string(k) +
                             " has no mass properties: make it with box_collider(size, density), "
                             "sphere_collider(radius, density), ..., mesh_collider(mesh, density), or set "
                             "its props_C (primitive_mass(collider, density))");
      if (!(mp.mass > 0) || !std::isfinite(mp.mass))
        throw InputError(body_label(defs_, i) + ": mass must be positive");
      const std::string bad = d.mass_override ? mass_problem(mp, 1e-7) : inertia_problem(mp.inertia, 1e-7);
      if (!bad.empty()) throw InputError(body_label(defs_, i) + ": " + bad);
      const PrincipalAxes pa = principal_axes(mp.inertia);
      m.mass = mp.mass;
      m.c_B = mp.com;
      m.I_P = pa.moments;
      m.q_BP = Quat(pa.R).normalized();
    }
    const bool dynamic = d.type == BodyType::dynamic;
    m.inv_mass = dynamic ? 1.0 / m.mass : 0.0;
    m.inv_I_P = dynamic ? Vec3(m.I_P.cwiseInverse()) : Vec3::Zero();
    const Vec3& I = m.I_P;
    m.isotropic = (I.maxCoeff() - I.minCoeff()) <= 1e-12 * I.maxCoeff();
    if (dynamic)
      m.gyro_rate = std::max(
          {1.0, std::fabs(I[1] - I[2]) / I[0], std::fabs(I[2] - I[0]) / I[1], std::fabs(I[0] - I[1]) / I[2]});
    const Quat q_WB = d.q_WB.normalized();
    s.q_WP = (q_WB * m.q_BP).normalized();
    s.x_W = d.p_WB + q_WB * m.c_B;
    s.v_W = m.is_static ? Vec3::Zero() : d.v_W;
    s.w_P = m.is_static ? Vec3::Zero() : Vec3(s.q_WP.conjugate() * d.w_W);
    if (m.is_static) {
      profile_.static_bodies++;
    } else if (m.is_kinematic) {
      profile_.kinematic_bodies++;
      kinematic_.push_back(i);
    } else {
      dynamic_.push_back(i);
      const Integrator method = d.integrator.value_or(cfg_.integrator);
      const bool no_gyro = m.isotropic && method == Integrator::automatic;
      (no_gyro ? profile_.isotropic_bodies : profile_.gyroscopic_bodies)++;
      auto g =
          std::find_if(groups_.begin(), groups_.end(), [&](const Group& x) { return x.method == method; });
      if (g == groups_.end()) g = groups_.insert(groups_.end(), Group{method, {}});
      g->bodies.push_back(i);
    }
  }
  if (cfg_.threads > 1) pool_ = std::make_unique<WorkerPool>(cfg_.threads, cfg_.thread_backoff);
  chunk_sum_.resize(cfg_.threads);
  islands_.reset(model_);  // everyone awake (init_contacts collides once)
  init_joints();           // before init_forces and init_contacts: it takes jointed bodies out of groups_
  init_forces();           // before init_contacts: it takes bodies under forces out of groups_
  init_contacts();
  init_sleep();  // after init_contacts: needs the shapes
  init_continuous();
  check_spin();
}

WorldImpl::~WorldImpl() = default;

void WorldImpl::init_joints() {
  if (cfg_.joints.empty()) return;
  // A spring from the force list that joins a jointed body to another dynamic body (and so on,
  // through a chain of springs) binds them into one mechanism: its force is then evaluated inside
  // the mechanism's steps with both ends' states.
  std::vector<char> in_joint(defs_.size(), 0);
  auto moving = [&](int b) {  // (indices are checked later, with the joints' and the forces' messages)
    return b >= 0 && b < (int)defs_.size() && model_[b].inv_mass > 0 && !model_[b].is_kinematic;
  };
  for (const JointDef& j : cfg_.joints)
    for (int b : {j.parent, j.child, j.type == JointType::pulley ? j.wheel : -1})
      if (moving(b)) in_joint[b] = 1;
  std::vector<std::pair<int, int>> bonds;
  for (bool grew = true; grew;) {
    grew = false;
    for (const ForceDef& f : cfg_.forces) {
      if (f.kind != ForceKind::spring || !moving(f.body) || !moving(f.body_b)) continue;
      if (in_joint[f.body] == in_joint[f.body_b]) continue;  // neither (free bodies' forces) or both
      in_joint[f.body] = in_joint[f.body_b] = 1;
      bonds.emplace_back(f.body, f.body_b);
      grew = true;
    }
  }
  for (const ForceDef& f : cfg_.forces)  // springs between two mechanisms join them
    if (f.kind == ForceKind::spring && moving(f.body) && moving(f.body_b) && in_joint[f.body] &&
        in_joint[f.body_b])
      bonds.emplace_back(f.body, f.body_b);
  joints_.build(cfg_.joints, cfg_.joint_settings, defs_, model_, state_, warnings_, bonds);
  // Two jointed bodies never collide unless the joint says so (a hinge's two leaves overlap).
  for (const JointDef& j : joints_.joints())
    if (!j.collide_connected && j.parent >= 0 && j.child >= 0)
      cfg_.ignore_pairs.emplace_back(j.parent, j.child);
  for (int i : dynamic_) {
    if (!joints_.jointed(i)) {
      unjointed_dynamic_.push_back(i);
      continue;
    }
    profile_.jointed_bodies++;
  }
  for (Group& g : groups_)
    g.bodies.erase(
        std::remove_if(g.bodies.begin(), g.bodies.end(), [&](int i) { return joints_.jointed(i); }),
        g.bodies.end());
}

// Mechanisms split into fixed contiguous ranges, one per thread (each mechanism is independent of
// the others: the same results whatever the thread count).
bool WorldImpl::stage_joints() {
  const Wrench* wr = wrench_dirty_ ? wrench_.data() : nullptr;
  // A sleeping mechanism (its island asleep: docs/sleeping.md) is not stepped.
  if (islands_.enabled())
    for (Mechanism& m : joints_.mechanisms())
      for (const Link& l : m.links)
        if (l.body >= 0) {
          m.asleep = islands_.asleep(l.body);
          break;
        }
  const int n = joints_.mechanism_count();
  if (!pool_ || n < 2) return joints_.step(cfg_.dt, cfg_.gravity, wr, state_.data());
  for (ChunkSum& s : chunk_sum_) s.value = 0;
  auto work = [&](int c, int nc) {
    int b, e;
    share(n, c, nc, b, e);
    chunk_sum_[c].value = joints_.step_range(b, e, cfg_.dt, cfg_.gravity, wr, state_.data()) ? 0.0 : 1.0;
  };
  for_each_chunk(work);
  profile_.pool_runs = pool_->runs();
  profile_.pool_alone_runs = pool_->alone_runs();
  bool ok = true;
  for (const ChunkSum& s : chunk_sum_) ok = ok && s.value == 0;
  return ok;
}

void WorldImpl::require_unjointed(int i, const char* what) const {
  if (joints_.jointed(i))
    throw InputError(body_label(defs_, i) + " is jointed: it moves with its joints' coordinates and cannot " +
                     what + " alone");
}

// ------------------------------------------------------------------ the step pipeline
void WorldImpl::step() {
  if (!joints_.empty()) joints_.set_time(time());  // the loads' windows
  if (cfg_.forces.empty())
    clock_.skipped(Stage::forces);  // gravity is applied in integration: no pass for it
  else
    clock_.run(Stage::forces, [&] { return stage_forces(); });
  bool finite = true;
  bool solved = false;
  if (ccd_.enabled())
    ccd_.save_start_poses(islands_.awake_bodies_unsorted(), state_.data());  // sweeps' start
  if (collide_enabled_) {
    clock_.run(Stage::update_broad_phase, [&] { stage_broad_phase(); });
    if (contacts_.idle())
      clock_.skipped(Stage::collide);  // nothing close, nothing was: no contact bodies either
    else
      clock_.run(Stage::collide, [&] { contacts_.collide(collide_step(), islands_, profile_); });
    solved = !contacts_.bodies().empty();
    if (solved) finite = stage_solve_contacts();
  } else {
    clock_.skipped(Stage::update_broad_phase);
    clock_.skipped(Stage::collide);
  }
  if (!solved) {
    for (Stage st : {Stage::prepare_contacts, Stage::integrate_velocities, Stage::warm_start, Stage::solve,
                     Stage::integrate_positions, Stage::relax, Stage::restitution, Stage::store_impulses})
      clock_.skipped(st);
  }
  if (joints_.empty()) {
    clock_.skipped(Stage::joints);
  } else {
    clock_.run(Stage::joints, [&] { finite = stage_joints() && finite; });
  }
  finite = stage_integrate_and_check() && finite;
  clock_.ran(Stage::integrate);
  clock_.ran(Stage::check);
  if (!kinematic_.empty()) stage_kinematic();
  if (ccd_.enabled() && finite)
    clock_.run(Stage::continuous, [&] { return stage_continuous(); });
  else
    clock_.skipped(Stage::continuous);
  if (islands_.enabled())
    clock_.run(Stage::sleep, [&] { stage_sleep(); });
  else
    clock_.skipped(Stage::sleep);
  ++steps_;
  if (!finite) check_state();  // throws, naming the body and the time
  if (!finite && joints_.exceeded_joint() >= 0) {
    std::ostringstream os;
    os << "joints: the mechanism of joint '" << joints_.joint(joints_.exceeded_joint()).name
       << "' needed more than " << cfg_.joint_settings.max_steps
       << " internal steps in the step ending at t = " << time()
       << " s (raise simulation.joints.max_steps, or the tolerance)";
    throw StateError(os.str());
  }
  if (wrench_dirty_)
    clock_.run(Stage::clear, [&] { stage_clear(); });
  else
    clock_.skipped(Stage::clear);
  profile_.steps++;
  if (!joints_.empty()) profile_.joint_steps = joints_.internal_steps();
}

// Runs f(chunk, chunks) once per thread, chunk 0 on the calling thread. Every group is split the
// same way each step (chunk c is always the same bodies), so a body's state stays in the cache of
// the core that integrates it. This is also why the check runs in the same pass: when the main
// thread alone checked every body after a two-thread integration, each step moved the other
// core's half of the state between caches and two threads ran no faster than one.
template <typename F>
void WorldImpl::for_each_chunk(F& f) {
  if (!pool_) {
    f(0, 1);
    return;
  }
  pool_->run([](void* p, int c, int nc) { (*static_cast<F*>(p))(c, nc); }, &f);
}

namespace {
// Group g's bodies that chunk c of nc integrates (worker_pool.hpp's share of them).
inline void chunk_range(const std::vector<int>& v, int c, int nc, const int*& begin, int& count) {
  int b, e;
  share((int)v.size(), c, nc, b, e);
  begin = v.data() + b;
  count = e - b;
}
}  // namespace

// Stages 2 (integrate) and 4 (check) in one pass over each thread's chunk. The check is one
// running sum over values every integrator writes: a NaN or inf anywhere in a body's state
// reaches its orientation or centroid within the step, and then the sum; only then are the
// bodies searched (check_state) to name the first bad one. Profile: integrate is timed on the
// calling thread up to the end of its own chunk, check from there until every thread is done.
bool WorldImpl::stage_integrate_and_check() {
  using clock = std::chrono::steady_clock;
  const Wrench* wr = wrench_dirty_ ? wrench_.data() : nullptr;
  const bool timing = clock_.timing();
  clock::time_point t0, t_mid;
  if (timing) t0 = clock::now();
  // Bodies under forces first, on this thread alone (one coupled system: a spring joins two).
  const bool forced_finite =
      forces_.forced().empty() ||
      forces_.integrate(time(), (double)(steps_ + 1) * cfg_.dt, cfg_.dt, cfg_.gravity, state_.data(),
                        model_.data(), contacts_.in_contact(), !contacts_.bodies().empty());
  // Bodies the contact solver stepped this step are left out (free_ holds the rest).
  const bool some_in_contact = !contacts_.bodies().empty();
  if (!some_in_contact && islands_.sleeping() > 0) {
    // Nothing was solved (free_ is stale) but some bodies sleep: the awake ones only.
    for (size_t g = 0; g < groups_.size(); ++g) {
      free_[g].clear();
      for (int i : groups_[g].bodies)
        if (!islands_.asleep(i)) free_[g].push_back(i);
    }
  }
  const bool some_left_out = some_in_contact || islands_.sleeping() > 0;
  auto list = [&](size_t g) -> const std::vector<int>& {
    return some_left_out ? free_[g] : groups_[g].bodies;
  };
  auto work = [&](int c, int nc) {
    for (size_t g = 0; g < groups_.size(); ++g) {
      const int* idx;
      int n;
      chunk_range(list(g), c, nc, idx, n);
      integrate(groups_[g].method, idx, n, state_.data(), model_.data(), wr, cfg_.gravity, cfg_.dt);
    }
    if (c == 0 && timing) t_mid = clock::now();
    double sum = 0;
    for (size_t g = 0; g < groups_.size(); ++g) {
      const int* idx;
      int n;
      chunk_range(list(g), c, nc, idx, n);
      for (int j = 0; j < n; ++j) {
        const MotionState& s = state_[idx[j]];
        sum += s.q_WP.w() + s.x_W.x() + s.x_W.y() + s.x_W.z();
      }
    }
    chunk_sum_[c].value = sum;
  };
  for (ChunkSum& s : chunk_sum_) s.value = 0;  // the pool may run it as one chunk (sim/base/worker_pool.hpp)
  for_each_chunk(work);
  if (timing) {
    const clock::time_point t1 = clock::now();
    clock_.add_seconds(Stage::integrate, std::chrono::duration<double>(t_mid - t0).count());
    clock_.add_seconds(Stage::check, std::chrono::duration<double>(t1 - t_mid).count());
  }
  bool finite = forced_finite;
  for (const ChunkSum& s : chunk_sum_) finite = finite && std::isfinite(s.value);
  return finite;
}

void WorldImpl::stage_clear() {
  for (Wrench& w : wrench_) w = Wrench{};
  wrench_dirty_ = false;
}

void WorldImpl::check_state() const {
  for (int i : dynamic_) {
    const MotionState& s = state_[i];
    const char* what = !s.q_WP.coeffs().allFinite() ? "orientation"
                       : !all_finite(s.x_W)         ? "position"
                       : !all_finite(s.v_W)         ? "linear velocity"
                       : !all_finite(s.w_P)         ? "angular velocity"
                                                    : nullptr;
    if (what) {
      std::ostringstream os;
      os << body_label(defs_, i) << ": " << what << " became non-finite (NaN or infinity) at t = " << time()
         << " s (step " << steps_ << ")";
      throw StateError(os.str());
    }
  }
}

void WorldImpl::check_spin(double max_angle) {
  for (int i : dynamic_) {
    // A jointed body's rotation is resolved by its mechanism's adaptive internal steps.
    if (joints_.jointed(i)) continue;
    const double a = state_[i].w_P.norm() * cfg_.dt;
    if (a > max_angle && !spin_warned_[i]) {
      spin_warned_[i] = 1;
      std::ostringstream os;
      os << body_label(defs_, i) << " turns " << a << " rad per step at t = " << time()
         << " s; the rotation is under-resolved, use a timestep below " << max_angle / state_[i].w_P.norm()
         << " s";
      warnings_.push_back(os.str());
    }
  }
}

// ------------------------------------------------------------------ the article's interface
Quat WorldImpl::orientation(int i) const {
  return state_[i].q_WP * model_[i].q_BP.conjugate();
}

void WorldImpl::set_orientation(int i, const Quat& q_WB) {
  require_unjointed(i, "set its orientation");
  const Vec3 p = origin_position(i);
  const Vec3 w = angular_velocity(i);
  state_[i].q_WP = (q_WB.normalized() * model_[i].q_BP).normalized();
  set_origin_position(i, p);
  set_angular_velocity(i, w);
}

Vec3 WorldImpl::origin_position(int i) const {
  return state_[i].x_W - orientation(i) * model_[i].c_B;
}

void WorldImpl::set_origin_position(int i, const Vec3& p_W) {
  require_unjointed(i, "set its position");
  wake(i);
  state_[i].x_W = p_W + orientation(i) * model_[i].c_B;
}

Vec3 WorldImpl::local_to_world(int i, const Vec3& p_B) const {
  return orientation(i) * p_B + origin_position(i);
}
Vec3 WorldImpl::world_to_local(int i, const Vec3& p_W) const {
  return orientation(i).conjugate() * (p_W - origin_position(i));
}
Vec3 WorldImpl::local_to_world_vec(int i, const Vec3& v_B) const {
  return orientation(i) * v_B;
}
Vec3 WorldImpl::world_to_local_vec(int i, const Vec3& v_W) const {
  return orientation(i).conjugate() * v_W;
}

void WorldImpl::set_angular_velocity(int i, const Vec3& w_W) {
  require_unjointed(i, "set its angular velocity");
  wake(i);
  state_[i].w_P = model_[i].is_static ? Vec3::Zero() : Vec3(state_[i].q_WP.conjugate() * w_W);
}

Vec3 WorldImpl::angular_momentum(int i) const {
  return state_[i].q_WP * Vec3(model_[i].I_P.cwiseProduct(state_[i].w_P));
}

Mat3 WorldImpl::inverse_inertia_world(int i) const {
  const Mat3 R = state_[i].q_WP.toRotationMatrix();
  return R * model_[i].inv_I_P.asDiagonal() * R.transpose();
}

Mat3 WorldImpl::inertia_world(int i) const {
  const Mat3 R = state_[i].q_WP.toRotationMatrix();
  return R * model_[i].I_P.asDiagonal() * R.transpose();
}

Wrench& WorldImpl::wrench(int i) {
  wrench_dirty_ = true;
  return wrench_[i];
}

void WorldImpl::apply_force(int i, const Vec3& f_W, const Vec3& at_W) {
  wake(i);
  Wrench& w = wrench(i);
  w.f_W += f_W;
  w.tau_W += (at_W - state_[i].x_W).cross(f_W);
}

void WorldImpl::apply_force_local(int i, const Vec3& f_B, const Vec3& at_B) {
  apply_force(i, local_to_world_vec(i, f_B), local_to_world(i, at_B));
}

void WorldImpl::apply_central_force(int i, const Vec3& f_W) {
  wake(i);
  wrench(i).f_W += f_W;
}

void WorldImpl::apply_torque(int i, const Vec3& tau_W) {
  wake(i);
  wrench(i).tau_W += tau_W;
}

void WorldImpl::apply_impulse(int i, const Vec3& J_W, const Vec3& at_W) {
  wake(i);
  if (model_[i].inv_mass == 0) return;
  if (joints_.jointed(i)) {  // through its mechanism's inertia
    joints_.apply_impulse(i, J_W, at_W, Vec3::Zero(), state_.data());
    return;
  }
  state_[i].v_W += model_[i].inv_mass * J_W;
  apply_angular_impulse(i, (at_W - state_[i].x_W).cross(J_W));
}

void WorldImpl::apply_angular_impulse(int i, const Vec3& dL_W) {
  wake(i);
  if (model_[i].inv_mass == 0) return;
  if (joints_.jointed(i)) {
    joints_.apply_impulse(i, Vec3::Zero(), state_[i].x_W, dL_W, state_.data());
    return;
  }
  state_[i].w_P += model_[i].inv_I_P.cwiseProduct(state_[i].q_WP.conjugate() * dL_W);
}

void WorldImpl::normalize_orientation(int i) {
  state_[i].q_WP.normalize();
}

// ------------------------------------------------------------------ whole-world quantities
double WorldImpl::kinetic_energy() const {
  double e = 0;
  for (int i : dynamic_) {
    const BodyModel& m = model_[i];
    const MotionState& s = state_[i];
    e += 0.5 * m.mass * s.v_W.squaredNorm() + 0.5 * s.w_P.dot(m.I_P.cwiseProduct(s.w_P));
  }
  if (!joints_.empty()) e += joints_.armature_energy();  // rotors turning with joint coordinates
  return e;
}

double WorldImpl::potential_energy() const {
  double e = 0;
  for (int i : dynamic_) e -= model_[i].mass * cfg_.gravity.dot(state_[i].x_W);
  // Springs acting now store k (L - L0)^2 / 2 (their dashpots and all other forces do work).
  const double t = time();
  for (const std::vector<int>* list : {&forces_.continuous(), &forces_.jointed()})
    for (int k : *list) {
      const ForceDef& f = forces_.list()[k];
      if (f.kind != ForceKind::spring || !(f.from <= t && t < f.to)) continue;
      const Vec3 a =
          f.at_centroid ? state_[f.body].x_W : body_point_W(state_[f.body], model_[f.body], f.at_B);
      const Vec3 b = f.body_b < 0      ? f.anchor_W
                     : f.at_b_centroid ? state_[f.body_b].x_W
                                       : body_point_W(state_[f.body_b], model_[f.body_b], f.at_b_B);
      const double s = (a - b).norm() - f.rest_length;
      e += 0.5 * f.stiffness * s * s;
    }
  if (!joints_.empty()) e += joints_.spring_energy();  // joint springs (revolute, prismatic, distance)
  return e;
}

Vec3 WorldImpl::total_momentum() const {
  Vec3 p = Vec3::Zero();
  for (int i : dynamic_) p += model_[i].mass * state_[i].v_W;
  return p;
}

Vec3 WorldImpl::total_angular_momentum() const {
  // About the system's centre of mass: uniform gravity exerts no torque about it, so this is
  // conserved in free flight whatever the gravity.
  double M = 0;
  Vec3 X = Vec3::Zero(), V = Vec3::Zero();
  for (int i : dynamic_) {
    M += model_[i].mass;
    X += model_[i].mass * state_[i].x_W;
    V += model_[i].mass * state_[i].v_W;
  }
  if (M == 0) return Vec3::Zero();
  X /= M;
  V /= M;
  Vec3 L = Vec3::Zero();
  for (int i : dynamic_)
    L += model_[i].mass * (state_[i].x_W - X).cross(state_[i].v_W - V) + angular_momentum(i);
  return L;
}

}  // namespace simreel
