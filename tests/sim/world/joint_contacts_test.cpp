// Contacts on jointed bodies (sim/joints/contact_rows.hpp) through the public World, against
// closed forms of impacts through a mechanism's effective mass.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include <simreel/simreel.hpp>

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
  World ref(
      [&] {
        WorldConfig c = s.cfg;
        return c;
      }(),
      std::vector<BodyDef>{s.bodies[0]});
  for (int i = 0; i < 240; ++i) {
    w.step();
    ref.step();
  }
  EXPECT_EQ(w.joint_position(0), ref.joint_position(0));
  EXPECT_EQ(w.joint_speed(0), ref.joint_speed(0));
}
