// Fixed-size Eigen aliases used throughout simreel. Names of variables carry their frame, as in
// Drake: p_W is a point in world coordinates, R_WB rotates body-frame vectors into the world frame,
// I_B is an inertia tensor expressed in the body frame. Frames used in sim/:
//   W  world;  B  the body's model frame (its origin is the `position` users give);
//   P  the body's principal frame (origin at the centre of mass, axes along principal axes);
//   C  a collider's own frame inside the body.
// Units are SI everywhere: m, kg, s, rad, N, N m, kg m^2.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace simreel {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Skew-symmetric cross-product matrix: skew(a) * b == a.cross(b).
inline Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

inline bool all_finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

}  // namespace simreel
