// The public API (include/simreel/) as a program uses it: collider factories against the closed
// forms, the frames the accessors report, and the contact read-out against statics (a resting body's
// contact forces carry its weight; Newton's third law between the two sides' read-outs).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <simreel/simreel.hpp>

using namespace simreel;

namespace {

constexpr double kPi = std::numbers::pi;

BodyDef ground_body() {
  BodyDef g;
  g.name = "ground";
  g.type = BodyType::static_body;
  g.add_collider(plane_collider());
  return g;
}

}  // namespace

// Each factory's mass and inertia against its closed form (exact formulas: relative 1e-14 is
// rounding of a few operations).
TEST(PublicApi, ColliderFactoriesTakeADensity) {
  const double rho = 1000;
  const Collider b = box_collider(Vec3(1, 2, 3), rho);
  EXPECT_EQ(b.shape, ShapeKind::box);
  EXPECT_NEAR(b.props_C.mass, 6000, 1e-9);
  EXPECT_NEAR(b.props_C.inertia(0, 0), 6000 * (4 + 9) / 12.0, 1e-9);
  const Collider s = sphere_collider(0.5, rho);
  EXPECT_NEAR(s.props_C.mass, rho * 4 / 3.0 * kPi * 0.125, 1e-9);
  EXPECT_NEAR(s.props_C.inertia(2, 2), 0.4 * s.props_C.mass * 0.25, 1e-12);
  const Collider c = cylinder_collider(0.5, 2, rho);
  EXPECT_NEAR(c.props_C.mass, rho * kPi * 0.25 * 2, 1e-9);
  EXPECT_NEAR(c.props_C.inertia(2, 2), 0.5 * c.props_C.mass * 0.25, 1e-12);
  const Collider k = capsule_collider(0.5, 2, rho);  // a 1 m cylinder and a whole sphere
  EXPECT_NEAR(k.props_C.mass, rho * (kPi * 0.25 * 1 + 4 / 3.0 * kPi * 0.125), 1e-9);
  const Collider e = ellipsoid_collider(Vec3(1, 2, 3), rho);
  EXPECT_NEAR(e.props_C.mass, rho * 4 / 3.0 * kPi * 6, 1e-9);
  EXPECT_NEAR(e.props_C.inertia(0, 0), e.props_C.mass * (4 + 9) / 5.0, 1e-9);
  EXPECT_EQ(plane_collider().shape, ShapeKind::plane);
}

// A collider made by hand without mass properties is named, with the way to make one.
TEST(PublicApi, ColliderWithoutMassPropertiesIsNamed) {
  BodyDef d;
  d.name = "crate";
  Collider c;
  c.shape = ShapeKind::box;
  d.colliders.push_back(c);
  try {
    World w(WorldConfig{}, {d});
    FAIL() << "accepted a collider without mass properties";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("crate"), std::string::npos) << m;
    EXPECT_NE(m.find("collider 0 has no mass properties"), std::string::npos) << m;
    EXPECT_NE(m.find("box_collider(size, density)"), std::string::npos) << m;
  }
}

// Frames: q_WB = q_WP q_BP^-1, the body-frame angular velocity is R_BW w_W, the principal one
// R_PW w_W; the principal moments ascend and are the body's. A box offset and turned in its body.
TEST(PublicApi, PrincipalFrameAndBodyFrameAngularVelocity) {
  BodyDef d;
  Collider c = box_collider(Vec3(3, 2, 1), 100);
  c.q_BC = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  c.p_BC = Vec3(0.2, -0.1, 0.4);
  d.add_collider(c);
  d.q_WB = Quat(Eigen::AngleAxisd(1.1, Vec3(-1, 0.5, 2).normalized()));
  d.w_W = Vec3(0.3, -2, 5);
  WorldConfig cfg;
  cfg.gravity = Vec3::Zero();
  World w(cfg, {d});
  for (int k = 0; k < 10; ++k) w.step();
  const Quat q_WB = w.orientation(0);
  EXPECT_LT((w.principal_orientation(0) * w.principal_axes(0).conjugate()).angularDistance(q_WB), 1e-14);
  EXPECT_LT((w.angular_velocity_body(0) - q_WB.conjugate() * w.angular_velocity(0)).norm(), 1e-12);
  EXPECT_LT((w.angular_velocity_principal(0) - w.principal_orientation(0).conjugate() * w.angular_velocity(0))
                .norm(),
            1e-12);
  const Vec3 I = w.principal_moments(0);
  EXPECT_LE(I.x(), I.y());
  EXPECT_LE(I.y(), I.z());
  EXPECT_NEAR(I.x(), 600 * (4 + 1) / 12.0, 1e-9);  // the 3 m side's axis: m (b^2 + c^2) / 12
  EXPECT_NEAR(w.mass(0), 600, 1e-9);
  EXPECT_LT((w.local_centroid(0) - c.p_BC).norm(), 1e-15);
}

// A sphere at rest on the ground: the read-out's normal force is m g on the sphere, pointing up;
// the ground's own read-out is the same pair from its side (Newton's third law, exactly negated);
// the whole-world list holds it once. At rest the last substep's impulse cancels gravity's over the
// substep, so the force equals the weight to rounding (1e-9 relative allows a little settling).
TEST(PublicApi, ContactReadOutCarriesTheWeight) {
  BodyDef ball;
  ball.name = "ball";
  ball.add_collider(sphere_collider(0.1, 1000));
  ball.p_WB = Vec3(0, 0, 0.1);
  World w(WorldConfig{}, {ground_body(), ball});
  for (int k = 0; k < 240; ++k) w.step();
  const double weight = w.mass(1) * 9.81;

  std::vector<ContactData> all;
  ASSERT_EQ(w.contacts(all), 1);
  std::vector<ContactData> mine, ground;
  ASSERT_EQ(w.body_contacts(1, mine), 1);
  ASSERT_EQ(w.body_contacts(0, ground), 1);
  const ContactData& c = mine[0];
  EXPECT_EQ(c.body_b, 1);
  EXPECT_EQ(c.body_a, 0);
  EXPECT_EQ(c.collider_a, 0);
  EXPECT_EQ(c.collider_b, 0);
  ASSERT_EQ(c.count, 1);
  EXPECT_LT((c.normal_W - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(c.points[0].normal_force, weight, 1e-9 * weight);
  EXPECT_NEAR(c.force_W().z(), weight, 1e-9 * weight);
  EXPECT_LT(c.points[0].p_W.z(), 1e-3);
  EXPECT_NEAR(c.friction, 0.6, 1e-15);
  const ContactData& g = ground[0];
  EXPECT_EQ(g.body_b, 0);
  EXPECT_EQ(g.body_a, 1);
  EXPECT_EQ(g.normal_W, Vec3(-c.normal_W));
  EXPECT_EQ(g.force_W(), Vec3(-c.force_W()));
  EXPECT_EQ(g.points[0].normal_force, c.points[0].normal_force);
  EXPECT_EQ(all[0].force_W(), c.force_W());  // pair order: the ground's shape comes first
}

// A world whose bodies never touch reads out nothing, and appending keeps what was there.
TEST(PublicApi, NoContactsReadOutNothing) {
  BodyDef a;
  a.add_collider(sphere_collider(0.1, 1000));
  World w(WorldConfig{}, {a});
  w.step();
  std::vector<ContactData> out(2);
  EXPECT_EQ(w.contacts(out), 0);
  EXPECT_EQ(w.body_contacts(0, out), 0);
  EXPECT_EQ(out.size(), 2u);
}

// World moves: the moved-to world steps on from where the moved-from one was.
TEST(PublicApi, WorldMoves) {
  BodyDef a;
  a.add_collider(sphere_collider(0.1, 1000));
  World w(WorldConfig{}, {a});
  w.step();
  World moved = std::move(w);
  moved.step();
  EXPECT_EQ(moved.steps(), 2);
  EXPECT_NEAR(moved.linear_velocity(0).z(), -9.81 * 2 / 240.0, 1e-12);
}

// The article's interface, each call against what it must do: a pose set is read back (the
// centroid kept by set_orientation), velocities set wake a sleeper, a body-frame force equals the
// world-frame force rotated, a central force leaves the spin alone, an angular impulse changes
// the spin by I^-1 dL (1e-12: a few roundings of O(1) values).
TEST(PublicApi, ArticleInterfaceCalls) {
  BodyDef d;
  d.add_collider(box_collider(Vec3(0.3, 0.2, 0.1), 1000));
  d.p_WB = Vec3(1, 2, 3);
  WorldConfig cfg;
  cfg.gravity = Vec3::Zero();
  World w(cfg, {d});
  EXPECT_EQ(w.type(0), BodyType::dynamic);
  EXPECT_FALSE(w.has_forces());
  EXPECT_FALSE(w.has_contacts());  // one body: nothing to touch

  const Vec3 c = w.centroid(0);
  const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()));
  w.set_orientation(0, Quat(2 * q.coeffs()));  // not unit: normalised
  EXPECT_LT(w.orientation(0).angularDistance(q), 1e-15);
  EXPECT_EQ(w.centroid(0), c);
  w.normalize_orientation(0);
  EXPECT_LT(w.orientation(0).angularDistance(q), 1e-15);

  w.set_angular_velocity(0, Vec3(0.1, -0.2, 0.3));
  EXPECT_LT((w.angular_velocity(0) - Vec3(0.1, -0.2, 0.3)).norm(), 1e-15);

  // An angular impulse: dw = I_W^-1 dL.
  const Vec3 w0 = w.angular_velocity(0), dL(0.01, 0.02, -0.03);
  w.apply_angular_impulse(0, dL);
  EXPECT_LT((w.angular_velocity(0) - (w0 + w.inverse_inertia_world(0) * dL)).norm(), 1e-12);

  // A force in the body frame at a body point is the world force at the world point.
  World a(cfg, {d}), b(cfg, {d});
  for (World* x : {&a, &b}) x->set_orientation(0, q);
  const Vec3 f_B(1, -2, 0.5), p_B(0.1, 0.05, -0.02);
  a.apply_force_local(0, f_B, p_B);
  b.apply_force(0, b.local_to_world_vec(0, f_B), b.local_to_world(0, p_B));
  a.step();
  b.step();
  EXPECT_LT((a.linear_velocity(0) - b.linear_velocity(0)).norm(), 1e-15);
  EXPECT_LT((a.angular_velocity(0) - b.angular_velocity(0)).norm(), 1e-13);
  EXPECT_GT(a.angular_velocity(0).norm(), 1e-6);  // the off-centre point gave it a torque

  // A central force: velocity f dt / m, no spin.
  World e(cfg, {d});
  e.apply_central_force(0, Vec3(0, 0, 6));
  e.step();
  EXPECT_NEAR(e.linear_velocity(0).z(), 6 / e.mass(0) / 240.0, 1e-15);
  EXPECT_EQ(e.angular_velocity(0), Vec3::Zero());
  EXPECT_NO_THROW(e.check_state());
}

// check_spin names a body that turns more than the given angle a step, once.
TEST(PublicApi, CheckSpinWarnsOnce) {
  BodyDef d;
  d.name = "spinner";
  d.add_collider(sphere_collider(0.1, 1000));
  d.w_W = Vec3(0, 0, 240);  // 1 rad a 1/240 s step
  World w(WorldConfig{}, {d});
  const size_t before = w.warnings().size();
  w.check_spin(0.5);
  w.check_spin(0.5);
  ASSERT_EQ(w.warnings().size(), before + 0) << "the constructor already named it";
  bool named = false;
  for (const std::string& s : w.warnings()) named = named || s.find("spinner") != std::string::npos;
  EXPECT_TRUE(named);
}

// A resting box falls asleep; wake() makes it step again. The fingerprint is the model's: the
// same scene gives the same one, another scene another.
TEST(PublicApi, WakeAndFingerprint) {
  BodyDef box;
  box.add_collider(box_collider(Vec3(0.2, 0.2, 0.2), 500));
  box.p_WB = Vec3(0, 0, 0.1);
  World w(WorldConfig{}, {ground_body(), box});
  for (int k = 0; k < 480 && !w.asleep(1); ++k) w.step();
  ASSERT_TRUE(w.asleep(1));
  EXPECT_EQ(w.sleeping_count(), 1);
  w.wake(1);
  EXPECT_FALSE(w.asleep(1));
  EXPECT_EQ(w.sleeping_count(), 0);

  World same(WorldConfig{}, {ground_body(), box});
  EXPECT_EQ(same.fingerprint(), w.fingerprint());
  BodyDef ball;
  ball.add_collider(sphere_collider(0.1, 500));
  World other(WorldConfig{}, {ground_body(), ball});
  EXPECT_NE(other.fingerprint(), w.fingerprint());
}

// Mass composition: two unit cubes side by side compose to the 2 x 1 x 1 box's closed form
// (placed, parallel_axis and compose through the public header; exact formulas, rounding only).
TEST(PublicApi, ComposeTwoCubesIsABox) {
  Collider a = box_collider(Vec3::Ones(), 1000), b = a;
  a.p_BC = Vec3(-0.5, 0, 0);
  b.p_BC = Vec3(0.5, 0, 0);
  const MassProperties m = compose({a, b});
  const MassProperties box = box_collider(Vec3(2, 1, 1), 1000).props_C;
  EXPECT_NEAR(m.mass, box.mass, 1e-9);
  EXPECT_LT(m.com.norm(), 1e-15);
  EXPECT_LT((m.inertia - box.inertia).norm(), 1e-9 * box.inertia.norm());
  const Mat3 pa = parallel_axis(2.0, Vec3(0, 0, 3));
  EXPECT_EQ(pa, Vec3(18, 18, 0).asDiagonal().toDenseMatrix());
  const MassProperties moved = placed(a.props_C, Mat3::Identity(), Vec3(1, 2, 3));
  EXPECT_EQ(moved.com, Vec3(1, 2, 3));
}
