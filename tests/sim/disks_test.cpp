// Issue 15, the rolling disks: Euler's disk in steady motion (Moffatt, Nature 404, 2000) and a
// coin rolling in a circle on its rim. The references are the steady-motion relations derived
// below for a disk of finite thickness (rigid body, rolling without slipping on a level plane).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "tests/sim/contact_fixtures.hpp"

namespace simreel {
namespace {

using contact_test::ground;

constexpr double kG = 9.81;

// A disk: simreel's cylinder of radius a and thickness 2 h, axis along the body z.
struct Disk {
  double a = 0.05;          ///< m, radius
  double h = 0.0005;        ///< m, half thickness
  double density = 7800;    ///< kg/m^3
  double friction = 0.6;    ///< Coulomb
  double mass() const { return density * std::numbers::pi * a * a * 2 * h; }
  double A() const { return mass() * (a * a / 4 + h * h / 3); }  ///< about a diameter through G
  double C() const { return mass() * a * a / 2; }                ///< about the axis
};

// Steady rolling (derivation in the comment of steady_omega2): lean alpha between the disk and the
// plane, the centre G on a horizontal circle of radius rho (0: G at rest, Euler's disk), the frame
// e1 (up the disk from the contact), e2 (horizontal, along the line of nodes), e3 (the axis, upward)
// turning about the vertical at Omega. Body angular velocity w = Omega sin(alpha) e1 + w3 e3 with
// rolling w3 = Omega (h sin(alpha) - rho) / a; G moves at -Omega rho e2. Newton: N = m g, friction
// m Omega^2 rho towards the circle's centre; Euler about G, dH/dt = Omega z x H:
//   Omega^2 [A sin a cos a + C sin a (rho - h sin a) / a + m rho (a sin a + h cos a)]
//     = m g (a cos a - h sin a).
// With h = 0, rho = 0: Omega^2 sin(alpha) = 4 g / a (Moffatt); with h = 0 and v = Omega rho:
// tan(phi) = 3/2 v^2 / (g rho) + v^2 a sin(phi) / (4 g rho^2), phi = 90 deg - alpha the lean
// from the vertical (the classic tan(phi) = 3/2 v^2 / (g R) for rho >> a).
double steady_omega2(const Disk& d, double alpha, double rho) {
  const double s = std::sin(alpha), c = std::cos(alpha), m = d.mass();
  return m * kG * (d.a * c - d.h * s) /
         (d.A() * s * c + d.C() * s * (rho - d.h * s) / d.a + m * rho * (d.a * s + d.h * c));
}

struct Start {
  Vec3 e1, e2, e3;
  double omega;
};

// The disk in steady rolling at lean alpha, G on a circle of radius rho about a vertical axis on
// the +x side of G, contact point below, the plane at z = -depth (the soft contact's rest depth).
BodyDef steady_disk(const Disk& d, double alpha, double rho, double depth = 0) {
  const double s = std::sin(alpha), c = std::cos(alpha);
  const Vec3 e1(c, 0, s), e3(-s, 0, c), e2 = e3.cross(e1);  // e2 = +y
  const double W = std::sqrt(steady_omega2(d, alpha, rho));
  BodyDef b;
  b.name = "disk";
  b.q_WB = Quat(Eigen::AngleAxisd(-alpha, Vec3::UnitY()));
  b.p_WB = Vec3(0, 0, d.a * s + d.h * c - depth);
  const double w3 = W * (d.h * s - rho) / d.a;
  b.w_W = W * s * e1 + w3 * e3;
  b.v_W = -W * rho * e2;
  Collider col;
  col.shape = ShapeKind::cylinder;
  col.radius = d.a;
  col.height = 2 * d.h;
  col.props_C = cylinder_mass(d.a, 2 * d.h, d.density);
  col.friction = d.friction;
  b.add_collider(col);
  return b;
}

struct Sample {
  double t, alpha, omega, vG, height;
};

// Lean alpha (between disk and plane) and the precession rate of the axis's azimuth.
Sample sample(const World& w, int i) {
  const Vec3 e3 = w.local_to_world_vec(i, Vec3::UnitZ());
  const Vec3 om = w.angular_velocity(i);
  const Vec3 de3 = om.cross(e3);
  const double hx = e3.x(), hy = e3.y();
  Sample s;
  s.t = w.time();
  s.alpha = std::acos(std::fabs(e3.z()));
  s.omega = (hx * de3.y() - hy * de3.x()) / (hx * hx + hy * hy);
  s.vG = w.linear_velocity(i).norm();
  s.height = w.centroid(i).z();
  return s;
}

TEST(EulersDisk, Probe) {
  Disk d;
  if (const char* e = std::getenv("MU")) d.friction = std::atof(e);
  const double alpha0 = 20 * std::numbers::pi / 180;
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  if (const char* e = std::getenv("DT")) cfg.dt = 1.0 / std::atof(e);
  if (const char* e = std::getenv("SUB")) cfg.contacts.substeps = std::atoi(e);
  BodyDef disk = steady_disk(d, alpha0, 0, 1e-4);
  if (const char* e = std::getenv("KICK")) disk.v_W += Vec3(0, std::atof(e), 0);
  World w(cfg, {ground(d.friction), disk});
  double worst = 0;
  std::printf("E0 %.6f m %.5f W %.4f\n", contact_test::energy(w), d.mass(), std::sqrt(steady_omega2(d, alpha0, 0)));
  const long nsteps = std::lround(5 / cfg.dt);
  for (int k = 0; k < nsteps; ++k) {
    w.step();
    if (k < (std::getenv("NPR") ? std::atoi(std::getenv("NPR")) : 5)) {
      const Contact& c = w.contacts()[0];
      std::printf("  E %.7f count %d sep %.3e Pn %.4e (m g dt %.4e) Pf %.3e %.3e %.3e p %.5f %.5f %.5f\n", contact_test::energy(w), c.count, c.points[0].separation,
                  c.points[0].normal_impulse, d.mass() * kG * cfg.dt / w.substeps(), c.friction_impulse_W.x(), c.friction_impulse_W.y(),
                  c.friction_impulse_W.z(), c.points[0].p_W.x(), c.points[0].p_W.y(), c.points[0].p_W.z());
    }
    const Sample s = sample(w, 1);
    const double r = s.omega * s.omega * std::sin(s.alpha) * d.a / (4 * kG) - 1;
    const double rx = s.omega * s.omega / steady_omega2(d, s.alpha, 0) - 1;
    worst = std::max(worst, std::fabs(rx));
    if (k % (nsteps / 20) == nsteps / 20 - 1)
      std::printf("t %.3f alpha %.4f deg Omega %.4f vG %.2e z %.6f  ratio-1 %.3e exact-1 %.3e contacts %d E %.6f\n", s.t,
                  s.alpha * 180 / std::numbers::pi, s.omega, s.vG, s.height, r, rx,
                  w.contacts().empty() ? 0 : w.contacts()[0].count, contact_test::energy(w));
  }
  std::printf("worst %.3e\n", worst);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {
TEST(RollingCoin, Probe) {
  Disk d;
  d.a = 0.0125;
  d.h = std::getenv("HH") ? std::atof(std::getenv("HH")) : 2.5e-5;
  const double phi0 = 15 * std::numbers::pi / 180, rho = 0.3;
  const double alpha0 = std::numbers::pi / 2 - phi0;
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  if (const char* e = std::getenv("DT")) cfg.dt = 1.0 / std::atof(e);
  if (const char* e = std::getenv("SUB")) cfg.contacts.substeps = std::atoi(e);
  World w(cfg, {ground(d.friction), steady_disk(d, alpha0, rho, 1e-4)});
  const double W0 = std::sqrt(steady_omega2(d, alpha0, rho));
  std::printf("W0 %.4f v %.4f\n", W0, W0 * rho);
  const long nsteps = std::lround(5 / cfg.dt);
  for (long k = 0; k < nsteps; ++k) {
    w.step();
    if (k % (nsteps / 10) == nsteps / 10 - 1) {
      const Sample s = sample(w, 1);
      const double phi = std::numbers::pi / 2 - s.alpha;
      const double R = s.vG / std::fabs(s.omega);  // the centre's path radius
      const double approx = 1.5 * s.vG * s.vG / (kG * R);
      std::printf("t %.2f phi %.4f deg v %.5f Omega %.4f R %.5f tan(phi)/(3/2 v^2/gR)-1 %.3e E %.7f\n", s.t,
                  phi * 180 / std::numbers::pi, s.vG, s.omega, R, std::tan(phi) / approx - 1, contact_test::energy(w));
    }
  }
}
}  // namespace
}  // namespace simreel
