// R1 work-precision: every integrator at dt = 1/30 ... 1/3840 on the tumbling box (anchors' R1),
// run time against the max orientation, energy and momentum errors. CSV on stdout.
// Reference: classical RK4 in long double (64-bit mantissa) at dt = 1/7680 on (q, w_body); its
// own error is estimated against a run at 1/15360 and against Jacobi's closed form for w.
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench/bench_util.hpp"
#include "sim/dynamics/free_top.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "sim/world/world_impl.hpp"

using namespace simreel;
using LD = long double;

struct RefState {
  LD q[4], w[3];
};

static void ref_rhs(const LD* s, const LD* I, LD* d) {
  const LD qw = s[0], qx = s[1], qy = s[2], qz = s[3], wx = s[4], wy = s[5], wz = s[6];
  d[0] = 0.5L * (-qx * wx - qy * wy - qz * wz);
  d[1] = 0.5L * (qw * wx + qy * wz - qz * wy);
  d[2] = 0.5L * (qw * wy + qz * wx - qx * wz);
  d[3] = 0.5L * (qw * wz + qx * wy - qy * wx);
  d[4] = (I[1] - I[2]) / I[0] * wy * wz;
  d[5] = (I[2] - I[0]) / I[1] * wz * wx;
  d[6] = (I[0] - I[1]) / I[2] * wx * wy;
}

// Orientation (body to world) sampled every 1/30 s over T.
static std::vector<Quat> reference(int substeps_per_sample, std::vector<Vec3>* w_out = nullptr) {
  const LD I[3] = {2.5L, 5.0L, 6.5L};
  LD s[7] = {1, 0, 0, 0, 0.01L, 5.0L, 0.01L};
  const LD h = 1.0L / (30.0L * substeps_per_sample);
  std::vector<Quat> out{Quat::Identity()};
  if (w_out) w_out->push_back(Vec3(0.01, 5, 0.01));
  for (int k = 0; k < 600; ++k) {
    for (int j = 0; j < substeps_per_sample; ++j) {
      LD k1[7], k2[7], k3[7], k4[7], t[7];
      ref_rhs(s, I, k1);
      for (int i = 0; i < 7; ++i) t[i] = s[i] + 0.5L * h * k1[i];
      ref_rhs(t, I, k2);
      for (int i = 0; i < 7; ++i) t[i] = s[i] + 0.5L * h * k2[i];
      ref_rhs(t, I, k3);
      for (int i = 0; i < 7; ++i) t[i] = s[i] + h * k3[i];
      ref_rhs(t, I, k4);
      for (int i = 0; i < 7; ++i) s[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      const LD n = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + s[3] * s[3]);
      for (int i = 0; i < 4; ++i) s[i] /= n;
    }
    out.push_back(Quat((double)s[0], (double)s[1], (double)s[2], (double)s[3]));
    if (w_out) w_out->push_back(Vec3((double)s[4], (double)s[5], (double)s[6]));
  }
  return out;
}

static double angle(const Quat& a, const Quat& b) {
  const Quat d = a.conjugate() * b;
  return 2 * std::atan2(d.vec().norm(), std::fabs(d.w()));
}

int main() {
  std::vector<Vec3> wref;
  const std::vector<Quat> ref = reference(256, &wref);
  const std::vector<Quat> ref2 = reference(512);
  double self = 0, jac = 0;
  const FreeTop top(Vec3(2.5, 5, 6.5), Vec3(0.01, 5, 0.01));
  for (size_t k = 0; k < ref.size(); ++k) {
    self = std::max(self, angle(ref[k], ref2[k]));
    jac = std::max(jac, (wref[k] - top.angular_velocity(k / 30.0)).norm() / 5.0);
  }
  std::printf(
      "# reference: long-double RK4 at dt = 1/7680; vs dt = 1/15360: %.2e rad; w vs Jacobi: %.2e relative\n",
      self, jac);
  std::printf(
      "integrator,dt_inv,steps,wall_s_min,wall_s_median,us_per_step,max_orient_err_rad,max_rel_energy_err,"
      "max_rel_momentum_err\n");
  for (Integrator m : {Integrator::seed, Integrator::euler_gyro, Integrator::splitting, Integrator::rk4,
                       Integrator::automatic}) {
    for (int dtinv : {30, 60, 120, 240, 480, 960, 1920, 3840}) {
      WorldConfig c;
      c.dt = 1.0 / dtinv;
      c.gravity = Vec3::Zero();
      c.integrator = m;
      const long steps = 20L * dtinv;
      const int every = dtinv / 30;
      // Errors from one run sampled at 1/30 s; time from separate runs with nothing but stepping.
      double eang = 0, eE = 0, eL = 0;
      {
        World w(c, {r1_tumble_body()});
        const double E0 = w.kinetic_energy();
        const Vec3 L0 = w.angular_momentum(0);
        for (long s = 1; s <= steps; ++s) {
          w.step();
          eE = std::max(eE, std::fabs(w.kinetic_energy() - E0) / E0);
          eL = std::max(eL, (w.angular_momentum(0) - L0).norm() / L0.norm());
          if (s % every == 0) eang = std::max(eang, angle(w.orientation(0), ref[s / every]));
        }
      }
      const int reps = dtinv <= 480 ? 9 : 5;
      const bench::Timing t = bench::time_runs(reps, [&] {
        World w(c, {r1_tumble_body()});
        for (long s = 0; s < steps; ++s) w.step();
        if (w.impl().state(0).q_WP.w() == 12345.0) std::puts("#");
      });
      std::printf("%s,%d,%ld,%.6e,%.6e,%.4f,%.3e,%.3e,%.3e\n", to_string(m), dtinv, steps, t.min, t.median,
                  t.min / steps * 1e6, eang, eE, eL);
    }
  }
}
