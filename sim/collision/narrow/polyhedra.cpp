// Polyhedron pairs: box-box, box-hull, hull-hull (SAT + face clipping) and capsule-box,
// capsule-hull (GJK or SAT, segment clipping). Design note and tolerances: collide.cpp.
//
// References: D. Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013 (face
// and Gauss-map-pruned edge queries, axis hysteresis); Sutherland and Hodgman, "Reentrant polygon
// clipping", CACM 17(1), 1974; E. Catto's Box2D/Box3D manifolds (reference/incident faces, the
// capsule-on-face clip).
#include "sim/collision/narrow/internal.hpp"

namespace simreel::collide_detail {

namespace {

constexpr int kMaxFaceVerts = 64;                         // incident face vertices clipped (decimated beyond)
constexpr int kMaxClip = 2 * kMaxFaceVerts + 16;          // polygon buffer while clipping
constexpr int kMaxLocal = 128;                            // hull vertices/faces transformed once per call
constexpr double kRelFaceTol = 0.98, kRelEdgeTol = 0.90;  // Gregorius's hysteresis factors
// Whether separation x beats ref clearly: by a share (1 - rel) of |ref| plus tol. Gregorius's
// x > rel ref + tol, written for overlaps (ref < 0, where rel ref is the larger), inverts for a
// speculative pair (ref > 0: rel ref is the smaller), and let an edge pair win over a face 10%
// closer: two stacked cubes 12 mm apart got a one-point edge manifold, the falling cube was
// stopped at one point only and sank 11 mm into the one below (the R3 pile's landing).
inline double clear_margin(double ref, double rel, double tol) {
  return ref + (1 - rel) * std::fabs(ref) + tol;
}
constexpr double kParallelEdgeTol = 0.005;  // |E1 x E2| < this |E1||E2|: parallel, skipped

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

// Q's vertices, face normals and edges in P's frame, transformed once per call (or on the fly
// when Q has more than kMaxLocal of them).
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
  // min over Q's vertices of n . x (n in P's frame).
  double min_along(const Vec3& dir) const {
    if (!cached_v) {
      const Vec3 dQ = T->R.transpose() * dir;
      return dir.dot(T->p) + dQ.dot(Q->vertices[Q->support(-dQ)]);
    }
    double m = INFINITY;
    for (int i = 0; i < (int)Q->vertices.size(); ++i) m = std::min(m, dir.dot(v[i]));
    return m;
  }
};

struct FaceQuery {
  int face = -1;
  double sep = -INFINITY;
};
// The face of P that separates Q most; `prefer` (or -1) wins ties within `tol`.
FaceQuery query_faces(const ConvexPolyhedron& P, const QInP& Q, int prefer, double tol, double spec) {
  FaceQuery q;
  if (prefer >= 0 && prefer < (int)P.faces.size()) {
    q.face = prefer;
    q.sep = Q.min_along(P.faces[prefer].normal) - P.faces[prefer].offset;
    if (q.sep > spec) return q;
  }
  const double bonus = q.face >= 0 ? tol : 0;
  double best = q.sep + bonus;
  for (int f = 0; f < (int)P.faces.size(); ++f) {
    if (f == prefer) continue;
    const double s = Q.min_along(P.faces[f].normal) - P.faces[f].offset;
    if (s > best) {
      best = s, q.face = f, q.sep = s;
      if (s > spec) return q;
    }
  }
  return q;
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

// Q's edges in P's frame (origin, direction, the normals of the faces on either side), built once
// per call when Q has at most kMaxLocal edges, else on the fly.
struct QEdge {
  Vec3 p, e, u, v;
};
struct QEdges {
  const QInP* Q;
  QEdge d[kMaxLocal];
  bool cached;
  explicit QEdges(const QInP& q) : Q(&q) {
    cached = q.Q->edge_count() <= kMaxLocal;
    if (cached)
      for (int j = 0; j < q.Q->edge_count(); ++j) d[j] = make(j);
  }
  QEdge make(int j) const {
    const auto& h = Q->Q->edges[2 * j];
    const auto& t = Q->Q->edges[2 * j + 1];
    QEdge r;
    r.p = Q->vert(h.origin);
    r.e = Q->vert(t.origin) - r.p;
    r.u = Q->normal(h.face);
    r.v = Q->normal(t.face);
    return r;
  }
  // By value when not cached (a temporary); the reference stays valid for the loop body.
  const QEdge& get(int j) const {
    if (cached) return d[j];
    scratch = make(j);
    return scratch;
  }
  mutable QEdge scratch;
};

struct EdgeQuery {
  int ea = -1, eb = -1;  // edge indices (half-edges 2k)
  double sep = -INFINITY;
  Vec3 axis = Vec3::Zero();
};

// Edge pairs whose Gauss-map arcs cross (Gregorius's Minkowski-face test). Only axes whose
// separation exceeds `thr` are normalised (the test is decided on squares first): the others can
// neither separate nor win the axis choice.
EdgeQuery query_edges(const ConvexPolyhedron& P, const QInP& Q, double thr) {
  EdgeQuery q;
  const int EP = P.edge_count(), EQ = Q.Q->edge_count();
  const QEdges QE(Q);
  for (int i = 0; i < EP; ++i) {
    const auto& h1 = P.edges[2 * i];
    const auto& t1 = P.edges[2 * i + 1];
    const Vec3& p1 = P.vertices[h1.origin];
    const Vec3 e1 = P.vertices[t1.origin] - p1;
    const double e1sq = e1.squaredNorm();
    const Vec3& u1 = P.faces[h1.face].normal;
    const Vec3& v1 = P.faces[t1.face].normal;
    for (int j = 0; j < EQ; ++j) {
      // Arcs (u1, v1) and (-u2, -v2) cross (with B x A = -e1 and D x C = -e2); the first
      // condition alone rejects most pairs, so it is tested before the rest is loaded.
      const QEdge& q2 = QE.get(j);
      const double cba = q2.u.dot(e1), dba = q2.v.dot(e1);
      if (!(cba * dba < 0)) continue;
      const Vec3& p2 = q2.p;
      const Vec3& e2 = q2.e;
      const double adc = -u1.dot(e2), bdc = -v1.dot(e2);
      if (!(adc * bdc < 0 && cba * bdc > 0)) continue;
      const Vec3 x = e1.cross(e2);
      const double L2 = x.squaredNorm();
      if (L2 < kParallelEdgeTol * kParallelEdgeTol * e1sq * e2.squaredNorm()) continue;
      double num = x.dot(p2 - p1);
      if (x.dot(p1 - P.centroid) < 0) num = -num;
      const bool pass =
          thr >= 0 ? (num > 0 && num * num > thr * thr * L2) : (num >= 0 || num * num < thr * thr * L2);
      if (!pass) continue;
      Vec3 axis;
      const double s = edge_projection(p1, e1, p2, e2, P.centroid, &axis);
      if (s > q.sep) q.sep = s, q.ea = i, q.eb = j, q.axis = axis;
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

// The face of P round its support vertex along n (unit, P's frame) whose normal is nearest n
// (ties to the lowest index).
double best_face(const ConvexPolyhedron& P, const Vec3& n, int& face) {
  const int v = P.support(n);
  double best = -INFINITY;
  face = -1;
  const int first = P.vertex_edge[v];
  int e = first;
  do {
    const int g = P.edges[e].face;
    const double c = P.faces[g].normal.dot(n);
    if (c > best || (c == best && g < face)) best = c, face = g;
    e = P.edges[e ^ 1].next;
  } while (e != first);
  return best;
}

// Face contact: reference face f of R (normal from R towards I), incident body I given in R's
// frame by T. Writes world-frame candidates through R's pose; returns the count.
int face_contact(const ConvexPolyhedron& R, int f, const ConvexPolyhedron& I, const Rel& T, const Pose& xr,
                 double spec, Candidate* cand) {
  const auto& F = R.faces[f];
  const Vec3& n = F.normal;
  // Incident face: the most anti-parallel of the faces around I's deepest vertex along -n (the
  // most anti-parallel face overall need not touch: on a finely faceted hull it may be a
  // neighbour tilted away from the touching vertex).
  const Vec3 nI = T.R.transpose() * n;
  int inc;
  best_face(I, -nI, inc);
  // Its polygon in R's frame (at most kMaxFaceVerts: every k-th vertex beyond that).
  ClipVertex buf[2][kMaxClip];
  int n0 = 0;
  {
    const int b = I.face_begin[inc], nloop = I.face_begin[inc + 1] - b;
    const int stride = (nloop + kMaxFaceVerts - 1) / kMaxFaceVerts;
    for (int k = 0; k < nloop; k += stride) {
      const int e = I.face_edges[b + k], v = I.edges[e].origin;
      buf[0][n0++] = {Vec3(T.R * I.vertices[v] + T.p), (uint32_t)v, kTagEdge | (uint32_t)e};
    }
  }
  // Clip against the reference face's side planes. A face of more than kMaxFaceVerts corners (a
  // detailed hull's cap) is clipped to the polygon of every k-th corner, inscribed in it: each side
  // plane costs a pass over the incident polygon, and 1,500 of them cost 200 us a call.
  int cur = 0, np = n0;
  {
    const int b = R.face_begin[f], rloop = R.face_begin[f + 1] - b;
    const int rstride = (rloop + kMaxFaceVerts - 1) / kMaxFaceVerts;  // 1 up to kMaxFaceVerts corners
    for (int k = 0; k < rloop && np > 0; k += rstride) {
      const int e = R.face_edges[b + k];
      const int g = k + rstride < rloop ? R.face_edges[b + k + rstride] : R.face_edges[b];
      const Vec3& P = R.vertices[R.edges[e].origin];
      const Vec3& Q = R.vertices[R.edges[g].origin];
      const Vec3 s = (Q - P).cross(n);
      np = clip_polygon(buf[cur], np, s, s.dot(P), kTagPlane | (uint32_t)e, buf[cur ^ 1]);
      cur ^= 1;
    }
  }
  int nc = 0;
  for (int i = 0; i < np && nc < kMaxClip; ++i) {
    const double s = n.dot(buf[cur][i].x) - F.offset;
    if (s > spec) continue;
    cand[nc++] = {xr.apply(buf[cur][i].x - 0.5 * s * n), s, buf[cur][i].id};
  }
  if (nc == 0 && np == 0) {
    // Clipped away (the incident face lies off the reference face's prism: a deep or grazing
    // overlap): the incident body's deepest vertex, so an overlap never goes unreported.
    const int v = I.support(-nI);
    const Vec3 x = T.R * I.vertices[v] + T.p;
    const double s = n.dot(x) - F.offset;
    if (s <= spec) cand[nc++] = {xr.apply(x - 0.5 * s * n), s, (uint32_t)v};
  }
  return nc;
}

}  // namespace

namespace {

// Past this many edge pairs the separating-axis test costs more than GJK: its edge query is
// O(edges A x edges B) (two 40-point hulls, 13,000 pairs: 25 us a call; two 64-vertex ones,
// 35,000 pairs: 270 us), where GJK and EPA with hill-climbing supports grow about as sqrt(n).
constexpr long kSatEdgePairs = 16384;
// A cached reference face is kept while its normal is within this cosine of the best one's
// (about 1.1 degrees): the manifold's points keep their ids from step to step on a finely
// faceted hull, whose best face changes with every wobble.
constexpr double kKeepFaceCos = 2e-4;
constexpr double kTieDepth = 5e-5;  // m: depths this close count as equal when picking four points

// Hulls too detailed for the separating-axis test: the normal and separation by GJK (EPA when
// the solids overlap), then the reference face as the face of either hull that faces the other
// best (Jolt's manifold between two supporting faces), clipped as the SAT path clips it.
int hull_hull_detailed(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb,
                       double spec, PairCache& cache, Manifold& out) {
  const ConvexPolyhedron& A = *a.hull;
  const ConvexPolyhedron& B = *b.hull;
  const CoreDistance d = core_distance(Support(a, xa), Support(b, xb));
  out.normal_W = d.normal;
  if (d.separation > spec) {
    cache = {kCacheNone, -1, -1};
    return 0;
  }
  const Vec3 nA = xa.R.transpose() * d.normal, nB = -(xb.R.transpose() * d.normal);
  int fa, fb;
  double ca = best_face(A, nA, fa), cb = best_face(B, nB, fb);
  const double top = std::max(ca, cb);
  // A's face unless B's is clearly better (two caps nearly parallel must not swap every step).
  bool refA = !(cb > ca + kKeepFaceCos);
  if (cache.type == kCacheFaceA && cache.a >= 0 && cache.a < (int)A.faces.size() &&
      A.faces[cache.a].normal.dot(nA) >= top - kKeepFaceCos) {
    refA = true, fa = cache.a;
  } else if (cache.type == kCacheFaceB && cache.b >= 0 && cache.b < (int)B.faces.size() &&
             B.faces[cache.b].normal.dot(nB) >= top - kKeepFaceCos) {
    refA = false, fb = cache.b;
  }
  Candidate cand[kMaxClip];
  int nc;
  if (refA) {
    cache = {kCacheFaceA, fa, -1};
    out.normal_W = xa.R * A.faces[fa].normal;
    nc = face_contact(A, fa, B, relative(xa, xb), xa, spec, cand);
  } else {
    cache = {kCacheFaceB, -1, fb};
    out.normal_W = -(xb.R * B.faces[fb].normal);
    nc = face_contact(B, fb, A, relative(xb, xa), xb, spec, cand);
  }
  // Near-ties kept by the earlier candidate (the clip's order is fixed in the incident face): a
  // detailed face clipped to dozens of points at one depth otherwise gave another four points with
  // every wobble, and a stack on it crept at 1.5 mm/s.
  reduce_to_manifold(cand, nc, out.normal_W, out, kTieDepth, 1e-3);
  return out.count;
}

}  // namespace

int hull_hull(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
              PairCache& cache, Manifold& out) {
  const ConvexPolyhedron& A = *a.hull;
  const ConvexPolyhedron& B = *b.hull;
  if ((long)A.edge_count() * B.edge_count() > kSatEdgePairs)
    return hull_hull_detailed(a, xa, b, xb, spec, cache, out);
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
  const QInP BinA(B, TBA), AinB(A, TAB);
  const FaceQuery fa = query_faces(A, BinA, cache.type == kCacheFaceA ? cache.a : -1, tol, spec);
  if (fa.sep > spec) {
    cache = {kCacheFaceA, fa.face, -1};
    out.normal_W = xa.R * A.faces[fa.face].normal;
    return 0;
  }
  const FaceQuery fb = query_faces(B, AinB, cache.type == kCacheFaceB ? cache.b : -1, tol, spec);
  if (fb.sep > spec) {
    cache = {kCacheFaceB, -1, fb.face};
    out.normal_W = -(xb.R * B.faces[fb.face].normal);
    return 0;
  }
  const double face_best = std::max(fa.sep, fb.sep);
  const EdgeQuery eq = query_edges(A, BinA, std::min(spec, clear_margin(face_best, kRelEdgeTol, tol)));
  if (eq.sep > spec) {
    cache = {kCacheEdges, eq.ea, eq.eb};
    out.normal_W = xa.R * eq.axis;
    return 0;
  }
  // 3. Choose the axis: A's face, unless B's face or the edge pair is clearly better.
  const bool edge = eq.ea >= 0 && eq.sep > clear_margin(face_best, kRelEdgeTol, tol);
  if (edge) {
    cache = {kCacheEdges, eq.ea, eq.eb};
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
  const bool refA = !(fb.sep > clear_margin(fa.sep, kRelFaceTol, tol));
  if (refA) {
    cache = {kCacheFaceA, fa.face, -1};
    out.normal_W = xa.R * A.faces[fa.face].normal;
    nc = face_contact(A, fa.face, B, TBA, xa, spec, cand);
  } else {
    cache = {kCacheFaceB, -1, fb.face};
    out.normal_W = -(xb.R * B.faces[fb.face].normal);
    nc = face_contact(B, fb.face, A, TAB, xb, spec, cand);
  }
  reduce_to_manifold(cand, nc, out.normal_W, out);
  return out.count;
}

// ---------------------------------------------------------------- box against box
// The same SAT in closed form (the 15 axes of Gottschalk, Lin and Manocha's OBB test: 3 + 3 face
// normals, 9 edge-direction cross products), then the same face clipping as hull_hull on the
// boxes' polyhedra (make_box_polyhedron numbering: face 2i is -axis i, 2i+1 is +axis i). Cache:
// face indices as hull_hull; edges as kCacheBoxEdges with a = A's axis, b = B's axis.

namespace {
constexpr uint8_t kCacheBoxEdges = 4;

// Separation of B from A's face f (A's frame; C = B's axes in A, t = B's centre in A).
inline double box_face_sep(int f, const Vec3& ha, const Vec3& hb, const Mat3& absC, const Vec3& t) {
  const int i = f >> 1;
  const double sgn = (f & 1) ? 1.0 : -1.0;
  return sgn * t[i] - ha[i] - absC.row(i).dot(hb);
}
// The edge axis e_i x C_j (A's frame) in closed form (C orthonormal: the classic OBB terms):
// numerator |t.L| - rA - rB of its separation, |L|^2, and t.L (for the orientation).
struct BoxEdgeTerms {
  double num, len2, tl;
};
inline BoxEdgeTerms box_edge_terms(int i, int j, const Vec3& ha, const Vec3& hb, const Mat3& C,
                                   const Mat3& absC, const Vec3& t) {
  const int i1 = i == 2 ? 0 : i + 1, i2 = i == 0 ? 2 : i - 1;
  const int j1 = j == 2 ? 0 : j + 1, j2 = j == 0 ? 2 : j - 1;
  const double tl = t[i2] * C(i1, j) - t[i1] * C(i2, j);
  const double rA = ha[i1] * absC(i2, j) + ha[i2] * absC(i1, j);
  const double rB = hb[j1] * absC(i, j2) + hb[j2] * absC(i, j1);
  const double len2 = C(i1, j) * C(i1, j) + C(i2, j) * C(i2, j);
  return {std::fabs(tl) - rA - rB, len2, tl};
}
// Separation along e_i x C_j oriented from A to B (unit axis in *axis); -inf when parallel.
inline double box_edge_sep(int i, int j, const Vec3& ha, const Vec3& hb, const Mat3& C, const Mat3& absC,
                           const Vec3& t, Vec3* axis) {
  const BoxEdgeTerms e = box_edge_terms(i, j, ha, hb, C, absC, t);
  if (e.len2 < kParallelEdgeTol * kParallelEdgeTol) return -INFINITY;
  const double len = std::sqrt(e.len2);
  if (axis) {
    const Vec3 L = Vec3::Unit(i).cross(C.col(j));
    *axis = (e.tl >= 0 ? 1.0 : -1.0) * L / len;
  }
  return e.num / len;
}

// World normal of box face f (make_box_polyhedron numbering: 2i is -axis i, 2i+1 is +axis i).
inline Vec3 box_face_normal_W(const Pose& x, int f) {
  return (f & 1) ? Vec3(x.R.col(f >> 1)) : Vec3(-x.R.col(f >> 1));
}

struct BoxClipVertex {
  Vec3 x;
  uint32_t id, out_tag;
};

// Face contact of two boxes in the reference box R's frame: reference face on axis i with sign
// sr (normal sr e_i), incident box I with half extents hi, axes C (columns, R's frame) and centre
// t. The incident face is I's face most anti-parallel to the normal; its rectangle is clipped
// against the reference face's four side planes x_u = +-hr_u. Ids: incident vertex (box
// numbering), incident edge (kTagEdge | from << 3 | to), side plane (kTagPlane | 2u + (side > 0)).
int box_face_contact(const Vec3& hr, int i, double sr, const Vec3& hi, const Mat3& C, const Vec3& t,
                     const Pose& xr, double spec, Candidate* cand) {
  int j = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(C(i, k)) > std::fabs(C(i, j))) j = k;
  const double sj = sr * C(i, j) > 0 ? -1.0 : 1.0;  // the incident face's outward normal opposes sr e_i
  const int k1 = (j + 1) % 3, k2 = (j + 2) % 3;
  const Vec3 c = t + (sj * hi[j]) * C.col(j);
  const Vec3 a1 = hi[k1] * C.col(k1), a2 = hi[k2] * C.col(k2);
  const double s1[4] = {1, -1, -1, 1}, s2[4] = {1, 1, -1, -1};
  BoxClipVertex buf[2][16];
  uint32_t vid[4];
  for (int q = 0; q < 4; ++q) {
    vid[q] = (sj > 0 ? 1u << j : 0u) | (s1[q] > 0 ? 1u << k1 : 0u) | (s2[q] > 0 ? 1u << k2 : 0u);
    buf[0][q].x = c + s1[q] * a1 + s2[q] * a2;
    buf[0][q].id = vid[q];
  }
  for (int q = 0; q < 4; ++q) buf[0][q].out_tag = kTagEdge | (vid[q] << 3) | vid[(q + 1) & 3];
  int n = 4, cur = 0;
  const int u1 = (i + 1) % 3, u2 = (i + 2) % 3;
  const int axes[4] = {u1, u1, u2, u2};
  const double sides[4] = {1, -1, 1, -1};
  for (int p = 0; p < 4 && n > 0; ++p) {
    const int u = axes[p];
    const double sd = sides[p], off = hr[u];
    const uint32_t tag = kTagPlane | (uint32_t)(2 * u + (sd > 0));
    const BoxClipVertex* in = buf[cur];
    // Nothing outside this side plane (the usual case for most of the four): no copy.
    bool any_out = false;
    for (int q = 0; q < n; ++q) any_out |= sd * in[q].x[u] > off;
    if (!any_out) continue;
    BoxClipVertex* o = buf[cur ^ 1];
    int m = 0;
    for (int q = 0; q < n; ++q) {
      const BoxClipVertex& A = in[q];
      const BoxClipVertex& B = in[q + 1 == n ? 0 : q + 1];
      const double da = sd * A.x[u] - off, db = sd * B.x[u] - off;
      if (da <= 0) o[m++] = A;
      if ((da <= 0) != (db <= 0)) {
        BoxClipVertex& X = o[m++];
        X.x = A.x + (da / (da - db)) * (B.x - A.x);
        X.id = (A.out_tag & 0xFFFF) | (tag << 16);
        X.out_tag = da <= 0 ? tag : A.out_tag;
      }
    }
    n = m;
    cur ^= 1;
  }
  int nc = 0;
  for (int q = 0; q < n; ++q) {
    const Vec3& x = buf[cur][q].x;
    const double s = sr * x[i] - hr[i];
    if (s > spec) continue;
    Vec3 mid = x;
    mid[i] -= 0.5 * s * sr;
    cand[nc++] = {Vec3(xr.R(0, 0) * mid.x() + xr.R(0, 1) * mid.y() + xr.R(0, 2) * mid.z() + xr.p.x(),
                       xr.R(1, 0) * mid.x() + xr.R(1, 1) * mid.y() + xr.R(1, 2) * mid.z() + xr.p.y(),
                       xr.R(2, 0) * mid.x() + xr.R(2, 1) * mid.y() + xr.R(2, 2) * mid.z() + xr.p.z()),
                  s, buf[cur][q].id};
  }
  if (nc == 0 && n == 0) {
    // Clipped away (deep or grazing overlap): the incident box's deepest vertex.
    Vec3 x = t;
    uint32_t v = 0;
    for (int k = 0; k < 3; ++k) {
      const bool pos = sr * C(i, k) < 0;  // lowest along sr e_i
      x += (pos ? hi[k] : -hi[k]) * C.col(k);
      v |= pos ? (1u << k) : 0u;
    }
    const double s = sr * x[i] - hr[i];
    if (s <= spec) {
      Vec3 mid = x;
      mid[i] -= 0.5 * s * sr;
      cand[nc++] = {Vec3(xr.R.lazyProduct(mid) + xr.p), s, v};
    }
  }
  return nc;
}
}  // namespace

int box_box(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
            PairCache& cache, Manifold& out) {
  const Vec3 &ha = a.half_extents, &hb = b.half_extents;
  // Written out: Eigen's small products are not inlined at -O2 (measured ~15% of this function).
  Mat3 C;
  const Vec3 dp = xb.p - xa.p;
  Vec3 t;
  for (int i = 0; i < 3; ++i) {
    const double a0 = xa.R(0, i), a1 = xa.R(1, i), a2 = xa.R(2, i);
    for (int j = 0; j < 3; ++j) C(i, j) = a0 * xb.R(0, j) + a1 * xb.R(1, j) + a2 * xb.R(2, j);
    t[i] = a0 * dp.x() + a1 * dp.y() + a2 * dp.z();
  }
  const Mat3 absC = C.cwiseAbs();
  const Mat3 absCt = absC.transpose();
  const Vec3 tb(C(0, 0) * t.x() + C(1, 0) * t.y() + C(2, 0) * t.z(),
                C(0, 1) * t.x() + C(1, 1) * t.y() + C(2, 1) * t.z(),
                C(0, 2) * t.x() + C(1, 2) * t.y() + C(2, 2) * t.z());  // A's centre is at -tb in B's frame
  const double tol = 1e-3 * (ha.minCoeff() + hb.minCoeff());
  // 1. The cached axis first.
  if (cache.type == kCacheFaceA && cache.a >= 0 && cache.a < 6) {
    if (box_face_sep(cache.a, ha, hb, absC, t) > spec)
      return out.normal_W = box_face_normal_W(xa, cache.a), 0;
  } else if (cache.type == kCacheFaceB && cache.b >= 0 && cache.b < 6) {
    if (box_face_sep(cache.b, hb, ha, absCt, -tb) > spec)
      return out.normal_W = -(box_face_normal_W(xb, cache.b)), 0;
  } else if (cache.type == kCacheBoxEdges && cache.a >= 0 && cache.a < 3 && cache.b >= 0 && cache.b < 3) {
    Vec3 axis;
    if (box_edge_sep(cache.a, cache.b, ha, hb, C, absC, t, &axis) > spec)
      return out.normal_W = xa.R * axis, 0;
  }
  // 2. Faces of A and B (the cached face wins ties within tol), then the nine edge axes.
  auto faces = [&](const Vec3& h1, const Vec3& h2, const Mat3& ac, const Vec3& tt, int prefer) {
    FaceQuery q;
    double best = -INFINITY;
    if (prefer >= 0 && prefer < 6)
      q.face = prefer, q.sep = box_face_sep(prefer, h1, h2, ac, tt), best = q.sep + tol;
    for (int i = 0; i < 3; ++i) {
      const int f = tt[i] >= 0 ? 2 * i + 1 : 2 * i;
      if (f == prefer) continue;
      const double sep = box_face_sep(f, h1, h2, ac, tt);
      if (sep > best) best = sep, q.face = f, q.sep = sep;
    }
    return q;
  };
  const FaceQuery fa = faces(ha, hb, absC, t, cache.type == kCacheFaceA ? cache.a : -1);
  if (fa.sep > spec) {
    cache = {kCacheFaceA, fa.face, -1};
    return out.normal_W = box_face_normal_W(xa, fa.face), 0;
  }
  const FaceQuery fb = faces(hb, ha, absCt, -tb, cache.type == kCacheFaceB ? cache.b : -1);
  if (fb.sep > spec) {
    cache = {kCacheFaceB, -1, fb.face};
    return out.normal_W = -(box_face_normal_W(xb, fb.face)), 0;
  }
  // Edge axes: only those that could matter (separating beyond spec, or deep enough to win the
  // axis choice below) are normalised; the others are rejected without a square root.
  const double face_best = std::max(fa.sep, fb.sep);
  const double thr = std::min(spec, clear_margin(face_best, kRelEdgeTol, tol));
  int ei = -1, ej = -1;
  double esep = -INFINITY;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const BoxEdgeTerms e = box_edge_terms(i, j, ha, hb, C, absC, t);
      if (e.len2 < kParallelEdgeTol * kParallelEdgeTol) continue;
      // sep = num / sqrt(len2) > thr, decided on squares.
      const bool pass = thr >= 0 ? (e.num > 0 && e.num * e.num > thr * thr * e.len2)
                                 : (e.num >= 0 || e.num * e.num < thr * thr * e.len2);
      if (!pass) continue;
      const double sep = e.num / std::sqrt(e.len2);
      if (sep > esep) esep = sep, ei = i, ej = j;
    }
  Vec3 eaxis = Vec3::Zero();
  if (ei >= 0) box_edge_sep(ei, ej, ha, hb, C, absC, t, &eaxis);
  if (esep > spec) {
    cache = {kCacheBoxEdges, ei, ej};
    return out.normal_W = xa.R * eaxis, 0;
  }
  // 3. Axis choice, as hull_hull.
  if (ei >= 0 && esep > clear_margin(face_best, kRelEdgeTol, tol)) {
    cache = {kCacheBoxEdges, ei, ej};
    out.normal_W = xa.R * eaxis;
    // The supporting edges: A's along axis ei on the side of the normal, B's along ej opposite.
    Vec3 pa = Vec3::Zero(), qa;
    uint32_t bitsA = 0;
    for (int k = 0; k < 3; ++k)
      if (k != ei) {
        const bool pos = eaxis[k] >= 0;
        pa[k] = pos ? ha[k] : -ha[k];
        bitsA |= pos ? (1u << k) : 0u;
      }
    qa = pa;
    pa[ei] = -ha[ei], qa[ei] = ha[ei];
    const Vec3 nb = C.transpose() * eaxis;
    Vec3 pb = Vec3::Zero(), qb;
    uint32_t bitsB = 0;
    for (int k = 0; k < 3; ++k)
      if (k != ej) {
        const bool pos = nb[k] < 0;
        pb[k] = pos ? hb[k] : -hb[k];
        bitsB |= pos ? (1u << k) : 0u;
      }
    qb = pb;
    pb[ej] = -hb[ej], qb[ej] = hb[ej];
    pb = C * pb + t, qb = C * qb + t;
    double s, u;
    Vec3 c1, c2;
    closest_segments(pa, qa, pb, qb, s, u, c1, c2);
    const double sep = eaxis.dot(c2 - c1);
    if (sep <= spec) {
      const uint32_t fA = kTagEdge | ((uint32_t)ei << 3) | bitsA, fB = kTagEdge | ((uint32_t)ej << 3) | bitsB;
      out.points[0] = {xa.apply(0.5 * (c1 + c2)), sep, fA | (fB << 16)};
      out.count = 1;
    }
    return out.count;
  }
  Candidate cand[16];
  int nc;
  if (!(fb.sep > clear_margin(fa.sep, kRelFaceTol, tol))) {
    cache = {kCacheFaceA, fa.face, -1};
    out.normal_W = box_face_normal_W(xa, fa.face);
    nc = box_face_contact(ha, fa.face >> 1, (fa.face & 1) ? 1.0 : -1.0, hb, C, t, xa, spec, cand);
  } else {
    cache = {kCacheFaceB, -1, fb.face};
    out.normal_W = -(box_face_normal_W(xb, fb.face));
    nc = box_face_contact(hb, fb.face >> 1, (fb.face & 1) ? 1.0 : -1.0, ha, Mat3(C.transpose()), -tb, xb,
                          spec, cand);
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

// Least separation in a manifold (+inf when empty).
static double min_separation(const Manifold& m) {
  double s = INFINITY;
  for (int i = 0; i < m.count; ++i) s = std::min(s, m.points[i].separation);
  return s;
}

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
  // Shortcut (exact, no GJK): the segment is above the best face's plane and its lower end
  // projects inside that face. Every point of the hull is below the plane, so the distance is
  // that end's height; the usual case of a capsule resting on a face.
  if (fsep > 1e-9 * size) {
    const auto& F = H.faces[fbest];
    const Vec3& x = F.normal.dot(p0) <= F.normal.dot(p1) ? p0 : p1;
    bool inside = true;
    int e = F.edge;
    do {
      const Vec3& P = H.vertices[H.edges[e].origin];
      const Vec3& Q = H.vertices[H.edges[H.edges[e].next].origin];
      if ((Q - P).cross(F.normal).dot(x - P) > 0) inside = false;
      e = H.edges[e].next;
    } while (inside && e != F.edge);
    if (inside && capsule_face_points(H, fbest, p0, p1, r, xb, spec, out) > 0) return out.count;
    out.count = 0;
  }
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
    // The clipped segment must keep the depth GJK found (its deepest end may have been clipped
    // away when the closest point is at the face's border): otherwise GJK's single point.
    const double tol = 1e-7 * size;
    if (dmin < -0.999 && capsule_face_points(H, f, p0, p1, r, xb, spec, out) > 0 &&
        min_separation(out) <= s + tol)
      return out.count;
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
  if (ebest >= 0 && esep > clear_margin(fsep, kRelEdgeTol, tol)) {
    const Vec3& P = H.vertices[H.edges[2 * ebest].origin];
    const Vec3& Q = H.vertices[H.edges[2 * ebest + 1].origin];
    double s, t;
    Vec3 c1, c2;
    closest_segments(p0, p1, P, Q, s, t, c1, c2);
    // Axis from the hull out to the capsule; A -> B is its negation. The separation is the
    // axis's (the segment may pass inside the box, where the closest points of the two lines
    // say nothing about depth); the point is on the hull's edge, moved half way.
    const double sep = esep - r;
    out.normal_W = -(xb.R * eaxis);
    if (sep > spec) return 0;
    out.points[0] = {xb.apply(c2 + 0.5 * sep * eaxis), sep, 3 | ((kTagEdge | (uint32_t)ebest) << 16)};
    out.count = 1;
    return 1;
  }
  if (capsule_face_points(H, fbest, p0, p1, r, xb, spec, out) > 0 &&
      min_separation(out) <= fsep - r + 1e-7 * size)
    return out.count;
  // Clipped away, or the deepest end clipped off (the segment leaves the face's prism): the
  // deepest end against that face's plane, at the SAT depth.
  out.count = 0;
  const Vec3& n = H.faces[fbest].normal;
  const Vec3 x = n.dot(p0) <= n.dot(p1) ? p0 : p1;
  const double s = n.dot(x) - H.faces[fbest].offset - r;
  out.normal_W = -(xb.R * n);
  if (s <= spec) out.points[out.count++] = {xb.apply(x - (r + 0.5 * s) * n), s, 4 | ((uint32_t)fbest << 16)};
  return out.count;
}

}  // namespace simreel::collide_detail

namespace simreel::collide_detail {

// Cylinder or ellipsoid (A) against a box or hull (B).
int curved_hull(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double spec,
                PairCache& cache, Manifold& out) {
  if (convex_generic(a, xa, b, xb, spec, cache, out) == 0) return 0;
  // The hull face whose outward normal opposes the normal (A -> B) within ~2.6 degrees.
  const ConvexPolyhedron& H = *b.hull;
  const Vec3 n_B = xb.R.transpose() * out.normal_W;
  int f = 0;
  double dmin = INFINITY;
  for (int k = 0; k < (int)H.faces.size(); ++k) {
    const double d = H.faces[k].normal.dot(n_B);
    if (d < dmin) dmin = d, f = k;
  }
  if (dmin > -0.999) return out.count;
  const auto& F = H.faces[f];
  const Vec3 m = xb.R * F.normal;  // towards the cylinder
  const double d = m.dot(xb.p) + F.offset;
  // Cylinder: its rim points against the face's plane; ellipsoid: its exact support point along
  // -m, p_C = -diag(r^2) m_C / |diag(r) m_C| (as plane_ellipsoid).
  Vec3 q[5];
  int nq = 5;
  if (a.kind == CollideKind::cylinder) {
    cylinder_rim_points(a, xa, m, q);
  } else {
    const Vec3 mc = xa.R.transpose() * m;
    const Vec3 rm = a.radii.cwiseProduct(mc);
    q[0] = xa.apply(-a.radii.cwiseProduct(rm) / rm.norm());
    nq = 1;
  }
  Candidate c[5];
  int nc = 0;
  const double eps = 1e-12 * (a.bounding_radius + b.bounding_radius);
  for (int i = 0; i < nq; ++i) {
    const double s = m.dot(q[i]) - d;
    if (s > spec || (a.kind == CollideKind::cylinder && !cylinder_rim_point_used(i, xa.R.col(2), m)))
      continue;
    // Inside the face's prism (its side planes, hull frame)?
    const Vec3 x = xb.apply_inverse(q[i]);
    bool inside = true;
    int e = F.edge;
    do {
      const Vec3& P = H.vertices[H.edges[e].origin];
      const Vec3& Q = H.vertices[H.edges[H.edges[e].next].origin];
      if ((Q - P).cross(F.normal).dot(x - P) > eps) inside = false;
      e = H.edges[e].next;
    } while (inside && e != F.edge);
    if (inside) c[nc++] = {Vec3(q[i] - 0.5 * s * m), s, (uint32_t)i | ((uint32_t)f << 16)};
  }
  if (nc == 0) return out.count;  // off the face: keep GJK/EPA's point
  // The face points must keep GJK/EPA's depth (the deepest point may lie off the face, when the
  // shape overhangs its border or sinks deep): otherwise keep GJK/EPA's single point.
  double cmin = INFINITY;
  for (int i = 0; i < nc; ++i) cmin = std::min(cmin, c[i].s);
  if (cmin > out.points[0].separation + 1e-7 * (a.bounding_radius + b.bounding_radius)) return out.count;
  reduce_to_manifold(c, nc, Vec3(-m), out);
  return out.count;
}

}  // namespace simreel::collide_detail
