// Plane pairs, and the sphere and capsule pairs with closed forms (design note: collide.cpp).
#include "sim/collision/narrow/internal.hpp"

namespace simreel::collide_detail {

namespace {
// The plane of frame A (z = 0, solid below) in the world: unit normal n and offset d = n . x.
struct WorldPlane {
  Vec3 n;
  double d;
};
WorldPlane plane_of(const Pose& x) {
  const Vec3 n = x.R.col(2);
  return {n, n.dot(x.p)};
}
// A point q on B's surface at signed height s above the plane: A's surface point is q - s n.
void push_plane_point(Manifold& m, const WorldPlane& pl, const Vec3& q, double s, uint32_t id) {
  push_point(m, q - s * pl.n, pl.n, s, id);
}
}  // namespace

int plane_sphere(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                 PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  const Vec3 q = xb.p - b.radius * pl.n;
  const double s = pl.n.dot(q) - pl.d;
  if (s <= spec) push_plane_point(out, pl, q, s, 0);
  return out.count;
}

int plane_capsule(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                  PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  const Vec3 axis = xb.R.col(2) * b.half_length;
  for (int i = 0; i < 2; ++i) {
    const Vec3 q = xb.p + (i ? axis : Vec3(-axis)) - b.radius * pl.n;
    const double s = pl.n.dot(q) - pl.d;
    if (s <= spec) push_plane_point(out, pl, q, s, (uint32_t)i);
  }
  return out.count;
}

void cylinder_rim_points(const CollideShape& cyl, const Pose& xc, const Vec3& n, Vec3 q[5]) {
  // In the cylinder frame: the plane's normal m; the deepest rim point of a disk is at -r u/|u|,
  // u = m's component in the disk plane. Nearly standing (|u| tiny): the rim direction -x_C.
  const Vec3 m = xc.R.transpose() * n;
  Vec3 u(m.x(), m.y(), 0);
  const double un = u.norm();
  u = un > 1e-12 ? Vec3(u / un) : Vec3(Vec3::UnitX());
  const Vec3 v = Vec3::UnitZ().cross(u);  // u, v, z right-handed in the disk plane
  const double h = cyl.half_length, r = cyl.radius;
  // The lower disk is the one on the -m side: z = -h sign(m_z) (m_z = 0: both tie, take -h).
  const double zl = m.z() >= 0 ? -h : h;
  const Vec3 local[5] = {Vec3(-r * u.x(), -r * u.y(), zl), Vec3(-r * u.x(), -r * u.y(), -zl),
                         Vec3(-r * v.x(), -r * v.y(), zl), Vec3(r * v.x(), r * v.y(), zl),
                         Vec3(r * u.x(), r * u.y(), zl)};
  for (int i = 0; i < 5; ++i) q[i] = xc.apply(local[i]);
}

int plane_cylinder(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                   PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  Vec3 q[5];
  cylinder_rim_points(b, xb, pl.n, q);
  Candidate c[5];
  int n = 0;
  for (int i = 0; i < 5; ++i) {
    const double s = pl.n.dot(q[i]) - pl.d;
    if (s <= spec && cylinder_rim_point_used(i, xb.R.col(2), pl.n))
      c[n++] = {Vec3(q[i] - 0.5 * s * pl.n), s, (uint32_t)i};
  }
  reduce_to_manifold(c, n, pl.n, out);
  return out.count;
}

int plane_ellipsoid(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                    PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  // The point of the ellipsoid furthest along -n: p_C = -diag(r^2) m / |diag(r) m|, m = R^T n.
  const Vec3 m = xb.R.transpose() * pl.n;
  const Vec3 rm = b.radii.cwiseProduct(m);
  const Vec3 p_C = -b.radii.cwiseProduct(rm) / rm.norm();
  const Vec3 q = xb.apply(p_C);
  const double s = pl.n.dot(q) - pl.d;
  if (s <= spec) push_plane_point(out, pl, q, s, 0);
  return out.count;
}

int plane_box(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
              PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  // Height of the centre and of each half-extent axis along n; vertex i has the signs of its bits
  // (make_box_polyhedron's numbering), so ids are the box's vertex indices.
  const double hc = pl.n.dot(xb.p) - pl.d;
  const Vec3 ax = xb.R.col(0) * b.half_extents.x(), ay = xb.R.col(1) * b.half_extents.y(),
             az = xb.R.col(2) * b.half_extents.z();
  const double sx = pl.n.dot(ax), sy = pl.n.dot(ay), sz = pl.n.dot(az);
  // Quick reject: the lowest vertex.
  if (hc - std::fabs(sx) - std::fabs(sy) - std::fabs(sz) > spec) return 0;
  Candidate c[8];
  int n = 0;
  for (int i = 0; i < 8; ++i) {
    const double fx = (i & 1) ? 1 : -1, fy = (i & 2) ? 1 : -1, fz = (i & 4) ? 1 : -1;
    const double s = hc + fx * sx + fy * sy + fz * sz;
    if (s > spec) continue;
    const Vec3 q = xb.p + fx * ax + fy * ay + fz * az;
    c[n++] = {Vec3(q - 0.5 * s * pl.n), s, (uint32_t)i};
  }
  reduce_to_manifold(c, n, pl.n, out);
  return out.count;
}

int plane_hull(const CollideShape&, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
               PairCache&, Manifold& out) {
  const WorldPlane pl = plane_of(xa);
  out.normal_W = pl.n;
  const ConvexPolyhedron& H = *b.hull;
  const Vec3 m = xb.R.transpose() * pl.n;
  const double hc = pl.n.dot(xb.p) - pl.d;
  // Quick reject with the deepest vertex.
  const int lo = H.support(-m);
  if (hc + m.dot(H.vertices[lo]) > spec) return 0;
  // Candidates: the vertices below the speculative plane, kept in a fixed buffer; the reduction
  // then picks four.
  constexpr int kCap = 64;
  Candidate c[kCap];
  int n = 0, below = 0;
  for (int i = 0; i < (int)H.vertices.size(); ++i) {
    const double s = hc + m.dot(H.vertices[i]);
    if (s > spec) continue;
    ++below;
    if (n == kCap) continue;
    const Vec3 q = xb.apply(H.vertices[i]);
    c[n++] = {Vec3(q - 0.5 * s * pl.n), s, (uint32_t)i};
  }
  if (below > kCap) {
    // More than the buffer holds (a detailed hull's face on the plane): the vertices below the
    // speculative plane that reach farthest along four directions in the plane, fixed in the
    // hull's frame, so the four span the whole face and stay the same vertices from step to step
    // (the solver's friction anchors are kept by point id). Keeping the deepest 64 kept one side
    // of a 750-vertex cap, and choosing by depth changed the points with every wobble: the
    // body rocked 1.5 mm deep, then crept.
    const Vec3 u = any_perpendicular(m), w = m.cross(u);
    const Vec3 dirs[4] = {u, -u, w, -w};
    int pick[4] = {-1, -1, -1, -1};
    double best[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < (int)H.vertices.size(); ++i) {
      if (hc + m.dot(H.vertices[i]) > spec) continue;
      for (int k = 0; k < 4; ++k) {
        const double r = dirs[k].dot(H.vertices[i]);
        if (r > best[k]) best[k] = r, pick[k] = i;
      }
    }
    n = 0;
    for (int k = 0; k < 4; ++k) {
      if (pick[k] < 0 || std::find(pick, pick + k, pick[k]) != pick + k) continue;
      const double s = hc + m.dot(H.vertices[pick[k]]);
      c[n++] = {Vec3(xb.apply(H.vertices[pick[k]]) - 0.5 * s * pl.n), s, (uint32_t)pick[k]};
    }
  }
  reduce_to_manifold(c, n, pl.n, out);
  return out.count;
}

// ---------------------------------------------------------------- spheres and capsules

namespace {
// Two spheres (centres ca, cb, radii ra, rb) as one contact point; n_fallback when concentric.
void sphere_pair_point(const Vec3& ca, double ra, const Vec3& cb, double rb, const Vec3& n_fallback,
                       double spec, uint32_t id, Manifold& out) {
  const Vec3 d = cb - ca;
  const double dist = d.norm();
  const Vec3 n = dist > 1e-12 * (ra + rb) ? Vec3(d / dist) : n_fallback;
  out.normal_W = n;
  const double s = dist - ra - rb;
  if (s <= spec) push_point(out, ca + ra * n, n, s, id);
}
}  // namespace

int sphere_sphere(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                  PairCache&, Manifold& out) {
  sphere_pair_point(xa.p, a.radius, xb.p, b.radius, Vec3::UnitZ(), spec, 0, out);
  return out.count;
}

int sphere_capsule(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                   PairCache&, Manifold& out) {
  const Vec3 axis = xb.R.col(2) * b.half_length;
  double t;
  const Vec3 q = closest_on_segment(xa.p, xb.p - axis, xb.p + axis, t);
  sphere_pair_point(xa.p, a.radius, q, b.radius, any_perpendicular(xb.R.col(2)), spec, 0, out);
  return out.count;
}

int capsule_capsule(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                    PairCache&, Manifold& out) {
  const Vec3 ua = xa.R.col(2), ub = xb.R.col(2);
  const Vec3 pa = xa.p - a.half_length * ua, qa = xa.p + a.half_length * ua;
  const Vec3 pb = xb.p - b.half_length * ub, qb = xb.p + b.half_length * ub;
  double s, t;
  Vec3 ca, cb;
  closest_segments(pa, qa, pb, qb, s, t, ca, cb);
  const double ra = a.radius, rb = b.radius;
  Vec3 d = cb - ca;
  double dist = d.norm();
  Vec3 n;
  if (dist > 1e-12 * (ra + rb)) {
    n = d / dist;
  } else {
    // Core segments cross: the common perpendicular, towards B's centre.
    const Vec3 c = ua.cross(ub);
    n = c.squaredNorm() > 1e-20 ? Vec3(c.normalized()) : any_perpendicular(ua);
    if (n.dot(xb.p - xa.p) < 0) n = -n;
    dist = 0;
  }
  out.normal_W = n;
  if (dist - ra - rb > spec) return 0;
  // Parallel within 1e-3 rad and overlapping along the axis: two points at the ends of the
  // overlap, so a capsule lying on another does not rock.
  const double sin2 = ua.cross(ub).squaredNorm();
  if (sin2 < 1e-6 && a.half_length > 0 && b.half_length > 0) {
    const double L = 2 * a.half_length;
    double t0 = (pb - pa).dot(ua) / L, t1 = (qb - pa).dot(ua) / L;
    if (t0 > t1) std::swap(t0, t1);
    t0 = std::max(t0, 0.0), t1 = std::min(t1, 1.0);
    if (t1 - t0 > 1e-9) {
      const double ts[2] = {t0, t1};
      for (int i = 0; i < 2; ++i) {
        const Vec3 xa_i = pa + ts[i] * (qa - pa);
        double tb;
        const Vec3 xb_i = closest_on_segment(xa_i, pb, qb, tb);
        const double si = (xb_i - xa_i).dot(n) - ra - rb;
        if (si <= spec) push_point(out, xa_i + ra * n, n, si, (uint32_t)i);
      }
      if (out.count > 0) return out.count;
    }
  }
  push_point(out, ca + ra * n, n, dist - ra - rb, 2);
  return out.count;
}

int sphere_box(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
               PairCache&, Manifold& out) {
  const Vec3 c = xb.apply_inverse(xa.p);
  const Vec3& h = b.half_extents;
  const Vec3 q = c.cwiseMax(-h).cwiseMin(h);
  Vec3 n_B;  // from the sphere's centre towards B's surface point, box frame
  double s;
  Vec3 surf_B;
  if (q != c) {
    const Vec3 d = q - c;
    const double dist = d.norm();
    n_B = d / dist;
    s = dist - a.radius;
    surf_B = q;
  } else {
    // Centre inside: the nearest face (lowest axis index on ties).
    int k = 0;
    double best = INFINITY;
    for (int i = 0; i < 3; ++i) {
      const double gap = h[i] - std::fabs(c[i]);
      if (gap < best) best = gap, k = i;
    }
    const double sign = c[k] >= 0 ? 1.0 : -1.0;
    n_B = Vec3::Zero();
    n_B[k] = -sign;  // sphere -> box is into the box: against the face's outward normal
    surf_B = c;
    surf_B[k] = sign * h[k];
    s = -best - a.radius;
  }
  const Vec3 n = xb.R * n_B;
  out.normal_W = n;
  if (s > spec) return 0;
  const Vec3 pB = xb.apply(surf_B);
  push_point(out, pB - s * n, n, s, 0);
  return out.count;
}

namespace {
// Closest point of a convex face (hull frame) to p, p outside the face's plane or not.
Vec3 closest_on_face(const ConvexPolyhedron& H, int f, const Vec3& p) {
  const auto& F = H.faces[f];
  const Vec3 proj = p - (F.normal.dot(p) - F.offset) * F.normal;
  bool inside = true;
  int e = F.edge;
  do {
    const Vec3& P = H.vertices[H.edges[e].origin];
    const Vec3& Q = H.vertices[H.edges[H.edges[e].next].origin];
    if ((Q - P).cross(F.normal).dot(proj - P) > 0) {
      inside = false;
      break;
    }
    e = H.edges[e].next;
  } while (e != F.edge);
  if (inside) return proj;
  Vec3 best = proj;
  double bd = INFINITY;
  e = F.edge;
  do {
    const Vec3& P = H.vertices[H.edges[e].origin];
    const Vec3& Q = H.vertices[H.edges[H.edges[e].next].origin];
    double t;
    const Vec3 x = closest_on_segment(p, P, Q, t);
    const double d2 = (x - p).squaredNorm();
    if (d2 < bd) bd = d2, best = x;
    e = H.edges[e].next;
  } while (e != F.edge);
  return best;
}
}  // namespace

int sphere_hull(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                PairCache&, Manifold& out) {
  const ConvexPolyhedron& H = *b.hull;
  const Vec3 c = xb.apply_inverse(xa.p);
  int fmax = 0;
  double dmax = -INFINITY;
  for (int f = 0; f < (int)H.faces.size(); ++f) {
    const double d = H.faces[f].normal.dot(c) - H.faces[f].offset;
    if (d > dmax) dmax = d, fmax = f;
  }
  if (dmax - a.radius > spec) {  // a separating face plane: beyond reach
    out.normal_W = -(xb.R * H.faces[fmax].normal);
    return 0;
  }
  Vec3 n_B, surf_B;
  double s;
  if (dmax <= 0) {
    // Centre inside: out through the face of least depth.
    n_B = -H.faces[fmax].normal;
    surf_B = c - dmax * H.faces[fmax].normal;
    s = dmax - a.radius;
  } else {
    // Outside: the closest point lies on a face whose plane the centre is above.
    double bd = INFINITY;
    for (int f = 0; f < (int)H.faces.size(); ++f) {
      if (H.faces[f].normal.dot(c) - H.faces[f].offset <= 0) continue;
      const Vec3 x = closest_on_face(H, f, c);
      const double d2 = (x - c).squaredNorm();
      if (d2 < bd) bd = d2, surf_B = x;
    }
    const double dist = std::sqrt(bd);
    n_B = dist > 0 ? Vec3((surf_B - c) / dist) : Vec3(-H.faces[fmax].normal);
    s = dist - a.radius;
  }
  const Vec3 n = xb.R * n_B;
  out.normal_W = n;
  if (s > spec) return 0;
  push_point(out, xb.apply(surf_B) - s * n, n, s, 0);
  return out.count;
}

}  // namespace simreel::collide_detail
