// The public World (include/simreel/world.hpp): each call forwards to the private implementation
// (world_impl.hpp), and the contact read-out turns the solver's records into forces.
#include <simreel/world.hpp>

#include <algorithm>

#include "sim/world/world_impl.hpp"

namespace simreel {

World::World(const WorldConfig& config, std::vector<BodyDef> bodies)
    : impl_(std::make_unique<WorldImpl>(config, std::move(bodies))) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::step() {
  impl_->step();
}
double World::time() const {
  return impl_->time();
}
long World::steps() const {
  return impl_->steps();
}
const WorldConfig& World::config() const {
  return impl_->config();
}
int World::body_count() const {
  return impl_->body_count();
}
int World::dynamic_count() const {
  return impl_->dynamic_count();
}
BodyType World::type(int i) const {
  return impl_->type(i);
}
const BodyDef& World::def(int i) const {
  return impl_->def(i);
}

double World::mass(int i) const {
  return impl_->model(i).mass;
}
const Vec3& World::local_centroid(int i) const {
  return impl_->local_centroid(i);
}
const Vec3& World::principal_moments(int i) const {
  return impl_->model(i).I_P;
}
const Quat& World::principal_axes(int i) const {
  return impl_->model(i).q_BP;
}
Mat3 World::inertia_world(int i) const {
  return impl_->inertia_world(i);
}
Mat3 World::inverse_inertia_world(int i) const {
  return impl_->inverse_inertia_world(i);
}

const Vec3& World::centroid(int i) const {
  return impl_->centroid(i);
}
Vec3 World::origin_position(int i) const {
  return impl_->origin_position(i);
}
void World::set_origin_position(int i, const Vec3& p_W) {
  impl_->set_origin_position(i, p_W);
}
Quat World::orientation(int i) const {
  return impl_->orientation(i);
}
void World::set_orientation(int i, const Quat& q_WB) {
  impl_->set_orientation(i, q_WB);
}
Quat World::principal_orientation(int i) const {
  return impl_->state(i).q_WP;
}
Mat3 World::rotation(int i) const {
  return impl_->rotation(i);
}
Mat3 World::inverse_rotation(int i) const {
  return impl_->inverse_rotation(i);
}
Vec3 World::local_to_world(int i, const Vec3& p_B) const {
  return impl_->local_to_world(i, p_B);
}
Vec3 World::world_to_local(int i, const Vec3& p_W) const {
  return impl_->world_to_local(i, p_W);
}
Vec3 World::local_to_world_vec(int i, const Vec3& v_B) const {
  return impl_->local_to_world_vec(i, v_B);
}
Vec3 World::world_to_local_vec(int i, const Vec3& v_W) const {
  return impl_->world_to_local_vec(i, v_W);
}
const Vec3& World::linear_velocity(int i) const {
  return impl_->linear_velocity(i);
}
void World::set_linear_velocity(int i, const Vec3& v_W) {
  impl_->set_linear_velocity(i, v_W);
}
Vec3 World::angular_velocity(int i) const {
  return impl_->angular_velocity(i);
}
void World::set_angular_velocity(int i, const Vec3& w_W) {
  impl_->set_angular_velocity(i, w_W);
}
Vec3 World::angular_velocity_body(int i) const {
  return impl_->model(i).q_BP * impl_->state(i).w_P;
}
const Vec3& World::angular_velocity_principal(int i) const {
  return impl_->state(i).w_P;
}
Vec3 World::angular_momentum(int i) const {
  return impl_->angular_momentum(i);
}
void World::normalize_orientation(int i) {
  impl_->normalize_orientation(i);
}

void World::apply_force(int i, const Vec3& f_W, const Vec3& at_W) {
  impl_->apply_force(i, f_W, at_W);
}
void World::apply_force_local(int i, const Vec3& f_B, const Vec3& at_B) {
  impl_->apply_force_local(i, f_B, at_B);
}
void World::apply_central_force(int i, const Vec3& f_W) {
  impl_->apply_central_force(i, f_W);
}
void World::apply_torque(int i, const Vec3& tau_W) {
  impl_->apply_torque(i, tau_W);
}
void World::apply_impulse(int i, const Vec3& J_W, const Vec3& at_W) {
  impl_->apply_impulse(i, J_W, at_W);
}
void World::apply_angular_impulse(int i, const Vec3& dL_W) {
  impl_->apply_angular_impulse(i, dL_W);
}
bool World::has_forces() const {
  return impl_->has_forces();
}
bool World::impulse_applied(int k) const {
  return impl_->impulse_applied(k);
}

double World::kinetic_energy() const {
  return impl_->kinetic_energy();
}
double World::potential_energy() const {
  return impl_->potential_energy();
}
Vec3 World::total_momentum() const {
  return impl_->total_momentum();
}
Vec3 World::total_angular_momentum() const {
  return impl_->total_angular_momentum();
}
void World::check_state() const {
  impl_->check_state();
}
void World::check_spin(double max_angle) {
  impl_->check_spin(max_angle);
}
const std::vector<std::string>& World::warnings() const {
  return impl_->warnings();
}

bool World::has_contacts() const {
  return impl_->has_contacts();
}
int World::substeps() const {
  return impl_->substeps();
}
const ContactStats& World::contact_stats() const {
  return impl_->contact_stats();
}

namespace {

// A solver record as forces: the last substep's impulses over the substep h. A point's share of
// the pair's friction (solved at the manifold's centre) follows its normal impulse; `sign` -1
// reads the pair from body a's side (normal and forces negated, sides swapped).
ContactData contact_data(const Contact& c, const ShapeTable& shapes, double h, double sign) {
  ContactData d;
  const bool flip = sign < 0;
  d.body_a = flip ? c.body_b : c.body_a;
  d.body_b = flip ? c.body_a : c.body_b;
  d.collider_a = shapes[flip ? c.shape_b : c.shape_a].collider;
  d.collider_b = shapes[flip ? c.shape_a : c.shape_b].collider;
  d.normal_W = sign * c.normal_W;
  d.count = c.count;
  d.friction = c.friction;
  d.restitution = c.restitution;
  double sum = 0;
  for (int j = 0; j < c.count; ++j) sum += c.points[j].normal_impulse;
  for (int j = 0; j < c.count; ++j) {
    const double lam = c.points[j].normal_impulse;
    const Vec3 F = (sum > 0 ? lam / sum : 1.0 / c.count) * c.friction_impulse_W;
    ContactData::Point& p = d.points[j];
    p.p_W = c.points[j].p_W;
    p.separation = c.points[j].separation;
    p.normal_force = lam / h;
    p.friction_force_W = sign * F / h;
    p.force_W = sign * (lam * c.normal_W + F) / h;
  }
  return d;
}

}  // namespace

int World::contacts(std::vector<ContactData>& out) const {
  if (!impl_->has_contacts()) return 0;
  const double h = impl_->config().dt / std::max(1, impl_->substeps());
  const size_t before = out.size();
  impl_->for_each_contact([&](const Contact& c) {
    if (c.count > 0) out.push_back(contact_data(c, impl_->shapes(), h, 1.0));
  });
  return (int)(out.size() - before);
}

int World::body_contacts(int i, std::vector<ContactData>& out) const {
  const size_t before = out.size();
  if (!impl_->has_contacts()) return 0;
  const double h = impl_->config().dt / std::max(1, impl_->substeps());
  impl_->for_each_contact([&](const Contact& c) {
    if (c.count == 0 || (c.body_a != i && c.body_b != i)) return;
    out.push_back(contact_data(c, impl_->shapes(), h, c.body_b == i ? 1.0 : -1.0));
  });
  return (int)(out.size() - before);
}

bool World::asleep(int i) const {
  return impl_->asleep(i);
}
int World::joint_count() const {
  return impl_->joints().joint_count();
}
int World::find_joint(std::string_view name) const {
  return impl_->joints().find(name);
}
double World::joint_position(int j, int k) const {
  return impl_->joints().position(j, k);
}
double World::joint_speed(int j, int k) const {
  return impl_->joints().speed(j, k);
}
double World::joint_force(int j, int k) const {
  return impl_->joints().force(j, k);
}
void World::joint_reaction(int j, Vec3& force_W, Vec3& torque_W) const {
  impl_->joints().reaction(j, &impl_->state(0), impl_->config().gravity, force_W, torque_W);
}
double World::joint_gap() const {
  return joint_count() == 0 ? 0.0 : impl_->joints().gap(&impl_->state(0));
}
double World::joint_angular_gap() const {
  return joint_count() == 0 ? 0.0 : impl_->joints().angular_gap(&impl_->state(0));
}
int World::sleeping_count() const {
  return impl_->sleeping_count();
}
void World::wake(int i) {
  impl_->wake(i);
}

void World::save_state(std::ostream& os) const {
  impl_->save_state(os);
}
void World::restore_state(std::istream& is) {
  impl_->restore_state(is);
}
uint64_t World::fingerprint() const {
  return impl_->fingerprint();
}

void World::set_profiling(bool on) {
  impl_->set_profiling(on);
}
const Profile& World::profile() const {
  return impl_->profile();
}

}  // namespace simreel
