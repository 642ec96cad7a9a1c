// Spatial (6D) vectors for the articulated-body algorithm, in Featherstone's conventions
// ("Rigid Body Dynamics Algorithms", 2008, ch. 2): a motion vector is [w; v] (angular first; v is
// the velocity of the body point at the frame's origin), a force vector [n; f] (moment about the
// origin first). Every link frame here has its origin at the link's centre of mass.
#pragma once
#include <Eigen/Core>

#include <simreel/math.hpp>

namespace simreel {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
// Up to six columns with no heap: a joint's motion subspace and the ABA terms built from it.
using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;
using MatXX6 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using VecX6 = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

// Motion cross product v x m (Featherstone eq. 2.31).
inline Vec6 cross_motion(const Vec6& v, const Vec6& m) {
  const Vec3 w = v.head<3>(), u = v.tail<3>(), mw = m.head<3>(), mu = m.tail<3>();
  Vec6 r;
  r << w.cross(mw), w.cross(mu) + u.cross(mw);
  return r;
}

// Force cross product v x* f (Featherstone eq. 2.32).
inline Vec6 cross_force(const Vec6& v, const Vec6& f) {
  const Vec3 w = v.head<3>(), u = v.tail<3>(), n = f.head<3>(), ff = f.tail<3>();
  Vec6 r;
  r << w.cross(n) + u.cross(ff), w.cross(ff);
  return r;
}

// The motion transform from frame A to frame B, where E rotates A-coordinates into B-coordinates
// and r is B's origin in A-coordinates: X [w; v] = [E w; E (v - r x w)] (Featherstone eq. 2.24).
inline Mat6 motion_transform(const Mat3& E, const Vec3& r) {
  Mat6 X;
  X.topLeftCorner<3, 3>() = E;
  X.topRightCorner<3, 3>().setZero();
  X.bottomLeftCorner<3, 3>() = -E * skew(r);
  X.bottomRightCorner<3, 3>() = E;
  return X;
}

// A rigid body's spatial inertia about its centre of mass, in its principal axes.
inline Mat6 spatial_inertia(double mass, const Vec3& I_P) {
  Mat6 M = Mat6::Zero();
  M.topLeftCorner<3, 3>().diagonal() = I_P;
  M.bottomRightCorner<3, 3>().diagonal().setConstant(mass);
  return M;
}

}  // namespace simreel
