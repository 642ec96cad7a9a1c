// The Verlet joint integrator (JointIntegrator::verlet, Mechanism::advance_verlet) against the
// scheme's own closed forms: its period error on a pendulum, its stability limit on a chain's
// fastest mode and on a damped spring, and the saved-state and thread guarantees.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include <simreel/simreel.hpp>

#include "sim/joints/articulation.hpp"
#include "tests/fixtures/joint_bodies.hpp"
#include "tests/fixtures/joint_reference.hpp"

namespace simreel {
namespace {

using test::Bodies;
constexpr double kPi = std::numbers::pi;

JointSettings verlet(int substeps = 0) {
  JointSettings js;
  js.integrator = JointIntegrator::verlet;
  js.substeps = substeps;
  return js;
}

// A bob of 1 kg, 1e-3 kg m^2 about its centre, 1 m from a y hinge at the origin, released at rest.
struct Pendulum {
  Bodies b;
  Articulations art;
  double m = 1, Icm = 1e-3, d = 1, g = 9.81;
  Pendulum(double theta0, const JointSettings& js) {
    b.add("bob", m, Vec3::Constant(Icm), Vec3(d * std::sin(theta0), 0, -d * std::cos(theta0)));
    JointDef j;
    j.type = JointType::revolute;
    j.child = 0;
    j.axis_W = Vec3::UnitY();
    std::vector<std::string> warnings;
    art.build({j}, js, b.defs, b.model, b.state, warnings);
    EXPECT_TRUE(warnings.empty());
  }
};

// Velocity Verlet on x'' = -w^2 x turns with sin(w~ h / 2) = w h / 2, so its period is short by
// 1 - w h / (2 asin(w h / 2)), -(w h)^2 / 24 to leading order. A 10 deg pendulum is that oscillator
// up to its amplitude's share of the error (theta0^2 / 16 of it, 0.2%): one closed-form period run
// in N equal steps, the shortfall read from the speed there as in the dopri5 period test.
TEST(Verlet, PendulumPeriodShortensByTheSchemesClosedForm) {
  const double th0 = 10 * kPi / 180;
  double previous = 0;
  for (int sub : {1, 2}) {
    Pendulum p(th0, verlet(sub));
    const double Ip = p.Icm + p.m * p.d * p.d, w = std::sqrt(p.m * p.g * p.d / Ip);
    const double T = ref::pendulum_period(th0, Ip, p.m, p.g, p.d);
    const int N = (int)std::ceil(T * 60);
    for (int i = 0; i < N; ++i) ASSERT_TRUE(p.art.step(T / N, Vec3(0, 0, -p.g), nullptr, p.b.state.data()));
    const double h = T / N / sub;
    const double expected = w * h / (2 * std::asin(w * h / 2)) - 1;
    // The coordinate is zero at the start, rotated about +y toward the bottom: at the turning
    // point its acceleration is +w^2 sin(theta0).
    const double dT = -p.art.speed(0) / (w * w * std::sin(th0));
    std::printf("substeps %d: dT/T %.4e, scheme's closed form %.4e\n", sub, dT / T, expected);
    EXPECT_NEAR(dT / T / expected, 1, 0.01) << sub;
    EXPECT_EQ(p.art.internal_steps(), (long)N * sub);
    if (sub == 2) {
      EXPECT_NEAR(previous / (dT / T), 4, 0.05);  // second order
    }
    previous = dT / T;
  }
}

// A chain of n rods (l, ml) hinged about y from the origin, released straight at `tilt` rad; the
// last rod may carry a point mass `end` (kg) at its free end.
struct Chain {
  Bodies b;
  Articulations art;
  std::vector<std::string> warnings;
  double scale = 0;  ///< J: M g n l
  Chain(int n, double tilt, const JointSettings& js, double l = 0.1, double ml = 0.01, double end = 0) {
    const Vec3 dir(std::sin(tilt), 0, -std::cos(tilt));
    std::vector<JointDef> joints;
    for (int i = 0; i < n; ++i) {
      double I = ml * l * l / 12, m = ml, c = 0.5 * l;
      if (i == n - 1 && end > 0) {  // the rod and the point mass as one body about their centre
        c = (ml * 0.5 * l + end * l) / (ml + end);
        I += ml * (0.5 * l - c) * (0.5 * l - c) + end * (l - c) * (l - c);
        m += end;
      }
      b.add("link" + std::to_string(i), m, Vec3(I, I, 1e-9 * I), dir * (i * l + c));
      JointDef j;
      j.type = JointType::revolute;
      j.parent = i - 1;
      j.child = i;
      j.anchor_W = dir * (i * l);
      j.axis_W = Vec3::UnitY();
      joints.push_back(j);
    }
    art.build(joints, js, b.defs, b.model, b.state, warnings);
    scale = (n * ml + end) * 9.81 * n * l;
  }
  /// The worst energy error over `frames` frames of 1/60 s, in M g N l; NaN if a step failed.
  double worst_energy_error(int frames) {
    const double g = 9.81, E0 = b.energy(g);
    double worst = 0;
    for (int i = 0; i < frames; ++i) {
      if (!art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, b.state.data())) return NAN;
      worst = std::max(worst, std::abs(b.energy(g) - E0) / scale);
    }
    return worst;
  }
};

// The fastest mode's rate, measured by power iteration at the first frame, against the largest
// eigenfrequency of the linearised hanging chain: M q'' = -K q with M_jk = sum_i m L_ij L_ik + I
// delta_jk and K diagonal, m g times the length of chain below each joint's link (rods: a link's
// centre at l / 2). The first frame iterates until a pair moves the rate by under 1% (the next
// mode at 116 / 132 of it leaves the estimate about as far again below: within 1e-2, what the
// step count needs); the later measurements' single pairs converge on it: within 1e-3 after a
// second (6 of them).
TEST(Verlet, MeasuredRateIsTheHangingChainsFastestEigenfrequency) {
  const int n = 20;
  const double l = 0.1, ml = 0.01, g = 9.81, I = ml * l * l / 12;
  Chain c(n, 0, verlet());
  ASSERT_TRUE(c.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, c.b.state.data()));
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n), K = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) L(i, j) = l;
    L(i, i) = l / 2;
    K(i, i) = ml * g * (l * (n - 1 - i) + l / 2);
  }
  const Eigen::MatrixXd M = ml * L.transpose() * L + I * Eigen::MatrixXd::Identity(n, n);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  const double w_max = std::sqrt(es.eigenvalues().maxCoeff());
  const double first = c.art.mechanisms()[0].verlet.rate;
  EXPECT_NEAR(first / w_max, 1, 1e-2);
  EXPECT_EQ(c.art.internal_steps(), 2);  // 132 / 60 = 2.2 per frame: two steps keep it under 1.4
  for (int i = 1; i < 60; ++i) ASSERT_TRUE(c.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, c.b.state.data()));
  const double rate = c.art.mechanisms()[0].verlet.rate;
  std::printf("measured %.4f 1/s at the first frame, %.4f after a second; linearised chain %.4f 1/s\n", first,
              rate, w_max);
  EXPECT_NEAR(rate / w_max, 1, 1e-3);
}

// The chain released from 30 degrees at 1/60 s: two steps a frame (one frame in ten three, where
// the swing stiffens it, or a growth of the rate is foreseen, past 168 1/s), no frame handed to
// dopri5, and the energy error bounded (a
// symplectic scheme's error oscillates instead of drifting). One step a frame diverges.
TEST(Verlet, SwingingChainKeepsEnergyBounded) {
  Chain c(20, kPi / 6, verlet());
  ASSERT_TRUE(c.warnings.empty());
  const double g = 9.81, E0 = c.b.energy(g);
  double first = 0, second = 0;
  for (int i = 0; i < 600; ++i) {
    ASSERT_TRUE(c.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, c.b.state.data())) << i;
    double& worst = i < 300 ? first : second;
    worst = std::max(worst, std::abs(c.b.energy(g) - E0) / c.scale);
  }
  const Mechanism& m = c.art.mechanisms()[0];
  std::printf("rate %.1f 1/s, steps a frame %.3f, max |dE| %.2e then %.2e M g N l, dopri5 frames %ld\n",
              m.verlet.rate, c.art.internal_steps() / 600.0, first, second, m.verlet.unresolved);
  EXPECT_GE(c.art.internal_steps(), 1200);
  EXPECT_LE(c.art.internal_steps(), 1320);  // 2.11 measured
  EXPECT_EQ(m.verlet.unresolved, 0);
  // Second order with the fastest mode at rate h = 1.1: 2e-4 measured.
  EXPECT_LT(std::max(first, second), 1e-3);
  EXPECT_LT(second, 3 * first);  // bounded, not growing

  Chain one(20, kPi / 6, verlet(1));
  bool failed = false;
  for (int i = 0; i < 600 && !failed; ++i)
    failed = !one.art.step(1.0 / 60, Vec3(0, 0, -g), nullptr, one.b.state.data()) ||
             !(std::abs(one.b.energy(g) - E0) < one.scale);
  EXPECT_TRUE(failed) << "one step a frame (rate h = 2.2) should diverge";
}

// Released level, the chain is slack at first (rate 34 1/s: one step a frame) and tightens as it
// falls; at the bottom its end whips round. The rate, measured every frame while it changes,
// keeps the steps stable; the whip's frames, which fixed steps do not resolve, go to dopri5. The
// energy error is Verlet's in a fast fall (7e-3 of M g N l at 40 frames in two steps each,
// 2e-3 in four: the scheme's own error, the same with the rates solved implicitly), and the whip
// is chaotic: which of its frames Verlet keeps changes with the last bit, and with it the worst
// error, 0.11 to 0.56 of M g N l over releases 1e-10 rad apart. So five releases: every one stays
// bounded (a diverging run passes 1 within a frame), and their median (0.14) is the scheme's.
TEST(Verlet, LevelChainTightensWhipsAndStaysStable) {
  std::vector<double> worsts;
  for (int k = 0; k < 5; ++k) {
    Chain c(20, kPi / 2 + 1e-10 * k, verlet());
    const double worst = c.worst_energy_error(300);
    ASSERT_FALSE(std::isnan(worst));
    const Mechanism& m = c.art.mechanisms()[0];
    std::printf("level chain +%de-10 rad: max |dE| %.2e M g N l, dopri5 frames %ld of 300\n", k, worst,
                m.verlet.unresolved);
    EXPECT_GT(m.verlet.unresolved, 0);
    EXPECT_LT(m.verlet.unresolved, 300);
    EXPECT_LT(worst, 1.0);
    worsts.push_back(worst);
  }
  std::sort(worsts.begin(), worsts.end());
  EXPECT_LT(worsts[2], 0.3);
}

// A chain whose last link carries 1000 times a link's mass, released from 30 degrees: its fastest
// mode (1.1e3 1/s at 100 links) is the light links' wobble under the end's weight, which carries
// the largest joint rates and almost none of the energy. Verlet steps it at that mode's rate;
// the predictor's error, large against the largest rate, is under 3e-3 of the motion in the mass
// metric, so no frame goes to dopri5 (a largest-rate test alone sent 52 of 600 there, at 140
// steps each: seven times the run's cost for the same energy error).
TEST(Verlet, HeavyChainsFastModeStaysWithVerlet) {
  Chain c(100, kPi / 6, verlet(), 0.1, 0.01, 10.0);
  const double worst = c.worst_energy_error(600);
  ASSERT_FALSE(std::isnan(worst));
  const Mechanism& m = c.art.mechanisms()[0];
  std::printf("1000:1 chain: rate %.0f 1/s, %.2f steps a frame, dopri5 frames %ld, max |dE| %.2e M g N l\n",
              m.verlet.rate, c.art.internal_steps() / 600.0, m.verlet.unresolved, worst);
  EXPECT_EQ(m.verlet.unresolved, 0);
  EXPECT_LT(c.art.internal_steps(), 600 * 16);  // 14.7 a frame measured
  EXPECT_LT(worst, 2e-7);                       // 6e-8 measured (Verlet's second order)
}

// A hinge spring with heavy damping (k = 3 N m/rad, c = 4 N m s/rad, I = 0.02 kg m^2): overdamped,
// roots s = (-c +- sqrt(c^2 - 4 k I)) / (2 I), -0.75 and -199 1/s. The fast root is the rate
// measured (199 h = 3.3 at 1/60: three steps a frame); the angle follows the two-root closed form.
TEST(Verlet, DampedSpringMeasuresItsFastRootAndDecaysAsTheClosedForm) {
  const double k = 3, c = 4, I = 0.02;
  auto make = [&](const JointSettings& js, Bodies& b, Articulations& art) {
    b.add("wheel", 1.0, Vec3(0.01, 0.01, I), Vec3::Zero());
    b.state[0].w_P = Vec3(0, 0, 1.0);
    JointDef j;
    j.type = JointType::revolute;
    j.child = 0;
    j.axis_W = Vec3::UnitZ();
    j.spring = JointSpring{k, c, 0};
    std::vector<std::string> warnings;
    art.build({j}, js, b.defs, b.model, b.state, warnings);
  };
  Bodies b;
  Articulations art;
  make(verlet(), b, art);
  const double disc = std::sqrt(c * c - 4 * k * I), s1 = (-c + disc) / (2 * I), s2 = (-c - disc) / (2 * I);
  // x(0) = 0, x'(0) = 1: x = (e^{s1 t} - e^{s2 t}) / (s1 - s2), 5e-3 at most.
  double worst = 0;
  for (int i = 1; i <= 120; ++i) {
    ASSERT_TRUE(art.step(1.0 / 60, Vec3::Zero(), nullptr, b.state.data())) << i;
    const double t = i / 60.0, x = (std::exp(s1 * t) - std::exp(s2 * t)) / (s1 - s2);
    worst = std::max(worst, std::abs(art.position(0) - x));
  }
  const Mechanism& m = art.mechanisms()[0];
  std::printf("damped spring: rate %.2f 1/s (fast root %.2f), dopri5 frames %ld, worst error %.2e rad\n",
              m.verlet.rate, -s2, m.verlet.unresolved, worst);
  EXPECT_NEAR(m.verlet.rate / -s2, 1, 1e-3);
  // The transient (the fast root's 5 ms) changes the acceleration by more than Verlet's steps
  // resolve: dopri5 takes those frames; Verlet's second order then follows the slow root.
  EXPECT_GT(m.verlet.unresolved, 0);
  EXPECT_LT(m.verlet.unresolved, 20);
  // 9.5e-7 measured (2e-4 of the 5e-3 amplitude): the frames dopri5 takes are exact to its
  // tolerance, the rest second order; which frames those are moves it by a few tenths.
  EXPECT_LT(worst, 2e-6);

  Bodies b1;
  Articulations a1;
  make(verlet(1), b1, a1);
  bool failed = false;
  for (int i = 0; i < 120 && !failed; ++i)
    failed = !a1.step(1.0 / 60, Vec3::Zero(), nullptr, b1.state.data()) || std::abs(a1.position(0)) > 1;
  EXPECT_TRUE(failed) << "one step a frame (rate h = 3.3) should diverge";
}

// Limits make a hybrid system that Verlet does not step: that mechanism keeps dopri5, with a
// warning, to the same bits as a run that asked for dopri5.
TEST(Verlet, MechanismWithLimitsKeepsDopri5WithAWarning) {
  auto run = [](const JointSettings& js, std::vector<std::string>& warnings) {
    Bodies b;
    b.add("bob", 1, Vec3::Constant(1e-3), Vec3(1, 0, 0));
    JointDef j;
    j.type = JointType::revolute;
    j.child = 0;
    j.axis_W = Vec3::UnitY();
    j.limits = JointLimits{-0.5, 0.5, 0};
    Articulations art;
    art.build({j}, js, b.defs, b.model, b.state, warnings);
    for (int i = 0; i < 60; ++i) EXPECT_TRUE(art.step(1.0 / 60, Vec3(0, 0, -9.81), nullptr, b.state.data()));
    return std::pair(art.position(0), art.speed(0));
  };
  std::vector<std::string> wv, wd;
  const auto v = run(verlet(), wv), d = run(JointSettings{}, wd);
  ASSERT_EQ(wv.size(), 1u);
  EXPECT_NE(wv[0].find("limits, a motor or friction"), std::string::npos) << wv[0];
  EXPECT_NE(wv[0].find("'bob'"), std::string::npos) << wv[0];
  EXPECT_TRUE(wd.empty());
  EXPECT_EQ(v, d);
}

// Four chains of 10 links in a World: two threads give one thread's bits, and a state saved at
// any of the first 20 frames (the rate is measured at frames 0, 8 and 16) resumes to the straight
// run's bits: the carried acceleration and the measured mode are saved.
std::string saved(const World& w) {
  std::ostringstream os;
  w.save_state(os);
  return os.str();
}
WorldConfig chains_config(int threads) {
  WorldConfig cfg;
  cfg.dt = 1.0 / 60;
  cfg.threads = threads;
  cfg.joint_settings = verlet();
  return cfg;
}
std::vector<BodyDef> chains_bodies(WorldConfig& cfg) {
  std::vector<BodyDef> bodies;
  for (int c = 0; c < 4; ++c) {
    const double tilt = 0.2 + 0.3 * c;
    const Vec3 dir(std::sin(tilt), 0, -std::cos(tilt));
    Vec3 p(0, 0.5 * c, 0);
    for (int k = 0; k < 10; ++k) {
      BodyDef b;
      b.name = "c" + std::to_string(c) + "_" + std::to_string(k);
      b.p_WB = p + 0.05 * dir;
      Collider col = sphere_collider(0.01, 1000);
      col.collide = false;
      b.colliders.push_back(col);
      b.mass_override = MassProperties{0.01, Vec3::Zero(), 1e-5 * Mat3::Identity()};
      JointDef j;
      j.type = JointType::revolute;
      j.parent = k == 0 ? -1 : (int)bodies.size() - 1;
      j.child = (int)bodies.size();
      j.anchor_W = p;
      j.axis_W = Vec3::UnitY();
      cfg.joints.push_back(j);
      bodies.push_back(std::move(b));
      p += 0.1 * dir;
    }
  }
  return bodies;
}
TEST(Verlet, ResumesBitForBitAndThreadsAgree) {
  WorldConfig c1 = chains_config(1), c2 = chains_config(2);
  std::vector<BodyDef> b1 = chains_bodies(c1), b2 = chains_bodies(c2);
  World a(c1, b1), b(c2, b2);
  EXPECT_TRUE(a.warnings().empty());
  std::vector<std::string> at(21);
  for (int k = 1; k <= 40; ++k) {
    a.step();
    b.step();
    if (k <= 20) at[k] = saved(a);
  }
  EXPECT_EQ(saved(a), saved(b));
  EXPECT_GE(a.profile().joint_steps, 4 * 40);
  for (int from = 1; from <= 20; ++from) {
    World w(c1, b1);
    std::istringstream is(at[from]);
    w.restore_state(is);
    for (int k = from + 1; k <= 40; ++k) w.step();
    ASSERT_EQ(saved(w), saved(a)) << "resumed from frame " << from;
  }
}

// Verlet's evaluation in world axes (derivative_world) and its read-out (write_bodies_world)
// against the link-frame algorithm (mechanisms with modes or rows keep it), on a mechanism with
// every feature they share:
// hinges and sliders on skew axes, bodies turned off their principal axes, a sprung and damped
// hinge with a rotor's armature, and a wrench on one body, 2 m from the world's origin. The two
// differ only in rounding: the accelerations agree to 1e-12 of their size, the bodies' written
// poses and velocities to 1e-13 (measured 4e-15 of 14.6 rad/s^2, and 1.4e-15).
TEST(Verlet, WorldAxesEvaluationMatchesTheLinkFrameOne) {
  Bodies b;
  std::vector<JointDef> joints;
  Vec3 p(1.3, -1.2, 1.0);
  for (int i = 0; i < 6; ++i) {
    const Quat q(Eigen::AngleAxisd(0.3 * i + 0.2, Vec3(1, 2, 3).normalized()));
    const Vec3 x = p + Vec3(0.1, 0.05 * i, -0.1);
    b.add("l" + std::to_string(i), 0.5 + 0.1 * i, Vec3(0.01, 0.02, 0.015 + 0.001 * i), x, q);
    JointDef j;
    j.type = i % 3 == 2 ? JointType::prismatic : JointType::revolute;
    j.parent = i - 1;
    j.child = i;
    j.anchor_W = p;
    j.axis_W = Vec3(std::sin(i), std::cos(i), 0.3 * i).normalized();
    if (i == 1) {
      j.spring = JointSpring{2.0, 0.3, 0.1};
      j.armature = 0.004;
    }
    joints.push_back(j);
    p = x + Vec3(0.05, 0, -0.05);
  }
  Articulations art;
  std::vector<std::string> warnings;
  art.build(joints, verlet(), b.defs, b.model, b.state, warnings);
  Mechanism& m = art.mechanisms()[0];
  ASSERT_TRUE(m.world_aba_ok());
  const int n = m.nq + m.nv;
  std::vector<double> y(n), d_link(n), d_world(n);
  for (int k = 0; k < m.nq; ++k) y[k] = 0.4 * std::sin(1.7 * k + 0.3), y[m.nq + k] = 1.5 * std::cos(2.3 * k);
  std::vector<Wrench> wr(b.state.size());
  wr[3].f_W = Vec3(0.7, -0.2, 1.1);
  wr[3].tau_W = Vec3(0.05, 0.02, -0.03);
  const Vec3 g(0, 0, -9.81);
  m.derivative(y.data(), d_link.data(), g, wr.data(), nullptr);
  m.derivative_world(y.data(), d_world.data(), g, wr.data());
  double size = 0, diff = 0;
  for (int k = 0; k < n; ++k) {
    size = std::max(size, std::abs(d_link[k]));
    diff = std::max(diff, std::abs(d_world[k] - d_link[k]));
  }
  std::printf("accelerations: largest %.3g, largest difference %.2e\n", size, diff);
  EXPECT_LT(diff, 1e-12 * size);

  // The read-outs at the mechanism's own coordinates and rates.
  std::copy(y.begin(), y.begin() + m.nq, m.q.begin());
  std::copy(y.begin() + m.nq, y.end(), m.v.begin());
  std::vector<MotionState> world_read = b.state, link_read = b.state;
  m.derivative_world(y.data(), d_world.data(), g, nullptr);
  m.write_bodies(world_read.data());  // derivative_world's kinematics are at q: the world read-out
  m.derivative(y.data(), d_link.data(), g, nullptr, nullptr);
  m.write_bodies(link_read.data());  // they are not any more: the link-frame one
  double worst = 0;
  for (size_t i = 0; i < b.state.size(); ++i) {
    const MotionState &a = world_read[i], &c = link_read[i];
    worst = std::max({worst, (a.x_W - c.x_W).norm(), (a.v_W - c.v_W).norm(), (a.w_P - c.w_P).norm(),
                      a.q_WP.angularDistance(c.q_WP)});
  }
  std::printf("bodies written: largest difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-13);
}

}  // namespace
}  // namespace simreel
