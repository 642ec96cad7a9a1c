// Rolling accuracy against the contact substep: the rattleback of scenes/rattleback.yaml spun
// -5 rad/s (the celt "minus", alone on the ground) for 22 s at 2^k contact substeps a step, printing
// per substep count its motion energy lost by the reversal and by the end, the reversal time and the
// peak reversed spin, then the observed order of the loss, log2(loss(h) / loss(h / 2)) between
// neighbouring rows. Ideal rolling keeps the energy; the independent no-slip reference reverses with
// a peak spin of 5.356 rad/s.   bench_rolling_convergence [scene] [seconds]  (CSV on stdout)
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
  double h_sub, loss_reversal, loss_end, t_reversal, peak;
};

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "scenes/rattleback.yaml";
  const double seconds = argc > 2 ? std::stod(argv[2]) : 22.0;
  Scene s = load_scene(path);
  // The "minus" celt and the ground alone.
  std::vector<BodyDef> bodies;
  for (const BodyDef& b : s.bodies)
    if (b.name == "minus" || b.type == BodyType::static_body) bodies.push_back(b);
  std::printf(
      "step_s,substeps,contact_hertz,h_sub_s,energy_lost_by_reversal,energy_lost_by_end,reversal_s,peak_"
      "reversed_spin_rad_s\n");
  std::vector<Row> rows;
  // First the substeps of the scene's step (1/240 s), then the step itself at 4 substeps: the same
  // substep lengths, reached the other way (the narrow phase, the soft contact's stiffness and the
  // tracked points' warm start are made once a step).
  const double dt0 = s.timestep;
  // Last, the soft contact's stiffness at 64 substeps: 120 Hz (the default) to 3840 Hz (a quarter
  // of the substep rate, the most it may be).
  for (int run = 0; run < 12; ++run) {
    const int n = run < 5 ? 4 << run : run < 9 ? 4 : 64;
    const double dt = run < 5 || run >= 9 ? dt0 : dt0 / (1 << (run - 4));
    Scene sc = s;
    sc.timestep = dt;
    WorldConfig c = world_config(sc, 1);
    c.contacts.substeps = n;
    if (run >= 9) c.contacts.contact_hertz = 120.0 * (4 << (run - 9)) * (run == 11 ? 2 : 1);
    World w(c, bodies);
    int celt = 0;
    while (w.def(celt).name != "minus") ++celt;
    const double E0 = w.kinetic_energy() + w.potential_energy(), K0 = w.kinetic_energy();
    Row r{n, c.dt / n, NAN, NAN, NAN, 0};
    double prev = w.angular_velocity(celt).z();
    const long steps = std::lround(seconds / c.dt);
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
    r.loss_end = (E0 - w.kinetic_energy() - w.potential_energy()) / K0;
    std::printf("%.6g,%d,%g,%.6g,%.5f,%.5f,%.4f,%.4f\n", dt, n, c.contacts.contact_hertz, r.h_sub,
                r.loss_reversal, r.loss_end, r.t_reversal, r.peak);
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
