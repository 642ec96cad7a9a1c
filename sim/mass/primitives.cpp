#include "sim/mass/primitives.hpp"

#include <cmath>
#include <numbers>

namespace simreel {
namespace {
constexpr double kPi = std::numbers::pi;

MassProperties diagonal(double m, double ixx, double iyy, double izz) {
  MassProperties mp;
  mp.mass = m;
  mp.com = Vec3::Zero();
  mp.inertia = Vec3(ixx, iyy, izz).asDiagonal();
  return mp;
}
}  // namespace

double box_volume(const Vec3& s) {
  return s.x() * s.y() * s.z();
}
double sphere_volume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}
double cylinder_volume(double r, double h) {
  return kPi * r * r * h;
}

MassProperties box_mass(const Vec3& s, double rho) {
  const double m = rho * box_volume(s);
  const Vec3 q = s.cwiseProduct(s);
  return diagonal(m, m / 12.0 * (q.y() + q.z()), m / 12.0 * (q.x() + q.z()), m / 12.0 * (q.x() + q.y()));
}

MassProperties sphere_mass(double r, double rho) {
  const double m = rho * sphere_volume(r);
  const double i = 0.4 * m * r * r;
  return diagonal(m, i, i, i);
}

MassProperties cylinder_mass(double r, double h, double rho) {
  const double m = rho * cylinder_volume(r, h);
  const double ixx = m * (3.0 * r * r + h * h) / 12.0;
  return diagonal(m, ixx, ixx, 0.5 * m * r * r);
}

double ellipsoid_volume(const Vec3& r) {
  return 4.0 / 3.0 * kPi * r.x() * r.y() * r.z();
}

// Solid ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 <= 1: I_xx = m (b^2 + c^2) / 5, cyclically (the unit
// ball's second moment m/5 per axis, scaled by each semi-axis squared).
MassProperties ellipsoid_mass(const Vec3& r, double rho) {
  const double m = rho * ellipsoid_volume(r);
  const Vec3 q = r.cwiseProduct(r);
  return diagonal(m, m / 5.0 * (q.y() + q.z()), m / 5.0 * (q.x() + q.z()), m / 5.0 * (q.x() + q.y()));
}

MassProperties capsule_mass(double r, double h, double rho) {
  const double L = h - 2.0 * r;  // length of the cylindrical part
  const double mc = rho * cylinder_volume(r, L);
  const double ms = rho * sphere_volume(r);  // both hemispheres together
  const double izz = 0.5 * mc * r * r + 0.4 * ms * r * r;
  const double ixx = mc * (3.0 * r * r + L * L) / 12.0 + ms * (0.4 * r * r + 0.25 * L * L + 0.375 * L * r);
  return diagonal(mc + ms, ixx, ixx, izz);
}

}  // namespace simreel
