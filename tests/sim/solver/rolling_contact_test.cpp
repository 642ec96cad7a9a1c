// Rolling contact (sim/solver/rolling_contact.cpp): bodies rolling without slip on a fixed flat
// surface keep their energy (no-slip rolling does no work), slip exactly where Coulomb friction
// cannot hold them, and resume from a saved state bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "tests/sim/solver/contact_fixtures.hpp"

namespace simreel {
namespace {

using namespace contact_test;

// Body 1 of the world, touching the ground (body 0) at one point of a smooth shape.
struct Roller {
  const char* what;
  BodyDef body;
};

// Each smooth shape rolling and rocking on the level ground without slipping (friction 2), started
// touching at its lowest point with the velocity no slip gives: a sphere whose centre of mass is 1
// cm off its centre (it rocks), a uniform ellipsoid spun about a tilted axis (it wobbles and
// wanders), a weighted capsule rocking on one end, and a coin rolling on its rim.
std::vector<Roller> rollers() {
  std::vector<Roller> out;
  auto place = [](BodyDef& b, const Vec3& w_W, const Vec3& lowest_B) {
    // lowest_B: the contact point in the body frame for the body's orientation; the body origin is
    // put so that it touches z = 0 there, and v = w x (G - P).
    const Vec3 P = b.q_WB * lowest_B;
    b.p_WB = -P;
    b.w_W = w_W;
    const Vec3 G = b.p_WB + b.q_WB * (b.mass_override ? b.mass_override->com : Vec3::Zero());
    b.v_W = w_W.cross(G - Vec3(0, 0, 0));
  };
  {
    BodyDef b = sphere(0.05, Vec3::Zero(), 2.0);
    b.mass_override = MassProperties{0.5, Vec3(0.01, 0, 0), Vec3(5e-4, 6e-4, 5.5e-4).asDiagonal()};
    b.q_WB = Quat(Eigen::AngleAxisd(deg(30), Vec3::UnitY()));
    place(b, Vec3(0.5, 1.0, 6.0), b.q_WB.conjugate() * Vec3(0, 0, -0.05));
    out.push_back({"off-centre sphere", b});
  }
  {
    BodyDef b;
    b.name = "ellipsoid";
    Collider c;
    c.shape = ShapeKind::ellipsoid;
    c.radii = Vec3(0.08, 0.05, 0.03);
    c.props_C = ellipsoid_mass(c.radii, 1000);
    c.friction = 2.0;
    b.append_collider(c);
    b.q_WB = Quat(Eigen::AngleAxisd(deg(20), Vec3(1, 1, 0).normalized()));
    // The support point against -z: A d / sqrt(d^T A d), d = R^T (0, 0, -1).
    const Vec3 d = b.q_WB.conjugate() * Vec3(0, 0, -1);
    const Vec3 A = c.radii.cwiseProduct(c.radii);
    place(b, Vec3(0.3, -0.2, 8.0), A.cwiseProduct(d) / std::sqrt(d.dot(A.cwiseProduct(d))));
    out.push_back({"ellipsoid", b});
  }
  {
    // A roly-poly: a short capsule weighted below its lower end's centre, rocking on that end.
    BodyDef b = capsule(0.03, 0.1, Vec3::Zero(), 2.0);
    b.mass_override = MassProperties{0.3, Vec3(0, 0, -0.03), Vec3(4e-4, 4e-4, 1.5e-4).asDiagonal()};
    b.q_WB = Quat(Eigen::AngleAxisd(deg(20), Vec3::UnitX()));
    const Vec3 axis = b.q_WB * Vec3::UnitZ();
    // The lower end's sphere centre, 2 cm down the axis, then its radius straight down.
    place(b, Vec3(1.0, 0, 5.0), b.q_WB.conjugate() * (-0.02 * axis + Vec3(0, 0, -0.03)));
    out.push_back({"roly-poly capsule on its end", b});
  }
  {
    BodyDef b;
    b.name = "coin";
    Collider c;
    c.shape = ShapeKind::cylinder;
    c.radius = 0.0125;
    c.height = 0.002;
    c.props_C = cylinder_mass(c.radius, c.height, 7800);
    c.friction = 2.0;
    b.add_collider(c);
    b.q_WB = Quat(Eigen::AngleAxisd(deg(80), Vec3::UnitX()));  // leaning 10 degrees
    const Vec3 axis = b.q_WB * Vec3::UnitZ();
    const Vec3 down = (Vec3(0, 0, -1) - Vec3(0, 0, -1).dot(axis) * axis).normalized();
    const double end = axis.z() > 0 ? -0.001 : 0.001;
    place(b, -25.0 * axis + Vec3(0, 0, 2.0), b.q_WB.conjugate() * (end * axis + 0.0125 * down));
    out.push_back({"coin on its rim", b});
  }
  return out;
}

// Over 10 s at the default step, every step rolled (the contact pushes inside its cone throughout)
// and the energy kept to 1e-7 of the kinetic energy: the integrator's tolerance is 1e-10 per
// internal step (relative), some 10^4 to 10^5 internal steps. The soft solver on the same bodies
// loses 1e-3 to 1e-1 of it (printed).
TEST(RollingContact, EveryShapeKeepsItsEnergyWhileRolling) {
  for (const Roller& r : rollers()) {
    double drift[2] = {0, 0};
    long rolled = 0;
    double ke0 = 0;
    for (int soft = 0; soft < 2; ++soft) {
      WorldConfig cfg;
      cfg.contacts.sleep = false;
      cfg.contacts.rolling = soft == 0;
      World w(cfg, {ground(2.0), r.body});
      const double E0 = energy(w);
      ke0 = w.kinetic_energy();
      while (w.time() < 10.0) {
        w.step();
        drift[soft] = std::max(drift[soft], std::fabs(energy(w) - E0));
      }
      if (soft == 0) rolled = w.profile().rolling_bodies;
      drift[soft] /= ke0;
    }
    std::printf(
        "[measure] %s: kinetic energy %.4g J, energy kept to %.1e of it rolling (%ld of 2400 steps rolled); "
        "the "
        "soft solver's %.1e\n",
        r.what, ke0, drift[0], rolled, drift[1]);
    EXPECT_EQ(rolled, 2400) << r.what;
    EXPECT_LT(drift[0], 1e-7) << r.what;
  }
}

// A ball on a 30 degree incline rolls at 5/7 g sin(theta) when friction can hold it (mu >= 2/7
// tan(theta) = 0.165) and slides at g (sin(theta) - mu cos(theta)) when it cannot: the rolling
// step is given back to the solver when its contact force would leave the friction cone.
TEST(RollingContact, SlipsExactlyWhereFrictionCannotHold) {
  const double theta = deg(30), r = 0.1, g = 9.81;
  const Quat tilt(Eigen::AngleAxisd(theta, Vec3::UnitY()));
  const Vec3 n = tilt * Vec3::UnitZ(), down_slope = tilt * Vec3::UnitX();
  for (double mu : {0.1, 0.3}) {
    WorldConfig cfg;
    cfg.contacts.sleep = false;
    World w(cfg, {ground(mu, 0, tilt), sphere(r, r * n, mu)});
    for (int k = 0; k < 24; ++k) w.step();  // 0.1 s
    const double t0 = w.time(), s0 = w.linear_velocity(1).dot(down_slope);
    while (w.time() < 1.0) w.step();
    const double a = (w.linear_velocity(1).dot(down_slope) - s0) / (w.time() - t0);
    const bool rolls = mu >= 2.0 / 7.0 * std::tan(theta);
    const double expected =
        rolls ? 5.0 / 7.0 * g * std::sin(theta) : g * (std::sin(theta) - mu * std::cos(theta));
    std::printf("[measure] mu %.2f: a = %.6f m/s^2, %s %.6f; %ld steps rolled\n", mu, a,
                rolls ? "5/7 g sin" : "g (sin - mu cos)", expected, w.profile().rolling_bodies);
    EXPECT_NEAR(a, expected, 1e-6 * expected) << "mu " << mu;
    if (rolls)
      EXPECT_GE(w.profile().rolling_bodies, 239) << "mu " << mu;
    else
      EXPECT_EQ(w.profile().rolling_bodies, 0) << "mu " << mu;
  }
}

// Saved while rolling (the internal step proposals are part of the state) and resumed, the run
// ends with the straight run's bits.
TEST(RollingContact, ResumedRunEqualsStraightRun) {
  const std::vector<Roller> all = rollers();
  const std::vector<BodyDef> bodies{ground(2.0), all[1].body};
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  World straight(cfg, bodies), first(cfg, bodies);
  for (int k = 0; k < 300; ++k) straight.step(), first.step();
  std::stringstream saved;
  first.save_state(saved);
  World resumed(cfg, bodies);
  resumed.restore_state(saved);
  for (int k = 0; k < 300; ++k) straight.step(), resumed.step();
  EXPECT_EQ(straight.profile().rolling_bodies, 600);
  EXPECT_EQ(state_hash(straight), state_hash(resumed));
}

// A dumbbell (two balls of radius r at the ends of a massless rod, 2 L apart) on a frictionless
// floor with regularised friction on (so its two balls are feet of one problem), one ball down and
// the other raised by theta0, let go. The floor pushes only upward, so G falls straight down and
// the rod's angle obeys (M L^2 cos^2 th + I) th'' - M L^2 cos th sin th th'^2 + M g L cos th = 0
// (Lagrange; integrated here by RK4 at 1e-6 s). The raised ball lands when th = 0, as a plastic
// impact at both balls: both stop moving along the normal, which for this body is every motion, so
// it lies at rest from that step on. The energy is kept until then (1e-8 of M g L sin th0).
TEST(RollingContact, ALiftedFootLandsWhereTheMotionSaysAndStops) {
  const double r = 0.05, L = 0.2, M = 1.0, I = 0.012, g = 9.81, th0 = deg(30);
  // The reference's landing time.
  double th = th0, om = 0, t_land = 0;
  const double hr = 1e-6;
  auto acc = [&](double a, double w) {
    return (M * L * L * std::cos(a) * std::sin(a) * w * w - M * g * L * std::cos(a)) /
           (M * L * L * std::cos(a) * std::cos(a) + I);
  };
  while (th > 0) {
    const double k1a = om, k1w = acc(th, om);
    const double k2a = om + hr / 2 * k1w, k2w = acc(th + hr / 2 * k1a, om + hr / 2 * k1w);
    const double k3a = om + hr / 2 * k2w, k3w = acc(th + hr / 2 * k2a, om + hr / 2 * k2w);
    const double k4a = om + hr * k3w, k4w = acc(th + hr * k3a, om + hr * k3w);
    const double th1 = th + hr / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);
    om += hr / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
    t_land += th1 > 0 ? hr : hr * th / (th - th1);
    th = th1;
  }
  BodyDef b;
  b.name = "dumbbell";
  for (double side : {-1.0, 1.0}) {
    Collider c = sphere_collider(r, 1000, 0.0, 0.0);
    c.p_BC = Vec3(side * L, 0, 0);
    b.add_collider(c);
  }
  b.mass_override = MassProperties{M, Vec3::Zero(), Vec3(0.002, I, I).asDiagonal()};
  b.q_WB = Quat(Eigen::AngleAxisd(-th0, Vec3::UnitY()));  // the +x ball raised
  b.p_WB = Vec3(0, 0, r + L * std::sin(th0));
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  cfg.contacts.slip_speed = 0.01;
  World w(cfg, {ground(0.0), b});
  const double E0 = energy(w);
  double drift = 0, t_rest = -1, moving_after = 0, height_after = 0;
  while (w.time() < t_land + 0.5) {
    w.step();
    const double speed = w.linear_velocity(1).norm() + w.angular_velocity(1).norm() * L;
    if (t_rest < 0 && speed < 1e-9) t_rest = w.time();
    if (t_rest < 0) drift = std::max(drift, std::fabs(energy(w) - E0));
    if (t_rest >= 0) {
      moving_after = std::max(moving_after, speed);
      height_after = std::max(height_after, std::fabs(w.centroid(1).z() - r));
    }
  }
  std::printf(
      "[measure] dumbbell: lands at rest in the step ending %.6f s (the motion's landing %.6f s); energy "
      "kept to "
      "%.1e of M g L sin th0 before; after: speed <= %.1e, |z_G - r| <= %.1e m; %ld of %ld steps rolled\n",
      t_rest, t_land, drift / (M * g * L * std::sin(th0)), moving_after, height_after,
      w.profile().rolling_bodies, w.profile().steps);
  EXPECT_GE(t_rest, t_land);
  EXPECT_LE(t_rest, t_land + cfg.dt);
  EXPECT_LT(drift, 1e-8 * M * g * L * std::sin(th0));
  EXPECT_LT(moving_after, 1e-9);
  EXPECT_LT(height_after, 1e-9);
  EXPECT_EQ(w.profile().rolling_bodies, w.profile().steps);
}

}  // namespace
}  // namespace simreel
