#include <simreel/mass_properties.hpp>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

namespace simreel {

MassProperties placed(const MassProperties& mp, const Mat3& R_BC, const Vec3& p_BC) {
  MassProperties out;
  out.mass = mp.mass;
  out.com = p_BC + R_BC * mp.com;
  out.inertia = R_BC * mp.inertia * R_BC.transpose();
  return out;
}

Mat3 parallel_axis(double m, const Vec3& r) {
  return m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
}

void MassAccumulator::add(const MassProperties& mp) {
  if (n_ == 0) ref_ = mp.com;
  const Vec3 r = mp.com - ref_;
  m_ += mp.mass;
  mc_ += mp.mass * r;
  I_origin_ += mp.inertia + parallel_axis(mp.mass, r);
  ++n_;
}

MassProperties MassAccumulator::result() const {
  MassProperties out;
  out.mass = m_;
  if (m_ == 0) {  // massless (a static body of planes only): no centre to speak of, the origin
    out.com = Vec3::Zero();
    out.inertia = Mat3::Zero();
    return out;
  }
  const Vec3 c = mc_ / m_;  // centre relative to ref_
  out.com = ref_ + c;
  // Shift from ref_ to the centre: I_com = I_ref - m (|c|^2 1 - c c^T).
  out.inertia = I_origin_ - parallel_axis(m_, c);
  out.inertia = 0.5 * (out.inertia + out.inertia.transpose()).eval();
  return out;
}

PrincipalAxes principal_axes(const Mat3& inertia) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(inertia);
  PrincipalAxes pa;
  pa.moments = es.eigenvalues();  // ascending
  pa.R = es.eigenvectors();
  if (pa.R.determinant() < 0) pa.R.col(2) = -pa.R.col(2);
  // Deterministic sign convention: make the largest component of the first two axes positive.
  for (int k = 0; k < 2; ++k) {
    Eigen::Index i;
    pa.R.col(k).cwiseAbs().maxCoeff(&i);
    if (pa.R(i, k) < 0) {
      pa.R.col(k) = -pa.R.col(k);
      pa.R.col(2) = -pa.R.col(2);
    }
  }
  return pa;
}

std::string inertia_problem(const Mat3& I, double rel_tol) {
  if (!I.allFinite()) return "inertia tensor is not finite";
  const double scale = I.cwiseAbs().maxCoeff();
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return "inertia tensor is not symmetric";
  const Vec3 m = principal_axes(I).moments;
  std::ostringstream os;
  if (!(m[0] > 0.0)) {
    os << "principal moment " << m[0] << " kg m^2 is not positive";
    return os.str();
  }
  if (m[2] > (m[0] + m[1]) * (1.0 + rel_tol)) {
    os << "principal moments (" << m[0] << ", " << m[1] << ", " << m[2]
       << ") violate the triangle inequality";
    return os.str();
  }
  return {};
}

}  // namespace simreel
