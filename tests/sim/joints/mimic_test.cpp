// A joint that mimics another (JointMimic: URDF's mimic, a pair of gears; sim/joints/articulation.hpp,
// a coupling row) against closed forms: geared to a flywheel, a pendulum swings as one with the
// flywheel's inertia reflected through the gear ratio squared (the elliptic-integral period with
// I_p + n^2 I_w), the two angles keep their ratio to round-off, and energy is kept. A joint's rotor
// inertia (armature) is that reflected inertia: a pendulum with armature n^2 I_w moves as the
// geared one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <simreel/error.hpp>

#include "sim/joints/articulation.hpp"
#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

using test::Bodies;

// A bob (1 kg at 1 m, 1e-3 kg m^2 about its centre) hinged about +y at the origin, released
// horizontal, geared to a balanced flywheel (0.05 kg m^2 about its axle, +y through (3, 0, 0))
// whose angle is n times the pendulum's.
struct GearedPendulum {
  static constexpr double m = 1, d = 1, Icm = 1e-3, Iw = 0.05, g = 9.81;
  Bodies b;
  Articulations art;
  explicit GearedPendulum(double n) {
    b.add("bob", m, Vec3::Constant(Icm), Vec3(-d, 0, 0));  // phi0 = 90 degrees about +y
    b.add("flywheel", 2, Vec3(Iw, Iw, Iw), Vec3(3, 0, 0));
    JointDef pivot;
    pivot.name = "pivot";
    pivot.type = JointType::revolute;
    pivot.child = 0;
    pivot.axis_W = Vec3::UnitY();
    JointDef axle = pivot;
    axle.name = "axle";
    axle.child = 1;
    axle.anchor_W = Vec3(3, 0, 0);
    axle.mimic = JointMimic{0, n};
    std::vector<std::string> warnings;
    art.build({pivot, axle}, {}, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty());
  }
  bool step(double dt) { return art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()); }
};

// The same pendulum with the flywheel left out and a rotor inertia (armature) of n^2 I_w on its
// hinge instead: the reflected inertia the gear gave it, so the same motion.
struct RotorPendulum {
  static constexpr double m = 1, d = 1, Icm = 1e-3, g = 9.81;
  Bodies b;
  Articulations art;
  explicit RotorPendulum(double armature) {
    b.add("bob", m, Vec3::Constant(Icm), Vec3(-d, 0, 0));
    JointDef pivot;
    pivot.name = "pivot";
    pivot.type = JointType::revolute;
    pivot.child = 0;
    pivot.axis_W = Vec3::UnitY();
    pivot.armature = armature;
    std::vector<std::string> warnings;
    art.build({pivot}, {}, b.defs, b.model, b.state, warnings);
  }
  bool step(double dt) { return art.step(dt, Vec3(0, 0, -g), nullptr, b.state.data()); }
};

// A differential: a flywheel whose angle is n q_a + n q_b of two identical pendulums released
// together (JointMimic with a further leader, `also`). The flywheel pushes both alike, so
// q_a = q_b = phi, and its 2 n phi' shares its energy between them: each swings as one pendulum
// with rotor inertia Iw (2 n)^2 / 2. The flywheel keeps its combination to round-off, and energy
// holds. (With n1 != n2 the two would be pushed unequally and part.)
TEST(JointMimic, DifferentialSharesItsFlywheelBetweenTwoPendulums) {
  const double n1 = -1, n2 = -1, Iw = GearedPendulum::Iw, g = GearedPendulum::g;
  Bodies b;
  b.add("bob_a", 1, Vec3::Constant(1e-3), Vec3(-1, 0, 0));
  b.add("bob_b", 1, Vec3::Constant(1e-3), Vec3(-1, 5, 0));
  b.add("flywheel", 2, Vec3(Iw, Iw, Iw), Vec3(3, 0, 0));
  JointDef pa;
  pa.name = "pivot_a";
  pa.type = JointType::revolute;
  pa.child = 0;
  pa.axis_W = Vec3::UnitY();
  JointDef pb = pa;
  pb.name = "pivot_b";
  pb.child = 1;
  pb.anchor_W = Vec3(0, 5, 0);
  JointDef axle = pa;
  axle.name = "axle";
  axle.child = 2;
  axle.anchor_W = Vec3(3, 0, 0);
  axle.mimic = JointMimic{0, n1, std::nullopt, {{1, n2}}};
  Articulations art;
  std::vector<std::string> warnings;
  art.build({pa, pb, axle}, {}, b.defs, b.model, b.state, warnings);
  RotorPendulum rotor(Iw * (n1 + n2) * (n1 + n2) / 2);
  const double E0 = b.energy(g);
  double apart = 0, energy = 0, coupled = 0;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data()));
    ASSERT_TRUE(rotor.step(1.0 / 60));
    apart = std::max(apart, std::abs(art.position(0) - rotor.art.position(0)));
    energy = std::max(energy, std::abs(b.energy(g) - E0));
    coupled = std::max(coupled, std::abs(art.position(2) - n1 * art.position(0) - n2 * art.position(1)));
  }
  std::printf("differential against rotor: %.1e rad apart over 4 s, energy %.1e J, combination %.1e\n", apart,
              energy, coupled);
  EXPECT_GT(std::abs(art.position(2)), 0.5);  // the flywheel turned
  EXPECT_LT(apart, 1e-8);                     // 9e-10 measured
  EXPECT_LT(energy, 3e-8);                    // J, of 2 m g d = 19.6 (1e-8 measured)
  EXPECT_LT(coupled, 1e-12);
}

TEST(JointArmature, RotorInertiaIsTheGearsReflectedInertia) {
  const double n = -2, Iw = GearedPendulum::Iw;
  GearedPendulum geared(n);
  RotorPendulum rotor(n * n * Iw);
  const double E0 = rotor.b.energy(rotor.g) + rotor.art.armature_energy();
  double apart = 0, energy = 0;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(geared.step(1.0 / 60));
    ASSERT_TRUE(rotor.step(1.0 / 60));
    apart = std::max(apart, std::abs(geared.art.position(0) - rotor.art.position(0)));
    energy = std::max(
        energy, std::abs(rotor.b.energy(rotor.g) + rotor.art.armature_energy() - E0) / (rotor.m * rotor.g));
  }
  std::printf("rotor against gear: %.1e rad apart over 4 s, energy %.1e m g d\n", apart, energy);
  // Two integrations of the same equations at tolerance 1e-10: their difference, not round-off.
  EXPECT_LT(apart, 1e-8);
  EXPECT_LT(energy, 1e-8);
  EXPECT_GT(std::abs(rotor.art.position(0)), 0.5);
  // Without the armature the rotor pendulum is faster: the difference is not small.
  RotorPendulum bare(0), with(n * n * Iw);
  for (int i = 1; i <= 30; ++i) ASSERT_TRUE(bare.step(1.0 / 60) && with.step(1.0 / 60));
  EXPECT_GT(std::abs(bare.art.position(0) - with.art.position(0)), 0.1);
}

TEST(JointMimic, GearedPendulumSwingsWithTheReflectedInertia) {
  // Released at rest from phi0 = pi/2, the pendulum reaches the bottom after a quarter of its
  // period, K(sin(phi0/2)) sqrt(I_eff / (m g d)), I_eff = m d^2 + Icm + n^2 Iw.
  const double n = -2;
  GearedPendulum p(n);
  const double Ieff = p.m * p.d * p.d + p.Icm + n * n * p.Iw;
  const double quarter =
      ref::elliptic_K(std::sin(std::numbers::pi / 4)) * std::sqrt(Ieff / (p.m * p.g * p.d));
  const double E0 = p.b.energy(p.g);
  double ratio = 0, energy = 0, t_cross = NAN;
  double phi_prev = std::numbers::pi / 2, w_prev = 0;
  const double dt = 1.0 / 60;
  for (int i = 1; i <= 240; ++i) {
    ASSERT_TRUE(p.step(dt));
    const double q = p.art.position(0), qf = p.art.position(1);
    ratio = std::max(ratio, std::abs(qf - n * q));
    energy = std::max(energy, std::abs(p.b.energy(p.g) - E0) / (p.m * p.g * p.d));
    // The angle from the downward vertical: phi0 + q (a turn about +y takes -x towards -z).
    const double phi = std::numbers::pi / 2 + q, w = p.art.speed(0);
    if (std::isnan(t_cross) && phi <= 0 && phi_prev > 0) {
      // The crossing on the frame's cubic Hermite interpolant (its error ~1e-11 of the period).
      double a = 0, c = 1;
      auto h = [&](double s) {
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * phi_prev + (s3 - 2 * s2 + s) * dt * w_prev + (-2 * s3 + 3 * s2) * phi +
               (s3 - s2) * dt * w;
      };
      for (int it = 0; it < 100; ++it) (h(0.5 * (a + c)) > 0 ? a : c) = 0.5 * (a + c);
      t_cross = (i - 1 + 0.5 * (a + c)) * dt;
    }
    phi_prev = phi;
    w_prev = w;
  }
  std::printf("geared pendulum: quarter period %.12f s (exact %.12f), ratio %.1e rad, energy %.1e m g d\n",
              t_cross, quarter, ratio, energy);
  EXPECT_NEAR(t_cross / quarter, 1, 1e-8);
  EXPECT_LT(ratio, 1e-12);
  EXPECT_LT(energy, 1e-8);
  EXPECT_LT(p.art.gap(p.b.state.data()), 1e-12);
}

TEST(JointMimic, MistakesAreNamed) {
  Bodies b;
  b.add("a", 1, Vec3::Constant(0.01), Vec3(0, 0, -1));
  b.add("c", 1, Vec3::Constant(0.01), Vec3(2, 0, -1));
  JointDef j0;
  j0.name = "j0";
  j0.type = JointType::revolute;
  j0.child = 0;
  j0.axis_W = Vec3::UnitY();
  JointDef j1 = j0;
  j1.name = "j1";
  j1.child = 1;
  j1.anchor_W = Vec3(2, 0, 0);
  auto error = [&](JointDef x0, JointDef x1) {
    Articulations art;
    std::vector<std::string> w;
    try {
      art.build({x0, x1}, {}, b.defs, b.model, b.state, w);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  JointDef f = j1;
  f.mimic = JointMimic{1, 1};
  EXPECT_NE(error(j0, f).find("joint 'j1': mimics no other joint"), std::string::npos);
  f.mimic = JointMimic{0, 0};
  EXPECT_NE(error(j0, f).find("the mimic's multiplier must be a finite, nonzero number"), std::string::npos);
  JointDef s = j0;
  s.type = JointType::spherical;
  f.mimic = JointMimic{0, 1};
  EXPECT_NE(error(s, f).find("mimics joint 'j0', which is not a revolute or prismatic joint"),
            std::string::npos);
  JointDef l = j0;
  l.mimic = JointMimic{1, 1};
  EXPECT_NE(error(l, f).find("which mimics another itself"), std::string::npos);
}

}  // namespace
}  // namespace simreel
