// Narrow phase: contact manifolds between two convex shapes.
//
// CONVENTIONS (sim/collision/narrow/manifold.hpp): the normal points from A into B in the caller's order;
// a point's separation is the signed distance between the two surfaces along the normal (< 0:
// overlap); its position is the midpoint between the surfaces; points with separation <=
// `speculative` are reported, at most four. Pair functions are written for A's kind <= B's kind
// (CollideKind order); collide() swaps the arguments otherwise, negates the normal and swaps the
// two 16-bit halves of each feature id. Everything is double precision, allocation-free and
// deterministic: loops run in index order and ties go to the lowest index.
//
// PAIRS AND ALGORITHMS
//   plane-sphere, plane-ellipsoid   1 point, closed form. The ellipsoid's deepest point along -n is
//                                   p_C = -diag(r^2) m / |diag(r) m|, m = R^T n (exact support).
//   plane-capsule                   2 points: the two hemisphere bottoms.
//   plane-cylinder                  the exact deepest rim point; with the side facing the plane
//                                   (axis within ~2.6 degrees of it) also the other end disk's (a
//                                   lying cylinder rests on 2 points), with the cap facing it
//                                   (axis within ~2.6 degrees of the normal) three more rim points
//                                   of the lower disk at 90 degree steps (a standing one on 4).
//                                   On its rim it touches at one point: a speculative point would
//                                   move the friction centre off the contact (cylinder-on-face the
//                                   same).
//   plane-box, plane-hull           every vertex below the speculative distance, reduced to 4.
//   sphere-sphere, sphere-capsule   closed form (closest point on the segment).
//   capsule-capsule                 segment-segment closest points (Ericson 5.1.9); 2 points when
//                                   the segments are parallel within 1e-3 rad and overlap along
//                                   their length.
//   sphere-box                      closest point on the box by clamping; centre inside: the
//                                   nearest face.
//   sphere-hull                     closest point on the faces (exact, no iteration); centre
//                                   inside: the face of least depth.
//   capsule-box, capsule-hull       Segment above the best face's plane with its lower end over
//                                   that face: exact from the face alone (the resting case, no
//                                   GJK). Otherwise GJK between the segment and the hull when they
//                                   are apart; SAT (hull faces, segment x hull edges) when the
//                                   segment touches the hull. When the normal is a hull face's
//                                   (within ~2.6 degrees) the segment is clipped against the
//                                   face's side planes (up to 2 points, as Box3D), kept only if
//                                   the clip keeps the deepest depth (else 1 exact point).
//   box-box                         SAT in closed form over the 15 axes (3 + 3 face normals, 9
//                                   edge-direction cross products; Gottschalk, Lin, Manocha,
//                                   "OBBTree", SIGGRAPH 1996), edge axes rejected on squares before
//                                   any square root; face contact by clipping the incident face's
//                                   rectangle against the reference face's 4 side planes in the
//                                   reference box's frame; up to 4 points. Same axis hysteresis,
//                                   cache and ids scheme as below (cache type 4: box edge axes).
//   box-hull, hull-hull             SAT over both bodies' face normals and the edge pairs whose
//                                   Gauss-map arcs intersect (D. Gregorius, "The Separating Axis
//                                   Test between Convex Polyhedra", GDC 2013), the last axis kept
//                                   in PairCache (type 1 face of A, 2 face of B, 3 edge pair) and
//                                   tested first (early out when separated by more than the
//                                   speculative distance); the cached face also wins ties within
//                                   kAbsTol. Axis choice with hysteresis: B's face wins over A's
//                                   only when its separation exceeds sA + 0.02 |sA| + kAbsTol,
//                                   an edge pair only when it exceeds max(face) + 0.1 |max(face)|
//                                   + kAbsTol (for overlaps, Gregorius's kRelFaceTol (0.98) * sA
//                                   + kAbsTol), kAbsTol = 1e-3 * (sum of the two inner
//                                   radii) - so a reported depth may exceed the minimum one by
//                                   those margins, never fall short of it. Face contact: reference
//                                   face; incident face = the most anti-parallel of the faces
//                                   around the other body's deepest vertex; Sutherland-Hodgman
//                                   clipping (CACM 17(1), 1974) against the reference face's side
//                                   planes, points kept below the reference plane + speculative,
//                                   reduced to 4 (clipped away entirely: the deepest vertex).
//                                   Edge contact: 1 point, the closest points of the two edges.
//                                   Cost: the edge loop is O(edges A x edges B): ~1 us for two
//                                   8-vertex hulls, ~4.5 us box against a 40-vertex hull, ~45 us
//                                   for two 40-vertex hulls (keep collision hulls small).
//   cylinder-box, cylinder-hull,    GJK/EPA (below) for the normal; when it is a hull face's
//   ellipsoid-box, ellipsoid-hull   normal (within ~2.6 degrees), the exact points against that
//                                   face's plane, as for a plane, those inside the face: the
//                                   cylinder's rim points (stands on 4 points, lies on 2, rolls on
//                                   its exact rim point), the ellipsoid's exact support point (no
//                                   EPA facets while it rolls on a face); otherwise GJK/EPA's
//                                   single point.
//   cylinder-cylinder,              GJK/EPA (below) for the normal and witnesses; the normal picks
//   capsule-cylinder                each shape's feature (cylinders.cpp): its cap when the axis is
//                                   within ~2.6 degrees of the normal, its side within ~2.6 degrees
//                                   of perpendicular, else its rim. Then exact geometry: cap on cap,
//                                   the lens where the discs overlap (projected along the reference
//                                   cap's normal, exact for a tilted incident disc: the rims'
//                                   crossings by Newton on the incident rim): its support points in
//                                   four directions (along and across the centre line, or the
//                                   incident body's x and y when the centres nearly coincide), plus
//                                   its deepest point (the support point down the incident cap's
//                                   slope) when more than 1e-5 x size deeper, reduced to 4; the
//                                   reference cap is kept in PairCache (type 1 A's, 2 B's). A side on
//                                   a cap: the side's line clipped to the disc exactly (2 points). Two
//                                   sides with axes parallel within ~2.6 degrees: the ends of the
//                                   axes' overlap, each from A's surface along the normal to B's
//                                   side. Otherwise one exact point: a rim on a cap (its deepest rim
//                                   point, as plane-cylinder), crossed sides (the axes' closest
//                                   points), a rim on a side or on a rim (Newton on the rim
//                                   parameters from EPA's witnesses: the rim point nearest the
//                                   side's axis; the rim pair joined perpendicular to both). A
//                                   capsule lying on a cap (its axis within ~2.6 degrees of the cap's
//                                   plane): its segment clipped to the disc, at capsule radius (2
//                                   points); an end on a cap: that end's sphere; alongside a side,
//                                   axes parallel: as two sides. A manifold that would not keep
//                                   GJK/EPA's depth (to 1e-7 x size; the lens: its deepest point),
//                                   or a pair no case covers: GJK/EPA's single point.
//   everything else                 GJK (Gilbert-Johnson-Keerthi, with Ericson's closest-point-on-
//   (sphere-cylinder; ellipsoid     simplex sub-algorithm) on the cores with the sphere/capsule
//   with all but box and hull)      radius as a margin; when the cores overlap, EPA (van den
//                                   Bergen 2001) from GJK's final simplex. 1 point.
//
//   static triangle mesh with     collide_mesh() (triangles.cpp), not this table: the mesh's tree
//   any of the above              gives the triangles near the shape, each collided in closed form
//                                 (sphere, capsule) or by GJK/EPA and face clipping, internal edges
//                                 handled, grouped into up to four manifolds by normal.
//
// REDUCTION (more than 4 candidates): the deepest point, then the point furthest from it in the
// contact plane, then the two points making the largest signed areas on either side of that
// diagonal (the quadrilateral of largest area containing the deepest point); ties to the lowest
// index, so the choice is deterministic.
//
// FEATURE IDS: plane pairs use the vertex or point index (plane-cylinder: 0 the lower disk's
// deepest rim point, 1 the upper disk's, 2-4 the lower disk's points at +90, -90, 180 degrees from
// it); polyhedron face contacts use (feature of the incident polygon edge, feature of the clip
// plane) with 14-bit indices tagged by kind (incident vertex, incident half-edge 0x4000,
// reference side plane 0x8000), so they persist while the same features touch; an unclipped
// incident vertex is its vertex index; cylinder and capsule-cylinder points carry a tag per
// feature pair plus the point's index (internal.hpp: kIdLens + direction 0-3, kIdLensDeep,
// kIdCapSide / kIdSides / kIdCapsuleCap / kIdCapsuleSide + line end 0-1, one exact point's own
// tag, kIdGeneric for GJK/EPA's point). Ids are unique within a manifold. Hulls may have at most
// 16383 half-edges for the ids to stay unique.
//
// SHAPES: a box needs `hull` (its make_box_polyhedron) for box-hull and capsule-box; box-box,
// box-plane and sphere-box read only half_extents. Plane-plane gives no contact.
//
// TOLERANCES: GJK stops when |v|^2 - v.w <= 1e-12 |v|^2 (relative gap), when a support point
// repeats, or after 64 iterations; |v| <= 1e-10 * (size of the pair) counts as touching. EPA stops
// when the support along the closest face's normal gains <= 1e-9 * size, after 64 iterations, or
// when its 64 vertices / 128 faces are used up (the best face so far is returned). Incident faces
// with more than kMaxFaceVerts = 64 vertices are clipped as a 64-vertex sub-polygon (every k-th
// vertex); hulls with more than 128 vertices, faces or edges transform them on the fly (slower, same
// result). Stack use: hull_hull ~40 KB (fixed arrays), EPA ~20 KB, the rest under 4 KB.
#include <simreel/profile.hpp>
#include "sim/base/enum_names.hpp"
#include "sim/collision/narrow/internal.hpp"

namespace simreel {

namespace {
constexpr EnumNames<CollideKind, (std::size_t)CollideKind::count> kCollideKinds{
    {"plane", "sphere", "capsule", "cylinder", "ellipsoid", "box", "hull", "mesh"}};
static_assert(kCollideKinds.complete());
}  // namespace

const char* to_string(CollideKind k) {
  return kCollideKinds(k);
}

const char* narrow_kind_name(int k) {
  static_assert((int)CollideKind::count == Profile::kNarrowKinds);
  return k >= 0 && k < Profile::kNarrowKinds ? to_string((CollideKind)k) : "?";
}

namespace collide_detail {

void closest_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, double& s, double& t,
                      Vec3& c1, Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double tiny = 1e-30;
  if (a <= tiny && e <= tiny) {
    s = t = 0;
  } else if (a <= tiny) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= tiny) {
      t = 0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
}

void reduce_to_manifold(const Candidate* c, int n, const Vec3& normal, Manifold& out, double tie_depth,
                        double tie_rel) {
  out.normal_W = normal;
  out.count = 0;
  if (n <= 0) return;
  if (n <= 4) {
    for (int i = 0; i < n; ++i) out.points[out.count++] = {c[i].p_W, c[i].s, c[i].id};
    return;
  }
  // 1: deepest.
  int i1 = 0;
  for (int i = 1; i < n; ++i)
    if (c[i].s < c[i1].s - tie_depth) i1 = i;
  // 2: furthest from it in the contact plane.
  auto planar = [&](const Vec3& d) { return Vec3(d - normal.dot(d) * normal); };
  int i2 = -1;
  double best = -1;
  for (int i = 0; i < n; ++i) {
    if (i == i1) continue;
    const double d2 = planar(c[i].p_W - c[i1].p_W).squaredNorm();
    if (d2 > best + tie_rel * std::max(best, 0.0)) best = d2, i2 = i;
  }
  // 3 and 4: largest signed area on each side of the diagonal 1-2.
  const Vec3 e = c[i2].p_W - c[i1].p_W;
  const double atol = tie_rel * best;
  int i3 = -1, i4 = -1;
  double amax = 0, amin = 0;
  for (int i = 0; i < n; ++i) {
    if (i == i1 || i == i2) continue;
    const double a = e.cross(c[i].p_W - c[i1].p_W).dot(normal);
    if (a > amax + atol) amax = a, i3 = i;
    if (a < amin - atol) amin = a, i4 = i;
  }
  const int keep[4] = {i1, i2, i3, i4};
  for (int k : keep)
    if (k >= 0) out.points[out.count++] = {c[k].p_W, c[k].s, c[k].id};
}

namespace {
constexpr int K = (int)CollideKind::count;
struct Table {
  PairFn f[K][K] = {};
  constexpr Table() {
    using C = CollideKind;
    auto set = [&](C a, C b, PairFn fn) { f[(int)a][(int)b] = fn; };
    // Convex kinds only: a static mesh pairs through collide_mesh() (triangles.cpp).
    constexpr int kConvex = (int)C::mesh;
    for (int a = 1; a < kConvex; ++a)
      for (int b = a; b < kConvex; ++b) f[a][b] = convex_generic;
    set(C::plane, C::sphere, plane_sphere);
    set(C::plane, C::capsule, plane_capsule);
    set(C::plane, C::cylinder, plane_cylinder);
    set(C::plane, C::ellipsoid, plane_ellipsoid);
    set(C::plane, C::box, plane_box);
    set(C::plane, C::hull, plane_hull);
    set(C::sphere, C::sphere, sphere_sphere);
    set(C::sphere, C::capsule, sphere_capsule);
    set(C::capsule, C::capsule, capsule_capsule);
    set(C::sphere, C::box, sphere_box);
    set(C::sphere, C::hull, sphere_hull);
    set(C::capsule, C::cylinder, capsule_cylinder);
    set(C::cylinder, C::cylinder, cylinder_cylinder);
    set(C::capsule, C::box, capsule_hull);
    set(C::capsule, C::hull, capsule_hull);
    set(C::cylinder, C::box, curved_hull);
    set(C::cylinder, C::hull, curved_hull);
    set(C::ellipsoid, C::box, curved_hull);
    set(C::ellipsoid, C::hull, curved_hull);
    set(C::box, C::box, box_box);
    set(C::box, C::hull, hull_hull);
    set(C::hull, C::hull, hull_hull);
  }
};
const Table kTable;
}  // namespace

}  // namespace collide_detail

int collide(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double speculative,
            PairCache& cache, Manifold& out) {
  using namespace collide_detail;
  out.count = 0;
  out.normal_W = Vec3::UnitZ();
  const int ka = (int)a.kind, kb = (int)b.kind;
  if (ka >= K || kb >= K) return 0;
  if (ka <= kb) {
    const PairFn f = kTable.f[ka][kb];
    return f ? f(a, xa, b, xb, speculative, cache, out) : 0;
  }
  const PairFn f = kTable.f[kb][ka];
  if (!f) return 0;
  f(b, xb, a, xa, speculative, cache, out);
  out.normal_W = -out.normal_W;
  for (int i = 0; i < out.count; ++i) {
    const uint32_t id = out.points[i].id;
    out.points[i].id = (id >> 16) | (id << 16);
  }
  return out.count;
}

}  // namespace simreel
