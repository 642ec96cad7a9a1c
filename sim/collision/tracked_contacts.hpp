// Contacts whose point runs over a smooth surface (docs/contacts.md "Rolling on a curved surface"):
// a cylinder's rim, an ellipsoid (the rattleback), a sphere whose centre is off the centre of mass
// (the tippe top) or a capsule's end, touching a flat surface (a plane, a box face) with one point.
// Such a point is not a material point: as the body turns it runs over the surface (round the rim,
// along the ellipsoid), so the lever arms, the gap and the effective masses a constraint made once
// per step would hold for a point the contact has left. Here they follow it: after each substep's
// move the point is found again as the shape's support point along the surface's normal, and the
// constraint is made there, with the body's world inertia of that moment.
//
// The solver calls three things (sim/solver/contact_solver.cpp):
//   track_begin   in prepare, per one-point manifold: whether it is such a contact, and its record;
//   track_point   before each substep's velocity update (after the move and its relax): the support
//                 point, the anchors, the gap pivot and the map from spin to the contact's slide;
//   track_turn    in every solve of such a point: the workless velocity target (below).
#pragma once
#include "sim/collision/shape_table.hpp"
#include "sim/dynamics/state.hpp"
#include <simreel/math.hpp>

namespace simreel {

struct SolverBody;
struct ContactConstraint;
struct ConstraintPoint;
struct Contact;

struct TrackedContact {
  int con = -1;                            ///< the constraint's index in the solver's list
  int side = 0;                            ///< +1: the point runs over B's surface; -1: over A's
  CollideKind kind = CollideKind::sphere;  ///< sphere, capsule, cylinder (its rim) or ellipsoid
  double radius = 0, half_length = 0;      ///< m (sphere, capsule, cylinder)
  Vec3 radii = Vec3::Zero();               ///< m (ellipsoid)
  Mat3 R0 = Mat3::Identity();              ///< the shape frame's rotation, world, at the step's start
  Vec3 c0 = Vec3::Zero();  ///< m, the shape frame's origin from the body's centre of mass, world, step start
  Vec3 x0 = Vec3::Zero();  ///< m, the point's anchor on the tracked body at the step's start
  Vec3 o0 = Vec3::Zero();  ///< m, the other body's anchor at the step's start
  Vec3 m = Vec3::Zero();   ///< unit, from the tracked body towards the other (into the flat surface)
  /// m, world: the contact's slide over the tracked surface is slide (m x w), w the tracked body's
  /// spin relative to the other's (made by track_point; see there).
  Mat3 slide = Mat3::Zero();
};

// Whether contact c (one point; the constraint k made from it) is one whose point runs over the
// surface of the shape on `side` (+1: B's, -1: A's) against a flat surface, and if so its record
// t (the constraint's index set by the caller). Sets the point's gap pivot to the anchor (the gap is
// then followed through the tracked point exactly: track_point).
bool track_begin(TrackedContact& t, ContactConstraint& k, const Contact& c, const ShapeTable& shapes,
                 const MotionState* state, int side);

// The support point now (the tracked body turned by its dR so far this step), as the point's
// anchors and gap pivot, and t.slide. False (nothing changed) where the point is not unique: a
// cylinder square to the surface on its end face, a capsule lying on its side.
bool track_point(TrackedContact& t, ContactConstraint& k, const SolverBody& A, const SolverBody& B);

// The workless velocity target (see tracked_contacts.cpp): the constraint solves J v = -d.turn for
// each direction d (normal, tangents), turn = sign (w x r') h / 2.
Vec3 track_turn(const TrackedContact& t, const ConstraintPoint& p, const Vec3& wA, const Vec3& wB, double h);

}  // namespace simreel
