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

// The same transform applied without forming the 6x6 matrix: X v.
inline Vec6 transform_motion(const Mat3& E, const Vec3& r, const Vec6& v) {
  const Vec3 w = v.head<3>();
  Vec6 out;
  out << E * w, E * (Vec3(v.tail<3>()) - r.cross(w));
  return out;
}

// X^T f: a force on frame B's side carried back to frame A (Featherstone eq. 2.25 transposed).
inline Vec6 transform_force_back(const Mat3& E, const Vec3& r, const Vec6& f) {
  const Vec3 ff = E.transpose() * f.tail<3>();
  Vec6 out;
  out << E.transpose() * f.head<3>() + r.cross(ff), ff;
  return out;
}

// X^T I X for a symmetric spatial inertia I = [A B; B^T C] given in frame B, carried to frame A,
// by 3x3 blocks (about half the work of two 6x6 products). With A', B', C' the blocks rotated into
// A's axes (E^T . E) and S = r x:  [A' - B'S + S B'^T - S C' S,  B' + S C';  B'^T - C' S,  C'].
inline Mat6 transform_inertia_back(const Mat3& E, const Vec3& r, const Mat6& I) {
  const Mat3 Et = E.transpose();
  const Mat3 A = Et * I.topLeftCorner<3, 3>() * E;
  const Mat3 B = Et * I.topRightCorner<3, 3>() * E;
  const Mat3 C = Et * I.bottomRightCorner<3, 3>() * E;
  const Mat3 S = skew(r);
  const Mat3 SC = S * C;
  const Mat3 BS = B * S;
  Mat6 out;
  out.topLeftCorner<3, 3>() = A - BS - BS.transpose() - SC * S;
  out.topRightCorner<3, 3>() = B + SC;
  out.bottomLeftCorner<3, 3>() = (B + SC).transpose();
  out.bottomRightCorner<3, 3>() = C;
  return out;
}

// A rigid body's spatial inertia about its centre of mass, in its principal axes.
inline Mat6 spatial_inertia(double mass, const Vec3& I_P) {
  Mat6 M = Mat6::Zero();
  M.topLeftCorner<3, 3>().diagonal() = I_P;
  M.bottomRightCorner<3, 3>().diagonal().setConstant(mass);
  return M;
}

}  // namespace simreel
