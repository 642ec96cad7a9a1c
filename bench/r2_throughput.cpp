// R2 throughput: N free tumbling boxes under gravity (anchors' R2: same generator and seed),
// dt = 1/240, 1000 steps; body-steps per second for each integrator with 1 and 2 threads, beside
// the plain article loop (state as matrices, as ../shared/anchors/src/ref_seed.cpp) run here.
#include <cstdio>
#include <memory>

#include "bench/bench_util.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "sim/dynamics/state.hpp"

#ifdef SIMREEL_BENCH_BULLET
#include <btBulletDynamicsCommon.h>
#endif

using namespace simreel;

#ifdef SIMREEL_BENCH_BULLET
// Bullet 3.24 double precision (Debian's libbullet-dev, -float64 libraries) on the same boxes, as
// the anchors run it: one btDiscreteDynamicsWorld, each body in collision group 1 with mask 0 so
// no pair is ever tested (free bodies), deactivation off, default flags (implicit gyroscopic
// term), stepSimulation(dt, 0) = exactly one internal step. Returns the stepping wall time.
static double bullet_r2_seconds(const std::vector<BodyDef>& defs) {
  btDefaultCollisionConfiguration cfg;
  btCollisionDispatcher disp(&cfg);
  btDbvtBroadphase bp;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&disp, &bp, &solver, &cfg);
  world.setGravity(btVector3(0, 0, -9.81));
  std::vector<std::unique_ptr<btBoxShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  for (const BodyDef& d : defs) {
    // Boxes are single colliders centred on the body origin with principal axes along the body
    // axes, so Bullet's body frame and ours coincide.
    const MassProperties& mp = d.mass_B();
    const Vec3 half = 0.5 * d.colliders[0].size;
    shapes.push_back(std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), half.z())));
    const Vec3 I = mp.inertia.diagonal();
    btRigidBody::btRigidBodyConstructionInfo ci(mp.mass, nullptr, shapes.back().get(),
                                                btVector3(I.x(), I.y(), I.z()));
    ci.m_startWorldTransform = btTransform(btQuaternion(d.q_WB.x(), d.q_WB.y(), d.q_WB.z(), d.q_WB.w()),
                                           btVector3(d.p_WB.x(), d.p_WB.y(), d.p_WB.z()));
    bodies.push_back(std::make_unique<btRigidBody>(ci));
    world.addRigidBody(bodies.back().get(), 1, 0);
    bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    bodies.back()->setAngularVelocity(btVector3(d.w_W.x(), d.w_W.y(), d.w_W.z()));
  }
  const double t0 = bench::now_s();
  for (int s = 0; s < 1000; ++s) world.stepSimulation(btScalar(1.0 / 240), 0);
  const double wall = bench::now_s() - t0;
  for (auto& b : bodies) world.removeRigidBody(b.get());
  return wall;
}
#endif

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
#ifdef SIMREEL_BENCH_BULLET
    {
      // One timed run at N = 10000 (about 13 s), three at N = 1000; no warm-up run.
      std::vector<double> walls;
      for (int r = 0; r < (N >= 10000 ? 1 : 3); ++r) walls.push_back(bullet_r2_seconds(defs));
      std::sort(walls.begin(), walls.end());
      const double mn = walls.front(), md = walls[walls.size() / 2];
      std::printf("bullet_f64,default_no_pairs,%d,1,1000,%.5f,%.5f,%.4e,%.2f,%zu\n", N, mn, md,
                  N * 1000.0 / mn, mn / (N * 1000.0) * 1e9, sizeof(btRigidBody));
    }
#endif
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
