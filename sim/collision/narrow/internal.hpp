// Narrow-phase internals shared by the pair functions (not part of the interface). See the design
// note at the top of sim/collision/narrow/collide.cpp for conventions, algorithms and tolerances.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/collision/narrow/manifold.hpp"

namespace simreel::collide_detail {

// A pair function: A's kind <= B's kind in CollideKind order (collide() swaps otherwise).
using PairFn = int (*)(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb,
                       double speculative, PairCache& cache, Manifold& out);

// PairCache::type values.
enum CacheType : uint8_t { kCacheNone = 0, kCacheFaceA = 1, kCacheFaceB = 2, kCacheEdges = 3 };

// Appends a point from A's surface point pA, the normal n (A to B) and the separation s: the
// reported point is the midpoint between the surfaces, pA + (s/2) n.
inline void push_point(Manifold& m, const Vec3& pA, const Vec3& n, double s, uint32_t id) {
  ManifoldPoint& q = m.points[m.count++];
  q.p_W = pA + (0.5 * s) * n;
  q.separation = s;
  q.id = id;
}

// A contact point before reduction: p_W is already the midpoint.
struct Candidate {
  Vec3 p_W;
  double s;
  uint32_t id;
};

// Writes at most four of the n candidates (s <= speculative already) into out: the deepest
// first, then the one furthest from it, then the two that maximise the quadrilateral's area on
// either side of that diagonal (projected on the plane normal to n). Ties go to the lowest index;
// with tie_depth (m) and tie_rel > 0 near-ties too: a later candidate displaces the one kept only
// when deeper by more than tie_depth, or farther or larger in area by more than tie_rel of the
// largest (triangles.cpp: clipped points equal to the shape's own to rounding stay behind them).
void reduce_to_manifold(const Candidate* c, int n, const Vec3& normal, Manifold& out, double tie_depth = 0,
                        double tie_rel = 0);

// Closest point to p on segment [a, b]; t in [0, 1] its parameter.
inline Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b, double& t) {
  const Vec3 ab = b - a;
  const double L2 = ab.squaredNorm();
  t = L2 > 0 ? std::clamp((p - a).dot(ab) / L2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Closest point of triangle (a, b, c) to q (Ericson, Real-Time Collision Detection, 5.1.5), and the
// feature it lies on: f = 0 the face, 1 + k edge k (vertex k to k + 1), 4 + k vertex k.
Vec3 closest_on_triangle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, int& f);

// Triangle tri as a three-vertex hull about its centroid (pose: the centroid, no rotation), for
// GJK/EPA against a triangle of a mesh. The hull is one per thread and reused, so nothing is
// allocated after a thread's first call; the shape is valid until that thread's next call.
CollideShape triangle_hull(const Vec3 tri[3], Pose& pose);

// Closest points c1 = p1 + s (q1 - p1), c2 = p2 + t (q2 - p2) of two segments (Ericson, Real-Time
// Collision Detection, 5.1.9), with the parallel case resolved to s = 0 (or its clamp).
void closest_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, double& s, double& t,
                      Vec3& c1, Vec3& c2);

// A unit vector perpendicular to unit u (deterministic).
inline Vec3 any_perpendicular(const Vec3& u) {
  const Vec3 t = std::fabs(u.x()) < 0.57735 ? Vec3::UnitX()
                                            : (std::fabs(u.y()) < 0.57735 ? Vec3::UnitY() : Vec3::UnitZ());
  return u.cross(t).normalized();
}

// Which feature of a cylinder with unit axis u faces a unit direction n: its cap when
// |u . n| >= kCosTol (~2.6 degrees, as curved_hull's face test), its side when |u . n| <= kSinTol
// (sqrt(1 - kCosTol^2)), else its rim.
constexpr double kCosTol = 0.999;
constexpr double kSinTol = 0.04471;

// The rim points of a cylinder against a plane of unit normal n (pointing from the plane to the
// cylinder), in the world: 0 the lower disk's deepest point (exact), 1 the upper disk's, 2-4 the
// lower disk's points at +90, -90 and 180 degrees from the deepest one.
void cylinder_rim_points(const CollideShape& cyl, const Pose& xc, const Vec3& n, Vec3 q[5]);

// Whether a manifold against a plane of normal n uses rim point i of cylinder_rim_points: the
// deepest always; the upper disk's only when the side faces the plane (a lying cylinder rests on
// both ends of its line), the other three only when the cap does (a standing one on four points).
// A cylinder on its rim touches at one point, and a speculative point in the manifold would move
// the friction centre (the solver applies friction at the centre of the manifold's points) off
// the contact: a disk rolling on its rim (Euler's disk, a rolling coin) was braked and toppled.
inline bool cylinder_rim_point_used(int i, const Vec3& axis_W, const Vec3& n) {
  const double c = std::fabs(axis_W.dot(n));
  return i == 0 || (i == 1 ? c <= kSinTol : c >= kCosTol);
}

// Feature ids of the cylinder-cylinder and capsule-cylinder points (cylinders.cpp): a tag per
// feature pair plus the point's index (lens: support direction 0-3, then 4 the deepest point;
// lines: end 0 or 1). kIdGeneric marks GJK/EPA's own point (no exact feature pair applied).
constexpr uint32_t kIdLens = 0x10, kIdLensDeep = 0x14, kIdCapSide = 0x20, kIdSides = 0x30, kIdCapRim = 0x40,
                   kIdCrossed = 0x41, kIdRimSide = 0x42, kIdRimRim = 0x43, kIdCapsuleCap = 0x50,
                   kIdCapsuleEnd = 0x52, kIdCapsuleSide = 0x60, kIdGeneric = 0x7F;

// ---------------------------------------------------------------- support mapping (GJK/EPA)
// A shape as GJK sees it: a core (sphere: its centre; capsule: its segment; the others: the
// whole solid) plus a margin (the sphere or capsule radius).
struct Support {
  const CollideShape* shape = nullptr;
  const Pose* pose = nullptr;
  double margin = 0;
  explicit Support(const CollideShape& s, const Pose& x);
  Vec3 support_W(const Vec3& d_W) const;  ///< a core point maximising d . p
  Vec3 centre_W() const { return pose->p; }
};

// Signed distance between the cores of two shapes: separation > 0 (GJK, exact to the tolerance)
// or < 0 (EPA penetration depth), normal from A to B, pA and pB the witness points on the cores.
struct CoreDistance {
  Vec3 pA = Vec3::Zero(), pB = Vec3::Zero(), normal = Vec3::UnitZ();
  double separation = 0;
  bool ok = true;  ///< false when EPA fell back to the centre-line axis
};
CoreDistance core_distance(const Support& A, const Support& B);
// GJK only: the distance (0 when the cores overlap, then normal is meaningless).
CoreDistance gjk_distance(const Support& A, const Support& B, bool& overlap);

// ---------------------------------------------------------------- pair functions (A kind <= B kind)
int plane_sphere(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                 Manifold&);
int plane_capsule(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                  Manifold&);
int plane_cylinder(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                   Manifold&);
int plane_ellipsoid(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                    Manifold&);
int plane_box(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
              Manifold&);
int plane_hull(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
               Manifold&);
int sphere_sphere(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                  Manifold&);
int sphere_capsule(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                   Manifold&);
int capsule_capsule(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                    Manifold&);
int sphere_box(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
               Manifold&);
int sphere_hull(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                Manifold&);
int capsule_hull(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                 Manifold&);
int box_box(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
            Manifold&);
int hull_hull(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
              Manifold&);
int curved_hull(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                Manifold&);
int cylinder_cylinder(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                      Manifold&);
int capsule_cylinder(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                     Manifold&);
int convex_generic(const CollideShape&, const Pose&, const CollideShape&, const Pose&, double, PairCache&,
                   Manifold&);

}  // namespace simreel::collide_detail
