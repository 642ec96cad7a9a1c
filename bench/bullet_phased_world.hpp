// Bullet's discrete world with its internal phases timed (bench/r3_contacts.cpp and
// bench/free_bodies.cpp print them beside simreel's stage profile). Include only where
// SIMREEL_BENCH_BULLET is defined.
#pragma once
#include <btBulletDynamicsCommon.h>

#include "bench/bench_util.hpp"

namespace simreel::bench {

struct PhasedWorld : btDiscreteDynamicsWorld {
  enum { predict, collision, islands, solve, integrate, activation, n };
  double t[n] = {};  ///< s per phase, summed over steps
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;
  template <typename F>
  void timed(int k, F f) {
    const double t0 = now_s();
    f();
    t[k] += now_s() - t0;
  }
  void predictUnconstraintMotion(btScalar ts) override {
    timed(predict, [&] { btDiscreteDynamicsWorld::predictUnconstraintMotion(ts); });
  }
  void performDiscreteCollisionDetection() override {
    timed(collision, [&] { btDiscreteDynamicsWorld::performDiscreteCollisionDetection(); });
  }
  void calculateSimulationIslands() override {
    timed(islands, [&] { btDiscreteDynamicsWorld::calculateSimulationIslands(); });
  }
  void solveConstraints(btContactSolverInfo& si) override {
    timed(solve, [&] { btDiscreteDynamicsWorld::solveConstraints(si); });
  }
  void integrateTransforms(btScalar ts) override {
    timed(integrate, [&] { btDiscreteDynamicsWorld::integrateTransforms(ts); });
  }
  void updateActivationState(btScalar ts) override {
    timed(activation, [&] { btDiscreteDynamicsWorld::updateActivationState(ts); });
  }
};

}  // namespace simreel::bench
