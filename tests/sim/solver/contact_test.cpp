// Contact physics against closed forms, as a physicist would accept them. Every test
// builds its World from BodyDefs (tests/sim/solver/contact_fixtures.hpp), samples the trajectory every
// step, and states its closed form, its tolerance and the reason for that tolerance.
//
// Sources of error common to all contact tests, used in the tolerance reasoning below:
//   - the soft contact (contact_hertz 30, damping ratio 10, linear_slop 0.5 mm) lets a resting body
//     sink by about the slop, so a sphere's lever arm to its contact point is r - O(0.5 mm);
//   - the solver steps bodies in contact with substepped semi-implicit Euler (4 substeps of
//     dt / 4 = 1/960 s): positions lag velocities by O(v h / 2) per motion;
//   - ballistic flight between contacts is integrated exactly (constant gravity) up to rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>

#include "sim/world/world_impl.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"

namespace simreel {
namespace {

using namespace contact_test;

constexpr double g = 9.81;

// ------------------------------------------------------------------ 1. rolling / slipping on an incline

// Accelerations along the slope of a solid sphere released at rest on a static plane tilted by
// theta about x. Returns the slope of a least-squares line through the along-slope velocity,
// sampled every step for t in [0.25 s, 1.5 s] (after the start transient: the first steps settle
// the soft contact and warm start the friction impulse).
double incline_acceleration(double theta, double mu, double* max_slip = nullptr) {
  const Quat q(Eigen::AngleAxisd(theta, Vec3::UnitX()));
  const Vec3 n = q * Vec3::UnitZ();
  const Vec3 down = q * Vec3(0, -1, 0);  // the steepest descent direction in the plane
  const double r = 0.1;
  World w(WorldConfig{}, {ground(mu, 0, q), sphere(r, r * n, mu, 0)});
  std::vector<double> ts, vs;
  double slip = 0;
  for (int k = 1; w.time() < 1.5; ++k) {
    w.step();
    const double t = w.time();
    if (t < 0.25) continue;
    ts.push_back(t);
    vs.push_back(down.dot(w.linear_velocity(1)));
    // Velocity of the sphere's material point at the contact (rolling: 0): its lowest surface
    // point, r below the centre along n. (The sphere rests ~0.5 mm deep; rolling without
    // slipping is about its own radius, not about the midpoint of the overlap: at 36 rad/s the
    // 0.28 mm between the two would read as 1 cm/s of slip.)
    if (!w.impl().contacts().empty() && w.impl().contacts()[0].count > 0) {
      const Vec3 vc = w.linear_velocity(1) + w.angular_velocity(1).cross(-r * n);
      slip = std::max(slip, (vc - n.dot(vc) * n).norm());  // tangential: the normal part is not slip
    }
  }
  if (max_slip) *max_slip = slip;
  return fit_line(ts, vs).b;
}

// Closed form, rolling without slipping (mu >= 2/7 tan theta): a = 5/7 g sin theta (I = 2/5 m r^2).
// Tolerance 0.5% (the issue's). Reason: the soft contact sinks the sphere by ~the slop (0.5 mm),
// so the contact point is at r - O(0.25 mm) from the centre: with r = 0.1 m the effective
// 1 + I/(m r'^2) changes by < 0.2%; the linear fit of an exactly linear velocity adds nothing.
TEST(ContactIncline, SolidSphereRollsWithoutSlippingAtFiveSeventhsGSinTheta) {
  const double theta = deg(20), mu = 0.5;
  ASSERT_GE(mu, 2.0 / 7.0 * std::tan(theta));
  const double a = incline_acceleration(theta, mu);
  const double expect = 5.0 / 7.0 * g * std::sin(theta);
  std::printf("[measure] rolling incline: a = %.6f, 5/7 g sin = %.6f, rel %.2e\n", a, expect, a / expect - 1);
  EXPECT_NEAR(a / expect, 1.0, 5e-3);
}

// Rolling means the material point at the contact is at rest in the tangent plane. Tolerance
// 1 mm/s: after the relax pass the one-point friction constraint of a sphere (isotropic tangent
// effective mass) is solved exactly, and gravity's g sin(theta) h = 3.5 mm/s per substep is
// removed by the next solve, never left at the end of a step.
TEST(ContactIncline, RollingSphereContactPointIsAtRest) {
  double slip = 0;
  incline_acceleration(deg(20), 0.5, &slip);
  std::printf("[measure] rolling incline: largest tangential slip at the contact %.3e m/s\n", slip);
  EXPECT_LT(slip, 1e-3);
}

// Closed form, slipping (mu < 2/7 tan theta): a = g (sin theta - mu cos theta). Tolerance 0.5%:
// the friction force is mu N exactly once the tangent impulse hits the disk limit, so only the
// normal impulse's soft-contact error remains (N = m g cos theta once settled, < 0.1%).
TEST(ContactIncline, SolidSphereSlipsAtGSinMinusMuCos) {
  const double theta = deg(20), mu = 0.05;
  ASSERT_LT(mu, 2.0 / 7.0 * std::tan(theta));
  const double a = incline_acceleration(theta, mu);
  const double expect = g * (std::sin(theta) - mu * std::cos(theta));
  std::printf("[measure] slipping incline: a = %.6f, g(sin - mu cos) = %.6f, rel %.2e\n", a, expect,
              a / expect - 1);
  EXPECT_NEAR(a / expect, 1.0, 5e-3);
}

// Closed form: a solid sphere rolling without slipping on a level floor with no rolling
// resistance (the default, 0) keeps its speed forever (no force does work), and rests at the
// depth the soft contact gives any resting body (about the slop, 0.5 mm), whatever its speed.
// Tolerances: speed within 1e-3 after 2 s (the velocity solve is exact for one point of a sphere;
// 1e-3 is far above rounding and far below the rolling resistance of any real ball), penetration
// below 1 mm (twice the slop).
TEST(ContactFriction, SphereRollingOnALevelFloorKeepsItsSpeedAndDoesNotSink) {
  for (double v0 : {1.0, 5.0, 10.0}) {
    const double r = 0.05;
    BodyDef b = sphere(r, Vec3(0, 0, r), 0.6, 0);
    b.v_W = Vec3(v0, 0, 0);
    b.w_W = Vec3(0, v0 / r, 0);
    World w(WorldConfig{}, {ground(0.6, 0), b});
    double lowest = 0;
    for (int k = 0; k < 480; ++k) {
      w.step();
      lowest = std::min(lowest, w.centroid(1).z() - r);
    }
    const double v = w.linear_velocity(1).x();
    std::printf(
        "[measure] rolling on a floor at %.0f m/s (%.0f rad/s): speed after 2 s %.5f (rel %.2e), deepest "
        "%.3e m\n",
        v0, v0 / r, v, v / v0 - 1, -lowest);
    EXPECT_NEAR(v / v0, 1.0, 1e-3) << "v0 " << v0;
    EXPECT_LT(-lowest, 1e-3) << "v0 " << v0;
  }
}

// ------------------------------------------------------------------ 2. a box sliding to rest

// Closed form: a box sliding at v0 on a level floor decelerates at mu g and stops after
// v0^2 / (2 mu g). Tolerance 1% (the issue's). Reason: the position lags by v h / 2 per substep of
// semi-implicit Euler, about v0 (dt/4)/2 = 1.6 mm of 917 mm (0.2%); the per-point friction disk
// sums to mu N exactly while all four corners slide.
TEST(ContactFriction, BoxSlidingOnAFloorStopsAfterV0SquaredOverTwoMuG) {
  const double mu = 0.5, v0 = 3.0, s = 0.2;
  BodyDef b = box(Vec3::Constant(s), Vec3(0, 0, s / 2), mu, 0);
  b.v_W = Vec3(v0, 0, 0);
  World w(WorldConfig{}, {ground(mu, 0), b});
  const double x0 = w.centroid(1).x();
  double stop_t = -1;
  for (int k = 0; k < 480; ++k) {
    w.step();
    if (stop_t < 0 && w.linear_velocity(1).norm() < 1e-6) stop_t = w.time();
  }
  const double dist = w.centroid(1).x() - x0;
  const double expect = v0 * v0 / (2 * mu * g);
  std::printf(
      "[measure] sliding box: distance %.6f m, v0^2/(2 mu g) = %.6f m, rel %.2e; stopped at %.4f s "
      "(v0/(mu g) = %.4f s)\n",
      dist, expect, dist / expect - 1, stop_t, v0 / (mu * g));
  EXPECT_NEAR(dist / expect, 1.0, 0.01);
  EXPECT_LT(w.linear_velocity(1).norm(), 1e-3);  // and it stays stopped
  EXPECT_GT(stop_t, 0);
}

// ------------------------------------------------------------------ 3. skid then roll

// Closed form: a solid sphere thrown at v0 without spin slides, friction mu m g decelerates it
// (a = -mu g) and spins it up (alpha = 5 mu g / (2 r)); the contact slip v - r w falls at
// 7/2 mu g and vanishes at t = 2 v0 / (7 mu g), after which it rolls at v = 5/7 v0.
// Measured: the slip line fitted over the sliding phase, extrapolated to zero (the sampling step
// would otherwise quantise t to dt = 0.5% of it), and the mean speed over 0.5 s of rolling.
// Tolerance 1% (the issue's). Reason: soft-contact sinking changes the lever r by < 0.3%.
TEST(ContactFriction, BallThrownWithoutSpinRollsAtFiveSeventhsV0) {
  const double mu = 0.1, v0 = 3.0, r = 0.1;
  BodyDef b = sphere(r, Vec3(0, 0, r), mu, 0);
  b.v_W = Vec3(v0, 0, 0);
  World w(WorldConfig{}, {ground(mu, 0), b});
  const double t_roll = 2 * v0 / (7 * mu * g);
  std::vector<double> ts, slips, vroll;
  while (w.time() < t_roll + 0.7) {
    w.step();
    const double slip = w.linear_velocity(1).x() - r * w.angular_velocity(1).y();
    if (slip > 0.2 * v0 && w.time() > 0.05) ts.push_back(w.time()), slips.push_back(slip);
    if (w.time() > t_roll + 0.2) vroll.push_back(w.linear_velocity(1).x());
  }
  const Line L = fit_line(ts, slips);
  const double t_meas = -L.a / L.b;
  double v = 0;
  for (double x : vroll) v += x;
  v /= (double)vroll.size();
  std::printf(
      "[measure] skid->roll: t_roll %.6f s vs 2v0/(7 mu g) %.6f s (rel %.2e); v %.6f vs 5/7 v0 %.6f (rel "
      "%.2e)\n",
      t_meas, t_roll, t_meas / t_roll - 1, v, 5.0 / 7 * v0, v / (5.0 / 7 * v0) - 1);
  EXPECT_NEAR(t_meas / t_roll, 1.0, 0.01);
  EXPECT_NEAR(v / (5.0 / 7 * v0), 1.0, 0.01);
}

// ------------------------------------------------------------------ 4. bounces

// Drops `b` (a sphere or a flat box, its lowest point at height h0 over the floor) and returns the
// apex heights of its lowest point after each of the first `n` bounces, each the vertex of the
// parabola through the three samples around the sampled maximum (exact for ballistic flight).
// restitution_threshold is lowered to 5 cm/s so that the fifth bounce at e = 0.5 (impact
// ~0.3 m/s) still bounces: the default 1 m/s threshold deliberately kills slow bounces.
std::vector<double> apexes(BodyDef b, double e, double half_height, int n, double duration) {
  WorldConfig cfg;
  cfg.contacts.restitution_threshold = 0.05;
  World w(cfg, {ground(0.6, e), b});
  std::vector<double> y{w.centroid(1).z() - half_height};
  std::vector<double> out;
  while (w.time() < duration && (int)out.size() < n) {
    w.step();
    y.push_back(w.centroid(1).z() - half_height);
    const size_t k = y.size() - 2;
    if (k >= 1 && y[k] > y[k - 1] && y[k] >= y[k + 1] && y[k] > 1e-4)
      out.push_back(parabola_peak(y[k - 1], y[k], y[k + 1]));
  }
  return out;
}

// Closed form: each bounce keeps e of the impact speed, so apex n is e^(2n) h0. Tolerance 2% of
// each apex (the issue's). Reason: restitution acts in the substep of impact; the velocity it
// reverses is the one before the impulse, which includes up to h = 1/960 s of gravity, and the
// stop at the surface happens mid-substep: both are O(g h / v) per bounce, < 0.5% here.
void check_decay(double e, double h0) {
  const double r = 0.1;
  const std::vector<double> a = apexes(sphere(r, Vec3(0, 0, r + h0), 0.6, e), e, r, 5, 20);
  ASSERT_EQ(a.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const double expect = std::pow(e, 2 * (k + 1)) * h0;
    std::printf("[measure] e=%.2f bounce %d: apex %.6g m vs e^2n h0 %.6g m (rel %.2e)\n", e, k + 1, a[k],
                expect, a[k] / expect - 1);
    EXPECT_NEAR(a[k] / expect, 1.0, 0.02) << "bounce " << k + 1;
  }
}
TEST(ContactRestitution, SphereApexHeightsDecayAsESquaredToTheN) {
  check_decay(0.8, 1.0);
  check_decay(0.5, 2.0);  // h0 = 2 m keeps the fifth apex (2 mm) many steps long
}

// Closed form: with e = 1 every apex equals h0. Tolerance 1% over ten bounces (the issue's) and no
// gain: max apex <= h0 (1 + 1e-3). Reason for 1e-3: restitution reverses the pre-impulse speed,
// which is at most g h = 1 cm/s above the true impact speed at 4.4 m/s; that could add at most
// 2 g h / v = 0.5% per bounce if it were not offset by the travel lost mid-substep
// (sim/solver/contact_solver.cpp); any systematic gain accumulates over ten bounces, so 1e-3 bounds it at
// 1e-4 per bounce.
void check_elastic(const BodyDef& b, double half_height, double h0, const char* what) {
  const std::vector<double> a = apexes(b, 1.0, half_height, 10, 20);
  ASSERT_EQ(a.size(), 10u) << what;
  double hi = 0, lo = 1e9;
  for (double x : a) hi = std::max(hi, x), lo = std::min(lo, x);
  for (int k = 0; k < 10; ++k) std::printf("[measure] e=1 %s bounce %d apex %.7f\n", what, k + 1, a[k]);
  std::printf("[measure] e=1 %s: ten apexes in [%.7f, %.7f] m, h0 %.3f m (min rel %.2e, max rel %.2e)\n",
              what, lo, hi, h0, lo / h0 - 1, hi / h0 - 1);
  for (int k = 0; k < 10; ++k) EXPECT_NEAR(a[k] / h0, 1.0, 0.01) << what << " bounce " << k + 1;
  EXPECT_LE(hi, h0 * (1 + 1e-3)) << what << ": a bounce gained energy";
}
TEST(ContactRestitution, RestitutionOneHoldsTheHeightForTenBouncesSphereAndFlatBox) {
  const double h0 = 1.0, r = 0.1, s = 0.2;
  check_elastic(sphere(r, Vec3(0, 0, r + h0), 0.6, 1.0), r, h0, "sphere");
  check_elastic(box(Vec3::Constant(s), Vec3(0, 0, s / 2 + h0), 0.6, 1.0), s / 2, h0, "flat box");
}

// Closed form: with e = 0 the body stays on the floor after the first contact. Tolerance: no
// apex above 1 mm, i.e. twice the slop the soft contact may push out (a push-out is not a bounce).
void check_dead(const BodyDef& b, double half_height, const char* what) {
  World w(WorldConfig{}, {ground(0.6, 0), b});
  bool touched = false;
  double hi = 0;
  while (w.time() < 3) {
    w.step();
    for (const Contact& c : w.impl().contacts())
      for (int j = 0; j < c.count; ++j) touched = touched || c.points[j].normal_impulse > 0;
    if (touched) hi = std::max(hi, w.centroid(1).z() - half_height);
  }
  std::printf("[measure] e=0 %s: highest lowest-point after first contact %.3e m\n", what, hi);
  EXPECT_TRUE(touched) << what;
  EXPECT_LT(hi, 1e-3) << what;
}
TEST(ContactRestitution, RestitutionZeroStaysDown) {
  check_dead(sphere(0.1, Vec3(0, 0, 1.1), 0.6, 0), 0.1, "sphere");
  check_dead(box(Vec3::Constant(0.2), Vec3(0, 0, 1.1), 0.6, 0), 0.1, "flat box");
}

// ------------------------------------------------------------------ 8. energy

// A contact never adds energy. Measured: the largest rise of total mechanical energy (KE + PE)
// between consecutive steps over 3 s, for drops onto the plane. Free flight conserves energy to
// rounding (the exact constant-gravity integrator; the rigid rotation is torque-free), so any
// rise is the contact's. Tolerance: m g x (the deepest overlap seen) + 1e-9 m g h0. Reason: the
// soft contact pushes out overlap without taking kinetic energy, lifting a body by at most that
// depth: a genuine but bounded gain (it restores potential energy the overlap lost), below
// 3e-4 of m g h0 here. A bounce that kept more than e of the impact speed
// would rise by far more (1% of m g h0 per % of speed).
void check_energy(BodyDef b, double e, const char* what) {
  b.colliders[0].restitution = e;
  World w(WorldConfig{}, {ground(0.6, e), b});
  const double scale = w.impl().model(1).mass * g * (w.centroid(1).z() + 1.0);
  double E = energy(w), rise = 0;
  int at = -1;
  for (int k = 0; k < 720; ++k) {
    w.step();
    const double E1 = energy(w);
    if (E1 - E > rise) rise = E1 - E, at = k;
    E = E1;
  }
  std::printf(
      "[measure] energy %s e=%.0f: largest rise %.3e J (%.2e of m g h0) at step %d; max penetration %.2e m\n",
      what, e, rise, rise / scale, at, w.contact_stats().max_penetration);
  // The bound from the comment above: pushing out the deepest overlap seen lifts the body by at
  // most that depth, m g x overlap (plus rounding).
  EXPECT_LE(rise, w.impl().model(1).mass * g * w.contact_stats().max_penetration + 1e-9 * scale)
      << what << " e=" << e;
}
TEST(ContactEnergy, ContactsNeverAddEnergy) {
  for (double e : {0.0, 1.0}) {
    check_energy(sphere(0.1, Vec3(0, 0, 1.1)), e, "sphere");
    check_energy(box(Vec3::Constant(0.2), Vec3(0, 0, 1.1)), e, "flat box");
    BodyDef t = box(Vec3(0.4, 0.2, 0.1), Vec3(0, 0, 1.2), 0.6, 0, 1000,
                    Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 0.5).normalized())));
    t.w_W = Vec3(3, -5, 2);
    t.v_W = Vec3(1, 0, 0);
    check_energy(t, e, "tumbling box");
  }
}

// ------------------------------------------------------------------ 9. determinism

std::vector<BodyDef> busy_scene() {
  std::vector<BodyDef> v{ground(0.5, 0.3)};
  for (int i = 0; i < 4; ++i) {
    BodyDef s = sphere(0.1 + 0.02 * i, Vec3(0.15 * i, 0.05 * i, 0.3 + 0.25 * i), 0.4 + 0.1 * i, 0.2 * i);
    s.v_W = Vec3(0.3 * i - 0.4, 0.1, 0);
    s.w_W = Vec3(1, 2, 3 - i);
    v.push_back(s);
  }
  for (int i = 0; i < 4; ++i) {
    BodyDef b = box(Vec3(0.3, 0.2, 0.1 + 0.05 * i), Vec3(1 + 0.5 * i, -0.3, 0.2 + 0.3 * i), 0.6, 0.1 * i, 800,
                    Quat(Eigen::AngleAxisd(0.3 * i, Vec3(1, 1, 1).normalized())));
    b.w_W = Vec3(0, 4 - i, 1);
    v.push_back(b);
  }
  for (int i = 0; i < 6; ++i) {  // free flyers, so the threads have free-flight work to split
    BodyDef b = box(Vec3(0.3, 0.2, 0.1), Vec3(5 + i, 0, 30), 0.6, 0, 500);
    b.w_W = Vec3(1 + i, 0.01, 0.2);
    v.push_back(b);
  }
  return v;
}
uint64_t run_busy(int threads, int steps, int* max_points = nullptr) {
  WorldConfig cfg;
  cfg.threads = threads;
  World w(cfg, busy_scene());
  for (int k = 0; k < steps; ++k) w.step();
  if (max_points) *max_points = w.contact_stats().contacts_max;
  return state_hash(w);
}
// Bit-identical, no tolerance: the same binary and inputs must give the same bits however many
// threads run the free-flight stage, and however often the scene is run.
TEST(ContactDeterminism, SameSceneSameBitsAcrossRunsAndThreads) {
  int points = 0;
  const uint64_t a = run_busy(1, 720, &points);
  ASSERT_GT(points, 4) << "the scene must actually have contacts";
  EXPECT_EQ(a, run_busy(1, 720));
  EXPECT_EQ(a, run_busy(2, 720));
}

// ------------------------------------------------------------------ 10. kinematic and static bodies

// A kinematic body moves with its given velocity, whatever gravity and contacts do: exactly (the
// velocity is never touched; the angular velocity is kept in the world frame, re-expressed each
// step, so it may differ by rounding); its position advances by v dt per step (rounding only).
TEST(ContactKinematic, KinematicBodyKeepsItsVelocityAndPushes) {
  const double r = 0.1;
  BodyDef pusher = sphere(r, Vec3(-0.5, 0, r), 0.6, 0, 1000, BodyType::kinematic);
  pusher.v_W = Vec3(1, 0, 0);
  BodyDef spinner =
      box(Vec3(0.4, 0.4, 0.4), Vec3(3, 0, 0.15), 0.6, 0, 1000, Quat::Identity(), BodyType::kinematic);
  spinner.v_W = Vec3(0, 0.5, 0);
  spinner.w_W = Vec3(0, 0, 2);  // sweeping through the floor: kinematic-static pairs never collide
  World w(WorldConfig{}, {ground(0.6, 0), pusher, sphere(r, Vec3(0, 0, r), 0.6, 0), spinner});
  const Vec3 x1 = w.centroid(1), x3 = w.centroid(3);
  double min_gap = 1e9;
  for (int k = 0; k < 480; ++k) {
    w.step();
    EXPECT_EQ(w.linear_velocity(1), Vec3(1, 0, 0));
    EXPECT_EQ(w.linear_velocity(3), Vec3(0, 0.5, 0));
    EXPECT_LT((w.angular_velocity(3) - Vec3(0, 0, 2)).norm(), 1e-14);
    if (w.centroid(2).x() > w.centroid(1).x())
      min_gap = std::min(min_gap, (w.centroid(2) - w.centroid(1)).norm() - 2 * r);
  }
  const double t = w.time();
  EXPECT_LT((w.centroid(1) - (x1 + t * Vec3(1, 0, 0))).norm(), 1e-12);
  EXPECT_LT((w.centroid(3) - (x3 + t * Vec3(0, 0.5, 0))).norm(), 1e-12);
  // The box turned by w t about z (rounding only: each step's rotation is exact).
  const Quat expect(Eigen::AngleAxisd(2 * t, Vec3::UnitZ()));
  EXPECT_LT(w.orientation(3).angularDistance(expect), 1e-12);
  // The pusher drove the dynamic sphere ahead of it, never overlapping it by more than 1 mm
  // (twice the slop: the soft contact lets it in by about that while pushing).
  std::printf("[measure] kinematic pusher: dynamic sphere at x = %.4f (pusher %.4f), min gap %.2e m\n",
              w.centroid(2).x(), w.centroid(1).x(), min_gap);
  EXPECT_GT(w.centroid(2).x(), w.centroid(1).x() + 2 * r - 1e-3);
  EXPECT_GT(min_gap, -1e-3);
}

TEST(ContactKinematic, KinematicBoxPushesASphere) {
  SKIP_WITHOUT(has_box_sphere(), "box-sphere");
  const double r = 0.1;
  BodyDef pusher =
      box(Vec3(0.2, 1, 0.2), Vec3(-0.5, 0, 0.1), 0.6, 0, 1000, Quat::Identity(), BodyType::kinematic);
  pusher.v_W = Vec3(1, 0, 0);
  World w(WorldConfig{}, {ground(0.6, 0), pusher, sphere(r, Vec3(0, 0, r), 0.6, 0)});
  for (int k = 0; k < 480; ++k) {
    w.step();
    ASSERT_EQ(w.linear_velocity(1), Vec3(1, 0, 0));
  }
  EXPECT_GT(w.centroid(2).x(), w.centroid(1).x() + 0.1 + r - 1e-3);
}

// A static body has zero velocity whatever is set, and never moves.
TEST(ContactKinematic, StaticBodyGivenAVelocityStaysPut) {
  BodyDef s = box(Vec3(1, 1, 1), Vec3(0, 0, 0.5), 0.6, 0, 1000, Quat::Identity(), BodyType::static_body);
  s.v_W = Vec3(3, 2, 1);
  s.w_W = Vec3(1, 2, 3);
  World w(WorldConfig{}, {ground(), s, sphere(0.1, Vec3(3, 0, 0.1))});
  const Vec3 x = w.centroid(1);
  for (int k = 0; k < 240; ++k) w.step();
  EXPECT_EQ(w.linear_velocity(1), Vec3::Zero());
  EXPECT_EQ(w.angular_velocity(1), Vec3::Zero());
  EXPECT_EQ(w.centroid(1), x);
}

// ------------------------------------------------------------------ 11. filtering

// Two spheres flying at each other in zero gravity. Unfiltered they collide (the control); with
// group/mask excluding each other, with ignore_pairs, or with collide = false on one, they pass
// through: positions x0 + v t and velocities unchanged (exact: constant velocity, rounding only).
struct Pass {
  double x1, v1;
};
Pass fly(const std::function<void(BodyDef&, BodyDef&, WorldConfig&)>& setup) {
  const double r = 0.1;
  BodyDef a = sphere(r, Vec3(-0.5, 0, 0)), b = sphere(r, Vec3(0.5, 0, 0));
  a.v_W = Vec3(1, 0, 0);
  b.v_W = Vec3(-1, 0, 0);
  WorldConfig cfg;
  cfg.gravity = Vec3::Zero();
  setup(a, b, cfg);
  World w(cfg, {a, b});
  for (int k = 0; k < 240; ++k) w.step();
  return {w.centroid(0).x(), w.linear_velocity(0).x()};
}
TEST(ContactFilter, ExcludedPairsPassThroughEachOther) {
  const Pass hit = fly([](BodyDef&, BodyDef&, WorldConfig&) {});
  EXPECT_LT(hit.v1, 0.5) << "control: unfiltered spheres must collide";
  auto check = [](const Pass& p, const char* what) {
    EXPECT_NEAR(p.x1, 0.5, 1e-12) << what;
    EXPECT_EQ(p.v1, 1.0) << what;
  };
  check(fly([](BodyDef& a, BodyDef& b, WorldConfig&) {
          a.colliders[0].group = 1, a.colliders[0].mask = 1;
          b.colliders[0].group = 2, b.colliders[0].mask = 2;
        }),
        "group/mask");
  check(fly([](BodyDef& a, BodyDef& b, WorldConfig&) {  // one-sided exclusion is enough
          a.colliders[0].mask = ~2u;
          b.colliders[0].group = 2;
        }),
        "one-sided mask");
  check(fly([](BodyDef&, BodyDef&, WorldConfig& c) { c.ignore_pairs = {{1, 0}}; }), "ignore_pairs");
  check(fly([](BodyDef& a, BodyDef&, WorldConfig&) { a.colliders[0].collide = false; }), "collide=false");
}

// collide = false: a mass-only collider never touches the ground either: it falls through on the
// exact free-fall parabola.
TEST(ContactFilter, MassOnlyColliderFallsThroughTheGround) {
  BodyDef s = sphere(0.1, Vec3(0, 0, 0.5));
  s.colliders[0].collide = false;
  World w(WorldConfig{}, {ground(), s});
  for (int k = 0; k < 240; ++k) w.step();
  const double t = w.time();
  EXPECT_NEAR(w.centroid(1).z(), 0.5 - 0.5 * g * t * t, 1e-12);
}

// ------------------------------------------------------------------ 12. free flight unchanged

// A body touching nothing in a world that has a ground and contacts elsewhere keeps the accurate
// free-flight integrator: its state is bit-identical to the same body alone in an empty world,
// and its centroid is x0 + v0 t + g t^2 / 2 to rounding (480 steps at |x| ~ 30 m: ~1e-12 m; the
// tolerance 1e-10 m is that with margin, far below any integration error).
TEST(ContactFreeFlight, BodyTouchingNothingKeepsTheExactFreeFlight) {
  BodyDef flyer = box(Vec3(0.4, 0.2, 0.1), Vec3(2, 1, 30), 0.6, 0, 700,
                      Quat(Eigen::AngleAxisd(0.4, Vec3(0.2, 1, 0.3).normalized())));
  flyer.v_W = Vec3(1, -2, 3);
  flyer.w_W = Vec3(0.5, 7, -1);  // tumbling (asymmetric box: full rotational dynamics)
  World busy(WorldConfig{},
             {ground(), sphere(0.1, Vec3(0, 0, 0.1)), box(Vec3::Constant(0.2), Vec3(1, 0, 0.15)), flyer});
  World alone(WorldConfig{}, {flyer});
  const Vec3 x0 = alone.centroid(0), v0 = alone.linear_velocity(0);
  for (int k = 0; k < 480; ++k) {
    busy.step();
    alone.step();
  }
  ASSERT_GT(busy.contact_stats().contacts_max, 0) << "the busy world must have contacts";
  const MotionState &a = busy.impl().state(3), &b = alone.impl().state(0);
  EXPECT_EQ(a.x_W, b.x_W);
  EXPECT_EQ(a.v_W, b.v_W);
  EXPECT_EQ(a.w_P, b.w_P);
  EXPECT_EQ(a.q_WP.coeffs(), b.q_WP.coeffs());
  const double t = busy.time();
  const Vec3 expect = x0 + v0 * t + 0.5 * t * t * Vec3(0, 0, -g);
  EXPECT_LT((a.x_W - expect).norm(), 1e-10);
}

// Bodies that overlap at the start are named in a warning with the depth (not silently pushed
// apart); touching within the slop is not an overlap.
TEST(ContactWarnings, StartingOverlapIsNamedWithItsDepth) {
  BodyDef a = sphere(0.5, Vec3(0, 0, 3)), b = sphere(0.5, Vec3(0.9, 0, 3));
  a.name = "left";
  b.name = "right";
  const World w(WorldConfig{}, {ground(), a, b});
  ASSERT_EQ(w.warnings().size(), 1u);
  const std::string& msg = w.warnings()[0];
  EXPECT_NE(msg.find("'left' and 'right' overlap by 0.1 m"), std::string::npos) << msg;
  const World ok(WorldConfig{}, {ground(), sphere(0.5, Vec3(0, 0, 0.5))});  // resting exactly
  EXPECT_TRUE(ok.warnings().empty()) << ok.warnings()[0];
}

// A ball of unequal moments (I = 4, 4, 7.5 g m^2 about its centre, the centre of mass) spinning
// about no principal axis on a frictionless floor: the floor pushes straight up through the centre,
// so the angular momentum about the centre of mass is constant, direction and size. Through the
// solver (frictionless, it cannot roll), the gyroscopic term must use the world inertia of the
// body as turned within the step: with the step's, |L| drifted 2.8% in 0.5 s at the default step
// (first order in dt). Tolerance 0.5%: the substeps' midpoint rule, 0.36% measured at 4 substeps.
TEST(ContactGyro, UnequalMomentsOnAFrictionlessFloorKeepTheirAngularMomentum) {
  BodyDef b = sphere(0.1, Vec3(0, 0, 0.1), 0.0);
  b.mass_override = MassProperties{2.0, Vec3::Zero(), Vec3(4e-3, 4e-3, 7.5e-3).asDiagonal()};
  b.w_W = Vec3(10, 0, 6);
  WorldConfig cfg;
  cfg.contacts.sleep = false;
  World w(cfg, {ground(0.0), b});
  const Vec3 L0 = w.angular_momentum(1);
  double worst = 0;
  while (w.time() < 0.5) {
    w.step();
    worst = std::max(worst, (w.angular_momentum(1) - L0).norm() / L0.norm());
  }
  std::printf("[measure] unequal moments on a frictionless floor, 0.5 s: |L - L0| / |L0| <= %.2e\n", worst);
  EXPECT_GT(w.profile().solver_bodies, 100);  // the solver's
  EXPECT_LT(worst, 5e-3);
}

}  // namespace
}  // namespace simreel
