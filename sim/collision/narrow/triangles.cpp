// Narrow phase against a static triangle mesh (design: docs/collision.md, "Static triangle meshes").
//
// PER TRIANGLE (world frame: vertices p0 p1 p2 counter-clockwise about the front normal n)
//   sphere    closest point on the triangle (Ericson, Real-Time Collision Detection, 5.1.5), which
//             also names the triangle's feature: face, edge or vertex.
//   capsule   closest points of the segment and the triangle: each end against the triangle, the
//             segment against each edge (Ericson 5.1.9), and the segment crossing the face. A face
//             contact clips the segment to the triangle's three side planes: its two ends are the
//             points (a capsule lying across several triangles gets the part over each).
//   box, hull, cylinder, ellipsoid
//             GJK/EPA between the triangle and the shape (gjk.cpp) for the normal and the feature
//             of the triangle its witness point lies on. A face contact then takes the shape's exact
//             points against the triangle's plane, kept where they lie over the triangle: the
//             incident face (the face most opposed to n) clipped against the three side planes
//             (Sutherland-Hodgman) for boxes and hulls, the rim points of plane-cylinder for a
//             cylinder, the exact support point for an ellipsoid. A triangle whose edges and
//             vertices are all inactive (inside a flat or concave patch) always gives a face
//             contact, so GJK/EPA is skipped there.
//   One-sided: a shape wholly behind a triangle's plane gets nothing from it, and a face contact
//   is kept while the shape's centre is at most its radius (sphere, capsule) behind the plane.
//
// INTERNAL EDGES (the ideas of Jolt's InternalEdgeRemovingCollector and Box2D's chain shapes,
// written for this mesh data): a contact on an edge or vertex of a triangle keeps its own normal
// only if that feature is active (a boundary edge, or an edge bent convex by more than
// kActiveEdgeAngle) and its normal points out of the neighbour's face region across the edge
// (nu . out_nb >= 0); in the neighbour's face region it is dropped (the neighbour's face contact
// stands for it); at an inactive feature (a flat or concave edge) it becomes the triangle's face
// contact, along n. So a sphere or box crossing a flat mesh sees one plane, and at a concave
// crease each side pushes along its own normal. A kept contact is also dropped when its normal
// points behind the triangle (one-sided), and a vertex's when an edge of any triangle around the
// vertex leads toward the shape (the vertex is then not the nearest point: vertex_is_nearest).
//
// MERGING: each triangle's contact joins the manifold whose normal is within kMergeAngle of its
// own (else starts one, at most kMaxMeshManifolds; then it joins the nearest). Within a manifold
// a point whose id is already there keeps the deeper of the two (the same sphere, box vertex or
// rim point seen from two triangles of one plane); the manifold's normal is that of its deepest
// point's triangle; more than four points are reduced as collide.cpp's REDUCTION says.
//
// FEATURE IDS: the shape's own feature where the point is one (sphere 0, capsule ends 0 and 1,
// box or hull vertex index, cylinder rim points 0-4, ellipsoid 0): these survive the shape's
// move from one triangle to the next, so warm starting works across triangle edges. Points made
// by clipping, and single edge or vertex points, carry the triangle's index (bits 8-29) and the
// feature, tagged by bit 31 (clipped) or bit 30 (edge or vertex point).
#include <algorithm>
#include <array>

#include "sim/collision/narrow/internal.hpp"
#include "sim/collision/narrow/mesh.hpp"
#include "sim/geometry/trimesh.hpp"

namespace simreel {

namespace collide_detail {

// (internal.hpp)
Vec3 closest_on_triangle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, int& f) {
  const Vec3 ab = b - a, ac = c - a, ap = q - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return f = 4, a;
  const Vec3 bp = q - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return f = 5, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return f = 1, Vec3(a + (d1 / (d1 - d3)) * ab);
  const Vec3 cp = q - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return f = 6, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return f = 3, Vec3(a + (d2 / (d2 - d6)) * ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return f = 2, Vec3(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  const double den = 1.0 / (va + vb + vc);
  return f = 0, Vec3(a + ab * (vb * den) + ac * (vc * den));
}

namespace {

constexpr int kClusterCap = 32;
constexpr double kMergeCos = 0.9961946980917455;  // cos 5 degrees
constexpr double kFaceCos = 0.999;                // ~2.6 degrees: the normal is the face's
constexpr int kMaxPoly = 72;

struct WorldTri {
  Vec3 p[3];
  int v[3];                  // the mesh's (welded) vertex indices
  const TriMeshShape* mesh;  // the mesh, for a vertex's other triangles
  const Mat3* R_WM;          // the mesh's orientation
  Vec3 n;
  Vec3 out_nb[3];
  Vec3 side[3];  // outward unit normals of the side planes through each edge (in the plane)
  uint8_t active;
  uint32_t index;
};

// What internal-edge handling does with a contact on feature f (0 face, 1 + k edge k, 4 + k
// vertex k) whose normal is nu.
enum Action { kKeep, kFace, kDrop };
Action edge_rule(const WorldTri& t, int f, const Vec3& nu) {
  if (f == 0 || nu.dot(t.n) >= kFaceCos) return kFace;
  if (f <= 3) {
    const int k = f - 1;
    if (!((t.active >> k) & 1)) return kFace;
    return nu.dot(t.out_nb[k]) < -1e-9 ? kDrop : kKeep;
  }
  const int k = f - 4;
  if (!((t.active >> (3 + k)) & 1)) return kFace;
  return (nu.dot(t.out_nb[k]) < -1e-9 || nu.dot(t.out_nb[(k + 2) % 3]) < -1e-9) ? kDrop : kKeep;
}

// The feature of the triangle a point on it lies on (barycentric weights below 1e-7 count as 0).
int feature_of(const WorldTri& t, const Vec3& x) {
  const Vec3 n2 = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]);
  const double inv = 1.0 / n2.squaredNorm();
  double l[3];
  l[0] = (t.p[1] - x).cross(t.p[2] - x).dot(n2) * inv;
  l[1] = (t.p[2] - x).cross(t.p[0] - x).dot(n2) * inv;
  l[2] = 1.0 - l[0] - l[1];
  constexpr double tol = 1e-7;
  int small = 0, last_big = 0, last_small = 0;
  for (int k = 0; k < 3; ++k) {
    if (l[k] < tol)
      ++small, last_small = k;
    else
      last_big = k;
  }
  if (small == 0) return 0;
  if (small == 1) return 1 + (last_small + 1) % 3;  // the edge opposite that vertex
  return 4 + last_big;
}

bool inside(const WorldTri& t, const Vec3& x, double tol) {
  for (int k = 0; k < 3; ++k)
    if (t.side[k].dot(x - t.p[k]) > tol) return false;
  return true;
}

bool shape_feature(uint32_t id) {
  return (id & 0xC0000000u) == 0;
}

// collide.cpp's reduction with the shape's own points first and winning near-ties: on a flat
// patch the points made by clipping at inner edges lie at the depth of the shape's points to
// rounding, between them, and must not displace them (a capsule lying flat would otherwise keep a
// middle point and one end, and tip). The stable partition is written out over a fixed buffer:
// std::stable_partition takes a temporary buffer from the heap (found by AddressSanitizer as an
// operator new(nothrow) the allocation count did not see), and a step must not allocate.
void reduce_mesh(Candidate* c, int n, const Vec3& normal, Manifold& out) {
  Candidate rest[kClusterCap];
  int kept = 0, moved = 0;
  for (int i = 0; i < n; ++i) {
    if (shape_feature(c[i].id))
      c[kept++] = c[i];
    else
      rest[moved++] = c[i];
  }
  std::copy(rest, rest + moved, c + kept);
  reduce_to_manifold(c, n, normal, out, 1e-10, 1e-9);
}

uint32_t clip_id(uint32_t tri, int side, int edge) {
  return 0x80000000u | ((tri & 0x3FFFFFu) << 8) | ((uint32_t)side << 6) | (uint32_t)(edge & 63);
}
uint32_t feature_id(uint32_t tri, int f) {
  return 0x40000000u | ((tri & 0x3FFFFFu) << 8) | (uint32_t)f;
}

struct Cluster {
  Vec3 n;
  double deepest;
  int count;
  Candidate c[kClusterCap];
};

struct Collector {
  Cluster cl[kMaxMeshManifolds];
  int n = 0;
  // For triangles over which the shape has none of its exact points (cylinder rim points, an
  // ellipsoid's support point), the shape's nearest point along the face normal: added at the end,
  // only where no manifold of that normal already has a point as deep. On a flat or convex patch
  // the neighbour's face contact is always as deep and they are dropped; in a concave crease where
  // each face's exact points fall beyond it, they are the contact.
  static constexpr int kMaxFallback = 16;
  Candidate fb[kMaxFallback];
  Vec3 fb_n[kMaxFallback];
  int nfb = 0;

  void defer(const Vec3& normal, const Candidate& q) {
    if (nfb < kMaxFallback) fb_n[nfb] = normal, fb[nfb++] = q;
  }
  void finish() {
    for (int k = 0; k < nfb; ++k) {
      bool covered = false;
      for (int i = 0; i < n && !covered; ++i)
        covered = cl[i].n.dot(fb_n[k]) >= kMergeCos && cl[i].deepest <= fb[k].s + 1e-9;
      if (!covered) add(fb_n[k], fb[k]);
    }
  }

  void add(const Vec3& normal, const Candidate& q) {
    int best = -1;
    double bd = -2;
    for (int i = 0; i < n; ++i) {
      const double d = cl[i].n.dot(normal);
      if (d > bd) bd = d, best = i;
    }
    if (best < 0 || (bd < kMergeCos && n < kMaxMeshManifolds)) {
      best = n++;
      cl[best].n = normal;
      cl[best].deepest = INFINITY;
      cl[best].count = 0;
    }
    Cluster& c = cl[best];
    if (q.s < c.deepest) c.deepest = q.s, c.n = normal;
    for (int i = 0; i < c.count; ++i)
      if (c.c[i].id == q.id) {
        if (q.s < c.c[i].s) c.c[i] = q;
        return;
      }
    if (c.count == kClusterCap) {
      Manifold m;
      reduce_mesh(c.c, c.count, c.n, m);
      c.count = m.count;
      for (int i = 0; i < m.count; ++i) c.c[i] = {m.points[i].p_W, m.points[i].separation, m.points[i].id};
    }
    c.c[c.count++] = q;
  }
};

void push(Collector& col, const Vec3& n, const Vec3& x_B, double s, uint32_t id) {
  // x_B on the shape's surface; the reported point is the midpoint, x_B - (s/2) n.
  col.add(n, Candidate{Vec3(x_B - 0.5 * s * n), s, id});
}

// Whether vertex k of t is the nearest point of the mesh around it to a shape in direction nu
// from it: no edge of the mesh leaving the vertex (those of every triangle around it, found
// through the tree) goes toward the shape, nu . (w - v) <= 0 for each other end w. Otherwise a
// point along that edge is nearer: the vertex is not where the shape touches, and its contact
// plane (through the vertex, normal nu) cuts through the mesh there, so it is no separating plane.
// edge_rule sees only the two edges of t itself: on a straight convex edge of a closed mesh, the
// vertices farther along it passed, and a ball sliding off a wall's edge at 36 m/s got contacts
// on them within the speculative distance (6 and 48 mm, normals tilted 36 and 70 degrees along
// the edge, closing at 5 and 12 m/s) and left with a 4.5 m/s kick away from the face.
bool vertex_is_nearest(const WorldTri& t, int k, const Vec3& nu) {
  const TriMeshShape& M = *t.mesh;
  const int vi = t.v[k];
  const Vec3& v = M.vertices[vi];
  const Vec3 nu_M = t.R_WM->transpose() * nu;
  const Vec3 tiny = Vec3::Constant(1e-9 * (1.0 + v.cwiseAbs().maxCoeff()));
  bool nearest = true;
  M.bvh.query(v - tiny, v + tiny, [&](int ti) {
    const MeshTriangle& T = M.triangles[ti];
    for (int j = 0; j < 3 && nearest; ++j) {
      if (T.v[j] != vi) continue;
      for (int o : {T.v[(j + 1) % 3], T.v[(j + 2) % 3]}) {
        const Vec3 e = M.vertices[o] - v;
        if (nu_M.dot(e) > 1e-6 * e.norm()) nearest = false;  // (1e-6: room for GJK's normals)
      }
    }
  });
  return nearest;
}

// A contact on an active edge or vertex f of t with its own normal n (Action kKeep). Dropped when
// n points behind the triangle (one-sided, as a face contact: at a closed mesh's convex edge the
// neighbour, which the shape is in front of, gives the same contact; at an open sheet's boundary
// a shape behind it is not held there), and at a vertex that is not the mesh's nearest point.
void push_feature(Collector& col, const WorldTri& t, int f, const Vec3& n, const Vec3& x_B, double s,
                  uint32_t id) {
  if (n.dot(t.n) < 0) return;
  if (f >= 4 && !vertex_is_nearest(t, f - 4, n)) return;
  push(col, n, x_B, s, id);
}

// ------------------------------------------------------------------ sphere
void sphere_triangle(const WorldTri& t, const CollideShape& b, const Pose& xb, double spec, Collector& col) {
  const Vec3 q = xb.p;
  const double r = b.radius;
  int f;
  const Vec3 cp = closest_on_triangle(q, t.p[0], t.p[1], t.p[2], f);
  const Vec3 v = q - cp;
  const double dist = v.norm();
  if (dist > r + spec) return;
  const Vec3 nu = dist > 1e-12 * r ? Vec3(v / dist) : t.n;
  const Action act = edge_rule(t, f, nu);
  if (act == kDrop) return;
  if (act == kKeep) {
    push_feature(col, t, f, nu, Vec3(q - r * nu), dist - r, 0);
    return;
  }
  // The face's own region: the distance to its plane. An inactive edge or vertex: the face normal
  // with the true distance (never deeper than the neighbour's face contact on a flat or convex
  // fold, so it never lifts the sphere there; it keeps the contact in a concave crease).
  const double d = t.n.dot(q - t.p[0]);
  if (d < -r) return;  // one-sided: the centre is more than a radius behind
  const double s = f == 0 ? d - r : dist - r;
  if (s <= spec) push(col, t.n, Vec3(q - r * t.n), s, 0);
}

// ------------------------------------------------------------------ capsule
void capsule_triangle(const WorldTri& t, const CollideShape& b, const Pose& xb, double spec, Collector& col) {
  const Vec3 P0 = xb.apply(Vec3(0, 0, -b.half_length)), P1 = xb.apply(Vec3(0, 0, b.half_length));
  const double r = b.radius;
  double best = INFINITY;
  int feat = 0;
  Vec3 cseg = P0, ctri = P0;
  for (const Vec3& e : {P0, P1}) {
    int f;
    const Vec3 c = closest_on_triangle(e, t.p[0], t.p[1], t.p[2], f);
    const double d2 = (e - c).squaredNorm();
    if (d2 < best) best = d2, feat = f, cseg = e, ctri = c;
  }
  for (int k = 0; k < 3; ++k) {
    double s, u;
    Vec3 c1, c2;
    closest_segments(P0, P1, t.p[k], t.p[(k + 1) % 3], s, u, c1, c2);
    const double d2 = (c1 - c2).squaredNorm();
    if (d2 < best) {
      best = d2, cseg = c1, ctri = c2;
      feat = u <= 0 ? 4 + k : (u >= 1 ? 4 + (k + 1) % 3 : 1 + k);
    }
  }
  const double d0 = t.n.dot(P0 - t.p[0]), d1 = t.n.dot(P1 - t.p[0]);
  if ((d0 < 0) != (d1 < 0)) {
    const Vec3 x = P0 + (d0 / (d0 - d1)) * (P1 - P0);
    if (inside(t, x, 0)) best = 0, feat = 0, cseg = ctri = x;
  }
  if (best > (r + spec) * (r + spec)) return;
  const double dist = std::sqrt(best);
  const Vec3 nu = dist > 1e-12 * r ? Vec3((cseg - ctri) / dist) : t.n;
  const Action act = edge_rule(t, feat, nu);
  if (act == kDrop) return;
  if (act == kKeep) {
    push_feature(col, t, feat, nu, Vec3(cseg - r * nu), dist - r, feature_id(t.index, feat));
    return;
  }
  // Face: the segment clipped to the triangle's side planes.
  double t0 = 0, t1 = 1;
  const Vec3 D = P1 - P0;
  for (int k = 0; k < 3 && t0 <= t1; ++k) {
    const double f0 = t.side[k].dot(P0 - t.p[k]), fd = t.side[k].dot(D);
    if (fd == 0) {
      if (f0 > 0) t0 = 2;  // wholly outside
      continue;
    }
    const double tc = -f0 / fd;
    if (fd > 0)
      t1 = std::min(t1, tc);
    else
      t0 = std::max(t0, tc);
  }
  if (t0 > t1) {
    // Nothing of the segment over the triangle (an inactive edge or vertex is nearest): the
    // nearest point, along the face normal, at its true distance.
    if (feat != 0 && dist - r <= spec) {
      const double sep = dist - r;
      col.defer(t.n, Candidate{Vec3(cseg - r * t.n - 0.5 * sep * t.n), sep, feature_id(t.index, feat)});
    }
    return;
  }
  for (int e = 0; e < 2; ++e) {
    const double tp = e == 0 ? t0 : t1;
    if (e == 1 && t1 == t0) break;
    const Vec3 x = P0 + tp * D;
    const double d = t.n.dot(x - t.p[0]);
    if (d < -r) continue;
    const double s = d - r;
    if (s > spec) continue;
    const uint32_t id = (tp == 0.0) ? 0u : (tp == 1.0 ? 1u : clip_id(t.index, 3, e));
    push(col, t.n, Vec3(x - r * t.n), s, id);
  }
}

// ------------------------------------------------------------------ box, hull, cylinder, ellipsoid
// The shape's exact points against the triangle's plane, kept over the triangle; returns how many.
int face_points(const WorldTri& t, const CollideShape& b, const Pose& xb, double spec, Collector& col) {
  const Vec3& n = t.n;
  const double tol = 1e-9 * std::max(1.0, b.bounding_radius);
  int added = 0;
  auto keep = [&](const Vec3& x, uint32_t id) {
    const double s = n.dot(x - t.p[0]);
    if (s <= spec) push(col, n, x, s, id), ++added;
  };
  switch (b.kind) {
    case CollideKind::box:
    case CollideKind::hull: {
      const ConvexPolyhedron& H = *b.hull;
      const Vec3 m = xb.R.transpose() * n;
      int inc = 0;
      double md = INFINITY;
      for (int f = 0; f < (int)H.faces.size(); ++f) {
        const double d = H.faces[f].normal.dot(m);
        if (d < md) md = d, inc = f;
      }
      struct PV {
        Vec3 x;
        uint32_t id;
      };
      PV buf[2][kMaxPoly];
      int cnt = 0;
      const int e0 = H.faces[inc].edge;
      int e = e0;
      do {
        if (cnt < kMaxPoly - 4)
          buf[0][cnt++] = {xb.apply(H.vertices[H.edges[e].origin]), (uint32_t)H.edges[e].origin};
        e = H.edges[e].next;
      } while (e != e0);
      int cur = 0;
      for (int k = 0; k < 3 && cnt > 0; ++k) {
        const PV* in = buf[cur];
        PV* out = buf[1 - cur];
        int m2 = 0;
        for (int i = 0; i < cnt; ++i) {
          const PV& a = in[i];
          const PV& c = in[(i + 1) % cnt];
          const double fa = t.side[k].dot(a.x - t.p[k]), fc = t.side[k].dot(c.x - t.p[k]);
          if (fa <= tol) out[m2++] = a;
          if ((fa <= tol) != (fc <= tol) && m2 < kMaxPoly) {
            const double u = fa / (fa - fc);
            out[m2++] = {Vec3(a.x + u * (c.x - a.x)), clip_id(t.index, k, i)};
          }
        }
        cnt = m2;
        cur = 1 - cur;
      }
      for (int i = 0; i < cnt; ++i) keep(buf[cur][i].x, buf[cur][i].id);
      break;
    }
    case CollideKind::cylinder: {
      Vec3 q[5];
      cylinder_rim_points(b, xb, n, q);
      for (int i = 0; i < 5; ++i)
        if (inside(t, q[i], tol)) keep(q[i], (uint32_t)i);
      break;
    }
    case CollideKind::ellipsoid: {
      const Vec3 m = xb.R.transpose() * n;
      const Vec3 rm = b.radii.cwiseProduct(m);
      const Vec3 q = xb.apply(Vec3(-b.radii.cwiseProduct(rm) / rm.norm()));
      if (inside(t, q, tol)) keep(q, 0);
      break;
    }
    default:
      break;
  }
  return added;
}

void convex_triangle(const WorldTri& t, const CollideShape& b, const Pose& xb, double spec, Collector& col) {
  const Support B(b, xb);
  // Quick rejects: wholly above the plane by more than the speculative distance, or wholly behind.
  if (t.n.dot(B.support_W(-t.n) - t.p[0]) > spec) return;
  if (t.n.dot(B.support_W(t.n) - t.p[0]) < 0) return;
  // Boxes and hulls on a triangle whose features are all inactive (inside a flat or concave patch):
  // always a face contact, and the incident face clipped to the triangle finds every part of it
  // over the triangle, so GJK/EPA is skipped. A cylinder's or ellipsoid's few exact points may all
  // lie beyond the triangle while the body overlaps it: those always run GJK/EPA.
  const bool polyhedral = b.kind == CollideKind::box || b.kind == CollideKind::hull;
  if (t.active != 0 || !polyhedral) {
    // GJK/EPA against the triangle as a three-vertex hull centred on its centroid.
    Pose tp;
    const CollideShape ts = triangle_hull(t.p, tp);
    const Support A(ts, tp);
    const CoreDistance d = core_distance(A, B);
    if (d.separation > spec) return;
    const int f = feature_of(t, d.pA);
    const Action act = edge_rule(t, f, d.normal);
    if (act == kDrop) return;
    if (act == kKeep) {
      push_feature(col, t, f, d.normal, d.pB, d.separation, feature_id(t.index, f));
      return;
    }
    // A face contact, or an inactive edge or vertex: if none of the shape's exact points lies over
    // the triangle (a cylinder lying across it, a shape reaching past a concave crease), GJK/EPA's
    // point along the face normal, deferred (Collector::finish).
    // Apart: GJK's true distance; overlapping: EPA's depth is along its own axis, not the face
    // normal, so the depth of the shape's deepest point below the face's plane stands for it.
    if (face_points(t, b, xb, spec, col) == 0 && d.separation <= spec) {
      Vec3 x = d.pB;
      double sep = d.separation;
      if (sep <= 0) {
        x = B.support_W(-t.n);
        sep = t.n.dot(x - t.p[0]);
      }
      col.defer(t.n, Candidate{Vec3(x - 0.5 * sep * t.n), sep, feature_id(t.index, f)});
    }
    return;
  }
  face_points(t, b, xb, spec, col);
}

}  // namespace

CollideShape triangle_hull(const Vec3 tri[3], Pose& pose) {
  thread_local ConvexPolyhedron hull = [] {
    ConvexPolyhedron p;
    p.vertices.resize(3);
    return p;
  }();
  CollideShape s;
  s.kind = CollideKind::hull;
  s.hull = &hull;
  pose = Pose();
  pose.p = (tri[0] + tri[1] + tri[2]) / 3.0;
  double rad = 0;
  for (int k = 0; k < 3; ++k) {
    hull.vertices[k] = tri[k] - pose.p;
    rad = std::max(rad, hull.vertices[k].norm());
  }
  s.bounding_radius = rad;
  return s;
}

}  // namespace collide_detail

int collide_mesh(const CollideShape& mesh, const Pose& xm, const CollideShape& b, const Pose& xb,
                 const Vec3& lo_W, const Vec3& hi_W, double speculative, Manifold out[kMaxMeshManifolds]) {
  using namespace collide_detail;
  const TriMeshShape& M = *mesh.mesh;
  // The query box in the mesh frame: the box of the world box turned into it.
  const Vec3 c_W = 0.5 * (lo_W + hi_W), e_W = 0.5 * (hi_W - lo_W);
  const Vec3 c = xm.R.transpose() * (c_W - xm.p);
  const Vec3 e = xm.R.transpose().cwiseAbs() * e_W;
  Collector col;
  M.bvh.query(c - e, c + e, [&](int ti) {
    const MeshTriangle& T = M.triangles[ti];
    WorldTri t;
    t.mesh = &M;
    t.R_WM = &xm.R;
    for (int k = 0; k < 3; ++k) t.p[k] = xm.apply(M.vertices[T.v[k]]), t.v[k] = T.v[k];
    t.n = xm.R * T.normal;
    for (int k = 0; k < 3; ++k) {
      t.out_nb[k] = xm.R * T.out_nb[k];
      t.side[k] = (t.p[(k + 1) % 3] - t.p[k]).cross(t.n).normalized();
    }
    t.active = T.active;
    t.index = (uint32_t)ti;
    switch (b.kind) {
      case CollideKind::sphere:
        sphere_triangle(t, b, xb, speculative, col);
        break;
      case CollideKind::capsule:
        capsule_triangle(t, b, xb, speculative, col);
        break;
      case CollideKind::cylinder:
      case CollideKind::ellipsoid:
      case CollideKind::box:
      case CollideKind::hull:
        convex_triangle(t, b, xb, speculative, col);
        break;
      default:
        break;
    }
  });
  col.finish();
  for (int i = 0; i < col.n; ++i) reduce_mesh(col.cl[i].c, col.cl[i].count, col.cl[i].n, out[i]);
  return col.n;
}

}  // namespace simreel
