// Mass properties stated rather than drawn (BodyDef::mass_override, scene key `mass_properties`):
// the override reaches the World in place of the colliders' composition, and a free body with a
// given inertia moves as the closed form says.
#include <gtest/gtest.h>

#include <cmath>

#include <simreel/body.hpp>
#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "sim/mass/primitives.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

Collider unit_sphere() {
  Collider c;
  c.shape = ShapeKind::sphere;
  c.radius = 0.5;
  c.props_C = primitive_mass(c, 1000.0);
  return c;
}

// diag(I1, I1, I3) about an axis tilted away from every body axis: a tensor with products of inertia.
const Quat kTilt = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
Mat3 tilted_top(double I1, double I3) {
  const Mat3 R = kTilt.toRotationMatrix();
  return R * Vec3(I1, I1, I3).asDiagonal() * R.transpose();
}

TEST(MassOverride, ReplacesTheCollidersCompositionInTheWorld) {
  BodyDef b;
  b.append_collider(unit_sphere());  // alone: 523.6 kg, centre at the origin, isotropic
  MassProperties mp;
  mp.mass = 2.5;
  mp.com = Vec3(0.1, -0.2, 0.05);
  mp.inertia = tilted_top(0.4, 0.3);
  b.mass_override = mp;
  EXPECT_EQ(b.mass_B().mass, 2.5);
  EXPECT_EQ(b.mass_B().com, mp.com);
  b.p_WB = Vec3(1, 2, 3);
  WorldConfig cfg;
  cfg.gravity.setZero();
  World w(cfg, {b});
  EXPECT_EQ(w.impl().model(0).mass, 2.5);
  EXPECT_EQ(w.local_centroid(0), mp.com);
  EXPECT_LT((w.centroid(0) - Vec3(1.1, 1.8, 3.05)).norm(), 1e-15);
  EXPECT_LT((w.inertia_world(0) - mp.inertia).norm(), 1e-14);
  EXPECT_FALSE(w.impl().model(0).isotropic);
}

TEST(MassOverride, WorldRefusesUnphysicalStatedProperties) {
  auto refused = [](MassProperties mp) {
    BodyDef b;
    b.name = "odd";
    b.append_collider(unit_sphere());
    b.mass_override = mp;
    try {
      World w(WorldConfig{}, {b});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  MassProperties ok{1.0, Vec3::Zero(), Vec3(1, 2, 2.5).asDiagonal()};
  EXPECT_EQ(mass_problem(ok), "");
  MassProperties m = ok;
  m.mass = 0;
  EXPECT_NE(refused(m).find("mass must be positive"), std::string::npos) << refused(m);
  m = ok;
  m.inertia(0, 1) = 0.5;  // not symmetric
  EXPECT_NE(refused(m).find("not symmetric"), std::string::npos) << refused(m);
  m = ok;
  m.inertia(0, 0) = -1;
  EXPECT_NE(refused(m).find("not positive"), std::string::npos) << refused(m);
  m = ok;
  m.inertia(2, 2) = 3.5;  // 3.5 > 1 + 2
  EXPECT_NE(refused(m).find("triangle inequality"), std::string::npos) << refused(m);
  m = ok;
  m.com.x() = std::nan("");
  EXPECT_NE(refused(m).find("centre of mass"), std::string::npos) << refused(m);
}

// Torque-free symmetric top (Goldstein, Classical Mechanics, 3rd ed., sec. 5.6): the symmetry
// axis e3 turns about the constant angular momentum L at the rate |L| / I1 at a fixed angle, and
// the angular velocity turns about e3, in the body, at (I3 - I1) / I1 w3. Both are checked here
// with the tensor given explicitly (products of inertia, a centre of mass off the collider's).
TEST(MassOverride, FreeSymmetricTopPrecessesAtTheClosedFormRate) {
  const double I1 = 0.4, I3 = 0.25;
  BodyDef b;
  b.append_collider(unit_sphere());
  b.mass_override = MassProperties{3.0, Vec3(0.02, 0.01, -0.03), tilted_top(I1, I3)};
  const Vec3 e3_B = kTilt * Vec3::UnitZ();
  // Spin mostly about the symmetry axis, plus a transverse part: a 0.3 rad nutation cone.
  const Vec3 t_B = e3_B.cross(Vec3::UnitX()).normalized();
  const double w3 = 6.0, wt = 1.5;
  b.w_W = w3 * e3_B + wt * t_B;  // body frame = world frame at t = 0
  b.v_W = Vec3(0.3, 0, 0);
  WorldConfig cfg;
  cfg.gravity.setZero();
  cfg.dt = 1.0 / 240.0;
  World w(cfg, {b});
  const Vec3 L = w.angular_momentum(0);
  const Vec3 x0 = w.centroid(0);
  const double rate = L.norm() / I1;  // precession of e3 about L
  const double T = 5.0;
  const int n = (int)std::lround(T / cfg.dt);
  for (int k = 0; k < n; ++k) w.step();
  const Vec3 e3_now = w.local_to_world_vec(0, e3_B);
  const Vec3 e3_ref = Eigen::AngleAxisd(rate * T, L.normalized()) * e3_B;
  EXPECT_LT((e3_now - e3_ref).norm(), 1e-6) << "precession of the symmetry axis about L";
  // In the body: w's transverse part turns about e3 at (I3 - I1) / I1 w3.
  const Vec3 w_B = w.world_to_local_vec(0, w.angular_velocity(0));
  EXPECT_NEAR(w_B.dot(e3_B), w3, 1e-9);
  const double lambda = (I3 - I1) / I1 * w3;
  const Vec3 wt_ref = wt * (Eigen::AngleAxisd(lambda * T, e3_B) * t_B);
  EXPECT_LT((w_B - w_B.dot(e3_B) * e3_B - wt_ref).norm(), 1e-6 * wt);
  EXPECT_LT((w.angular_momentum(0) - L).norm(), 1e-9 * L.norm());
  EXPECT_LT((w.centroid(0) - x0 - Vec3(0.3 * T, 0, 0)).norm(), 1e-12);
}

}  // namespace
}  // namespace simreel
