// Polyhedron pairs: box-box, box-hull, hull-hull (SAT + face clipping) and capsule-box,
// capsule-hull (GJK or SAT, segment clipping). Design note and tolerances: collide.cpp.
//
// References: D. Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013 (face
// and Gauss-map-pruned edge queries, axis hysteresis); Sutherland and Hodgman, "Reentrant polygon
// clipping", CACM 17(1), 1974; E. Catto's Box2D/Box3D manifolds (reference/incident faces, the
// capsule-on-face clip).
#include "sim/collide/internal.hpp"

namespace simreel::collide_detail {

namespace {

constexpr int kMaxFaceVerts = 64;                         // incident face vertices clipped (decimated beyond)
constexpr int kMaxClip = 2 * kMaxFaceVerts + 16;          // polygon buffer while clipping
constexpr int kMaxLocal = 256;                            // hull vertices/faces transformed once per call
constexpr double kRelFaceTol = 0.98, kRelEdgeTol = 0.90;  // Gregorius's hysteresis factors
constexpr double kParallelEdgeTol = 0.005;                // |E1 x E2| < this |E1||E2|: parallel, skipped

// Feature tags (14-bit indices): vertex v, half-edge of the incident face, reference side plane.
constexpr uint32_t kTagEdge = 0x4000, kTagPlane = 0x8000;

// Q's frame to P's: x_P = R x_Q + p.
struct Rel {
  Mat3 R;
  Vec3 p;
};
Rel relative(const Pose& xp, const Pose& xq) {
  return {xp.R.transpose() * xq.R, xp.R.transpose() * (xq.p - xp.p)};
}

double abs_tol(const ConvexPolyhedron& P, const ConvexPolyhedron& Q) {
  return 1e-3 * (P.inner_radius + Q.inner_radius);
}

// Separation of Q from P's face f (Q in P's frame through T).
double face_separation(const ConvexPolyhedron& P, int f, const ConvexPolyhedron& Q, const Rel& T) {
  const Vec3& n = P.faces[f].normal;
  const Vec3 nQ = T.R.transpose() * n;
  const Vec3& v = Q.vertices[Q.support(-nQ)];
  return n.dot(T.p) - P.faces[f].offset + nQ.dot(v);
}

struct FaceQuery {
  int face = -1;
  double sep = -INFINITY;
};
// The face of P that separates Q most; `prefer` (or -1) wins ties within `tol`.
FaceQuery query_faces(const ConvexPolyhedron& P, const ConvexPolyhedron& Q, const Rel& T, int prefer,
                      double tol, double spec) {
  FaceQuery q;
  if (prefer >= 0 && prefer < (int)P.faces.size()) {
    q.face = prefer;
    q.sep = face_separation(P, prefer, Q, T);
    if (q.sep > spec) return q;
  }
  const double bonus = q.face >= 0 ? tol : 0;
  double best = q.sep + bonus;
  for (int f = 0; f < (int)P.faces.size(); ++f) {
    if (f == prefer) continue;
    const double s = face_separation(P, f, Q, T);
    if (s > best) {
      best = s, q.face = f, q.sep = s;
      if (s > spec) return q;
    }
  }
  return q;
}

bool is_minkowski_face(const Vec3& a, const Vec3& b, const Vec3& bxa, const Vec3& c, const Vec3& d,
                       const Vec3& dxc) {
  const double cba = c.dot(bxa), dba = d.dot(bxa), adc = a.dot(dxc), bdc = b.dot(dxc);
  return cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0;
}

// Separation along E1 x E2 oriented away from P's centroid c1, or -inf when parallel.
double edge_projection(const Vec3& p1, const Vec3& e1, const Vec3& p2, const Vec3& e2, const Vec3& c1,
                       Vec3* axis) {
  const Vec3 x = e1.cross(e2);
  const double L = x.norm();
  if (L < kParallelEdgeTol * std::sqrt(e1.squaredNorm() * e2.squaredNorm())) return -INFINITY;
  Vec3 n = x / L;
  if (n.dot(p1 - c1) < 0) n = -n;
  if (axis) *axis = n;
  return n.dot(p2 - p1);
}

// Q's vertices and face normals in P's frame, transformed once (or on the fly when too many).
struct QInP {
  const ConvexPolyhedron* Q;
  const Rel* T;
  Vec3 v[kMaxLocal], n[kMaxLocal];
  bool cached_v, cached_n;
  QInP(const ConvexPolyhedron& q, const Rel& t) : Q(&q), T(&t) {
    cached_v = (int)q.vertices.size() <= kMaxLocal;
    cached_n = (int)q.faces.size() <= kMaxLocal;
    if (cached_v)
      for (int i = 0; i < (int)q.vertices.size(); ++i) v[i] = t.R * q.vertices[i] + t.p;
    if (cached_n)
      for (int i = 0; i < (int)q.faces.size(); ++i) n[i] = t.R * q.faces[i].normal;
  }
  Vec3 vert(int i) const { return cached_v ? v[i] : Vec3(T->R * Q->vertices[i] + T->p); }
  Vec3 normal(int f) const { return cached_n ? n[f] : Vec3(T->R * Q->faces[f].normal); }
};

struct EdgeQuery {
  int ea = -1, eb = -1;  // edge indices (half-edges 2k)
  double sep = -INFINITY;
  Vec3 axis = Vec3::Zero();
};

EdgeQuery query_edges(const ConvexPolyhedron& P, const QInP& Q, double spec) {
  EdgeQuery q;
  const int EP = P.edge_count(), EQ = Q.Q->edge_count();
  for (int i = 0; i < EP; ++i) {
    const auto& h1 = P.edges[2 * i];
    const auto& t1 = P.edges[2 * i + 1];
    const Vec3& p1 = P.vertices[h1.origin];
    const Vec3 e1 = P.vertices[t1.origin] - p1;
    const Vec3& u1 = P.faces[h1.face].normal;
    const Vec3& v1 = P.faces[t1.face].normal;
    for (int j = 0; j < EQ; ++j) {
      const auto& h2 = Q.Q->edges[2 * j];
      const auto& t2 = Q.Q->edges[2 * j + 1];
      const Vec3 u2 = Q.normal(h2.face), v2 = Q.normal(t2.face);
      const Vec3 p2 = Q.vert(h2.origin);
      const Vec3 e2 = Q.vert(t2.origin) - p2;
      if (!is_minkowski_face(u1, v1, -e1, -u2, -v2, -e2)) continue;
      Vec3 axis;
      const double s = edge_projection(p1, e1, p2, e2, P.centroid, &axis);
      if (s > q.sep) {
        q.sep = s, q.ea = i, q.eb = j, q.axis = axis;
        if (s > spec) return q;
      }
    }
  }
  return q;
}

struct ClipVertex {
  Vec3 x;
  uint32_t id;
  uint32_t out_tag;  // feature tag of the polygon edge from this vertex to the next
};

// Sutherland-Hodgman against the plane s . x <= off; new points take (edge tag, plane tag) ids.
int clip_polygon(const ClipVertex* in, int n, const Vec3& s, double off, uint32_t plane_tag,
                 ClipVertex* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % n];
    const double da = s.dot(a.x) - off, db = s.dot(b.x) - off;
    const bool ina = da <= 0, inb = db <= 0;
    if (ina) out[m++] = a;
    if (ina != inb && m < kMaxClip) {
      const double t = da / (da - db);
      ClipVertex c;
      c.x = a.x + t * (b.x - a.x);
      c.id = (a.out_tag & 0xFFFF) | (plane_tag << 16);
      c.out_tag = ina ? plane_tag : a.out_tag;
      if (ina) out[m - 1].out_tag = a.out_tag;
      out[m++] = c;
    }
    if (m >= kMaxClip) break;
  }
  return m;
}

// Face contact: reference face f of R (normal from R towards I), incident body I given in R's
// frame by T. Writes world-frame candidates through R's pose; returns the count.
int face_contact(const ConvexPolyhedron& R, int f, const ConvexPolyhedron& I, const Rel& T, const Pose& xr,
                 double spec, Candidate* cand) {
  const auto& F = R.faces[f];
  const Vec3& n = F.normal;
  // Incident face: the most anti-parallel.
  const Vec3 nI = T.R.transpose() * n;
  int inc = 0;
  double dmin = INFINITY;
  for (int g = 0; g < (int)I.faces.size(); ++g) {
    const double d = I.faces[g].normal.dot(nI);
    if (d < dmin) dmin = d, inc = g;
  }
  // Its polygon in R's frame (at most kMaxFaceVerts: every k-th vertex beyond that).
  int nloop = 0;
  {
    int e = I.faces[inc].edge;
    do ++nloop, e = I.edges[e].next;
    while (e != I.faces[inc].edge && nloop <= 100000);
  }
  const int stride = (nloop + kMaxFaceVerts - 1) / kMaxFaceVerts;
  ClipVertex buf[2][kMaxClip];
  int n0 = 0;
  {
    int e = I.faces[inc].edge, k = 0;
    do {
      if (k % stride == 0) {
        const int v = I.edges[e].origin;
        buf[0][n0++] = {Vec3(T.R * I.vertices[v] + T.p), (uint32_t)v, kTagEdge | (uint32_t)e};
      }
      ++k;
      e = I.edges[e].next;
    } while (e != I.faces[inc].edge);
  }
  // Clip against the reference face's side planes.
  int cur = 0, np = n0;
  int e = F.edge;
  do {
    const Vec3& P = R.vertices[R.edges[e].origin];
    const Vec3& Q = R.vertices[R.edges[R.edges[e].next].origin];
    const Vec3 s = (Q - P).cross(n);
    np = clip_polygon(buf[cur], np, s, s.dot(P), kTagPlane | (uint32_t)e, buf[cur ^ 1]);
    cur ^= 1;
    e = R.edges[e].next;
  } while (e != F.edge && np > 0);
  int nc = 0;
  const Vec3 n_W = xr.R * n;
  for (int i = 0; i < np && nc < kMaxClip; ++i) {
    const double s = n.dot(buf[cur][i].x) - F.offset;
    if (s > spec) continue;
    cand[nc++] = {xr.apply(buf[cur][i].x - 0.5 * s * n), s, buf[cur][i].id};
  }
  (void)n_W;
  return nc;
}

}  // namespace

int hull_hull(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
              PairCache& cache, Manifold& out) {
  const ConvexPolyhedron& A = *a.hull;
  const ConvexPolyhedron& B = *b.hull;
  const Rel TBA = relative(xa, xb), TAB = relative(xb, xa);
  const double tol = abs_tol(A, B);
  // 1. The cached axis first: still separating beyond the speculative distance -> done.
  if (cache.type == kCacheFaceA && cache.a >= 0 && cache.a < (int)A.faces.size()) {
    const double s = face_separation(A, cache.a, B, TBA);
    if (s > spec) {
      out.normal_W = xa.R * A.faces[cache.a].normal;
      return 0;
    }
  } else if (cache.type == kCacheFaceB && cache.b >= 0 && cache.b < (int)B.faces.size()) {
    const double s = face_separation(B, cache.b, A, TAB);
    if (s > spec) {
      out.normal_W = -(xb.R * B.faces[cache.b].normal);
      return 0;
    }
  } else if (cache.type == kCacheEdges && cache.a >= 0 && cache.a < A.edge_count() && cache.b >= 0 &&
             cache.b < B.edge_count()) {
    const Vec3& p1 = A.vertices[A.edges[2 * cache.a].origin];
    const Vec3 e1 = A.vertices[A.edges[2 * cache.a + 1].origin] - p1;
    const Vec3 p2 = TBA.R * B.vertices[B.edges[2 * cache.b].origin] + TBA.p;
    const Vec3 e2 =
        TBA.R * (B.vertices[B.edges[2 * cache.b + 1].origin] - B.vertices[B.edges[2 * cache.b].origin]);
    Vec3 axis;
    const double s = edge_projection(p1, e1, p2, e2, A.centroid, &axis);
    if (s > spec) {
      out.normal_W = xa.R * axis;
      return 0;
    }
  }
  // 2. Full SAT, the cached face preferred within the tolerance.
  const FaceQuery fa = query_faces(A, B, TBA, cache.type == kCacheFaceA ? cache.a : -1, tol, spec);
  if (fa.sep > spec) {
    cache = {kCacheFaceA, fa.face, -1, Vec3::Zero()};
    out.normal_W = xa.R * A.faces[fa.face].normal;
    return 0;
  }
  const FaceQuery fb = query_faces(B, A, TAB, cache.type == kCacheFaceB ? cache.b : -1, tol, spec);
  if (fb.sep > spec) {
    cache = {kCacheFaceB, -1, fb.face, Vec3::Zero()};
    out.normal_W = -(xb.R * B.faces[fb.face].normal);
    return 0;
  }
  const QInP BinA(B, TBA);
  const EdgeQuery eq = query_edges(A, BinA, spec);
  if (eq.sep > spec) {
    cache = {kCacheEdges, eq.ea, eq.eb, Vec3::Zero()};
    out.normal_W = xa.R * eq.axis;
    return 0;
  }
  // 3. Choose the axis: A's face, unless B's face or the edge pair is clearly better.
  const double face_best = std::max(fa.sep, fb.sep);
  const bool edge = eq.ea >= 0 && eq.sep > kRelEdgeTol * face_best + tol;
  if (edge) {
    cache = {kCacheEdges, eq.ea, eq.eb, Vec3::Zero()};
    const Vec3& p1 = A.vertices[A.edges[2 * eq.ea].origin];
    const Vec3& q1 = A.vertices[A.edges[2 * eq.ea + 1].origin];
    const Vec3 p2 = BinA.vert(B.edges[2 * eq.eb].origin), q2 = BinA.vert(B.edges[2 * eq.eb + 1].origin);
    double s, t;
    Vec3 c1, c2;
    closest_segments(p1, q1, p2, q2, s, t, c1, c2);
    const double sep = eq.axis.dot(c2 - c1);
    out.normal_W = xa.R * eq.axis;
    if (sep <= spec) {
      out.points[0] = {xa.apply(0.5 * (c1 + c2)), sep,
                       (kTagEdge | (uint32_t)eq.ea) | ((kTagEdge | (uint32_t)eq.eb) << 16)};
      out.count = 1;
    }
    return out.count;
  }
  Candidate cand[kMaxClip];
  int nc;
  const bool refA = !(fb.sep > kRelFaceTol * fa.sep + tol);
  if (refA) {
    cache = {kCacheFaceA, fa.face, -1, Vec3::Zero()};
    out.normal_W = xa.R * A.faces[fa.face].normal;
    nc = face_contact(A, fa.face, B, TBA, xa, spec, cand);
  } else {
    cache = {kCacheFaceB, -1, fb.face, Vec3::Zero()};
    out.normal_W = -(xb.R * B.faces[fb.face].normal);
    nc = face_contact(B, fb.face, A, TAB, xb, spec, cand);
  }
  reduce_to_manifold(cand, nc, out.normal_W, out);
  return out.count;
}

// ---------------------------------------------------------------- capsule against box or hull

namespace {
// Clips the segment [x0, x1] (hull frame) against the side planes of face f; false if nothing is left.
bool clip_segment_to_face(const ConvexPolyhedron& H, int f, Vec3& x0, Vec3& x1, uint32_t& id0,
                          uint32_t& id1) {
  const Vec3& n = H.faces[f].normal;
  int e = H.faces[f].edge;
  do {
    const Vec3& P = H.vertices[H.edges[e].origin];
    const Vec3& Q = H.vertices[H.edges[H.edges[e].next].origin];
    const Vec3 s = (Q - P).cross(n);
    const double off = s.dot(P);
    const double d0 = s.dot(x0) - off, d1 = s.dot(x1) - off;
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) {
      x0 = x0 + (d0 / (d0 - d1)) * (x1 - x0);
      id0 = kTagPlane | (uint32_t)e;
    } else if (d1 > 0) {
      x1 = x0 + (d0 / (d0 - d1)) * (x1 - x0);
      id1 = kTagPlane | (uint32_t)e;
    }
    e = H.edges[e].next;
  } while (e != H.faces[f].edge);
  return true;
}

// Capsule segment (hull frame) lying on face f: up to two points. Normal A->B is -n_f.
int capsule_face_points(const ConvexPolyhedron& H, int f, const Vec3& p0, const Vec3& p1, double r,
                        const Pose& xb, double spec, Manifold& out) {
  Vec3 x0 = p0, x1 = p1;
  uint32_t id0 = 0, id1 = 1;
  if (!clip_segment_to_face(H, f, x0, x1, id0, id1)) return -1;
  const Vec3& n = H.faces[f].normal;
  out.normal_W = -(xb.R * n);
  const Vec3 xs[2] = {x0, x1};
  const uint32_t ids[2] = {id0, id1};
  const int npts = (x1 - x0).squaredNorm() > 1e-24 ? 2 : 1;
  for (int i = 0; i < npts; ++i) {
    const double s = n.dot(xs[i]) - H.faces[f].offset - r;
    if (s > spec) continue;
    // Midpoint between the capsule surface (x - r n) and the face: x - (r + s/2) n.
    out.points[out.count++] = {xb.apply(xs[i] - (r + 0.5 * s) * n), s, ids[i] | ((uint32_t)f << 16)};
  }
  return out.count;
}
}  // namespace

int capsule_hull(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                 PairCache&, Manifold& out) {
  const ConvexPolyhedron& H = *b.hull;
  const double r = a.radius;
  // The segment in the hull frame.
  const Vec3 u_W = xa.R.col(2) * a.half_length;
  const Vec3 p0 = xb.apply_inverse(xa.p - u_W), p1 = xb.apply_inverse(xa.p + u_W);
  // Face query (also an early out).
  int fbest = 0;
  double fsep = -INFINITY;
  for (int f = 0; f < (int)H.faces.size(); ++f) {
    const auto& F = H.faces[f];
    const double s = std::min(F.normal.dot(p0), F.normal.dot(p1)) - F.offset;
    if (s > fsep) fsep = s, fbest = f;
  }
  if (fsep - r > spec) {
    out.normal_W = -(xb.R * H.faces[fbest].normal);
    return 0;
  }
  const double size = std::max(a.bounding_radius + b.bounding_radius, 1e-300);
  const Support SA(a, xa), SB(b, xb);
  bool overlap;
  const CoreDistance g = gjk_distance(SA, SB, overlap);
  if (!overlap && g.separation > 1e-9 * size) {
    // Apart: GJK's normal; when it is a face's normal (within ~2.6 deg), clip on that face.
    const double s = g.separation - r;
    if (s > spec) {
      out.normal_W = g.normal;
      return 0;
    }
    const Vec3 n_B = xb.R.transpose() * g.normal;
    int f = 0;
    double dmin = INFINITY;
    for (int k = 0; k < (int)H.faces.size(); ++k) {
      const double d = H.faces[k].normal.dot(n_B);
      if (d < dmin) dmin = d, f = k;
    }
    if (dmin < -0.999 && capsule_face_points(H, f, p0, p1, r, xb, spec, out) > 0) return out.count;
    out.count = 0;
    out.normal_W = g.normal;
    push_point(out, g.pA + r * g.normal, g.normal, s, 2);
    return out.count;
  }
  // The segment touches the hull: SAT over the faces and the segment x edge axes.
  const Vec3 d = p1 - p0;
  const double dL = d.norm();
  int ebest = -1;
  double esep = -INFINITY;
  Vec3 eaxis = Vec3::Zero();
  if (dL > 0) {
    for (int k = 0; k < H.edge_count(); ++k) {
      const Vec3& P = H.vertices[H.edges[2 * k].origin];
      const Vec3 E = H.vertices[H.edges[2 * k + 1].origin] - P;
      Vec3 x = d.cross(E);
      const double L = x.norm();
      if (L < kParallelEdgeTol * dL * E.norm()) continue;
      x /= L;
      if (x.dot(P - H.centroid) < 0) x = -x;
      const double hmax = x.dot(H.vertices[H.support(x)]);
      const double s = std::min(x.dot(p0), x.dot(p1)) - hmax;
      if (s > esep) esep = s, ebest = k, eaxis = x;
    }
  }
  const double tol = 1e-3 * H.inner_radius;
  if (ebest >= 0 && esep > kRelEdgeTol * fsep + tol) {
    const Vec3& P = H.vertices[H.edges[2 * ebest].origin];
    const Vec3& Q = H.vertices[H.edges[2 * ebest + 1].origin];
    double s, t;
    Vec3 c1, c2;
    closest_segments(p0, p1, P, Q, s, t, c1, c2);
    // Axis from the hull out to the capsule; A -> B is its negation.
    const double sep = eaxis.dot(c1 - c2) - r;
    out.normal_W = -(xb.R * eaxis);
    if (sep > spec) return 0;
    out.points[0] = {xb.apply(c1 - (r + 0.5 * sep) * eaxis), sep, 3 | ((kTagEdge | (uint32_t)ebest) << 16)};
    out.count = 1;
    return 1;
  }
  if (capsule_face_points(H, fbest, p0, p1, r, xb, spec, out) > 0) return out.count;
  // Clipped away (the segment is off the face's prism): the deepest end on that face's plane.
  out.count = 0;
  const Vec3& n = H.faces[fbest].normal;
  const Vec3 x = n.dot(p0) <= n.dot(p1) ? p0 : p1;
  const double s = n.dot(x) - H.faces[fbest].offset - r;
  out.normal_W = -(xb.R * n);
  if (s <= spec) out.points[out.count++] = {xb.apply(x - (r + 0.5 * s) * n), s, 4 | ((uint32_t)fbest << 16)};
  return out.count;
}

}  // namespace simreel::collide_detail
