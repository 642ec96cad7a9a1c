#include "app/runner/run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "app/scene/text.hpp"

#include <nlohmann/json.hpp>

namespace simreel {

Drift::Drift(const World& w)
    : E0_(w.kinetic_energy() + w.potential_energy()), L0_(w.total_angular_momentum()) {
  scale_ = std::max(std::fabs(E0_), w.kinetic_energy());
  prev_E_ = E0_;
  const std::vector<JointDef>& joints = w.config().joints;
  for (size_t j = 0; j < joints.size(); ++j)
    if (joints[j].limits) limited_.push_back((int)j);
}

void Drift::step(const World& w) {
  if (limit_reached_) return;
  // A limit stops its coordinate in the step that would carry it past the bound, so a coordinate
  // that would pass a bound within the next step at its present rate has reached it.
  const std::vector<JointDef>& joints = w.config().joints;
  const double h = w.config().dt;
  for (int j : limited_) {
    const JointLimits& l = *joints[j].limits;
    const double eps = 1e-9 * (1 + std::max(std::fabs(l.lower), std::fabs(l.upper)));
    const int coords = joints[j].type == JointType::universal ? 2 : 1;
    for (int k = 0; k < coords; ++k) {
      const double q = w.joint_position(j, k), v = w.joint_speed(j, k);
      if (q + h * std::min(0.0, v) <= l.lower + eps || q + h * std::max(0.0, v) >= l.upper - eps)
        limit_reached_ = true;
    }
  }
}

void Drift::sample(const World& w) {
  const double ke = w.kinetic_energy();
  scale_ = std::max(scale_, ke);
  const double E = ke + w.potential_energy();
  max_dE_ = std::max(max_dE_, std::fabs(E - E0_));
  max_rise_ = std::max(max_rise_, E - prev_E_);
  prev_E_ = E;
  max_dL_ = std::max(max_dL_, (w.total_angular_momentum() - L0_).norm());
  if (w.joint_count() > 0) {
    max_gap_ = std::max(max_gap_, w.joint_gap());
    max_angle_ = std::max(max_angle_, w.joint_angular_gap());
  }
}

double Drift::energy_rel() const {
  return scale_ > 0 ? max_dE_ / scale_ : 0.0;
}
double Drift::momentum_rel() const {
  return L0_.norm() > 0 ? max_dL_ / L0_.norm() : max_dL_;
}

WorldConfig world_config(const Scene& s, int threads) {
  WorldConfig c;
  c.dt = s.timestep;
  c.gravity = s.gravity;
  c.integrator = s.integrator;
  c.threads = threads;
  c.contacts = s.contacts;
  c.ignore_pairs = s.ignore_pairs;
  c.forces = s.forces;
  c.joints = s.joints;
  c.joint_settings = s.joint_settings;
  return c;
}

Conservation conservation(const Scene& scene, const World& world, const Drift* drift) {
  Conservation c;
  auto breaks = [](bool& flag, std::string& why, const std::string& reason) {
    if (!flag) return;  // the first reason is enough
    flag = false;
    why = reason;
  };
  bool fixed_body = false;  // a static or kinematic body: something outside the moving system
  for (int i = 0; i < world.body_count(); ++i)
    if (world.type(i) != BodyType::dynamic) fixed_body = true;
  for (const JointDef& j : scene.joints) {
    const bool outside = j.parent < 0 || world.type(j.parent) != BodyType::dynamic;
    if (outside)
      breaks(c.angular_momentum, c.angular_momentum_why,
             "a joint holds '" + world.def(j.child).name + "' to " +
                 (j.parent < 0 ? std::string("the world") : "'" + world.def(j.parent).name + "'"));
    if (j.friction > 0) breaks(c.energy, c.energy_why, "joint friction takes energy");
    if (j.motor) breaks(c.energy, c.energy_why, "a joint's motor gives and takes energy");
    if (j.spring && j.spring->damping > 0) breaks(c.energy, c.energy_why, "a joint's damper takes energy");
    if (j.limits && (!drift || drift->limit_reached()))
      breaks(c.energy, c.energy_why, "a joint reached its limits, which stop it inelastically");
    if (outside && world.type(j.parent < 0 ? j.child : j.parent) == BodyType::kinematic)
      breaks(c.energy, c.energy_why, "a kinematic body drives the mechanism");
  }
  // Contacts that happened (a ground the pendulum never reaches takes nothing from it).
  if (world.has_contacts() && world.contact_stats().contacts_max > 0) {
    if (fixed_body)
      breaks(c.angular_momentum, c.angular_momentum_why,
             "contacts with the ground or a fixed body push from outside");
    // Every collider frictionless and perfectly elastic (restitution 1): impacts keep the energy.
    bool elastic = true;
    for (int i = 0; i < world.body_count(); ++i)
      for (const Collider& k : world.def(i).colliders)
        elastic = elastic && k.friction == 0 && k.restitution == 1;
    if (!elastic)
      breaks(c.energy, c.energy_why,
             "contacts take energy (friction, impacts that are not perfectly elastic)");
  }
  for (const ForceDef& f : scene.forces) {
    const bool windowed = std::isfinite(f.from) || std::isfinite(f.to);
    if (f.kind == ForceKind::spring) {
      if (f.body_b < 0)
        breaks(c.angular_momentum, c.angular_momentum_why, "a spring is anchored to the world");
      if (f.damping > 0) breaks(c.energy, c.energy_why, "a spring's dashpot takes energy");
      if (windowed) breaks(c.energy, c.energy_why, "a spring acts for part of the run only");
      continue;
    }
    const char* what = f.kind == ForceKind::drag ? "drag" : "applied forces and torques";
    breaks(c.angular_momentum, c.angular_momentum_why, std::string(what) + " act from outside");
    breaks(c.energy, c.energy_why,
           std::string(what) + (f.kind == ForceKind::drag ? " takes energy" : " do work"));
  }
  return c;
}

RunSummary make_summary(const Scene& scene, const World& world, const Drift& drift, int frames,
                        double step_seconds) {
  RunSummary s;
  s.conserved = conservation(scene, world, &drift);
  s.scene = scene.path;
  s.integrator = scene.integrator;
  s.timestep = scene.timestep;
  s.duration = scene.duration;
  s.steps = world.steps();
  s.bodies = world.body_count();
  s.dynamic_bodies = world.dynamic_count();
  s.joints = world.joint_count();
  s.joint_error_max = drift.joint_gap();
  s.joint_angle_error_max = drift.joint_angle_gap();
  s.frames = frames;
  s.step_seconds = step_seconds;
  s.energy_rel_drift = drift.energy_rel();
  s.momentum_rel_drift = drift.momentum_rel();
  s.contacts = world.has_contacts();
  s.contacts_max = world.contact_stats().contacts_max;
  s.max_penetration = world.contact_stats().max_penetration;
  s.sleeping = world.sleeping_count();
  s.energy_gained = drift.energy_gained();
  s.warnings = scene.warnings;  // what the input probably gets wrong (an imported link's inertia)
  s.warnings.insert(s.warnings.end(), world.warnings().begin(), world.warnings().end());
  s.notes = scene.notes;  // printed once, at the start; the JSON carries them for scripts
  return s;
}

namespace {
struct NarrowKind {
  std::string pair;  ///< "plane-hull"
  long calls;
  double seconds;
};
// The pair kinds the narrow phase ran on, costliest first (ties: most calls, then name).
std::vector<NarrowKind> narrow_by_kind(const Profile& p) {
  std::vector<NarrowKind> v;
  for (int a = 0; a < Profile::kNarrowKinds; ++a)
    for (int b = a; b < Profile::kNarrowKinds; ++b)
      if (p.narrow_calls[a][b] > 0)
        v.push_back({std::string(narrow_kind_name(a)) + "-" + narrow_kind_name(b), p.narrow_calls[a][b],
                     p.narrow_seconds[a][b]});
  std::sort(v.begin(), v.end(), [](const NarrowKind& x, const NarrowKind& y) {
    if (x.seconds != y.seconds) return x.seconds > y.seconds;
    if (x.calls != y.calls) return x.calls > y.calls;
    return x.pair < y.pair;
  });
  return v;
}
}  // namespace

std::string summary_text(const RunSummary& s) {
  std::ostringstream o;
  o << s.scene << ": " << s.steps << " steps of " << s.timestep << " s (" << to_string(s.integrator) << "), "
    << s.bodies << " bodies (" << s.dynamic_bodies << " dynamic), " << s.frames << " frames\n";
  if (s.joints > 0)
    o << "  joints: " << s.joints << ", largest gap " << s.joint_error_max << " m and "
      << s.joint_angle_error_max << " rad (0 up to round-off: mechanisms move in joint coordinates)\n";
  o << "  stepping: " << s.step_seconds << " s wall";
  if (s.steps > 0 && s.step_seconds > 0) o << " (" << s.step_seconds / s.steps * 1e6 << " us/step)";
  o << "\n";
  if (s.render_seconds >= 0)
    o << "  rendering: " << s.render_seconds << " s, encoding thread busy " << s.encode_seconds << " s"
      << (s.encoder.empty() ? "" : " (" + s.encoder + ")") << " (" << s.renderer << ")\n";
  // Drift only of what the physics conserves here; what it does not, with the reason.
  if (s.conserved.energy)
    o << "  energy (conserved here): drift " << s.energy_rel_drift << " (relative)\n";
  else
    o << "  energy is not conserved here: " << s.conserved.energy_why << "\n";
  if (s.conserved.angular_momentum)
    o << "  angular momentum about the centre of mass (conserved here): drift " << s.momentum_rel_drift
      << " (relative)\n";
  else
    o << "  angular momentum is not conserved here: " << s.conserved.angular_momentum_why << "\n";
  if (s.contacts)
    o << "  contacts: at most " << s.contacts_max << " points in a step, deepest overlap "
      << s.max_penetration << " m, largest energy rise between frames " << s.energy_gained << " J, "
      << s.sleeping << " bodies asleep at the end\n";
  if (s.profile) {
    o << "  profile (stage: seconds, steps run, steps skipped):\n";
    for (int i = 0; i < (int)Stage::count; ++i)
      o << "    " << to_string((Stage)i) << ": " << s.profile->seconds[i] << " s, " << s.profile->runs[i]
        << ", " << s.profile->skipped[i] << "\n";
    o << "  bodies: " << s.profile->gyroscopic_bodies << " with gyroscopic dynamics, "
      << s.profile->isotropic_bodies << " isotropic (no gyroscopic work), " << s.profile->static_bodies
      << " static (never integrated), " << s.profile->kinematic_bodies << " kinematic\n";
    if (s.profile->jointed_bodies > 0)
      o << "  joints: " << s.profile->jointed_bodies << " bodies moved by their mechanisms' coordinates, "
        << s.profile->joint_steps << " internal Runge-Kutta steps ("
        << (double)s.profile->joint_steps / std::max(1L, s.profile->steps) << " a step)\n";
    if (s.profile->shapes > 0)
      o << "  contacts: " << s.profile->shapes << " shapes; summed over steps: " << s.profile->pairs
        << " candidate pairs, " << s.profile->fat_box_moves << " fat boxes left (tree updates), "
        << s.profile->contact_points << " contact points, " << s.profile->solver_bodies
        << " bodies through the solver, " << s.profile->impact_substeps
        << " substeps with an impact (one more sweep)\n";
    if (const auto kinds = narrow_by_kind(*s.profile); !kinds.empty()) {
      o << "  narrow phase by pair kind (calls, seconds), costliest first:";
      for (size_t k = 0; k < kinds.size(); ++k)
        o << (k ? "; " : " ") << kinds[k].pair << " " << kinds[k].calls << ", " << kinds[k].seconds;
      o << "\n";
    }
    if (s.profile->forces > 0)
      o << "  forces: " << s.profile->forces << " records (the drag is one per body), "
        << s.profile->forced_bodies << " bodies stepped by RK4 with the forces evaluated at every stage\n";
  }
  for (const std::string& w : s.warnings) o << "  warning: " << w << "\n";
  if (!s.output.empty()) o << "  wrote " << s.output << "\n";
  return o.str();
}

std::string summary_json(const RunSummary& s) {
  using J = nlohmann::ordered_json;  // keys in the order written; non-finite numbers become null
  J o;
  o["scene"] = s.scene;
  o["integrator"] = to_string(s.integrator);
  o["timestep"] = s.timestep;
  o["duration"] = s.duration;
  o["steps"] = s.steps;
  o["bodies"] = s.bodies;
  o["dynamic_bodies"] = s.dynamic_bodies;
  if (s.joints > 0) {  // absent without joints: a joint-free scene's summary keeps its keys
    o["joints"] = s.joints;
    o["joint_error_max"] = s.joint_error_max;
    o["joint_angle_error_max"] = s.joint_angle_error_max;
  }
  o["frames"] = s.frames;
  o["step_seconds"] = s.step_seconds;
  o["energy_rel_drift"] = s.energy_rel_drift;
  o["momentum_rel_drift"] = s.momentum_rel_drift;
  o["energy_conserved"] = s.conserved.energy;
  o["angular_momentum_conserved"] = s.conserved.angular_momentum;
  if (!s.conserved.energy) o["energy_not_conserved"] = s.conserved.energy_why;
  if (!s.conserved.angular_momentum) o["angular_momentum_not_conserved"] = s.conserved.angular_momentum_why;
  o["contacts_max"] = s.contacts_max;
  o["max_penetration"] = s.max_penetration;
  o["energy_gained"] = s.energy_gained;
  o["sleeping"] = s.sleeping;
  if (s.render_seconds >= 0) {
    o["render_seconds"] = s.render_seconds;
    o["encode_seconds"] = s.encode_seconds;
    o["renderer"] = s.renderer;
    if (!s.encoder.empty()) o["encoder"] = s.encoder;
  }
  if (s.profile) {
    J p;
    for (int i = 0; i < (int)Stage::count; ++i)
      p[to_string((Stage)i)] = {{"seconds", s.profile->seconds[i]},
                                {"runs", s.profile->runs[i]},
                                {"skipped", s.profile->skipped[i]}};
    p["bodies"] = {{"gyroscopic", s.profile->gyroscopic_bodies},
                   {"isotropic_no_gyroscopic_work", s.profile->isotropic_bodies},
                   {"static_never_integrated", s.profile->static_bodies},
                   {"kinematic", s.profile->kinematic_bodies}};
    p["contacts"] = {{"shapes", s.profile->shapes},
                     {"pairs", s.profile->pairs},
                     {"fat_box_moves", s.profile->fat_box_moves},
                     {"contact_points", s.profile->contact_points},
                     {"solver_bodies", s.profile->solver_bodies},
                     {"impact_substeps", s.profile->impact_substeps}};
    J narrow = J::array();
    for (const NarrowKind& k : narrow_by_kind(*s.profile))
      narrow.push_back({{"pair", k.pair}, {"calls", k.calls}, {"seconds", k.seconds}});
    p["narrow_phase"] = std::move(narrow);
    p["applied_forces"] = {{"records", s.profile->forces}, {"rk4_bodies", s.profile->forced_bodies}};
    if (s.profile->jointed_bodies > 0)
      p["joints"] = {{"jointed_bodies", s.profile->jointed_bodies},
                     {"internal_steps", s.profile->joint_steps}};
    o["profile"] = std::move(p);
  }
  if (!s.output.empty()) o["output"] = s.output;
  o["warnings"] = s.warnings;
  o["notes"] = s.notes;
  // Invalid UTF-8 in a name or path is replaced, not thrown on.
  return o.dump(-1, ' ', false, J::error_handler_t::replace);
}

}  // namespace simreel
