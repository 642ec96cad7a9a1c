// Accuracy of applied forces against dt (docs/forces.md): each case integrated two ways,
//   stages: the force list (WorldConfig::forces), evaluated at every RK4 stage (what simreel does);
//   stages_rk4: the same with `integrator: rk4` (no automatic substeps: one RK4 step per dt);
//   held:   the same force computed by the caller at the start of each step and passed in with
//           apply_force / apply_central_force, held constant over the step by the integrator (what
//           the integrators did with a wrench before; still what non-RK4 integrators do).
// Cases (no gravity unless said):
//   spring: k = 100 N/m, m = 1 kg, anchor spring, amplitude 0.1 m: relative error of the mean
//           period over 100 periods (upward zero crossings, cubic Hermite between steps);
//   drag:   quadratic c = 0.05 N s^2/m^2, m = 1 kg, g = 9.81, 10 s fall: max |v - v_t tanh(g t / v_t)| / v_t;
//   thrust: 3 N along body x at (0, 0.4, 0) of a 0.6 x 0.8 x 1 m, 2 kg box, 1 s: |v - v_Fresnel| in m/s.
// Output: CSV case,method,dt,error (and the auto substeps taken, for the spring).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include <simreel/world.hpp>
#include "tests/sim/dynamics/force_references.hpp"

using namespace simreel;

namespace {

BodyDef block(const Vec3& size, double mass, const Vec3& at, const std::string& name = "b") {
  BodyDef b = box_body(name.c_str(), size, mass);
  b.p_WB = at;
  return b;
}

// The spring of both measurements: a 1 kg block on a 100 N/m spring of rest length 1 m to the
// origin, released 0.1 m stretched, no gravity; the force evaluated at every stage (the scene's
// forces:) or, without `stages`, left to the caller to hold over each step.
constexpr double m = 1, k = 100, L0 = 1;
World spring_world(double dt, bool stages, Integrator in) {
  ForceDef f;
  f.kind = ForceKind::spring;
  f.body = 0;
  f.stiffness = k;
  f.rest_length = L0;
  WorldConfig cfg;
  cfg.dt = dt;
  cfg.integrator = in;
  cfg.gravity = Vec3::Zero();
  if (stages) cfg.forces = {f};
  return World(cfg, {block(Vec3(0.2, 0.2, 0.2), m, Vec3(0, 0, -L0 - 0.1))});
}

double spring_error(double dt, bool stages, Integrator in = Integrator::automatic) {
  World w = spring_world(dt, stages, in);
  const double T = 2 * std::numbers::pi * std::sqrt(m / k);
  std::vector<double> c;
  auto s_of = [&] { return -w.centroid(0).z() - L0; };
  auto d_of = [&] { return -w.linear_velocity(0).z(); };
  double t0 = 0, s0 = s_of(), d0 = d_of();
  while (w.time() < 101.5 * T) {
    if (!stages) {
      const Vec3 d = w.centroid(0);
      const double L = d.norm();
      w.apply_central_force(0, -k * (L - L0) * d / L);
    }
    w.step();
    const double t1 = w.time(), s1 = s_of(), d1 = d_of();
    if (s0 < 0 && s1 >= 0) {
      c.push_back(test::hermite_zero(t0, s0, d0, t1, s1, d1));
    }
    t0 = t1, s0 = s1, d0 = d1;
  }
  if (c.size() < 101) return NAN;  // lost its oscillation (amplitude gone or unstable)
  return std::fabs((c[100] - c[0]) / 100 / T - 1);
}

// The same spring: relative change of its energy (kinetic + elastic) after 100 periods.
double spring_energy(double dt, bool stages, Integrator in = Integrator::automatic) {
  World w = spring_world(dt, stages, in);
  auto energy = [&] {
    const double s = w.centroid(0).norm() - L0;
    return 0.5 * m * w.linear_velocity(0).squaredNorm() + 0.5 * k * s * s;
  };
  const double E0 = energy(), T = 2 * std::numbers::pi * std::sqrt(m / k);
  while (w.time() < 100 * T) {
    if (!stages) {
      const Vec3 d = w.centroid(0);
      const double L = d.norm();
      w.apply_central_force(0, -k * (L - L0) * d / L);
    }
    w.step();
  }
  return energy() / E0 - 1;
}

double drag_error(double dt, bool stages, Integrator in = Integrator::automatic) {
  const double m = 1, c = 0.05, g = 9.81;
  ForceDef f;
  f.kind = ForceKind::drag;
  f.body = 0;
  f.quadratic = c;
  WorldConfig cfg;
  cfg.dt = dt;
  cfg.integrator = in;
  if (stages) cfg.forces = {f};
  World w(cfg, {block(Vec3(0.2, 0.2, 0.2), m, Vec3(0, 0, 1000))});
  const double vt = std::sqrt(m * g / c);
  double worst = 0;
  while (w.time() < 10 - 1e-9) {
    if (!stages) w.apply_central_force(0, -c * w.linear_velocity(0).norm() * w.linear_velocity(0));
    w.step();
    worst = std::max(worst, std::fabs(-w.linear_velocity(0).z() - vt * std::tanh(g * w.time() / vt)));
  }
  return worst / vt;
}

double thrust_error(double dt, bool stages, Integrator in = Integrator::automatic) {
  const double m = 2, F = 3, r = 0.4;
  const Vec3 size(0.6, 0.8, 1.0);
  ForceDef f;
  f.kind = ForceKind::force;
  f.body = 0;
  f.vector = Vec3(F, 0, 0);
  f.frame = ForceFrame::body;
  f.at_centroid = false;
  f.at_B = Vec3(0, r, 0);
  WorldConfig cfg;
  cfg.dt = dt;
  cfg.integrator = in;
  cfg.gravity = Vec3::Zero();
  if (stages) cfg.forces = {f};
  World w(cfg, {block(size, m, Vec3::Zero())});
  while (w.time() < 1 - 1e-9) {
    if (!stages) w.apply_force_local(0, f.vector, f.at_B);
    w.step();
  }
  const double t = w.time();
  const double Izz = m / 12 * (size.x() * size.x() + size.y() * size.y());
  const double alpha = -r * F / Izz;
  const Vec3 v = test::offset_thrust_velocity(F, m, alpha, t);
  return (w.linear_velocity(0) - v).norm();
}

}  // namespace

int main() {
  std::printf("case,method,dt,error\n");
  for (double hz : {30.0, 60.0, 120.0, 240.0, 480.0, 960.0}) {
    const double dt = 1.0 / hz;
    for (int k = 0; k < 3; ++k) {
      const bool st = k < 2;
      const Integrator in = k == 1 ? Integrator::rk4 : Integrator::automatic;
      const char* m = k == 0 ? "stages" : k == 1 ? "stages_rk4" : "held";
      std::printf("spring,%s,1/%g,%.3g\n", m, hz, spring_error(dt, st, in));
      std::printf("spring_energy,%s,1/%g,%.3g\n", m, hz, spring_energy(dt, st, in));
      std::printf("drag,%s,1/%g,%.3g\n", m, hz, drag_error(dt, st, in));
      std::printf("thrust,%s,1/%g,%.3g\n", m, hz, thrust_error(dt, st, in));
    }
  }
  return 0;
}
