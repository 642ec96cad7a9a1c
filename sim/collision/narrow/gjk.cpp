// GJK distance and EPA penetration between the cores of two convex shapes, and the generic pair
// function built on them (design note and tolerances: collide.cpp).
//
// GJK: E. G. Gilbert, D. W. Johnson, S. S. Keerthi, "A fast procedure for computing the distance
// between complex objects in three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988;
// the simplex sub-problems solved by closest-point-on-segment/triangle/tetrahedron (C. Ericson,
// Real-Time Collision Detection, 5.1). EPA: G. van den Bergen, "Proximity queries and penetration
// depth computation on 3D game objects", GDC 2001.
#include "sim/collision/narrow/internal.hpp"

namespace simreel::collide_detail {

Support::Support(const CollideShape& s, const Pose& x) : shape(&s), pose(&x) {
  if (s.kind == CollideKind::sphere || s.kind == CollideKind::capsule) margin = s.radius;
}

Vec3 Support::support_W(const Vec3& d_W) const {
  const CollideShape& s = *shape;
  const Vec3 d = pose->R.transpose() * d_W;
  Vec3 p;
  switch (s.kind) {
    case CollideKind::sphere:
      p.setZero();
      break;
    case CollideKind::capsule:
      p = Vec3(0, 0, d.z() >= 0 ? s.half_length : -s.half_length);
      break;
    case CollideKind::cylinder: {
      const double rxy = std::hypot(d.x(), d.y());
      p = Vec3(0, 0, d.z() >= 0 ? s.half_length : -s.half_length);
      if (rxy > 0) p.x() = s.radius * d.x() / rxy, p.y() = s.radius * d.y() / rxy;
      break;
    }
    case CollideKind::ellipsoid: {
      const Vec3 rd = s.radii.cwiseProduct(d);
      const double k = rd.norm();
      p = k > 0 ? Vec3(s.radii.cwiseProduct(rd) / k) : Vec3::Zero();
      break;
    }
    case CollideKind::box:
      p = Vec3(d.x() >= 0 ? s.half_extents.x() : -s.half_extents.x(),
               d.y() >= 0 ? s.half_extents.y() : -s.half_extents.y(),
               d.z() >= 0 ? s.half_extents.z() : -s.half_extents.z());
      break;
    case CollideKind::hull:
      p = s.hull->vertices[s.hull->support(d)];
      break;
    default:
      p.setZero();
      break;
  }
  return pose->apply(p);
}

namespace {

struct SV {
  Vec3 a, b, w;  // support points on A and B, w = a - b
};
struct Simplex {
  SV v[4];
  double bc[4];  // barycentric weights of the closest point
  int n = 0;
  Vec3 closest() const {
    Vec3 x = Vec3::Zero();
    for (int i = 0; i < n; ++i) x += bc[i] * v[i].w;
    return x;
  }
  void witnesses(Vec3& pa, Vec3& pb) const {
    pa.setZero(), pb.setZero();
    for (int i = 0; i < n; ++i) pa += bc[i] * v[i].a, pb += bc[i] * v[i].b;
  }
};

// Closest point of triangle (a, b, c) to the origin as barycentric weights (Ericson 5.1.5).
void triangle_weights(const Vec3& a, const Vec3& b, const Vec3& c, double w[3]) {
  const Vec3 ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    w[0] = 1, w[1] = 0, w[2] = 0;
    return;
  }
  const Vec3 bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    w[0] = 0, w[1] = 1, w[2] = 0;
    return;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    {
      w[0] = 1 - v, w[1] = v, w[2] = 0;
      return;
    }
  }
  const Vec3 cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    w[0] = 0, w[1] = 0, w[2] = 1;
    return;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    {
      w[0] = 1 - t, w[1] = 0, w[2] = t;
      return;
    }
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    {
      w[0] = 0, w[1] = 1 - t, w[2] = t;
      return;
    }
  }
  const double den = 1 / (va + vb + vc);
  const double v = vb * den, t = vc * den;
  w[0] = 1 - v - t, w[1] = v, w[2] = t;
}

// Keeps the simplex vertices with positive weight (in order).
void compact(Simplex& s) {
  int k = 0;
  for (int i = 0; i < s.n; ++i)
    if (s.bc[i] > 0) s.v[k] = s.v[i], s.bc[k] = s.bc[i], ++k;
  s.n = k;
}

// Replaces the simplex by the face of it closest to the origin; returns true when the origin is
// inside the tetrahedron (overlap).
bool solve(Simplex& s) {
  switch (s.n) {
    case 1:
      s.bc[0] = 1;
      return false;
    case 2: {
      const Vec3 &a = s.v[0].w, &b = s.v[1].w;
      const Vec3 ab = b - a;
      const double L2 = ab.squaredNorm();
      double t = L2 > 0 ? -a.dot(ab) / L2 : 0;
      t = std::clamp(t, 0.0, 1.0);
      s.bc[0] = 1 - t, s.bc[1] = t;
      compact(s);
      return false;
    }
    case 3: {
      double w[3];
      triangle_weights(s.v[0].w, s.v[1].w, s.v[2].w, w);
      for (int i = 0; i < 3; ++i) s.bc[i] = w[i];
      compact(s);
      return false;
    }
    default: {
      // Tetrahedron: the origin is inside when it is on the inner side of all four faces.
      const int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
      bool inside = true;
      double best = INFINITY;
      Simplex bestS;
      for (const auto& f : faces) {
        const Vec3 &a = s.v[f[0]].w, &b = s.v[f[1]].w, &c = s.v[f[2]].w, &d = s.v[f[3]].w;
        const Vec3 nrm = (b - a).cross(c - a);
        const double so = -nrm.dot(a), sd = nrm.dot(d - a);
        if (so * sd >= 0 && sd != 0) continue;  // origin on d's side of this face
        inside = false;
        double w[3];
        triangle_weights(a, b, c, w);
        const Vec3 x = w[0] * a + w[1] * b + w[2] * c;
        const double d2 = x.squaredNorm();
        if (d2 < best) {
          best = d2;
          bestS.n = 3;
          for (int i = 0; i < 3; ++i) bestS.v[i] = s.v[f[i]], bestS.bc[i] = w[i];
        }
      }
      if (inside) {
        s.bc[0] = s.bc[1] = s.bc[2] = s.bc[3] = 0.25;
        return true;
      }
      s = bestS;
      compact(s);
      return false;
    }
  }
}

SV support_pair(const Support& A, const Support& B, const Vec3& d) {
  SV v;
  v.a = A.support_W(d);
  v.b = B.support_W(-d);
  v.w = v.a - v.b;
  return v;
}

double pair_size(const Support& A, const Support& B) {
  const double r = A.shape->bounding_radius + B.shape->bounding_radius;
  return r > 0 ? r : 1.0;  // bounding radii unset: unit scale
}

constexpr int kGjkMaxIter = 64;
constexpr int kEpaMaxIter = 64, kEpaMaxV = 64, kEpaMaxF = 128;

// GJK. Returns the final simplex; overlap when the origin is inside it (or within 1e-10 size).
Simplex run_gjk(const Support& A, const Support& B, bool& overlap, double& dist) {
  const double size = pair_size(A, B);
  Simplex s;
  Vec3 d = B.centre_W() - A.centre_W();
  if (d.squaredNorm() < 1e-30) d = Vec3::UnitX();
  s.v[0] = support_pair(A, B, -d);
  s.bc[0] = 1;
  s.n = 1;
  Vec3 v = s.v[0].w;
  overlap = false;
  for (int it = 0; it < kGjkMaxIter; ++it) {
    const double vv = v.squaredNorm();
    if (vv <= 1e-20 * size * size) {
      overlap = true;
      break;
    }
    const SV w = support_pair(A, B, -v);
    // Converged: the support does not get closer than the current point (relative gap).
    if (vv - v.dot(w.w) <= 1e-12 * vv) break;
    bool repeat = false;
    for (int i = 0; i < s.n; ++i)
      if ((s.v[i].w - w.w).squaredNorm() <= 1e-28 * size * size) repeat = true;
    if (repeat) break;
    const Simplex prev = s;
    s.v[s.n++] = w;
    if (solve(s)) {
      overlap = true;
      break;
    }
    const Vec3 nv = s.closest();
    if (nv.squaredNorm() >= vv) {  // no progress (rounding, or a degenerate simplex): keep the previous one
      s = prev;
      break;
    }
    v = nv;
  }
  // The distance and (in the callers) the normal come from the final simplex's witnesses.
  dist = overlap ? 0.0 : s.closest().norm();
  return s;
}

struct EpaFace {
  int i[3];
  Vec3 n;
  double dist;
  bool alive;
};

// Makes a face with outward normal (away from `inner`); false if degenerate.
bool make_face(const SV* V, int a, int b, int c, const Vec3& inner, EpaFace& f) {
  Vec3 n = (V[b].w - V[a].w).cross(V[c].w - V[a].w);
  const double L = n.norm();
  if (!(L > 1e-300)) return false;
  n /= L;
  if (n.dot(V[a].w - inner) < 0) n = -n, std::swap(b, c);
  f.i[0] = a, f.i[1] = b, f.i[2] = c;
  f.n = n;
  f.dist = n.dot(V[a].w);
  f.alive = true;
  return true;
}

// EPA from a simplex containing the origin (on its boundary or inside). False when degenerate.
bool run_epa(const Support& A, const Support& B, Simplex s, CoreDistance& out) {
  const double size = pair_size(A, B);
  // Complete the simplex to a tetrahedron (the origin may then lie on its boundary).
  {
    const Vec3 dirs[6] = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                          -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
    for (int guard = 0; s.n < 4 && guard < 4; ++guard) {
      Vec3 cand[6];
      int nc = 0;
      if (s.n == 1) {
        for (const Vec3& d : dirs) cand[nc++] = d;
      } else if (s.n == 2) {
        const Vec3 u = s.v[1].w - s.v[0].w;
        if (u.squaredNorm() < 1e-30) return false;
        const Vec3 p = any_perpendicular(u.normalized()), q = u.normalized().cross(p);
        cand[nc++] = p, cand[nc++] = -p, cand[nc++] = q, cand[nc++] = -q;
      } else {
        const Vec3 nrm = (s.v[1].w - s.v[0].w).cross(s.v[2].w - s.v[0].w);
        if (nrm.squaredNorm() < 1e-30) return false;
        cand[nc++] = nrm.normalized(), cand[nc++] = -nrm.normalized();
      }
      bool added = false;
      for (int k = 0; k < nc && !added; ++k) {
        const SV w = support_pair(A, B, cand[k]);
        // Accept when it raises the simplex's dimension.
        double gap;
        if (s.n == 1) {
          gap = (w.w - s.v[0].w).norm();
        } else if (s.n == 2) {
          const Vec3 u = (s.v[1].w - s.v[0].w).normalized();
          gap = u.cross(w.w - s.v[0].w).norm();
        } else {
          const Vec3 nrm = (s.v[1].w - s.v[0].w).cross(s.v[2].w - s.v[0].w).normalized();
          gap = std::fabs(nrm.dot(w.w - s.v[0].w));
        }
        if (gap > 1e-9 * size) s.v[s.n++] = w, added = true;
      }
      if (!added) return false;
    }
  }
  SV V[kEpaMaxV];
  EpaFace F[kEpaMaxF];
  int nv = 4, nf = 0;
  for (int i = 0; i < 4; ++i) V[i] = s.v[i];
  const Vec3 inner = 0.25 * (V[0].w + V[1].w + V[2].w + V[3].w);
  const int tet[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  for (const auto& t : tet)
    if (!make_face(V, t[0], t[1], t[2], inner, F[nf++])) return false;
  int best = 0;
  for (int it = 0; it < kEpaMaxIter; ++it) {
    best = -1;
    for (int f = 0; f < nf; ++f)
      if (F[f].alive && (best < 0 || F[f].dist < F[best].dist)) best = f;
    if (best < 0) return false;
    const SV w = support_pair(A, B, F[best].n);
    const double dnew = F[best].n.dot(w.w);
    if (dnew - F[best].dist <= 1e-9 * size || nv >= kEpaMaxV) break;
    // Remove the faces that see w; the horizon is their boundary edges.
    int edges[3 * kEpaMaxF][2];
    int ne = 0;
    for (int f = 0; f < nf; ++f) {
      if (!F[f].alive || F[f].n.dot(w.w - V[F[f].i[0]].w) <= 1e-12 * size) continue;
      F[f].alive = false;
      for (int k = 0; k < 3; ++k) {
        const int a = F[f].i[k], b = F[f].i[(k + 1) % 3];
        // A shared edge appears reversed in its neighbour: cancel the pair.
        bool cancelled = false;
        for (int e = 0; e < ne; ++e)
          if (edges[e][0] == b && edges[e][1] == a) {
            edges[e][0] = edges[ne - 1][0], edges[e][1] = edges[ne - 1][1];
            --ne;
            cancelled = true;
            break;
          }
        if (!cancelled) edges[ne][0] = a, edges[ne][1] = b, ++ne;
      }
    }
    V[nv] = w;
    const int iw = nv++;
    // Compact dead faces away to make room.
    int k = 0;
    for (int f = 0; f < nf; ++f)
      if (F[f].alive) F[k++] = F[f];
    nf = k;
    if (nf + ne > kEpaMaxF) break;
    bool bad = false;
    for (int e = 0; e < ne; ++e)
      if (!make_face(V, edges[e][0], edges[e][1], iw, inner, F[nf++])) bad = true;
    if (bad) return false;
  }
  best = -1;
  for (int f = 0; f < nf; ++f)
    if (F[f].alive && (best < 0 || F[f].dist < F[best].dist)) best = f;
  if (best < 0) return false;
  // Witnesses: barycentric coordinates of the origin's projection on the closest face.
  const EpaFace& f = F[best];
  const Vec3 &a = V[f.i[0]].w, &b = V[f.i[1]].w, &c = V[f.i[2]].w;
  const Vec3 p = f.dist * f.n;
  const double area = (b - a).cross(c - a).dot(f.n);
  double l1 = (c - b).cross(p - b).dot(f.n) / area, l2 = (a - c).cross(p - c).dot(f.n) / area;
  double l3 = 1 - l1 - l2;
  if (!(std::isfinite(l1) && std::isfinite(l2))) l1 = l2 = l3 = 1.0 / 3;
  out.pA = l1 * V[f.i[0]].a + l2 * V[f.i[1]].a + l3 * V[f.i[2]].a;
  out.pB = l1 * V[f.i[0]].b + l2 * V[f.i[1]].b + l3 * V[f.i[2]].b;
  out.normal = f.n;
  out.separation = -f.dist;
  out.ok = true;
  return true;
}

}  // namespace

CoreDistance gjk_distance(const Support& A, const Support& B, bool& overlap) {
  double dist;
  const Simplex s = run_gjk(A, B, overlap, dist);
  CoreDistance r;
  s.witnesses(r.pA, r.pB);
  (void)dist;
  r.separation = overlap ? 0.0 : (r.pB - r.pA).norm();
  if (r.separation > 0) r.normal = (r.pB - r.pA) / r.separation;
  return r;
}

CoreDistance core_distance(const Support& A, const Support& B) {
  bool overlap;
  double dist;
  const Simplex s = run_gjk(A, B, overlap, dist);
  CoreDistance r;
  if (!overlap) {
    s.witnesses(r.pA, r.pB);
    r.separation = (r.pB - r.pA).norm();
    r.normal = r.separation > 0 ? Vec3((r.pB - r.pA) / r.separation) : Vec3(Vec3::UnitZ());
    return r;
  }
  if (run_epa(A, B, s, r)) return r;
  // Fallback (degenerate EPA): the centre line as the axis, separation from the supports.
  Vec3 n = B.centre_W() - A.centre_W();
  n = n.squaredNorm() > 1e-30 ? Vec3(n.normalized()) : Vec3::UnitZ();
  r.pA = A.support_W(n);
  r.pB = B.support_W(-n);
  r.normal = n;
  r.separation = n.dot(r.pB - r.pA);
  r.ok = false;
  return r;
}

int convex_generic(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                   PairCache&, Manifold& out) {
  const Support A(a, xa), B(b, xb);
  const CoreDistance d = core_distance(A, B);
  out.normal_W = d.normal;
  const double s = d.separation - A.margin - B.margin;
  if (s > spec) return 0;
  push_point(out, d.pA + A.margin * d.normal, d.normal, s, 0);
  return out.count;
}

}  // namespace simreel::collide_detail
