#include "sim/collision/smooth_support.hpp"

#include <cmath>

namespace simreel {

bool smooth_support(const CollideShape& g, const Vec3& d, int end, Vec3& p, Mat3& J) {
  const int side = end != 0 ? end : d.z() >= 0 ? 1 : -1;
  switch (g.kind) {
    case CollideKind::sphere:
      p = g.radius * d;
      J = g.radius * (Mat3::Identity() - d * d.transpose());
      return true;
    case CollideKind::capsule:
      if (std::fabs(d.z()) <= kCapsuleMinSine || d.z() * side < 0) return false;
      p = Vec3(0, 0, side * g.half_length) + g.radius * d;
      J = g.radius * (Mat3::Identity() - d * d.transpose());
      return true;
    case CollideKind::ellipsoid: {
      const Vec3 A = g.radii.cwiseProduct(g.radii);
      const Vec3 Ad = A.cwiseProduct(d);
      const double s = std::sqrt(d.dot(Ad));
      p = Ad / s;
      J = Mat3(A.asDiagonal()) / s - Ad * Ad.transpose() / (s * s * s);
      return true;
    }
    case CollideKind::cylinder: {
      const double len = std::hypot(d.x(), d.y());
      if (len <= kRimMinSine || d.z() * side < 0) return false;
      const Vec3 e(d.x() / len, d.y() / len, 0);
      const Vec3 tan(-e.y(), e.x(), 0);  // z x e
      p = Vec3(0, 0, side * g.half_length) + g.radius * e;
      J = (g.radius / len) * tan * tan.transpose();
      return true;
    }
    default:
      return false;
  }
}

}  // namespace simreel
