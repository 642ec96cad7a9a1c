// R2 throughput: N free tumbling boxes under gravity (anchors' R2: same generator and seed),
// dt = 1/240, 1000 steps; body-steps per second for each integrator with 1 and 2 threads, beside
// the plain article loop (state as matrices, as ../shared/anchors/src/ref_seed.cpp) run here.
#include <cstdio>

#include "bench/bench_util.hpp"
#include "sim/scene_builders.hpp"

using namespace simreel;

// The article's loop as the anchors measured it: one struct per body, rotation matrix state,
// world inverse inertia R I^-1 R^T, axis-angle update, re-orthonormalise through a quaternion.
struct PlainBody {
  Vec3 x, v, w;
  Mat3 R;
  Vec3 I;
  double mass;
  void step(double dt, const Vec3& force) {
    v += force / mass * dt;
    const Mat3 Iw_inv = R * I.cwiseInverse().asDiagonal() * R.transpose();
    w += Iw_inv * Vec3::Zero() * dt;
    x += v * dt;
    const double a = w.norm() * dt;
    if (a > 0) R = Eigen::AngleAxisd(a, w.normalized()).toRotationMatrix() * R;
    R = Quat(R).normalized().toRotationMatrix();
  }
};

int main() {
  std::printf(
      "engine,variant,N,threads,steps,wall_s_min,wall_s_median,body_steps_per_s,ns_per_body_step,"
      "state_bytes_per_body\n");
  for (int N : {1000, 10000}) {
    const std::vector<BodyDef> defs = r2_free_boxes(N);
    {
      std::vector<PlainBody> init;
      for (const BodyDef& d : defs) {
        const MassProperties& mp = d.mass_B();
        init.push_back(
            {d.p_WB, Vec3::Zero(), d.w_W, d.q_WB.toRotationMatrix(), mp.inertia.diagonal(), mp.mass});
      }
      const bench::Timing t = bench::time_runs(3, [&] {
        std::vector<PlainBody> b = init;
        for (int s = 0; s < 1000; ++s)
          for (PlainBody& p : b) p.step(1.0 / 240, Vec3(0, 0, -9.81 * p.mass));
        if (b[0].x.z() == 1234.5) std::puts("#");
      });
      std::printf("plain_article_loop,seed_matrices,%d,1,1000,%.5f,%.5f,%.4e,%.2f,%zu\n", N, t.min, t.median,
                  N * 1000.0 / t.min, t.min / (N * 1000.0) * 1e9, sizeof(PlainBody));
    }
    for (Integrator m : {Integrator::automatic, Integrator::rk4, Integrator::splitting,
                         Integrator::euler_gyro, Integrator::seed}) {
      for (int threads : {1, 2}) {
        WorldConfig c;
        c.integrator = m;
        c.threads = threads;
        const bench::Timing t = bench::time_runs(3, [&] {
          World w(c, defs);
          const double t0 = bench::now_s();
          for (int s = 0; s < 1000; ++s) w.step();
          (void)t0;
        });
        // The timed region includes building the World (~1% at N = 10000); measured separately below.
        const bench::Timing build = bench::time_runs(3, [&] { World w(c, defs); });
        const double step_s = t.min - build.min;
        std::printf("simreel,%s,%d,%d,1000,%.5f,%.5f,%.4e,%.2f,%zu\n", to_string(m), N, threads, step_s,
                    t.median - build.min, N * 1000.0 / step_s, step_s / (N * 1000.0) * 1e9,
                    sizeof(MotionState) + sizeof(Wrench));
      }
    }
  }
}
