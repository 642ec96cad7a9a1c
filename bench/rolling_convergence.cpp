// Rolling accuracy: the rattleback of scenes/rattleback.yaml spun -5 rad/s (the celt "minus", alone
// on the ground) for 22 s. First the rolling contact (sim/solver/rolling_contact.hpp, the default) at
// the scene's step for rolling_tolerance 1e-5 .. 1e-12, then the soft solver (rolling: false) at 2^k
// contact substeps a step; each row its motion energy lost by the reversal and by the end, the
// reversal time, the peak reversed spin and the wall time; then the observed order of the loss
// between neighbouring rows: against the tolerance, log(loss ratio) / log(tolerance ratio), and
// against the substep, log2(loss(h) / loss(h / 2)). Ideal rolling keeps the energy; the
// independent no-slip reference reverses at 2.7604 s with a peak spin of 5.357 rad/s.
//   bench_rolling_convergence [scene] [seconds]  (CSV on stdout)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <simreel/world.hpp>
#include "app/runner/run.hpp"
#include "app/scene/scene.hpp"

using namespace simreel;

struct Row {
  int substeps;
  double h_sub, loss_reversal, loss_end, t_reversal, peak, seconds;
};

// Runs the world for `seconds`, following body `celt`'s vertical spin.
Row run(const WorldConfig& c, const std::vector<BodyDef>& bodies, double seconds) {
  World w(c, bodies);
  int celt = 0;
  while (w.def(celt).name != "minus") ++celt;
  const double E0 = w.kinetic_energy() + w.potential_energy(), K0 = w.kinetic_energy();
  Row r{c.contacts.substeps, c.dt / std::max(1, c.contacts.substeps), NAN, NAN, NAN, 0, 0};
  double prev = w.angular_velocity(celt).z();
  const long steps = std::lround(seconds / c.dt);
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) {
    w.step();
    const double wz = w.angular_velocity(celt).z();
    if (std::isnan(r.t_reversal) && prev < 0 && wz >= 0) {
      r.t_reversal = w.time() - c.dt * wz / (wz - prev);
      r.loss_reversal = (E0 - w.kinetic_energy() - w.potential_energy()) / K0;
    }
    r.peak = std::max(r.peak, wz);
    prev = wz;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.loss_end = (E0 - w.kinetic_energy() - w.potential_energy()) / K0;
  return r;
}

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "scenes/rattleback.yaml";
  const double seconds = argc > 2 ? std::stod(argv[2]) : 22.0;
  Scene s = load_scene(path);
  // The "minus" celt and the ground alone.
  std::vector<BodyDef> bodies;
  for (const BodyDef& b : s.bodies)
    if (b.name == "minus" || b.type == BodyType::static_body) bodies.push_back(b);
  const double dt0 = s.timestep;
  std::printf(
      "rolling_tolerance,step_s,energy_lost_by_reversal,energy_lost_by_end,reversal_s,peak_reversed_spin_rad_"
      "s,"
      "seconds\n");
  std::vector<double> tols, losses;
  for (int e = 5; e <= 12; ++e) {
    WorldConfig c = world_config(s, 1);
    c.contacts.rolling_tolerance = std::pow(10.0, -e);
    const Row r = run(c, bodies, seconds);
    std::printf("%.0e,%.6g,%.3e,%.3e,%.5f,%.5f,%.3f\n", c.contacts.rolling_tolerance, dt0, r.loss_reversal,
                r.loss_end, r.t_reversal, r.peak, r.seconds);
    std::fflush(stdout);
    tols.push_back(c.contacts.rolling_tolerance);
    losses.push_back(std::fabs(r.loss_end));
  }
  std::printf("\nfrom_tolerance,to_tolerance,order_of_energy_loss_in_tolerance\n");
  for (size_t k = 1; k < tols.size(); ++k)
    std::printf("%.0e,%.0e,%.3f\n", tols[k - 1], tols[k],
                std::log(losses[k - 1] / losses[k]) / std::log(10.0));
  std::printf(
      "\nstep_s,substeps,contact_hertz,h_sub_s,energy_lost_by_reversal,energy_lost_by_end,reversal_s,peak_"
      "reversed_spin_rad_s,seconds\n");
  std::vector<Row> rows;
  // The soft solver (rolling off): first the substeps of the scene's step (1/240 s), then the step
  // itself at 4 substeps: the same substep lengths, reached the other way (the narrow phase, the soft
  // contact's stiffness and the tracked points' warm start are made once a step). Last, the soft
  // contact's stiffness at 64 substeps: 120 Hz (the default) to 3840 Hz (a quarter of the substep
  // rate, the most it may be).
  for (int k = 0; k < 12; ++k) {
    const int n = k < 5 ? 4 << k : k < 9 ? 4 : 64;
    Scene sc = s;
    sc.timestep = k < 5 || k >= 9 ? dt0 : dt0 / (1 << (k - 4));
    WorldConfig c = world_config(sc, 1);
    c.contacts.rolling = false;
    c.contacts.substeps = n;
    if (k >= 9) c.contacts.contact_hertz = 120.0 * (4 << (k - 9)) * (k == 11 ? 2 : 1);
    const Row r = run(c, bodies, seconds);
    std::printf("%.6g,%d,%g,%.6g,%.5f,%.5f,%.4f,%.4f,%.3f\n", c.dt, n, c.contacts.contact_hertz, r.h_sub,
                r.loss_reversal, r.loss_end, r.t_reversal, r.peak, r.seconds);
    std::fflush(stdout);
    rows.push_back(r);
  }
  std::printf("\nfrom_h_sub_s,to_h_sub_s,by,order_of_energy_loss_by_end\n");
  for (size_t k = 1; k < 9; ++k) {
    const size_t a = k == 5 ? 0 : k - 1;  // the step series starts again from 4 substeps at the scene's step
    std::printf("%.6g,%.6g,%s,%.3f\n", rows[a].h_sub, rows[k].h_sub, k < 5 ? "substeps" : "step",
                std::log2(rows[a].loss_end / rows[k].loss_end));
  }
  return 0;
}
