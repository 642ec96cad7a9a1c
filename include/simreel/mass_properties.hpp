// Mass properties of a rigid body or collider, and the operations that compose them.
#pragma once
#include <limits>
#include <string>

#include <simreel/math.hpp>

namespace simreel {

// Mass, centre of mass and inertia tensor about the centre of mass, all expressed in one frame F
// (the frame is whatever the owner says: a collider's C, then the body's B after placement).
struct MassProperties {
  double mass = 0.0;                                                        ///< kg
  Vec3 com = Vec3::Zero();                                                  ///< m, in F
  Mat3 inertia = Mat3::Constant(std::numeric_limits<double>::quiet_NaN());  ///< kg m^2, about com, axes of F
};

// Re-expresses `mp` (given in frame C) in frame B, where C sits at p_BC with orientation R_BC:
// com_B = p_BC + R_BC com_C and I_B = R_BC I_C R_BC^T (a rotation does not change the point).
MassProperties placed(const MassProperties& mp, const Mat3& R_BC, const Vec3& p_BC);

// Inertia of a mass m at offset r from a point, about that point (parallel axis theorem):
// m (|r|^2 1 - r r^T).  Steiner's theorem, e.g. Goldstein, Classical Mechanics, 3rd ed., eq. 5.17.
Mat3 parallel_axis(double m, const Vec3& r);

// Sum of several bodies' mass properties expressed in one frame: total mass, mass-weighted centre,
// and the inertia of each about the common centre by the parallel axis theorem.
class MassAccumulator {
 public:
  void add(const MassProperties& mp);
  MassProperties result() const;
  int count() const { return n_; }

 private:
  // Accumulated about the frame origin: sum m, sum m c, sum (I_i + parallel_axis(m_i, c_i)).
  double m_ = 0.0;
  Vec3 mc_ = Vec3::Zero();
  Mat3 I_origin_ = Mat3::Zero();
  // First collider's centre: accumulating about it rather than the frame origin keeps precision
  // when every collider is far from the origin.
  Vec3 ref_ = Vec3::Zero();
  int n_ = 0;
};

// Principal moments (ascending) and axes: I = R diag(moments) R^T with R a proper rotation
// (det +1). Repeated moments are handled by the symmetric eigen-solver; the axes of a repeated
// pair are any orthonormal pair of its plane.
struct PrincipalAxes {
  Vec3 moments;  ///< kg m^2, ascending
  Mat3 R;        ///< columns are the principal axes in the frame the tensor was given in
};
PrincipalAxes principal_axes(const Mat3& inertia);

// Physical validity of an inertia tensor: symmetric, moments > 0, each moment at most the sum of
// the other two (triangle inequality, with a relative slack of `rel_tol` for rounding).
// Returns an empty string when valid, otherwise the reason.
std::string inertia_problem(const Mat3& inertia, double rel_tol = 1e-9);

}  // namespace simreel
