// Shared by the continuous-collision tests (ccd_test.cpp, ccd_mesh_test.cpp): the shots' world
// settings and the test for a centre passing through a target.
#pragma once
#include <cmath>

#include <simreel/world.hpp>

namespace simreel::ccd_test {

constexpr double kShotDt = 1.0 / 240.0;  // s
// The shot: a 5 cm steel sphere at 100 m/s at a 1 cm wall or plate.
constexpr double kRadius = 0.025;  // m
constexpr double kSpeed = 100;     // m/s
constexpr double kThick = 0.01;    // m
constexpr double kSteel = 7800;    // kg/m^3

// Whether a centre moving from `a` to `b` (in the target's frame, thin axis x) crossed the
// target's mid-plane x = 0 within its face, |y| and |z| at most `half`: through the target, not
// past its edge (a sphere sliding off a spinning plate's edge ends behind it legitimately).
inline bool crossed(const Vec3& a, const Vec3& b, double half) {
  if (!(a.x() <= 0 && b.x() > 0)) return false;
  const double f = -a.x() / (b.x() - a.x());
  const Vec3 c = a + f * (b - a);
  return std::fabs(c.y()) <= half && std::fabs(c.z()) <= half;
}

// No gravity, no sleeping, steps of kShotDt; continuous collision on or off.
inline WorldConfig shot_config(bool continuous = true) {
  WorldConfig cfg;
  cfg.dt = kShotDt;
  cfg.gravity = Vec3::Zero();
  cfg.contacts.continuous = continuous;
  cfg.contacts.sleep = false;
  return cfg;
}

}  // namespace simreel::ccd_test
