// Contacts on jointed bodies (sim/joints/contact_rows.hpp) through the public World, against
// closed forms of impacts through a mechanism's effective mass.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <simreel/simreel.hpp>

#include "tests/fixtures/joint_reference.hpp"

using namespace simreel;

namespace {

// A compound pendulum in zero gravity: a 1 kg steel-like ball (radius 5 cm) on a 0.5 kg rod,
// hinged about y 1 m above the ball's centre, turning at -2 rad/s (the ball moving along +x),
// 0.02 rad before the bottom; at the bottom it strikes a free ball of mass m2 at rest, with
// restitution 1 and no friction. The struck point's effective mass along x is I_p / L^2 (L = 1 m
// from the pivot to the contact line), not the ball's 1 kg nor the body's 1.5 kg.
struct Strike {
  static constexpr double r = 0.05, L = 1.0;
  std::vector<BodyDef> bodies;
  WorldConfig cfg;
  double Ip = 0;
  explicit Strike(double m2, int threads = 1) {
    const double pi = std::numbers::pi;
    BodyDef bob;
    bob.name = "bob";
    Collider ball = sphere_collider(r, 1.0 / (4.0 / 3.0 * pi * r * r * r));
    ball.friction = 0;
    ball.restitution = 1;
    bob.add_collider(ball);
    Collider rod = cylinder_collider(0.01, 0.9, 0.5 / (pi * 1e-4 * 0.9));
    rod.p_BC = Vec3(0, 0, 0.5);
    rod.collide = false;
    bob.add_collider(rod);
    const double th0 = 0.02;
    // About +y a turn by th0 takes the hanging (0, 0, -L) to (-L sin th0, 0, -L cos th0).
    bob.q_WB = Quat(Eigen::AngleAxisd(th0, Vec3::UnitY()));
    bob.p_WB = Vec3(0, 0, L) + bob.q_WB * Vec3(0, 0, -L);
    bob.w_W = Vec3(0, -2, 0);
    // The centre of mass (ball 1 kg at the origin, rod 0.5 kg 0.5 m up) moves with the turn.
    const Vec3 com = bob.p_WB + bob.q_WB * Vec3(0, 0, 0.5 * 0.5 / 1.5);
    bob.v_W = bob.w_W.cross(com - Vec3(0, 0, L));
    bodies.push_back(bob);
    BodyDef free;
    free.name = "struck";
    Collider b2 = sphere_collider(r, m2 / (4.0 / 3.0 * pi * r * r * r));
    b2.friction = 0;
    b2.restitution = 1;
    free.add_collider(b2);
    free.p_WB = Vec3(2 * r, 0, 0);
    bodies.push_back(free);
    cfg.dt = 1.0 / 240;
    cfg.gravity = Vec3::Zero();
    cfg.threads = threads;
    cfg.thread_backoff = false;
    cfg.contacts.sleep = false;
    JointDef j;
    j.name = "pivot";
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3(0, 0, L);
    j.axis_W = Vec3::UnitY();
    cfg.joints.push_back(j);
    // I_p: ball 2/5 m r^2 + m L^2; rod (0.9 m, radius 1 cm, centre 0.5 m below) m ((3 r^2 + h^2)/12 + d^2).
    Ip = 1.0 * (0.4 * r * r + L * L) + 0.5 * ((3e-4 + 0.81) / 12 + 0.25);
  }
};

std::string saved(const World& w) {
  std::ostringstream os;
  w.save_state(os);
  return os.str();
}

}  // namespace

// Newton's restitution through the effective mass m1 = I_p / L^2 (Goldsmith, "Impact", 1960, ch. 4:
// a pendulum striking a free body): the struck ball leaves at 2 m1 v / (m1 + m2) and the pendulum
// keeps (m1 - m2) / (m1 + m2) of its rate. Angular momentum about the pivot is kept through the
// impact (the pivot's reaction has no moment about it, and there is no gravity).
// Tolerance 5e-5 of the speeds (measured within 6e-6: the pendulum turns 0.0004 rad during the
// soft contact's few substeps, so the normal is not quite horizontal); taking the ball's own 1 kg
// or the body's 1.5 kg as the effective mass instead of I_p / L^2 = 1.16 kg would change the
// struck ball's speed by 7% and 3%. Angular momentum about the pivot: 1e-12 (measured 2e-16).
TEST(JointContacts, PendulumStrikesAFreeBallThroughItsEffectiveMass) {
  for (double m2 : {0.5, 1.1597625, 3.0}) {
    Strike s(m2);
    World w(s.cfg, s.bodies);
    const double w0 = w.joint_speed(0);
    ASSERT_NEAR(w0, -2.0, 1e-12);
    const double m1 = s.Ip / (s.L * s.L), v = 2.0 * s.L;
    auto L_pivot = [&] {
      // The ball's angular momentum about the pivot's y axis, plus the pendulum's I_p w.
      const Vec3 x = w.centroid(1) - Vec3(0, 0, s.L);
      return s.Ip * w.joint_speed(0) + m2 * x.cross(w.linear_velocity(1)).y();
    };
    const double L0 = L_pivot();
    for (int i = 0; i < 24; ++i) w.step();  // 0.1 s: the strike is at about 0.01 s
    const double v2 = w.linear_velocity(1).x(), w1 = w.joint_speed(0);
    const double v2_ref = 2 * m1 * v / (m1 + m2), w1_ref = w0 * (m1 - m2) / (m1 + m2);
    std::printf("m2 %.4f kg: struck ball %.6f m/s (closed form %.6f), pendulum %.6f rad/s (%.6f), L %.2e\n",
                m2, v2, v2_ref, w1, w1_ref, std::abs(L_pivot() - L0) / std::abs(L0));
    EXPECT_NEAR(v2, v2_ref, 5e-5 * v) << m2;
    EXPECT_NEAR(w1, w1_ref, 5e-5 * std::abs(w0)) << m2;
    EXPECT_LT(std::abs(L_pivot() - L0), 1e-12 * std::abs(L0)) << m2;
    EXPECT_LT(w.joint_gap(), 1e-14);
  }
}

// The contact path keeps the World's guarantees: the same bits on one and two threads, and a run
// saved in the middle of the strike and resumed equals the straight run.
TEST(JointContacts, SameBitsOnThreadsAndResumed) {
  Strike s1(0.5, 1), s2(0.5, 2);
  World a(s1.cfg, s1.bodies), b(s2.cfg, s2.bodies);
  std::string mid;
  for (int i = 0; i < 48; ++i) {
    a.step();
    b.step();
    if (i == 2) mid = saved(a);
  }
  EXPECT_EQ(saved(a), saved(b));
  World c(s1.cfg, s1.bodies);
  std::istringstream is(mid);
  c.restore_state(is);
  for (int i = 3; i < 48; ++i) c.step();
  EXPECT_EQ(saved(c), saved(a));
}

// A pendulum that swings past a wall without touching it keeps the adaptive integrator's
// accuracy: its contacts stay speculative (no impulse), so the contact solver hands the step back.
// Released at 60 degrees, the bob passes 1 cm from a wall for a whole period: the period matches
// the elliptic integral as without the wall.
TEST(JointContacts, SpeculativeContactsLeaveTheMechanismExact) {
  Strike s(1.0);
  s.cfg.gravity = Vec3(0, 0, -9.81);
  s.bodies[0].w_W.setZero();
  s.bodies[0].v_W.setZero();
  // A wall 1 cm behind the bob's swing plane (the bob moves in x-z at y = 0; its radius 5 cm).
  BodyDef wall;
  wall.name = "wall";
  wall.type = BodyType::static_body;
  wall.add_collider(box_collider(Vec3(3, 0.1, 3), 1000));
  wall.p_WB = Vec3(0, 0.05 + 0.01 + 0.05, 0);
  s.bodies[1] = wall;
  World w(s.cfg, s.bodies);
  World ref(s.cfg, std::vector<BodyDef>{s.bodies[0]});  // the same pendulum, no wall
  for (int i = 0; i < 240; ++i) {
    w.step();
    ref.step();
  }
  EXPECT_EQ(w.joint_position(0), ref.joint_position(0));
  EXPECT_EQ(w.joint_speed(0), ref.joint_speed(0));
}

namespace {

// Newton's cradle on hinges, as scenes/cradle_strings.yaml without its drawn strings: five balls
// (radius 5 cm, 1 kg, restitution 1, friction 0), each hinged about y 0.4 m above its centre, the
// pivots 0.101 m apart (1 mm gaps), ball 1 (index 0) let go from 30 degrees towards -x.
struct Cradle {
  static constexpr double r = 0.05, L = 0.4, gap = 0.001, pivot_z = 0.75;
  static constexpr int n = 5;
  std::vector<BodyDef> bodies;
  WorldConfig cfg;
  double angle = 30 * std::numbers::pi / 180;
  double pivot_x(int i) const { return (i - 2) * (2 * r + gap); }
  Cradle() {
    const double pi = std::numbers::pi;
    for (int i = 0; i < n; ++i) {
      BodyDef b;
      b.name = "ball" + std::to_string(i + 1);
      Collider ball = sphere_collider(r, 1.0 / (4.0 / 3.0 * pi * r * r * r));
      ball.friction = 0;
      ball.restitution = 1;
      b.add_collider(ball);
      // About +y a turn by a takes the hanging (0, 0, -L) to (-L sin a, 0, -L cos a).
      if (i == 0) b.q_WB = Quat(Eigen::AngleAxisd(angle, Vec3::UnitY()));
      b.p_WB = Vec3(pivot_x(i), 0, pivot_z) + b.q_WB * Vec3(0, 0, -L);
      bodies.push_back(b);
      JointDef j;
      j.name = "string" + std::to_string(i + 1);
      j.parent = -1;
      j.child = i;
      j.anchor_W = Vec3(pivot_x(i), 0, pivot_z);
      j.axis_W = Vec3::UnitY();
      cfg.joints.push_back(j);
    }
    cfg.dt = 1.0 / 240;
    cfg.contacts.restitution_threshold = 0.05;  // as the scene: the default 1 m/s would not bounce
    cfg.contacts.sleep = false;
  }
};

}  // namespace

// The cradle on hinges against the ideal event-driven model of the same cradle
// (ref::newtons_cradle: compound pendulums between impacts, each impact instantaneous, elastic and
// through the pendulums' effective masses I_p / k^2). The ideal system itself does not return the
// full height: with 1 mm gaps the balls' swings drift apart (the pendulums are not isochronous) and
// the end ball is back at 99.11% after ten exchanges, the rest going to the middle balls. The
// World must follow that: its end balls' turning heights (local maxima of z in the 240 Hz
// positions, refined by the parabola through the three samples around each) against the model's,
// ten exchanges. Tolerance 0.4 points of the release height, twice the measured 0.21 points (at
// the tenth exchange; +0.03 to -0.21 over the ten): the World applies an impact at the end of the
// contact substep in which the balls meet (1/960 s here), on average ~0.15 ms late, which shifts
// the phases of the later impacts (with 1/9600 s steps the difference at the tenth is 0.03 points).
// Teeth: the ideal loss itself is 0.9 points, so a cradle returning the full height would fail,
// and a solver losing 1% of the energy per exchange would be about 10 points low at the tenth.
// The hinges stay closed: the balls move in joint coordinates (joint_gap measured 1.2e-16 m).
TEST(JointContacts, NewtonsCradleOnHingesFollowsTheIdealExchanges) {
  const auto t_start = std::chrono::steady_clock::now();
  Cradle c;
  World w(c.cfg, c.bodies);
  ref::NewtonsCradle rc;
  rc.release_angle = c.angle;
  rc.duration = 7.0;
  const auto ideal = ref::cradle_exchanges(ref::newtons_cradle(rc));
  ASSERT_GE(ideal.size(), 10u);

  // Turning points of the end balls from the World's positions, step by step.
  const double z_rest = c.pivot_z - c.L, H = c.L * (1 - std::cos(c.angle));
  struct Exchange {
    double t, height;
    int ball;
  };
  std::vector<Exchange> measured;
  double worst_gap = 0;
  const int ends[2] = {0, Cradle::n - 1};
  std::array<double, 3> tz[2][3]{};  // per end ball: its last three samples (t, x, z)
  int samples = 0;
  const int steps = (int)std::lround(6.8 / c.cfg.dt);
  for (int s = 0; s <= steps; ++s) {
    if (s > 0) w.step();
    worst_gap = std::max(worst_gap, w.joint_gap());
    const double t = s * c.cfg.dt;
    for (int e = 0; e < 2; ++e) {
      const Vec3 p = w.centroid(ends[e]);
      tz[e][0] = tz[e][1];
      tz[e][1] = tz[e][2];
      tz[e][2] = {t, p.x(), p.z()};
    }
    if (++samples < 3) continue;
    for (int e = 0; e < 2; ++e) {
      const double z0 = tz[e][0][2], z1 = tz[e][1][2], z2 = tz[e][2][2];
      if (!(z1 > z0 && z1 >= z2)) continue;
      // Vertex of the parabola through the three samples.
      const double den = z0 - 2 * z1 + z2, u = den != 0 ? 0.5 * (z0 - z2) / den : 0.0;
      const double zm = z1 - 0.25 * (z0 - z2) * u, height = (zm - z_rest) / H;
      const bool outward = e == 0 ? tz[e][1][1] < c.pivot_x(0) : tz[e][1][1] > c.pivot_x(Cradle::n - 1);
      if (outward && height > 0.3) measured.push_back({tz[e][1][0] + u * c.cfg.dt, height, ends[e]});
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  ASSERT_GE(measured.size(), 10u);
  double worst = 0;
  for (int k = 0; k < 10; ++k) {
    const double d = measured[k].height - ideal[k].height;
    worst = std::max(worst, std::fabs(d));
    std::printf("exchange %2d: ball%d t %.3f s (ideal %.3f) height %.3f %% (ideal %.3f %%, %+.3f points)\n",
                k + 1, measured[k].ball + 1, measured[k].t, ideal[k].t, 100 * measured[k].height,
                100 * ideal[k].height, 100 * d);
    EXPECT_EQ(measured[k].ball, ideal[k].ball) << k;
    EXPECT_NEAR(measured[k].height, ideal[k].height, 0.004) << "exchange " << k + 1;
  }
  std::printf("largest difference %.3f points; largest joint gap %.2e m; %.2f s\n", 100 * worst, worst_gap,
              seconds);
  EXPECT_LT(worst_gap, 1e-14);
}

// A heavy flap (1 x 0.2 x 0.1 m, 100 kg) hinged to the end of a light plank (20 kg) that lies on
// the ground, swung down at 8 rad/s (1080 J) onto its stop (plastic) while the plank's contacts
// hold it down; the assembly then rocks up onto the flap's corner, falls over it and lands. The
// stop and the contacts only take energy away, yet while it falls over the corner each frame gains
// up to 0.068 J (0.4% of the energy that frame turns from potential to kinetic; not yet explained,
// so 0.2 J is allowed). The contacts' response must hold the coordinate its stop has just caught:
// one made at the frame's start without the stop pushed the flap through it and gained 4.9 J in
// one frame, which this bound catches.
TEST(JointContacts, AStopCaughtWhileInContactTakesNoEnergyIn) {
  const double s = std::sqrt(0.5), w = 8;
  WorldConfig cfg;
  cfg.dt = 1.0 / 240;
  cfg.gravity = Vec3(0, 0, -9.81);
  cfg.threads = 1;
  std::vector<BodyDef> bodies;
  BodyDef ground;
  ground.name = "ground";
  ground.type = BodyType::static_body;
  Collider floor = box_collider(Vec3(20, 20, 1), 1000);
  floor.friction = 0.7;
  ground.add_collider(floor);
  ground.p_WB = Vec3(0, 0, -0.5);
  for (int k = 0; k < 2; ++k) {
    BodyDef b;
    b.name = k == 0 ? "plank" : "flap";
    Collider c = box_collider(Vec3(1.0, 0.2, 0.1), k == 0 ? 1000 : 5000);
    c.friction = 0.7;
    b.add_collider(c);
    bodies.push_back(b);
  }
  bodies[0].p_WB = Vec3(0, 0, 0.05);
  // The flap raised 45 degrees about the hinge at the plank's end, turning down at w.
  bodies[1].q_WB = Quat(Eigen::AngleAxisd(-std::numbers::pi / 4, Vec3::UnitY()));
  bodies[1].p_WB = Vec3(0.5 + 0.5 * s, 0, 0.05 + 0.5 * s);
  bodies[1].w_W = Vec3(0, w, 0);
  bodies[1].v_W = Vec3(0, w, 0).cross(bodies[1].p_WB - Vec3(0.5, 0, 0.05));
  bodies.push_back(ground);
  JointDef j;
  j.name = "hinge";
  j.parent = 0;
  j.child = 1;
  j.anchor_W = Vec3(0.5, 0, 0.05);
  j.axis_W = Vec3::UnitY();
  j.limits = JointLimits{0, 0.6, 0};
  cfg.joints.push_back(j);
  World world(cfg, bodies);
  double E = world.kinetic_energy() + world.potential_energy(), gain = 0;
  const double E0 = E;
  bool stopped = false;
  for (int i = 0; i < 3 * 240; ++i) {
    world.step();
    const double e = world.kinetic_energy() + world.potential_energy();
    gain = std::max(gain, e - E);
    E = e;
    stopped = stopped || world.joint_position(0) >= 0.6 - 1e-12;
  }
  std::printf("flap slammed onto its stop in contact: largest gain in a frame %.1e J\n", gain);
  EXPECT_TRUE(stopped);  // it reached its stop
  EXPECT_LT(gain, 0.2);
  EXPECT_LT(E, E0);
}
