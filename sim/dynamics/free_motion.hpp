// Closed-form motion of a free rigid body: no torque about its centre of mass, at most a uniform
// gravity (which exerts none). The centre of mass follows x0 + v0 t + g t^2 / 2; the rotation is
// Euler's torque-free motion, whole, orientation included:
//   - asymmetric body (I1 < I2 < I3): the body angular velocity is Jacobi's (sim/dynamics/free_top.hpp);
//     the orientation follows from it with z-x-z Euler angles about the fixed angular momentum L
//     (Landau & Lifshitz, Mechanics, section 37): the body's L gives the nutation theta and the
//     spin psi at once (cos theta = L3 / |L|, tan psi = L1 / L2), and the precession phi about L
//     grows at phi' = |L| (I1 w1^2 + I2 w2^2) / (I1^2 w1^2 + I2^2 w2^2) (37.16), a periodic
//     function of t with the period of w^2, integrated here by Gauss-Legendre quadrature (10
//     points a panel, 256 panels a period): whole periods and whole panels summed once, the last
//     part of a panel at each call (a function of t alone, ~1e-13 rad);
//   - symmetric body (two equal moments It, the third I3): a rotation about L at |L| / It after
//     one about the symmetry axis at -(I3 - It) w3 / It, both uniform (section 33); a sphere-like
//     body (three equal) turns uniformly about its omega;
//   - a spin about a principal axis alone: uniform.
// The polar axis of the Euler angles is the one whose omega component never vanishes (I3 for a
// body on the major-axis side of the separatrix, I1 on the minor-axis side), so theta stays
// away from 0 and pi.
#pragma once
#include <array>
#include <optional>
#include <vector>

#include "sim/dynamics/free_top.hpp"
#include <simreel/math.hpp>

namespace simreel {

class FreeMotion {
 public:
  // I_P: principal moments, ascending (kg m^2); q_WP0: principal axes to world at t = 0;
  // w_P0: angular velocity on the principal axes (rad/s); x0, v0: centre of mass (m, m/s); g (m/s^2).
  // Throws std::domain_error for motion on the separatrix (an infinite flip period).
  FreeMotion(const Vec3& I_P, const Quat& q_WP0, const Vec3& w_P0, const Vec3& x0, const Vec3& v0,
             const Vec3& g);
  Quat orientation(double t) const;             ///< q_WP: principal axes to world
  Vec3 position(double t) const;                ///< m, centre of mass
  Vec3 angular_velocity_world(double t) const;  ///< rad/s

 private:
  enum class Kind { still, steady, symmetric, asymmetric };
  double phi_rate(double t) const;  // asymmetric: phi'(t), rad/s
  double phi_integral(double a, double b, int panels) const;
  Mat3 euler_part(double t, double phi) const;  // asymmetric: Rz(phi) Rx(theta) Rz(psi) Q

  Kind kind_ = Kind::still;
  Vec3 I_;
  Quat q0_;
  Vec3 w0_, x0_, v0_, g_;
  // steady: the axis (principal frame) and rate; symmetric: the symmetry axis, its rate, the
  // precession axis (world) and rate.
  Vec3 axis_P_ = Vec3::UnitZ();
  double rate_ = 0;
  Vec3 n_W_ = Vec3::UnitZ();
  double precession_ = 0;
  // asymmetric
  std::optional<FreeTop> top_;
  int polar_ = 2;                   // principal axis index of the Euler polar axis
  Mat3 align_;                      // L-frame to world: R_WP(t) = align_ euler_part(t)
  double period_ = 0;               // s, of phi'
  double phi_period_ = 0;           // rad, phi over one period
  std::vector<double> cumulative_;  // rad, phi at the panel boundaries of one period
  double L_ = 0;                    // |L|
};

}  // namespace simreel
