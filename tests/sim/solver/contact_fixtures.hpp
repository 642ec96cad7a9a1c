// Small builders for the contact tests: bodies made directly from BodyDefs, with the
// primitives' closed-form mass functions, plus the measurements the tests share (energy, a state
// hash, a least-squares line, a parabola through three samples) and a probe that tells whether the
// narrow phase in the build handles a pair (sim/collision/narrow/dev_stub.cpp, the development stand-in,
// only does sphere-plane, box-plane and sphere-sphere; the tests that need more skip with it).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <vector>

#include <simreel/body.hpp>
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/state_hash.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"

namespace simreel::contact_test {

inline constexpr double kPi = std::numbers::pi;
inline double deg(double d) {
  return d * kPi / 180.0;
}

// The static ground: one plane collider (massless: props_C.mass 0, inertia zero), the plane
// z = 0 of the collider frame with normal +z_C, tilted by q_WB (about the world origin).
inline BodyDef ground(double friction = 0.6, double restitution = 0.0, const Quat& q_WB = Quat::Identity(),
                      const Vec3& p_WB = Vec3::Zero()) {
  BodyDef b;
  b.name = "ground";
  b.type = BodyType::static_body;
  b.p_WB = p_WB;
  b.q_WB = q_WB;
  Collider c;
  c.shape = ShapeKind::plane;
  c.props_C.mass = 0;
  c.props_C.com = Vec3::Zero();
  c.props_C.inertia = Mat3::Zero();
  c.friction = friction;
  c.restitution = restitution;
  b.add_collider(c);
  return b;
}

inline Collider sphere_collider(double r, double density, double friction, double restitution) {
  Collider c;
  c.shape = ShapeKind::sphere;
  c.radius = r;
  c.props_C = sphere_mass(r, density);
  c.friction = friction;
  c.restitution = restitution;
  return c;
}

inline Collider box_collider(const Vec3& size, double density, double friction, double restitution) {
  Collider c;
  c.shape = ShapeKind::box;
  c.size = size;
  c.props_C = box_mass(size, density);
  c.friction = friction;
  c.restitution = restitution;
  return c;
}

inline BodyDef sphere(double r, const Vec3& at, double friction = 0.6, double restitution = 0.0,
                      double density = 1000.0, BodyType type = BodyType::dynamic) {
  BodyDef b;
  b.name = "sphere";
  b.type = type;
  b.p_WB = at;
  b.add_collider(sphere_collider(r, density, friction, restitution));
  return b;
}

inline BodyDef box(const Vec3& size, const Vec3& at, double friction = 0.6, double restitution = 0.0,
                   double density = 1000.0, const Quat& q = Quat::Identity(),
                   BodyType type = BodyType::dynamic) {
  BodyDef b;
  b.name = "box";
  b.type = type;
  b.p_WB = at;
  b.q_WB = q;
  b.add_collider(box_collider(size, density, friction, restitution));
  return b;
}

// Capsule along the body z axis, centred on the body origin; height is tip to tip.
inline BodyDef capsule(double r, double height, const Vec3& at, double friction = 0.6,
                       double restitution = 0.0, double density = 1000.0) {
  BodyDef b;
  b.name = "capsule";
  b.p_WB = at;
  Collider c;
  c.shape = ShapeKind::capsule;
  c.radius = r;
  c.height = height;
  c.props_C = capsule_mass(r, height, density);
  c.friction = friction;
  c.restitution = restitution;
  b.add_collider(c);
  return b;
}

// Total mechanical energy of the dynamic bodies (J): kinetic + uniform-gravity potential.
inline double energy(const World& w) {
  return w.kinetic_energy() + w.potential_energy();
}

using simreel::state_hash;

// Least-squares line y = a + b t; returns {a, b}.
struct Line {
  double a = 0, b = 0;
};
inline Line fit_line(const std::vector<double>& t, const std::vector<double>& y) {
  const double n = (double)t.size();
  double st = 0, sy = 0;
  for (size_t i = 0; i < t.size(); ++i) st += t[i], sy += y[i];
  const double tm = st / n, ym = sy / n;
  double stt = 0, sty = 0;
  for (size_t i = 0; i < t.size(); ++i) stt += (t[i] - tm) * (t[i] - tm), sty += (t[i] - tm) * (y[i] - ym);
  const double b = sty / stt;
  return {ym - b * tm, b};
}

// Vertex height of the parabola through three equally spaced samples y0, y1, y2 (y1 the largest).
// Exact for ballistic flight (constant acceleration), so an apex measured this way carries no
// sampling error.
inline double parabola_peak(double y0, double y1, double y2) {
  const double den = y0 - 2 * y1 + y2;
  if (den >= 0) return y1;
  const double u = 0.5 * (y0 - y2) / den;  // offset of the vertex from the middle sample, in steps
  return y1 - 0.25 * (y0 - y2) * u;
}

// Does the narrow phase in this build produce a contact between a dynamic body `probe` resting
// (slightly overlapping) on `support`? Used to detect the development stand-in
// (sim/collision/narrow/dev_stub.cpp), which returns no contact for box-box, capsule, cylinder, ellipsoid.
inline bool narrow_phase_touches(const BodyDef& support, const BodyDef& probe) {
  WorldConfig cfg;
  cfg.gravity = Vec3::Zero();
  World w(cfg, {support, probe});
  w.step();
  for (const Contact& c : w.impl().contacts())
    if (c.count > 0) return true;
  return false;
}
inline bool has_box_box() {
  return narrow_phase_touches(
      box(Vec3(1, 1, 1), Vec3(0, 0, 0), 0.6, 0, 1000, Quat::Identity(), BodyType::static_body),
      box(Vec3(1, 1, 1), Vec3(0, 0, 0.999)));
}
inline bool has_box_sphere() {
  return narrow_phase_touches(
      box(Vec3(1, 1, 1), Vec3(0, 0, 0), 0.6, 0, 1000, Quat::Identity(), BodyType::static_body),
      sphere(0.5, Vec3(0, 0, 0.999)));
}
inline bool has_capsule_plane() {
  return narrow_phase_touches(ground(), capsule(0.1, 1.0, Vec3(0, 0, 0.499)));
}

#define SKIP_WITHOUT(cond, what)                                                                    \
  if (!(cond))                                                                                      \
  GTEST_SKIP() << what                                                                              \
               << " is not handled by the narrow phase in this build (the development stand-in "    \
                  "sim/collision/narrow/dev_stub.cpp only does sphere-plane, box-plane and sphere-sphere); " \
                  "this test runs once the real narrow phase lands"

}  // namespace simreel::contact_test
