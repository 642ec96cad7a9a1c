// TEMPORARY development stand-in for the narrow phase (sphere/box against plane, sphere-sphere),
// replaced by sim/collide/collide.cpp when the narrow-phase branch lands. Not for release.
#include <cmath>

#include "sim/collide/manifold.hpp"
#include "sim/convex_hull.hpp"
#include "sim/error.hpp"

namespace simreel {

int collide(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
            PairCache&, Manifold& out) {
  out.count = 0;
  if (b.kind == CollideKind::plane && a.kind != CollideKind::plane) {
    PairCache c;
    int n = collide(b, xb, a, xa, spec, c, out);
    out.normal_W = -out.normal_W;
    return n;
  }
  if (a.kind == CollideKind::plane) {
    const Vec3 n = xa.R.col(2);
    const double d = n.dot(xa.p);
    out.normal_W = n;
    if (b.kind == CollideKind::sphere) {
      const double s = n.dot(xb.p) - d - b.radius;
      if (s > spec) return 0;
      out.points[0].p_W = xb.p - (b.radius + 0.5 * s) * n;
      out.points[0].separation = s;
      out.points[0].id = 0;
      return out.count = 1;
    }
    if (b.kind == CollideKind::box) {
      struct C {
        double s;
        int i;
        Vec3 p;
      } cs[8];
      for (int i = 0; i < 8; ++i) {
        const Vec3 v((i & 1) ? b.half_extents.x() : -b.half_extents.x(),
                     (i & 2) ? b.half_extents.y() : -b.half_extents.y(),
                     (i & 4) ? b.half_extents.z() : -b.half_extents.z());
        const Vec3 w = xb.apply(v);
        cs[i] = {n.dot(w) - d, i, w};
      }
      for (int i = 1; i < 8; ++i)
        for (int j = i; j > 0 && (cs[j].s < cs[j - 1].s); --j) std::swap(cs[j], cs[j - 1]);
      int k = 0;
      for (int i = 0; i < 4; ++i)
        if (cs[i].s <= spec) {
          out.points[k].p_W = cs[i].p - 0.5 * cs[i].s * n;
          out.points[k].separation = cs[i].s;
          out.points[k].id = (uint32_t)cs[i].i;
          ++k;
        }
      return out.count = k;
    }
    return 0;
  }
  if (a.kind == CollideKind::sphere && b.kind == CollideKind::sphere) {
    const Vec3 d = xb.p - xa.p;
    const double L = d.norm();
    const double s = L - a.radius - b.radius;
    if (s > spec) return 0;
    const Vec3 n = L > 0 ? Vec3(d / L) : Vec3::UnitZ();
    out.normal_W = n;
    out.points[0].p_W = xa.p + (a.radius + 0.5 * s) * n;
    out.points[0].separation = s;
    return out.count = 1;
  }
  return 0;
}

}  // namespace simreel
