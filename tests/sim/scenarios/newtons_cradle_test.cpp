// Newton's cradle, a hard case for contacts: a row of equal balls 1 mm apart, restitution
// 1. Closed form: with gaps, the collisions happen one pair at a time, and an elastic head-on
// collision of two equal masses exchanges their velocities; so the struck row passes the velocity
// from ball to ball and exactly the last ball leaves, at the speed of the one that struck (k balls
// striking: the last k leave). Momentum and energy are conserved.
//
// How the balls are held: they float in a row without gravity (no string, no floor), so every
// impulse in the run is one of the contact chain's. A second variant rests the row on a frictionless
// floor under gravity, so that each ball's floor contact is solved in the same sweeps as the chain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/sim/solver/contact_fixtures.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

using namespace contact_test;

struct CradleResult {
  std::vector<double> v;  ///< final x velocity of each ball, m/s
  double p0 = 0, p1 = 0;  ///< total x momentum before and after, kg m/s
  double E0 = 0, E1 = 0;  ///< total kinetic energy before and after, J
};

// n balls of radius r along x, `gap` apart (surface to surface), the first `strikers` of them
// moving together at v0 toward the rest (every neighbour `gap` apart, the strikers too: a cradle's
// balls hang `gap` apart, and two balls raised together keep their gap as they swing).
CradleResult run_cradle(int n, int strikers, double v0, double gap, bool on_floor, double duration = 0.3,
                        const ContactSettings* settings = nullptr) {
  const double r = 0.025, density = 7800;  // steel balls, 5 cm across
  WorldConfig cfg;
  if (settings) cfg.contacts = *settings;
  cfg.contacts.sleep = false;
  cfg.gravity = on_floor ? Vec3(0, 0, -9.81) : Vec3::Zero();
  std::vector<BodyDef> bodies;
  if (on_floor) bodies.push_back(ground(0.0, 0.0));
  const int first = (int)bodies.size();
  double x = 0;
  for (int i = 0; i < n; ++i) {
    BodyDef b = sphere(r, Vec3(x, 0, r), 0.0, 1.0, density);
    if (i < strikers) b.v_W = Vec3(v0, 0, 0);
    bodies.push_back(b);
    x += 2 * r + gap;
  }
  World w(cfg, bodies);
  CradleResult out;
  for (int i = 0; i < n; ++i) {
    out.p0 += w.impl().model(first + i).mass * w.linear_velocity(first + i).x();
  }
  out.E0 = w.kinetic_energy();
  while (w.time() < duration) w.step();
  for (int i = 0; i < n; ++i) {
    out.v.push_back(w.linear_velocity(first + i).x());
    out.p1 += w.impl().model(first + i).mass * w.linear_velocity(first + i).x();
  }
  out.E1 = w.kinetic_energy();
  return out;
}

void print(const char* what, const CradleResult& c, double v0) {
  std::printf("[measure] cradle %s: velocities", what);
  for (double v : c.v) std::printf(" %+.3e", v / v0);
  std::printf(" (x v0); momentum %+.2e, energy %+.2e (relative)\n", c.p1 / c.p0 - 1, c.E1 / c.E0 - 1);
}

// The criteria: the last `strikers` balls leave at v0 (within 0.5%), every other ball is
// left at rest (below 0.5% of v0: "exactly" that many leave), momentum and energy within 0.5%.
// Tolerance 0.5% is the issue's; measured, every figure is at rounding (1e-15), since the
// collisions are resolved one impact at a time by the restitution stage, each an exact exchange.
void check_cradle(const char* what, const CradleResult& c, int strikers, double v0) {
  print(what, c, v0);
  const int n = (int)c.v.size();
  for (int i = 0; i < n; ++i) {
    if (i >= n - strikers)
      EXPECT_NEAR(c.v[i] / v0, 1.0, 5e-3) << what << ": ball " << i + 1 << " should leave at v0";
    else
      EXPECT_LT(std::fabs(c.v[i] / v0), 5e-3) << what << ": ball " << i + 1 << " should stay";
  }
  EXPECT_NEAR(c.p1 / c.p0, 1.0, 5e-3) << what << ": momentum";
  EXPECT_NEAR(c.E1 / c.E0, 1.0, 5e-3) << what << ": energy";
}

// Default contact settings: impacts at 1.5 m/s, above the default restitution threshold (1 m/s).
// One, two and three strikers; the row floating, and resting on a frictionless floor. Before the
// fix in ContactSolver::restitution (a point could bounce once per step; the velocity a later
// bounce gave a shared ball read as an acceleration), two strikers at 1.5 m/s left the five balls
// at 0.08, 0.26, 0.30, 0.36 and 1.0 v0, losing 35% of the energy.
TEST(NewtonsCradle, StruckBallsSendOffAsManyAtTheirSpeed) {
  const double v0 = 1.5;
  for (bool floor : {false, true}) {
    for (int s : {1, 2, 3}) {
      char what[96];
      std::snprintf(what, sizeof what, "5 balls, %d striking at %.1f m/s%s", s, v0,
                    floor ? ", on a floor" : "");
      check_cradle(what, run_cradle(5, s, v0, 1e-3, floor), s, v0);
    }
  }
}

// A real cradle's speeds: a ball let go from 30 degrees on 20 cm strings strikes at 0.73 m/s, so
// the threshold is lowered to 5 cm/s (as scenes/newtons_cradle.yaml does). Swept over speeds
// from 0.5 to 2 m/s, which puts the impacts at every phase of the 1/240 s step and the second
// impact of a ball (two or three strikers) in the same step as its first from 0.72 m/s on.
TEST(NewtonsCradle, EveryPhaseOfTheStepFromHalfToTwoMetresPerSecond) {
  ContactSettings cs;
  cs.restitution_threshold = 0.05;
  for (double v0 = 0.5; v0 <= 2.0 + 1e-9; v0 += 0.1) {
    for (int s : {1, 2}) {
      char what[96];
      std::snprintf(what, sizeof what, "5 balls, %d striking at %.1f m/s", s, v0);
      check_cradle(what, run_cradle(5, s, v0, 1e-3, false, 0.3, &cs), s, v0);
    }
  }
}

// A longer row: seven balls, the impulse passing six gaps.
TEST(NewtonsCradle, SevenBalls) {
  check_cradle("7 balls, 1 striking at 1.2 m/s", run_cradle(7, 1, 1.2, 1e-3, false), 1, 1.2);
  check_cradle("7 balls, 2 striking at 1.2 m/s", run_cradle(7, 2, 1.2, 1e-3, false), 2, 1.2);
}

}  // namespace
}  // namespace simreel
