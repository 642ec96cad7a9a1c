#include "sim/collision/tracked_contacts.hpp"

#include <cmath>

#include "sim/collision/contact.hpp"
#include "sim/collision/smooth_support.hpp"
#include "sim/solver/contact_solver.hpp"

namespace simreel {

namespace {

// A sphere whose centre is this close to the body's centre of mass keeps its contact point under
// the centre of mass: the step's constraint is exact for it (docs/contacts.md "Rolling on a
// curved surface"), nothing to track.
constexpr double kSphereOffset = 1e-9;  ///< m

// Whether the other shape is flat where it touches: a plane, or a box face whose normal is n. The
// support point along a fixed normal is the contact only on a flat surface.
bool flat_at(const ShapeRecord& O, const MotionState& s, const Vec3& n) {
  switch (O.geom.kind) {
    case CollideKind::plane:
      return true;
    case CollideKind::box: {
      const Vec3 c = (ShapeTable::world_pose(O, s).R.transpose() * n).cwiseAbs();
      return c.maxCoeff() > 1 - 1e-9;
    }
    default:
      return false;
  }
}

// The tracked shape's support point along d and its derivative (sim/collision/smooth_support.hpp).
bool support(const TrackedContact& t, const Vec3& d, Vec3& p, Mat3& J) {
  CollideShape g;
  g.kind = t.kind;
  g.radius = t.radius;
  g.half_length = t.half_length;
  g.radii = t.radii;
  return smooth_support(g, d, 0, p, J);
}

}  // namespace

bool track_begin(TrackedContact& t, ContactConstraint& k, const Contact& c, const ShapeTable& shapes,
                 const MotionState* state, int side) {
  const ShapeRecord& S = shapes[side > 0 ? c.shape_b : c.shape_a];
  const ShapeRecord& O = shapes[side > 0 ? c.shape_a : c.shape_b];
  const MotionState& s = state[side > 0 ? c.body_b : c.body_a];
  const MotionState& so = state[side > 0 ? c.body_a : c.body_b];
  const Pose x = ShapeTable::world_pose(S, s);
  t.side = side;
  t.kind = S.geom.kind;
  t.radius = S.geom.radius;
  t.half_length = S.geom.half_length;
  t.radii = S.geom.radii;
  t.R0 = x.R;
  t.c0 = x.p - s.x_W;
  t.m = side > 0 ? Vec3(-k.n) : k.n;
  switch (S.geom.kind) {
    case CollideKind::cylinder:  // against anything, as since the rim contacts came (a face, in practice)
      break;
    case CollideKind::sphere:
      if (t.c0.norm() <= kSphereOffset) return false;
      [[fallthrough]];
    case CollideKind::capsule:
    case CollideKind::ellipsoid:
      if (!flat_at(O, so, k.n)) return false;
      break;
    default:
      return false;
  }
  Vec3 p;
  Mat3 J;
  if (!support(t, (x.R.transpose() * t.m).normalized(), p, J)) return false;
  // The gap is followed through the tracked point itself (its pivot, cX = rX, is the anchor
  // track_point moves with the support point): adjusted_separation = s - n.(cB - cA) stays right.
  ConstraintPoint& q = k.p[0];
  if (side > 0) {
    q.cB = q.rB;
    t.x0 = q.rB;
    t.o0 = q.rA;
  } else {
    q.cA = q.rA;
    t.x0 = q.rA;
    t.o0 = q.rB;
  }
  q.adjusted_separation = c.points[0].separation - k.n.dot(q.cB - q.cA);
  return true;
}

// The point's motion over the surface. With x(t) the support point along m of the shape turned by
// R(t) (centre c(t) from the centre of mass), r = c + R p(R^T m) and, m fixed (the flat surface at
// rest; for a moving one w is the spin relative to it, to first order),
//   r' = w x r + R J R^T (m x w)        (d(R^T m)/dt = -R^T (w x m) = R^T (m x w)),
// the material point's turn plus the slide of the contact over the surface: slide = R J R^T.
// For a sphere off the centre of mass this is r' = w x (r - rho m) = w x c (the centre's turn);
// for the rim it is a t m.(w x t) / m.e, the envelope theorem over the rim's angle.
bool track_point(TrackedContact& t, ContactConstraint& k, const SolverBody& A, const SolverBody& B) {
  const SolverBody& X = t.side > 0 ? B : A;  // the tracked body
  const SolverBody& O = t.side > 0 ? A : B;
  const Mat3 R = X.dR * t.R0;
  Vec3 p;
  Mat3 J;
  if (!support(t, (R.transpose() * t.m).normalized(), p, J)) return false;  // keep the last point
  const Vec3 r = X.dR * t.c0 + R * p;
  t.slide = R * J * R.transpose();
  // The other body's anchor: the same world point (its surface is flat there).
  const Vec3 o = t.o0 + (X.dp + r - t.x0) - O.dp;
  ConstraintPoint& q = k.p[0];
  if (t.side > 0) {
    q.rB = r;
    q.cB = X.dR.transpose() * r;
    q.rA = o;
  } else {
    q.rA = r;
    q.cA = X.dR.transpose() * r;
    q.rB = o;
  }
  k.fA = q.rA;
  k.fB = q.rB;
  return true;
}

// The velocity terms J v = d.(vX + wX x r - ...) of a tracked point, d the normal or a tangent,
// hold at the substep's start; over the substep the contact runs over the surface, r changes at r'
// (track_point) and J v at d.(w x r') h per substep. Solving for J v = -d.(w x r') h / 2 instead of 0
// makes the gap after the move right to the third order in h and the contact's impulses workless
// on a rolling body: the material point under the contact at mid-substep is the one held still.
// (Solving for 0 stopped the contact's new material point at each substep like an inelastic
// collision and let the gap fall by h^2/2 m.(w x r') per substep, for the soft contact to push back:
// a disk in steady rolling on its rim lost or gained energy and lean at the first order in h,
// Omega^2 sin(alpha) off by 17-24% after 1 s at h = 1/960 s; the rattleback lost its rocking to
// these micro-impacts within a second at 1/240 s. Measured.) Returns sign (w x r') h / 2, sign +
// for B's surface, - for A's, w the tracked body's spin relative to the other's.
Vec3 track_turn(const TrackedContact& t, const ConstraintPoint& p, const Vec3& wA, const Vec3& wB, double h) {
  const bool onB = t.side > 0;
  const Vec3 w = onB ? Vec3(wB - wA) : Vec3(wA - wB);
  const Vec3& r = onB ? p.rB : p.rA;
  const Vec3 turn = w.cross(w.cross(r) + t.slide * t.m.cross(w));
  return (onB ? 0.5 * h : -0.5 * h) * turn;
}

}  // namespace simreel
