#include "sim/dynamics/free_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace simreel {

namespace {

constexpr int kGauss = 10;  // Gauss-Legendre points per panel
constexpr int kPanelsPerPeriod = 256;

// Nodes and weights of Gauss-Legendre quadrature on [-1, 1], by Newton's method on P_n
// (Press et al., Numerical Recipes, 3rd ed., section 4.6).
struct GaussLegendre {
  double x[kGauss], w[kGauss];
  GaussLegendre() {
    const int n = kGauss;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), pp = 0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1, p2 = 0;
        for (int j = 0; j < n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j + 1) * z * p2 - j * p3) / (j + 1);
        }
        pp = n * (z * p1 - p2) / (z * z - 1);
        const double dz = p1 / pp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x[i] = z;
      w[i] = 2 / ((1 - z * z) * pp * pp);
    }
  }
};
const GaussLegendre& gauss() {
  static const GaussLegendre g;
  return g;
}

Mat3 rot_x(double a) {
  return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix();
}
Mat3 rot_z(double a) {
  return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix();
}

// Two moments equal to a relative 1e-9 (a cylinder's two transverse moments, computed apart).
bool same(double a, double b) {
  return std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b));
}

}  // namespace

FreeMotion::FreeMotion(const Vec3& I_P, const Quat& q_WP0, const Vec3& w_P0, const Vec3& x0, const Vec3& v0,
                       const Vec3& g)
    : I_(I_P), q0_(q_WP0.normalized()), w0_(w_P0), x0_(x0), v0_(v0), g_(g) {
  if (!(I_P[0] <= I_P[1] && I_P[1] <= I_P[2]))
    throw std::domain_error("FreeMotion needs ascending principal moments");
  const Vec3 L_P = I_.cwiseProduct(w0_);
  L_ = L_P.norm();
  if (!(w0_.norm() > 0)) return;  // still
  int nonzero = 0, axis = 0;
  for (int k = 0; k < 3; ++k)
    if (w0_[k] != 0) ++nonzero, axis = k;
  if (nonzero == 1) {  // about a principal axis alone: steady
    kind_ = Kind::steady;
    axis_P_ = Vec3::Unit(axis);
    rate_ = w0_[axis];
    return;
  }
  const bool s01 = same(I_[0], I_[1]), s12 = same(I_[1], I_[2]);
  if (s01 || s12) {
    // Symmetric: the distinct moment's axis is the symmetry axis (any axis if all three agree).
    const int k = s01 && s12 ? 2 : s01 ? 2 : 0;
    const double It = s01 && s12 ? (I_[0] + I_[1] + I_[2]) / 3
                      : s01      ? 0.5 * (I_[0] + I_[1])
                                 : 0.5 * (I_[1] + I_[2]);
    kind_ = Kind::symmetric;
    axis_P_ = Vec3::Unit(k);
    rate_ = -symmetric_top_body_precession(It, I_[k], w0_[k]);  // about the body's symmetry axis
    n_W_ = (q0_ * L_P).normalized();
    precession_ = symmetric_top_space_precession(It, L_);  // about L
    return;
  }
  kind_ = Kind::asymmetric;
  top_.emplace(I_, w0_);  // throws on the separatrix
  // On the major-axis side (L^2 > 2 E I2) w3 = c dn never vanishes; on the minor-axis side w1.
  polar_ = L_P.squaredNorm() < w0_.dot(L_P) * I_[1] ? 0 : 2;
  period_ = top_->flip_half_period();  // w^2 has half the period of w: 2 K / lambda
  // phi at the panel boundaries of one period, summed once: a call then integrates one panel.
  cumulative_.assign(kPanelsPerPeriod + 1, 0.0);
  const double h = period_ / kPanelsPerPeriod;
  for (int j = 0; j < kPanelsPerPeriod; ++j)
    cumulative_[j + 1] = cumulative_[j] + phi_integral(j * h, (j + 1) * h, 1);
  phi_period_ = cumulative_.back();
  align_ = q0_.toRotationMatrix() * euler_part(0, 0).transpose();
}

double FreeMotion::phi_rate(double t) const {
  const Vec3 w = top_->angular_velocity(t);
  const int a = (polar_ + 1) % 3, b = (polar_ + 2) % 3;
  const double ia = I_[a] * w[a], ib = I_[b] * w[b];
  return L_ * (ia * w[a] + ib * w[b]) / (ia * ia + ib * ib);
}

double FreeMotion::phi_integral(double a, double b, int panels) const {
  const GaussLegendre& gl = gauss();
  const double h = (b - a) / panels;
  double sum = 0;
  for (int p = 0; p < panels; ++p) {
    const double mid = a + (p + 0.5) * h;
    double s = 0;
    for (int i = 0; i < kGauss; ++i) s += gl.w[i] * phi_rate(mid + 0.5 * h * gl.x[i]);
    sum += 0.5 * h * s;
  }
  return sum;
}

Mat3 FreeMotion::euler_part(double t, double phi) const {
  // Axes relabelled (a, b, polar) -> (x, y, z), a cyclic (proper) permutation.
  const int a = (polar_ + 1) % 3, b = (polar_ + 2) % 3;
  const Vec3 w = top_->angular_velocity(t);
  const Vec3 L(I_[a] * w[a], I_[b] * w[b], I_[polar_] * w[polar_]);
  const double theta = std::acos(std::clamp(L.z() / L.norm(), -1.0, 1.0));
  const double psi = std::atan2(L.x(), L.y());
  Mat3 Q = Mat3::Zero();  // principal coordinates to relabelled ones
  Q(0, a) = Q(1, b) = Q(2, polar_) = 1;
  return rot_z(phi) * rot_x(theta) * rot_z(psi) * Q;
}

Quat FreeMotion::orientation(double t) const {
  switch (kind_) {
    case Kind::still:
      return q0_;
    case Kind::steady:
      return (q0_ * Quat(Eigen::AngleAxisd(rate_ * t, axis_P_))).normalized();
    case Kind::symmetric:
      return (Quat(Eigen::AngleAxisd(precession_ * t, n_W_)) * q0_ *
              Quat(Eigen::AngleAxisd(rate_ * t, axis_P_)))
          .normalized();
    case Kind::asymmetric:
      break;
  }
  // phi(t) = whole periods, whole panels of the rest, then the last part of a panel (phi' is
  // periodic in t).
  const double n = std::floor(t / period_), rest = t - n * period_, h = period_ / kPanelsPerPeriod;
  const int j = std::clamp((int)std::floor(rest / h), 0, kPanelsPerPeriod - 1);
  const double phi = n * phi_period_ + cumulative_[j] + phi_integral(j * h, rest, 1);
  return Quat(Mat3(align_ * euler_part(t, phi))).normalized();
}

Vec3 FreeMotion::position(double t) const {
  return x0_ + v0_ * t + 0.5 * g_ * t * t;
}

Vec3 FreeMotion::angular_velocity_world(double t) const {
  switch (kind_) {
    case Kind::still:
      return Vec3::Zero();
    case Kind::steady:
      return q0_ * (rate_ * axis_P_);
    case Kind::symmetric:
      return orientation(t) * (rate_ * axis_P_) + precession_ * n_W_;
    case Kind::asymmetric:
      break;
  }
  return orientation(t) * top_->angular_velocity(t);
}

}  // namespace simreel
