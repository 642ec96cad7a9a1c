#include "sim/world/applied_forces.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/dynamics/integrators.hpp"

namespace simreel {

namespace {
constexpr int kY = 13;  // doubles per body in the RK4 buffers: x, v, q (w x y z), w_P

void pack(const MotionState& s, double* y) {
  for (int k = 0; k < 3; ++k) y[k] = s.x_W[k], y[3 + k] = s.v_W[k], y[10 + k] = s.w_P[k];
  y[6] = s.q_WP.w(), y[7] = s.q_WP.x(), y[8] = s.q_WP.y(), y[9] = s.q_WP.z();
}
// The state as forces see it: the stage's quaternion scaled to unit length (RK4's stage values
// drift off the unit sphere by O(h^5); a rotation must be one).
void unpack_unit(const double* y, MotionState& s) {
  s.x_W = Vec3(y[0], y[1], y[2]);
  s.v_W = Vec3(y[3], y[4], y[5]);
  s.q_WP = Quat(y[6], y[7], y[8], y[9]).normalized();
  s.w_P = Vec3(y[10], y[11], y[12]);
}
}  // namespace

void AppliedForces::init(std::vector<ForceDef> forces, const std::vector<BodyDef>& defs,
                         const std::vector<BodyModel>& model, Integrator integrator,
                         const std::vector<char>& jointed) {
  const int n = (int)defs.size();
  forces_ = std::move(forces);
  std::vector<std::string> names;
  for (const BodyDef& d : defs) names.push_back(d.name);
  validate_forces(forces_, model, names);
  fired_.assign(forces_.size(), 0);
  forced_slot_.assign(n, -1);
  if (forces_.empty()) return;
  std::vector<char> acted(n, 0), read(n, 0);
  for (size_t k = 0; k < forces_.size(); ++k) {
    const ForceDef& f = forces_[k];
    if (is_impulse(f.kind)) {
      impulses_.push_back((int)k);
      continue;
    }
    auto on_jointed = [&](int b) { return b >= 0 && b < (int)jointed.size() && jointed[b]; };
    if (on_jointed(f.body) || (f.kind == ForceKind::spring && on_jointed(f.body_b))) {
      jointed_.push_back((int)k);
      continue;
    }
    continuous_.push_back((int)k);
    acted[f.body] = read[f.body] = 1;
    if (f.kind == ForceKind::spring && f.body_b >= 0) {
      read[f.body_b] = 1;
      acted[f.body_b] = !model[f.body_b].is_static && !model[f.body_b].is_kinematic;
    }
  }
  for (int i = 0; i < n; ++i)
    if (read[i]) involved_.push_back(i);
  // Dynamic bodies under auto or rk4 with a continuous force are stepped by the forced RK4 (World
  // takes them out of their integrator groups). Other integrators keep the force as a constant
  // wrench over the step.
  for (int i = 0; i < n; ++i) {
    const Integrator m = defs[i].integrator.value_or(integrator);
    if (defs[i].type == BodyType::dynamic && acted[i] &&
        (m == Integrator::automatic || m == Integrator::rk4)) {
      forced_slot_[i] = (int)forced_.size();
      forced_.push_back(i);
      forced_auto_.push_back(m == Integrator::automatic);
    }
  }
  eval_state_.assign(n, MotionState{});
  stage_wrench_.assign(n, Wrench{});
  user_wrench_.assign(forced_.size(), Wrench{});
  rate1_.assign(n, 0.0);
  rate2_.assign(n, 0.0);
  for (auto* b : {&y0_, &ys_, &k_, &acc_}) b->assign(kY * forced_.size(), 0.0);
  forced_now_.reserve(forced_.size());
  cuts_.reserve(2 * continuous_.size() + 2);
}

// The forced bodies that touched nothing this step, integrated together by classical RK4 on
// (x, v, q, w_P) with every force evaluated at every stage from the stage's states (a spring
// couples its two ends' stages). Split at the window edges inside the step (a force switching on
// or off is not smooth in time; each piece is), and under `auto` substepped so that the fastest
// rate (force_rates, spin) times the substep stays below kAutoMaxStepAngle. Bodies not stepped
// here that forces read (in contact, static, kinematic, other integrators) are seen at their
// start-of-step state.
bool AppliedForces::integrate(double t0, double t1, double dt, const Vec3& gravity, MotionState* state,
                              const BodyModel* model, const char* in_contact, bool some_in_contact) {
  forced_now_.clear();
  for (int i : forced_)
    if (!some_in_contact || !in_contact[i]) forced_now_.push_back(i);
  if (forced_now_.empty()) return true;
  if (continuous_.empty()) return true;
  // Substeps, from the start state (a function of the state: a resumed run takes the same).
  int n = 1;
  {
    for (int i : forced_now_) rate1_[i] = rate2_[i] = 0;
    for (int k : continuous_)
      force_rates(forces_[k], eval_state_.data(), model, rate2_.data(), rate1_.data());
    double r = 0;
    for (int i : forced_now_)
      if (forced_auto_[forced_slot_[i]])
        r = std::max(r, std::sqrt(rate2_[i]) + rate1_[i] + model[i].gyro_rate * state[i].w_P.norm());
    const double need = std::ceil(r * dt / kAutoMaxStepAngle - 1e-9);
    n = (int)std::clamp(need, 1.0, (double)kAutoMaxSubsteps);
  }
  cuts_.clear();
  for (int k : continuous_) {
    const ForceDef& f = forces_[k];
    for (double e : {f.from, f.to})
      if (e > t0 + 1e-9 * dt && e < t1 - 1e-9 * dt) cuts_.push_back(e);
  }
  std::sort(cuts_.begin(), cuts_.end());
  cuts_.erase(std::unique(cuts_.begin(), cuts_.end()), cuts_.end());
  double a = t0;
  for (size_t c = 0; c <= cuts_.size(); ++c) {
    const double b = c < cuts_.size() ? cuts_[c] : t1;
    const int m = std::max(1, (int)std::ceil(n * (b - a) / dt - 1e-9));
    for (int s = 0; s < m; ++s)
      rk4(s == 0 ? a : a + (b - a) * s / m, s + 1 == m ? b : a + (b - a) * (s + 1) / m, gravity, state,
          model);
    a = b;
  }
  double sum = 0;
  for (int i : forced_now_) {
    const MotionState& s = state[i];
    sum += s.q_WP.w() + s.x_W.x() + s.x_W.y() + s.x_W.z() + s.v_W.x() + s.w_P.x();
  }
  return std::isfinite(sum);
}

// One classical RK4 step from time a to b over forced_now_ (Kutta 1901; Hairer, Norsett, Wanner,
// "Solving ODEs I", II.1): k1 = f(y), k2 = f(y + h/2 k1), k3 = f(y + h/2 k2), k4 = f(y + h k3),
// y += h/6 (k1 + 2 k2 + 2 k3 + k4); f evaluates the forces at each stage's states. The window
// weight is that of the whole substep [a, b], which never straddles an edge (1 or 0).
void AppliedForces::rk4(double a, double b, const Vec3& gravity, MotionState* state, const BodyModel* model) {
  const double h = b - a;
  const int nb = (int)forced_now_.size();
  for (int j = 0; j < nb; ++j) {
    pack(state[forced_now_[j]], &y0_[kY * j]);
    std::fill_n(&acc_[kY * j], kY, 0.0);
  }
  static constexpr double c[4] = {0.0, 0.5, 0.5, 1.0};
  static constexpr double wgt[4] = {1.0, 2.0, 2.0, 1.0};
  for (int st = 0; st < 4; ++st) {
    for (int j = 0; j < nb; ++j) {
      const int i = forced_now_[j];
      double* ys = &ys_[kY * j];
      const double* y0 = &y0_[kY * j];
      const double* k = &k_[kY * j];
      if (st == 0) {
        std::copy_n(y0, kY, ys);
        eval_state_[i] = state[i];
      } else {
        for (int q = 0; q < kY; ++q) ys[q] = y0[q] + (c[st] * h) * k[q];
        unpack_unit(ys, eval_state_[i]);
      }
    }
    for (int i : involved_) stage_wrench_[i] = Wrench{};
    for (int j = 0; j < nb; ++j) stage_wrench_[forced_now_[j]] = user_wrench_[forced_slot_[forced_now_[j]]];
    WrenchSink sink{stage_wrench_.data(), eval_state_.data()};
    for (int kk : continuous_) {
      const ForceDef& f = forces_[kk];
      evaluate_force(f, window_weight(f, a, b), eval_state_.data(), model, sink);
    }
    for (int j = 0; j < nb; ++j) {
      const int i = forced_now_[j];
      double* k = &k_[kY * j];
      state_derivative(&ys_[kY * j], model[i], stage_wrench_[i], gravity, k);
      double* acc = &acc_[kY * j];
      for (int q = 0; q < kY; ++q) acc[q] += wgt[st] * k[q];
    }
  }
  const double h6 = h / 6.0;
  for (int j = 0; j < nb; ++j) {
    MotionState& s = state[forced_now_[j]];
    double* y = &y0_[kY * j];
    const double* acc = &acc_[kY * j];
    for (int q = 0; q < kY; ++q) y[q] += h6 * acc[q];
    unpack_unit(y, s);
  }
}

}  // namespace simreel
