// Per-body data split by use (Box2D's b2Body/b2BodySim, MuJoCo's mjModel/mjData):
//   BodyModel   static, set when the world is built (mass properties, classification);
//   MotionState what the integrators advance, 13 doubles (112 bytes with alignment);
//   Wrench      force and torque accumulated during a step, cleared after integration.
#pragma once
#include <simreel/math.hpp>

namespace simreel {

struct BodyModel {
  double mass = 0;               ///< kg
  double inv_mass = 0;           ///< 1/kg (0 for static bodies)
  Vec3 I_P = Vec3::Zero();       ///< kg m^2, principal moments, ascending
  Vec3 inv_I_P = Vec3::Zero();   ///< 1/(kg m^2)
  Quat q_BP = Quat::Identity();  ///< principal frame P in the body frame B
  Vec3 c_B = Vec3::Zero();       ///< m, centre of mass in the body frame (the article's local centroid)
  bool is_static = false;        ///< never moves
  bool is_kinematic = false;     ///< moves at its given velocity, infinite mass
  bool isotropic = false;        ///< I_P equal to 1e-12 relative: no gyroscopic term, rotation is exact
  // Bound on Euler's equations' rate per unit |w|: max(1, max_i |I_j - I_k| / I_i). The fastest
  // motion of w or q is at most gyro_rate |w| rad/s; `auto` substeps when that times h is large.
  double gyro_rate = 1.0;
};

struct MotionState {
  Quat q_WP = Quat::Identity();  ///< principal frame to world, unit
  Vec3 x_W = Vec3::Zero();       ///< m, centre of mass in the world (the article's global centroid)
  Vec3 v_W = Vec3::Zero();       ///< m/s, centre-of-mass velocity, world frame
  Vec3 w_P = Vec3::Zero();       ///< rad/s, angular velocity in the principal frame
};

struct Wrench {
  Vec3 f_W = Vec3::Zero();    ///< N, total force, world frame
  Vec3 tau_W = Vec3::Zero();  ///< N m, total torque about the centre of mass, world frame
};

}  // namespace simreel
