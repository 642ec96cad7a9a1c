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

// The products below on raw arrays write into out, which must not alias the inputs: the ABA's
// passes call them once per link and evaluation, and Eigen's comma initialisers of 3-vector
// halves were left out of line at -O2, with a stall each where scalar stores met a packed load.
// The Vec6 forms return the same bits.

// Motion cross product v x m (Featherstone eq. 2.31).
inline void cross_motion(const double* __restrict v, const double* __restrict m, double* __restrict out) {
  out[0] = v[1] * m[2] - v[2] * m[1];
  out[1] = v[2] * m[0] - v[0] * m[2];
  out[2] = v[0] * m[1] - v[1] * m[0];
  out[3] = (v[1] * m[5] - v[2] * m[4]) + (v[4] * m[2] - v[5] * m[1]);
  out[4] = (v[2] * m[3] - v[0] * m[5]) + (v[5] * m[0] - v[3] * m[2]);
  out[5] = (v[0] * m[4] - v[1] * m[3]) + (v[3] * m[1] - v[4] * m[0]);
}
inline Vec6 cross_motion(const Vec6& v, const Vec6& m) {
  Vec6 out;
  cross_motion(v.data(), m.data(), out.data());
  return out;
}

// Force cross product v x* f (Featherstone eq. 2.32).
inline void cross_force(const double* __restrict v, const double* __restrict f, double* __restrict out) {
  out[0] = (v[1] * f[2] - v[2] * f[1]) + (v[4] * f[5] - v[5] * f[4]);
  out[1] = (v[2] * f[0] - v[0] * f[2]) + (v[5] * f[3] - v[3] * f[5]);
  out[2] = (v[0] * f[1] - v[1] * f[0]) + (v[3] * f[4] - v[4] * f[3]);
  out[3] = v[1] * f[5] - v[2] * f[4];
  out[4] = v[2] * f[3] - v[0] * f[5];
  out[5] = v[0] * f[4] - v[1] * f[3];
}
inline Vec6 cross_force(const Vec6& v, const Vec6& f) {
  Vec6 out;
  cross_force(v.data(), f.data(), out.data());
  return out;
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
inline void transform_motion(const Mat3& E, const Vec3& r, const double* __restrict v,
                             double* __restrict out) {
  const double w0 = v[0], w1 = v[1], w2 = v[2];
  const double u0 = v[3] - (r[1] * w2 - r[2] * w1), u1 = v[4] - (r[2] * w0 - r[0] * w2),
               u2 = v[5] - (r[0] * w1 - r[1] * w0);
  for (int i = 0; i < 3; ++i) {
    out[i] = E(i, 0) * w0 + E(i, 1) * w1 + E(i, 2) * w2;
    out[i + 3] = E(i, 0) * u0 + E(i, 1) * u1 + E(i, 2) * u2;
  }
}
inline Vec6 transform_motion(const Mat3& E, const Vec3& r, const Vec6& v) {
  Vec6 out;
  transform_motion(E, r, v.data(), out.data());
  return out;
}
// out = X v + a.
inline void transform_motion_add(const Mat3& E, const Vec3& r, const double* __restrict v,
                                 const double* __restrict a, double* __restrict out) {
  double o[6];
  transform_motion(E, r, v, o);
  for (int i = 0; i < 6; ++i) out[i] = o[i] + a[i];
}

// X^T f: a force on frame B's side carried back to frame A (Featherstone eq. 2.25 transposed).
inline void transform_force_back(const Mat3& E, const Vec3& r, const double* __restrict f,
                                 double* __restrict out) {
  for (int i = 0; i < 3; ++i) {
    out[i] = E(0, i) * f[0] + E(1, i) * f[1] + E(2, i) * f[2];
    out[i + 3] = E(0, i) * f[3] + E(1, i) * f[4] + E(2, i) * f[5];
  }
  out[0] += r[1] * out[5] - r[2] * out[4];
  out[1] += r[2] * out[3] - r[0] * out[5];
  out[2] += r[0] * out[4] - r[1] * out[3];
}
inline Vec6 transform_force_back(const Mat3& E, const Vec3& r, const Vec6& f) {
  Vec6 out;
  transform_force_back(E, r, f.data(), out.data());
  return out;
}
// out += X^T f.
inline void add_transform_force_back(const Mat3& E, const Vec3& r, const double* __restrict f,
                                     double* __restrict out) {
  double o[6];
  transform_force_back(E, r, f, o);
  for (int i = 0; i < 6; ++i) out[i] += o[i];
}

// out += X^T I X: a symmetric spatial inertia I = [A B; B^T C] given in frame B, carried to frame
// A (the articulated-body and composite-rigid-body algorithms' inner product). With A', B', C' the
// blocks rotated into A's axes (E^T . E) and S = r x:  [A' - B'S + S B'^T - S C' S,  B' + S C';
// B'^T - C' S,  C'], written out by entries: the diagonal blocks are symmetric (6 of 9 entries
// each), r x (.) is a cross product rather than a product with a skew matrix, and nothing is left
// to out-of-line small-matrix products (Eigen's 3x3 products were a third of a 20-link chain's
// evaluation; this is about a tenth).
inline void add_transform_inertia_back(const Mat3& E, const Vec3& r, const Mat6& I, Mat6& out) {
  // Blocks rotated into the parent's axes: M' = E^T M E (A' and C' symmetric: upper triangles).
  double A[3][3], B[3][3], C[3][3], TA[3][3], TB[3][3], TC[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      TA[i][j] = I(i, 0) * E(0, j) + I(i, 1) * E(1, j) + I(i, 2) * E(2, j);
      TB[i][j] = I(i, 3) * E(0, j) + I(i, 4) * E(1, j) + I(i, 5) * E(2, j);
      TC[i][j] = I(i + 3, 3) * E(0, j) + I(i + 3, 4) * E(1, j) + I(i + 3, 5) * E(2, j);
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      B[i][j] = E(0, i) * TB[0][j] + E(1, i) * TB[1][j] + E(2, i) * TB[2][j];
      if (j < i) continue;
      A[i][j] = E(0, i) * TA[0][j] + E(1, i) * TA[1][j] + E(2, i) * TA[2][j];
      C[i][j] = E(0, i) * TC[0][j] + E(1, i) * TC[1][j] + E(2, i) * TC[2][j];
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j) A[i][j] = A[j][i], C[i][j] = C[j][i];
  const double x = r.x(), y = r.y(), z = r.z();
  // SC = r x C' (column by column), BS = B' [r]x (row i: -(r x b_i)), SCS = SC [r]x.
  double SC[3][3], BS[3][3], SCS[3][3];
  for (int j = 0; j < 3; ++j) {
    SC[0][j] = y * C[2][j] - z * C[1][j];
    SC[1][j] = z * C[0][j] - x * C[2][j];
    SC[2][j] = x * C[1][j] - y * C[0][j];
  }
  for (int i = 0; i < 3; ++i) {
    BS[i][0] = B[i][1] * z - B[i][2] * y;
    BS[i][1] = B[i][2] * x - B[i][0] * z;
    BS[i][2] = B[i][0] * y - B[i][1] * x;
    SCS[i][0] = SC[i][1] * z - SC[i][2] * y;
    SCS[i][1] = SC[i][2] * x - SC[i][0] * z;
    SCS[i][2] = SC[i][0] * y - SC[i][1] * x;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      out(i, j) += A[i][j] - BS[i][j] - BS[j][i] - SCS[i][j];
      const double b = B[i][j] + SC[i][j];
      out(i, j + 3) += b;
      out(j + 3, i) += b;
      out(i + 3, j + 3) += C[i][j];
    }
}

// I v for a 6x6 I: written out, as Eigen leaves the fixed-size product out of line at -O2.
inline Vec6 mat6_vec(const Mat6& I, const Vec6& v) {
  Vec6 o;
  for (int i = 0; i < 6; ++i)
    o[i] =
        I(i, 0) * v[0] + I(i, 1) * v[1] + I(i, 2) * v[2] + I(i, 3) * v[3] + I(i, 4) * v[4] + I(i, 5) * v[5];
  return o;
}
// out += I v.
inline void add_mat6_vec(const Mat6& I, const Vec6& v, double* __restrict out) {
  const Vec6 o = mat6_vec(I, v);
  for (int i = 0; i < 6; ++i) out[i] += o[i];
}

// A rigid body's spatial inertia about its centre of mass, in its principal axes.
inline Mat6 spatial_inertia(double mass, const Vec3& I_P) {
  Mat6 M = Mat6::Zero();
  M.topLeftCorner<3, 3>().diagonal() = I_P;
  M.bottomRightCorner<3, 3>().diagonal().setConstant(mass);
  return M;
}

}  // namespace simreel
