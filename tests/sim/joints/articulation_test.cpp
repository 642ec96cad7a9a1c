// Mechanisms in joint coordinates (sim/joints/articulation.hpp) against closed forms.
#include "sim/joints/articulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

using test::Bodies;

// A bob of mass m and inertia 1e-3 kg m^2 about its centre, 1 m below-and-rotated from a pivot at
// the origin, hinged about y, released at rest at theta0.
struct Pendulum {
  Bodies b;
  Articulations art;
  double m = 1, Icm = 1e-3, d = 1, g = 9.81;
  explicit Pendulum(double theta0, const JointSettings& js = {}) {
    const Vec3 x(d * std::sin(theta0), 0, -d * std::cos(theta0));
    b.add("bob", m, Vec3::Constant(Icm), x);
    JointDef j;
    j.name = "pivot";
    j.type = JointType::revolute;
    j.parent = -1;
    j.child = 0;
    j.anchor_W = Vec3::Zero();
    j.axis_W = Vec3::UnitY();
    std::vector<std::string> warnings;
    art.build({j}, js, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty());
  }
  double period(double theta0) const { return ref::pendulum_period(theta0, Icm + m * d * d, m, g, d); }
  double energy() const {
    const MotionState& s = b.state[0];
    const double Iw = Icm;  // isotropic
    return 0.5 * m * s.v_W.squaredNorm() + 0.5 * Iw * s.w_P.squaredNorm() + m * g * s.x_W.z();
  }
};

// The period of a pendulum released at theta0: run exactly one closed-form period T in N equal
// steps and read the joint speed there. At a turning point the speed crosses zero with slope
// theta'' = -(m g d / I_p) sin(theta0), so dT = -speed(T) / theta''.
TEST(Articulation, PendulumPeriodMatchesEllipticIntegral) {
  for (double deg : {10.0, 90.0, 170.0}) {
    const double th0 = deg * std::numbers::pi / 180;
    Pendulum p(th0);
    const double T = p.period(th0);
    const int N = (int)std::ceil(T * 60);
    const double dt = T / N;
    for (int i = 0; i < N; ++i) ASSERT_TRUE(p.art.step(dt, Vec3(0, 0, -p.g), nullptr, p.b.state.data()));
    const double Ip = p.Icm + p.m * p.d * p.d;
    const double acc = -(p.m * p.g * p.d / Ip) * std::sin(th0);
    const double dT = -p.art.speed(0) / acc;
    // The tolerance is the target for the first period: 1e-7 at 170 deg, 1e-8 below.
    EXPECT_LT(std::abs(dT / T), deg > 100 ? 1e-7 : 1e-8) << deg << " deg: dT/T " << dT / T;
    EXPECT_NEAR(p.art.position(0), 0.0, 1e-7) << deg;  // back where it started
    std::printf("theta0 %5.1f deg: T %.12f s, dT/T %.2e, steps %ld\n", deg, T, dT / T,
                p.art.internal_steps());
  }
}

TEST(Articulation, PendulumKeepsEnergyOverSixtySeconds) {
  for (double deg : {90.0, 170.0}) {
    const double th0 = deg * std::numbers::pi / 180;
    Pendulum p(th0);
    const double E0 = p.energy();
    double worst = 0;
    for (int i = 0; i < 3600; ++i) {
      ASSERT_TRUE(p.art.step(1.0 / 60, Vec3(0, 0, -p.g), nullptr, p.b.state.data()));
      worst = std::max(worst, std::abs(p.energy() - E0));
    }
    const double mgL = p.m * p.g * p.d;
    std::printf("theta0 %5.1f deg: max |dE| %.2e m g L, gap %.1e m, steps %ld\n", deg, worst / mgL,
                p.art.gap(p.b.state.data()), p.art.internal_steps());
    EXPECT_LT(worst / mgL, 1e-7) << deg;
    EXPECT_LT(p.art.gap(p.b.state.data()), 1e-12);
  }
}

// Kinetic + potential energy of the bodies of `b` (isotropic or principal inertia).
double energy(const Bodies& b, double g) {
  double E = 0;
  for (size_t i = 0; i < b.state.size(); ++i) {
    const MotionState& s = b.state[i];
    const BodyModel& m = b.model[i];
    E += 0.5 * m.mass * s.v_W.squaredNorm() + 0.5 * s.w_P.dot(m.I_P.cwiseProduct(s.w_P)) +
         m.mass * g * s.x_W.z();
  }
  return E;
}

// A chain of n links (rods of length l, mass ml, hinged about y) hanging from the origin, the last
// link carrying `ratio` times a link's mass at its end, released straight at `tilt` rad.
struct Chain {
  Bodies b;
  Articulations art;
  Chain(int n, double ratio, double tilt, double l = 0.1, double ml = 0.01) {
    const Vec3 dir(std::sin(tilt), 0, -std::cos(tilt));
    std::vector<JointDef> joints;
    for (int i = 0; i < n; ++i) {
      double m = ml;
      double c = 0.5 * l;  // centre of mass from the link's top pivot
      double I = ml * l * l / 12;
      if (i == n - 1) {  // the end mass, a point at the link's end
        const double M = ratio * ml;
        c = (ml * 0.5 * l + M * l) / (ml + M);
        I = ml * l * l / 12 + ml * std::pow(0.5 * l - c, 2) + M * std::pow(l - c, 2);
        m = ml + M;
      }
      // Principal frame: a rod's transverse moments; its axial moment is tiny but positive.
      b.add("link" + std::to_string(i), m, Vec3(I, I, 1e-9 * I), dir * (i * l + c));
      JointDef j;
      j.type = JointType::revolute;
      j.parent = i - 1;
      j.child = i;
      j.anchor_W = dir * (i * l);
      j.axis_W = Vec3::UnitY();
      joints.push_back(j);
    }
    std::vector<std::string> warnings;
    art.build(joints, {}, b.defs, b.model, b.state, warnings);
  }
};

// A chain of 100 links with an end mass 1000 times a link's, released from 30
// degrees. Joint coordinates leave no gap by construction (the read-out measures the anchors from
// the bodies' states: round-off only), and the energy must hold to 1e-6 of M g N l over 10 s.
TEST(Articulation, HeavyEndedChainSwingsWithoutGapsOrEnergyLoss) {
  const int n = 100;
  for (double ratio : {1000.0}) {
    Chain c(n, ratio, std::numbers::pi / 6);
    const double g = 9.81;
    const double E0 = energy(c.b, g);
    double M = 0;
    for (const BodyModel& m : c.b.model) M += m.mass;
    const double scale = M * g * n * 0.1;
    double worst = 0, worst_gap = 0;
    for (int i = 0; i < 600; ++i) {
      ASSERT_TRUE(c.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, c.b.state.data()))
          << ratio << " at step " << i;
      worst = std::max(worst, std::abs(energy(c.b, g) - E0));
      worst_gap = std::max(worst_gap, c.art.gap(c.b.state.data()));
    }
    std::printf("chain 1:%g: max |dE| %.2e M g N l, worst gap %.2e m, internal steps %ld\n", ratio,
                worst / scale, worst_gap, c.art.internal_steps());
    EXPECT_LT(worst / scale, 1e-6) << ratio;
    EXPECT_LT(worst_gap, 1e-10) << ratio;
  }
}

// Two links joined by a hinge, floating without gravity and spun: total momentum and angular
// momentum are invariants (no external force), the free root's and the hinge's coordinates
// together carry them.
TEST(Articulation, FloatingMechanismKeepsMomentum) {
  Bodies b;
  b.add("a", 2.0, Vec3(0.1, 0.2, 0.25), Vec3(0, 0, 0));
  b.add("b", 1.0, Vec3(0.05, 0.07, 0.09), Vec3(1, 0, 0));
  b.state[0].v_W = Vec3(0.3, -0.2, 0.1);
  b.state[0].w_P = Vec3(0.5, 1.5, -2.0);
  // b moves with a, plus its turn about the hinge at (0.5, 0, 0): 3 z x (0.5, 0, 0).
  b.state[1].v_W = b.state[0].v_W + (b.state[0].q_WP * b.state[0].w_P).cross(Vec3(1, 0, 0)) + Vec3(0, 1.5, 0);
  b.state[1].w_P = b.state[0].w_P + Vec3(0, 0, 3.0);  // the hinge turns at 3 rad/s about z
  JointDef j;
  j.type = JointType::revolute;
  j.parent = 0;
  j.child = 1;
  j.anchor_W = Vec3(0.5, 0, 0);
  j.axis_W = Vec3::UnitZ();
  Articulations art;
  std::vector<std::string> warnings;
  art.build({j}, {}, b.defs, b.model, b.state, warnings);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  auto momenta = [&](Vec3& p, Vec3& L) {
    p.setZero();
    L.setZero();
    for (int i = 0; i < 2; ++i) {
      const MotionState& s = b.state[i];
      p += b.model[i].mass * s.v_W;
      L += b.model[i].mass * s.x_W.cross(s.v_W) + s.q_WP * b.model[i].I_P.cwiseProduct(s.w_P);
    }
  };
  Vec3 p0, L0, p1, L1;
  momenta(p0, L0);
  const double E0 = energy(b, 0);
  for (int i = 0; i < 600; ++i) ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data()));
  momenta(p1, L1);
  // Not exact to round-off: Runge-Kutta keeps linear invariants only in the coordinates it
  // integrates, and momentum is linear in the bodies' velocities, not in q'. Each internal step
  // errs by at most the tolerance (1e-10): 1e-8 after a few hundred.
  EXPECT_LT((p1 - p0).norm(), 1e-8 * p0.norm()) << (p1 - p0).transpose();
  EXPECT_LT((L1 - L0).norm(), 1e-8 * L0.norm()) << (L1 - L0).transpose();
  EXPECT_LT(std::abs(energy(b, 0) - E0), 1e-8 * E0);
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
  EXPECT_LT(art.angular_gap(b.state.data()), 1e-12);
}

// A symmetric top on a ball joint (Lagrange's top): L_z (about the vertical through the pivot) and
// L_3 (about the figure axis) are exact invariants, and so is the energy.
TEST(Articulation, HeavyTopKeepsItsInvariants) {
  Bodies b;
  const double m = 1, l = 0.1, I1 = 2e-3, I3 = 4e-3, g = 9.81, th = 0.3;
  const Vec3 axis(std::sin(th), 0, std::cos(th));
  // Principal frame: z along the figure axis.
  const Quat q(Eigen::AngleAxisd(th, Vec3::UnitY()));
  b.add("top", m, Vec3(I1, I1, I3), axis * l, q);
  b.state[0].w_P = Vec3(0, 0, 150);  // spin about the figure axis, rad/s
  b.state[0].v_W = (q * b.state[0].w_P).cross(axis * l);
  JointDef j;
  j.type = JointType::spherical;
  j.parent = -1;
  j.child = 0;
  Articulations art;
  std::vector<std::string> warnings;
  JointSettings js;
  js.tolerance = 1e-11;  // 150 rad/s for 60 s: 1e-8 over 1.3e5 internal steps needs less than 1e-10 each
  art.build({j}, js, b.defs, b.model, b.state, warnings);
  ASSERT_TRUE(warnings.empty()) << warnings[0];
  auto invariants = [&](double& Lz, double& L3, double& E) {
    const MotionState& s = b.state[0];
    // About the pivot: I_pivot = I_cm + m (|r|^2 - r r^T); L = I_pivot w.
    const Vec3 wW = s.q_WP * s.w_P;
    const Vec3 L = s.q_WP * b.model[0].I_P.cwiseProduct(s.w_P) + m * s.x_W.cross(s.v_W);
    Lz = L.z();
    L3 = L.dot(s.q_WP * Vec3::UnitZ());
    E = 0.5 * m * s.v_W.squaredNorm() + 0.5 * s.w_P.dot(b.model[0].I_P.cwiseProduct(s.w_P)) +
        m * g * s.x_W.z();
    (void)wW;
  };
  double Lz0, L30, E0, Lz, L3, E;
  invariants(Lz0, L30, E0);
  double worst_z = 0, worst_3 = 0, worst_E = 0;
  for (int i = 0; i < 3600; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    invariants(Lz, L3, E);
    worst_z = std::max(worst_z, std::abs(Lz - Lz0) / std::abs(L30));
    worst_3 = std::max(worst_3, std::abs(L3 - L30) / std::abs(L30));
    worst_E = std::max(worst_E, std::abs(E - E0) / E0);
  }
  std::printf("top: L_z %.1e, L_3 %.1e, E %.1e (relative), internal steps %ld\n", worst_z, worst_3, worst_E,
              art.internal_steps());
  EXPECT_LT(worst_z, 1e-8);
  EXPECT_LT(worst_3, 1e-8);
  EXPECT_LT(worst_E, 1e-8);
  EXPECT_LT(art.gap(b.state.data()), 1e-12);
}

// The anchors' double pendulum: two 1 kg bobs (1e-3 kg m^2 about their centres) on 1 m massless
// rods, released horizontal. Against the independent reference (Lagrange's equations integrated
// by 6th-order Gauss-Legendre at 1/2000 s, good to 1e-13) for the first 2 s, before chaos
// amplifies the difference beyond any tolerance; energy over 60 s.
TEST(Articulation, DoublePendulumFollowsTheReferenceAndKeepsEnergy) {
  Bodies b;
  const double m = 1, Icm = 1e-3, L = 1, g = 9.81;
  b.add("upper", m, Vec3::Constant(Icm), Vec3(L, 0, 0));
  b.add("lower", m, Vec3::Constant(Icm), Vec3(2 * L, 0, 0));
  std::vector<JointDef> joints(2);
  joints[0].parent = -1;
  joints[0].child = 0;
  joints[0].axis_W = Vec3::UnitY();
  joints[1].parent = 0;
  joints[1].child = 1;
  joints[1].anchor_W = Vec3(L, 0, 0);
  joints[1].axis_W = Vec3::UnitY();
  Articulations art;
  std::vector<std::string> warnings;
  art.build(joints, {}, b.defs, b.model, b.state, warnings);
  const ref::PendulumLink link{m, L, Icm, L};
  const ref::DoublePendulum dp(link, link, g);
  ref::DoublePendulumTrajectory traj(
      dp, ref::DoublePendulumState{std::numbers::pi / 2, std::numbers::pi / 2, 0, 0});
  // The reference's angles are from the downward vertical, counterclockwise in (x, up); a positive
  // turn about +y moves a hanging bob towards -x, so theta = pi/2 - (sum of the joint angles).
  const double E0 = energy(b, g);
  double worst_state = 0, worst_E = 0;
  for (int i = 1; i <= 3600; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    worst_E = std::max(worst_E, std::abs(energy(b, g) - E0));
    if (i <= 120) {
      const ref::DoublePendulumState r = traj.sample(i / 60.0);
      const double th1 = std::numbers::pi / 2 - art.position(0);
      const double th2 = std::numbers::pi / 2 - art.position(0) - art.position(1);
      const double w1 = -art.speed(0), w2 = -art.speed(0) - art.speed(1);
      worst_state = std::max({worst_state, std::abs(th1 - r.theta1), std::abs(th2 - r.theta2),
                              std::abs(w1 - r.omega1) / 10, std::abs(w2 - r.omega2) / 10});
    }
  }
  const double scale = m * g * L;
  std::printf("double pendulum: state error over 2 s %.1e rad, max |dE| over 60 s %.1e m g L, steps %ld\n",
              worst_state, worst_E / scale, art.internal_steps());
  EXPECT_LT(worst_state, 1e-6);  // the bound: 1e-6 rad (and 1e-5 rad/s for the rates)
  EXPECT_LT(worst_E / scale, 1e-6);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// The block forms of the spatial transforms against the 6x6 matrices they replace.
TEST(Spatial, BlockTransformsMatchTheMatrices) {
  const Mat3 E = Quat(Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized())).toRotationMatrix();
  const Vec3 r(0.3, -1.2, 0.8);
  const Mat6 X = motion_transform(E, r);
  Mat6 I = Mat6::Random();
  I = (I + I.transpose()).eval();
  const Vec6 v = Vec6::Random();
  EXPECT_LT((transform_motion(E, r, v) - X * v).norm(), 1e-14);
  EXPECT_LT((transform_force_back(E, r, v) - X.transpose() * v).norm(), 1e-14);
  Mat6 acc = I;  // added onto what is there
  add_transform_inertia_back(E, r, I, acc);
  EXPECT_LT((acc - I - X.transpose() * I * X).norm(), 1e-13);
  // The raw-array forms the ABA's passes use: the same sums in the same order, so the same bits.
  const Vec6 m = Vec6::Random(), a = Vec6::Random();
  const Vec3 w = v.head<3>(), u = v.tail<3>(), m0 = m.head<3>(), m1 = m.tail<3>();
  Vec6 out;
  out << w.cross(m0), w.cross(m1) + u.cross(m0);  // Featherstone eq. 2.31
  EXPECT_EQ(cross_motion(v, m), out);
  out << w.cross(m0) + u.cross(m1), w.cross(m1);  // eq. 2.32
  EXPECT_EQ(cross_force(v, m), out);
  transform_motion_add(E, r, v.data(), a.data(), out.data());
  EXPECT_EQ(out, Vec6(transform_motion(E, r, v) + a));
  out = a;
  add_transform_force_back(E, r, v.data(), out.data());
  EXPECT_EQ(out, Vec6(a + transform_force_back(E, r, v)));
  out = a;
  add_mat6_vec(I, v, out.data());
  EXPECT_EQ(out, Vec6(a + mat6_vec(I, v)));
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// A Grashof crank-rocker four-bar (ground 0.4 m, crank 0.1 m, coupler 0.35 m, rocker 0.3 m) of
// uniform steel-like rods hinged about y, released at rest from crank angle 60 degrees, under
// gravity: a closed loop (the rocker's second hinge closes it). The loop's anchors must stay
// together to 1e-6 m at all times and the energy must hold to 1e-6 m g L over 20 s; the crank
// and rocker angles must satisfy Freudenstein's equation (the independent loop-closure reference).
TEST(Articulation, FourBarLinkageClosesItsLoopAndKeepsEnergy) {
  const double ground = 0.4, crank = 0.1, coupler = 0.35, rocker = 0.3, g = 9.81, rho_l = 2.0;  // kg/m
  ASSERT_TRUE(ref::is_grashof(ground, crank, coupler, rocker));
  const double th2 = std::numbers::pi / 3;
  const auto pose = ref::four_bar_pose(ground, crank, coupler, rocker, th2);
  ASSERT_TRUE(pose);
  // The reference's plane (x, y) is our (x, z).
  auto P = [](const Eigen::Vector2d& p) { return Vec3(p.x(), 0, p.y()); };
  const Vec3 A(0, 0, 0), D(ground, 0, 0), B = P(pose->B), C = P(pose->C);
  Bodies b;
  auto rod = [&](const std::string& name, const Vec3& from, const Vec3& to) {
    const Vec3 d = to - from;
    const double L = d.norm(), m = rho_l * L, I = m * L * L / 12;
    // Principal frame: z along the rod (axial moment tiny but positive).
    const Quat q = Quat::FromTwoVectors(Vec3::UnitZ(), d / L);
    return b.add(name, m, Vec3(I, I, 1e-9 * I), 0.5 * (from + to), q);
  };
  const int ic = rod("crank", A, B), ik = rod("coupler", B, C), ir = rod("rocker", D, C);
  auto hinge = [](int parent, int child, const Vec3& at) {
    JointDef j;
    j.parent = parent;
    j.child = child;
    j.anchor_W = at;
    j.axis_W = Vec3::UnitY();
    return j;
  };
  std::vector<JointDef> joints = {hinge(-1, ic, A), hinge(ic, ik, B), hinge(ik, ir, C), hinge(-1, ir, D)};
  Articulations art;
  std::vector<std::string> warnings;
  art.build(joints, {}, b.defs, b.model, b.state, warnings);
  ASSERT_EQ(art.mechanisms().size(), 1u);
  ASSERT_EQ(art.mechanisms()[0].loops.size(), 1u);
  const double E0 = energy(b, g);
  double M = 0;
  for (const BodyModel& m : b.model) M += m.mass;
  const double scale = M * g * ground;
  double worst_gap = 0, worst_E = 0, worst_fr = 0, swing = 0;
  for (int i = 0; i < 1200; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    worst_gap = std::max(worst_gap, art.gap(b.state.data()));
    worst_E = std::max(worst_E, std::abs(energy(b, g) - E0));
    // Freudenstein: the rocker's direction at the crank's current angle. A positive turn about +y
    // turns x towards -z, so the reference's counterclockwise angle (x towards +z) is minus ours.
    const double crank_angle = th2 - art.position(0);
    const auto r = ref::four_bar_pose(ground, crank, coupler, rocker, crank_angle);
    ASSERT_TRUE(r);
    const Vec3 tip = b.state[ir].x_W * 2 - D;  // the rocker's centre is halfway from D to C
    worst_fr = std::max(worst_fr, (tip - P(r->C)).norm());
    swing = std::max(swing, std::abs(art.position(0)));
  }
  EXPECT_GT(swing, 1.0);  // the crank really swings (rad)
  std::printf(
      "four-bar: crank swing %.2f rad, loop gap %.1e m, |dE| %.1e M g l, Freudenstein %.1e m, steps %ld\n",
      swing, worst_gap, worst_E / scale, worst_fr, art.internal_steps());
  EXPECT_LT(worst_gap, 1e-6);
  EXPECT_LT(worst_E / scale, 1e-6);
  EXPECT_LT(worst_fr, 1e-6);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// A 250 kg body on a vertical slider with a spring (k = 20 kN/m) and a damper (c = 1 kN s/m), the
// quarter car without its wheel, released at the spring's rest length: it settles at the static
// sag m g / k, oscillating at the damped frequency sqrt(k/m) sqrt(1 - zeta^2). The sag and the
// frequency are read from the motion (the mean of the first two turning points, their spacing)
// and held to 0.1% and 0.5% (a suspension's specification); the integrator's error is far below both.
TEST(Articulation, SliderSpringSagsAndRingsAsTheQuarterCar) {
  const ref::QuarterCar car{250, 20000, 1000};
  const double g = 9.81;
  Bodies b;
  b.add("body", car.m, Vec3(10, 10, 10), Vec3(0, 0, 1));
  JointDef j;
  j.type = JointType::prismatic;
  j.parent = -1;
  j.child = 0;
  j.anchor_W = Vec3(0, 0, 1);
  j.axis_W = Vec3::UnitZ();
  j.spring = JointSpring{car.k, car.c, 0};
  Articulations art;
  std::vector<std::string> warnings;
  art.build({j}, {}, b.defs, b.model, b.state, warnings);
  // Turning points (speed crossing zero) located between frames by linear interpolation of the
  // speed; at 1/960 s frames the interpolation error is far below the 0.5% asked.
  const double dt = 1.0 / 960;
  std::vector<double> t_turn, q_turn;
  double prev_v = 0, prev_q = 0;
  for (int i = 1; i <= 960 * 2 && t_turn.size() < 3; ++i) {
    ASSERT_TRUE(art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()));
    const double v = art.speed(0), q = art.position(0);
    if (i > 1 && (prev_v < 0) != (v < 0) && v != 0) {
      const double f = prev_v / (prev_v - v);
      t_turn.push_back((i - 1 + f) * dt);
      q_turn.push_back(prev_q + f * (q - prev_q));
    }
    prev_v = v;
    prev_q = q;
  }
  ASSERT_EQ(t_turn.size(), 3u);
  const double zeta = car.damping_ratio();
  const double wn = 2 * std::numbers::pi * car.natural_frequency_hz();
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  const double period = 2 * (t_turn[2] - t_turn[1]);  // half a period between turning points
  // The decaying oscillation about the sag: turning points x_k = -s + (-1)^k A r^k with
  // r = exp(-zeta wn pi / wd), so two successive ones give the sag: s = -(x_1 r + x_2) / (1 + r).
  const double r = std::exp(-zeta * wn * std::numbers::pi / wd);
  const double sag = -(q_turn[1] * r + q_turn[2]) / (1 + r);
  std::printf("quarter car: sag %.6f m (m g / k %.6f), period %.6f s (2 pi / w_d %.6f)\n", sag,
              car.static_sag(g), period, 2 * std::numbers::pi / wd);
  EXPECT_NEAR(sag / car.static_sag(g), 1, 1e-3);
  EXPECT_NEAR(period / (2 * std::numbers::pi / wd), 1, 5e-3);
}

// A torsion spring on a hinge, no gravity: simple harmonic at sqrt(k / I_axis) (I about the hinge).
TEST(Articulation, HingeSpringOscillatesAtItsFrequency) {
  const double k = 3.0, I = 0.02;  // N m/rad, kg m^2 about the hinge through the centre of mass
  Bodies b;
  b.add("wheel", 1.0, Vec3(0.01, 0.01, I), Vec3::Zero());
  b.state[0].w_P = Vec3(0, 0, 1.0);  // 1 rad/s about the hinge (z)
  JointDef j;
  j.type = JointType::revolute;
  j.parent = -1;
  j.child = 0;
  j.axis_W = Vec3::UnitZ();
  j.spring = JointSpring{k, 0, 0};
  Articulations art;
  std::vector<std::string> warnings;
  art.build({j}, {}, b.defs, b.model, b.state, warnings);
  const double w = ref::spring_joint_omega(k, I);
  // One full period in N equal steps: back at angle 0 with speed 1, to the integrator's accuracy.
  const int N = 120;
  for (int i = 0; i < N; ++i)
    ASSERT_TRUE(art.step(2 * std::numbers::pi / w / N, Vec3::Zero(), nullptr, b.state.data()));
  EXPECT_NEAR(art.position(0), 0, 1e-8);
  EXPECT_NEAR(art.speed(0), 1, 1e-8);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// The same heavy top's nutation against the roots of the cubic in cos(theta) and its mean
// precession against the quadrature over a nutation period (the independent reference). Sampled
// every 1/6000 s; each extreme of theta is the vertex of the parabola through three samples (its
// error, ~(w_n h)^4 theta, is 1e-9 rad here) and the precession is the azimuth's advance over
// four whole nutation periods, its end located the same way. Tolerances: 1e-5 rad on the bounds
// and 1e-6 relative on the rates.
TEST(Articulation, HeavyTopNutatesBetweenTheCubicsRootsAndPrecessesAtTheMeanRate) {
  Bodies b;
  const double m = 1, l = 0.1, I1 = 2e-3, I3 = 4e-3, g = 9.81, th = 0.3, spin = 150;
  const Vec3 axis(std::sin(th), 0, std::cos(th));
  const Quat q(Eigen::AngleAxisd(th, Vec3::UnitY()));
  b.add("top", m, Vec3(I1, I1, I3), axis * l, q);
  b.state[0].w_P = Vec3(0, 0, spin);
  b.state[0].v_W = (q * b.state[0].w_P).cross(axis * l);
  JointDef j;
  j.type = JointType::spherical;
  j.child = 0;
  Articulations art;
  std::vector<std::string> warnings;
  JointSettings js;
  js.tolerance = 1e-12;
  art.build({j}, js, b.defs, b.model, b.state, warnings);
  const ref::HeavyTopMotion ref = ref::heavy_top({I1 + m * l * l, I3, m, g, l}, {th, 0, 0, spin});
  const double h = 1.0 / 6000;
  double lo = 10, hi = -10;
  double th_m2 = 0, th_m1 = 0, az_m2 = 0, az_m1 = 0;
  double az = 0, az_prev = 0;  // unwrapped azimuth of the figure axis
  // The start is a lowest point (theta' = 0 there): the fourth lowest point after it ends four
  // whole nutation periods, over which the azimuth advances 4 T_n times the mean rate.
  int minima = 0;
  double t4 = 0, az4 = 0;
  const int n = (int)std::round(4.5 * ref.nutation_period / h);
  for (int i = 1; i <= n && minima < 4; ++i) {
    ASSERT_TRUE(art.step(h, Vec3(0, 0, -g), nullptr, b.state.data()));
    const Vec3 e3 = b.state[0].q_WP * Vec3::UnitZ();
    const double t = std::acos(std::clamp(e3.z(), -1.0, 1.0));
    const double a = std::atan2(e3.y(), e3.x());
    az += std::remainder(a - az_prev, 2 * std::numbers::pi);
    az_prev = a;
    if (i >= 3) {
      const double d1 = th_m1 - th_m2, d2 = t - th_m1;
      if ((d1 > 0) != (d2 > 0)) {  // an extreme at the middle sample: the parabola's vertex
        const double c2 = 0.5 * (t - 2 * th_m1 + th_m2), c1 = 0.5 * (t - th_m2);
        const double x = -c1 / (2 * c2);  // in steps from the middle sample
        const double v = th_m1 + c1 * x + c2 * x * x;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        if (c2 > 0 && ++minima == 4) {
          t4 = (i - 1 + x) * h;
          const double b2 = 0.5 * (az - 2 * az_m1 + az_m2), b1 = 0.5 * (az - az_m2);
          az4 = az_m1 + b1 * x + b2 * x * x;
        }
      }
    }
    th_m2 = th_m1;
    th_m1 = t;
    az_m2 = az_m1;
    az_m1 = az;
  }
  ASSERT_EQ(minima, 4);
  const double rate = az4 / t4;
  std::printf(
      "top: theta in [%.9f, %.9f] (cubic: [%.9f, %.9f]); nutation period %.9f s (%.9f); precession "
      "%.9f rad/s (%.9f)\n",
      lo, hi, ref.theta_min, ref.theta_max, t4 / 4, ref.nutation_period, rate, ref.mean_precession_rate);
  EXPECT_NEAR(lo, ref.theta_min, 1e-5);
  EXPECT_NEAR(hi, ref.theta_max, 1e-5);
  EXPECT_NEAR(t4 / 4 / ref.nutation_period, 1, 1e-6);
  EXPECT_NEAR(rate / ref.mean_precession_rate, 1, 1e-6);
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// All three of the anchors' chains (end mass 1, 100 and 1000 times a link), hanging straight and
// released from 30 degrees, 10 s each: no gap, energy to 1e-6 of M g N l (the long-test label:
// about a minute).
TEST(StressArticulation, ChainsOfEveryRatioHangAndSwingWithoutGapsOrEnergyLoss) {
  for (double tilt : {0.0, std::numbers::pi / 6})
    for (double ratio : {1.0, 100.0, 1000.0}) {
      Chain c(100, ratio, tilt);
      const double g = 9.81, E0 = energy(c.b, g);
      double M = 0;
      for (const BodyModel& m : c.b.model) M += m.mass;
      double worst = 0, worst_gap = 0;
      for (int i = 0; i < 600; ++i) {
        ASSERT_TRUE(c.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, c.b.state.data())) << ratio;
        worst = std::max(worst, std::abs(energy(c.b, g) - E0));
        worst_gap = std::max(worst_gap, c.art.gap(c.b.state.data()));
      }
      EXPECT_LT(worst / (M * g * 100 * 0.1), 1e-6) << "ratio " << ratio << " tilt " << tilt;
      EXPECT_LT(worst_gap, 1e-10) << "ratio " << ratio << " tilt " << tilt;
    }
}

}  // namespace
}  // namespace simreel

namespace simreel {
namespace {

// A wheel (a disc of 20 kg, radius 0.3 m, spinning about y) hung from a fixed chassis by a wheel
// joint: suspension along z with a spring k = 20 kN/m (no damping), a steering hinge about z
// driven to 0.2 rad by a position motor (time constant 0.1 s), and its axle about y driven at
// 30 rad/s. Released at the spring's rest length, the wheel drops to the sag m g / k and rings
// about it at sqrt(k / m) (the steering and spin do not load the slider: their axes pass through
// the wheel's centre); the steering angle follows 0.2 (1 - exp(-t / 0.1)) and the spin holds its
// rate. Closed forms exact to the integrator's error: 1e-7 of the sag (the tolerance's 1e-10
// absolute floor per step over two seconds of a 5 Hz ring: measured 3e-8), 1e-7 of the steering.
TEST(Articulation, WheelJointSuspendsSteersAndSpins) {
  const double m = 20, R = 0.3, k = 20000, g = 9.81;
  Bodies b;
  const double Iax = 0.5 * m * R * R, Id = 0.25 * m * R * R;
  b.add("wheel", m, Vec3(Id, Iax, Id), Vec3(0, 0, 0.5));
  JointDef j;
  j.name = "corner";
  j.type = JointType::wheel;
  j.parent = -1;
  j.child = 0;
  j.anchor_W = Vec3(0, 0, 0.5);
  j.axis_W = Vec3::UnitZ();
  j.axis2_W = Vec3::UnitY();
  j.spring = JointSpring{k, 0, 0};
  JointMotor drive;
  drive.speed = 30;
  drive.max_force = 1e6;
  j.motor = drive;
  JointMotor steer;
  steer.mode = JointMotor::Mode::position;
  steer.position = 0.2;
  steer.speed = std::numeric_limits<double>::infinity();
  steer.time_constant = 0.1;
  // A stiff servo: it reaches its 2 rad/s start rate in I v / T = 1e-9 s, which the closed form
  // (instant capture) leaves out: 1e-8 of the angle.
  steer.max_force = 1e9;
  j.steering = steer;
  Articulations art;
  std::vector<std::string> warnings;
  art.build({j}, {}, b.defs, b.model, b.state, warnings);
  const double w0 = std::sqrt(k / m), sag = m * g / k;
  double worst_z = 0, worst_steer = 0, worst_spin = 0;
  const int N = 120;
  for (int i = 1; i <= N; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    const double t = i / 60.0;
    // The slider's coordinate grows along +z: released at rest at 0, x(t) = -sag (1 - cos w0 t).
    worst_z = std::max(worst_z, std::abs(art.position(0, 0) + sag * (1 - std::cos(w0 * t))) / sag);
    worst_steer = std::max(worst_steer, std::abs(art.position(0, 1) - 0.2 * (1 - std::exp(-t / 0.1))) / 0.2);
    if (t > 0.05) worst_spin = std::max(worst_spin, std::abs(art.speed(0, 2) - 30) / 30);
    EXPECT_LT(art.gap(b.state.data()), 1e-14);
  }
  std::printf("wheel joint: suspension %.1e of the sag, steering %.1e, spin %.1e\n", worst_z, worst_steer,
              worst_spin);
  EXPECT_LT(worst_z, 1e-7);
  EXPECT_LT(worst_steer, 1e-7);
  EXPECT_LT(worst_spin, 1e-12);
}

}  // namespace
}  // namespace simreel
