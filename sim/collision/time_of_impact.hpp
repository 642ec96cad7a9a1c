// Continuous collision: the time of impact of two convex shapes carried by two moving bodies
// within a step, by conservative advancement on GJK distances (B. Mirtich, "Impulse-based dynamic
// simulation of rigid body systems", PhD thesis, Berkeley 1996, ch. 3; the bound below is his).
// The stage that uses it (World::stage_continuous, sim/world/continuous.cpp; docs/continuous-collision.md)
// sweeps each fast body from its pose at the step's start to its pose at the end.
//
// A body's sweep: its centre of mass moves on the straight line x0 -> x1 and its orientation
// turns at a constant rate from q0 to q1 (slerp, the shorter way: a body turning more than half a
// turn in one step is not followed; World::check_spin warns long before). A point of the body at
// distance r from the centre of mass then moves, per unit of the step's fraction t, at most
// |x1 - x0| along the line plus theta r, theta the angle from q0 to q1.
//
// Conservative advancement: with d the distance at fraction t and n the unit direction between the
// closest points (A to B), the gap can close no faster than
//   rate = n . (dxA - dxB) + thetaA rA + thetaB rB,
// so t may advance by (d - target) / rate without the shapes coming closer than target. For two
// translating shapes the distance is a convex function of t (the distance from a moving point to
// the fixed Minkowski difference), the tangent bound is exact and a negative rate proves they never
// meet; with rotation the bound follows Mirtich. It stops when d <= target + tolerance (a hit at
// that t), when the remaining step cannot close the gap (no hit), or after kToiMaxIterations (then
// the last t, still before contact, is reported as a hit: conservative).
#pragma once
#include "sim/collision/shape_table.hpp"

namespace simreel {

// One body's motion over a step.
struct Sweep {
  Vec3 x0 = Vec3::Zero();      ///< m, centre of mass at the step's start, world
  Vec3 dx = Vec3::Zero();      ///< m, its displacement over the step
  Quat q0 = Quat::Identity();  ///< principal frame to world at the start (MotionState::q_WP)
  Quat q1 = Quat::Identity();  ///< ... at the end
  double angle = 0;            ///< rad, the rotation from q0 to q1 (in [0, pi])
  bool moves = false;          ///< dx or angle non-zero
  Vec3 x_at(double t) const { return x0 + t * dx; }
  Quat q_at(double t) const;  ///< slerp, unit
};
Sweep make_sweep(const Vec3& x0, const Quat& q0, const Vec3& x1, const Quat& q1);

// World pose of shape r when its body's centre of mass is at x with orientation q (q_WP).
Pose shape_pose(const ShapeRecord& r, const Vec3& x, const Quat& q);

// m, the smallest width of a (non-plane) shape: a sphere's or capsule's diameter, a box's smallest
// side, a cylinder's smaller of diameter and height, an ellipsoid's smallest axis, a hull's
// smallest distance between a face plane and the opposite support point. 0 for planes.
double min_width(const CollideShape& g);

// m, distance between two shapes at poses xa, xb (negative or zero when they touch; planes are
// half-spaces), and the unit direction n from A's closest point to B's. Kinds the sweep does not
// know (none today) report +infinity.
double shape_distance(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, Vec3& n);

struct ToiInput {
  const CollideShape* a = nullptr;  ///< shape A and its pose in its body's principal frame
  Mat3 R_PA = Mat3::Identity();
  Vec3 p_PA = Vec3::Zero();
  const Sweep* sa = nullptr;
  double reach_a = 0;  ///< m, farthest point of A from its body's centre of mass
  const CollideShape* b = nullptr;
  Mat3 R_PB = Mat3::Identity();
  Vec3 p_PB = Vec3::Zero();
  const Sweep* sb = nullptr;
  double reach_b = 0;
  double target = 1e-4;       ///< m, the gap to stop at
  double tolerance = 2.5e-5;  ///< m, how close to target counts as arrived
  /// B is instead this still triangle (three world points, counter-clockwise about its front
  /// normal: a static mesh's triangle); b, R_PB, p_PB and reach_b are then unused, sb may be null.
  const Vec3* tri_b = nullptr;
};

struct ToiOutput {
  enum State { separated, hit, touching } state = separated;  ///< touching: within target at t = 0
  double t = 1;                                               ///< fraction of the step at the hit
  Vec3 normal = Vec3::UnitZ();                                ///< A to B at the hit
  int iterations = 0;                                         ///< distance queries
};

constexpr int kToiMaxIterations = 40;

ToiOutput time_of_impact(const ToiInput& in);

// m, distance between shape a at pose xa and the triangle tri (three world points), and the unit
// direction n from a's closest point to the triangle's (a sphere in closed form, Ericson 5.1.5; the
// others by GJK against the triangle). Zero or negative when they touch.
double triangle_distance(const CollideShape& a, const Pose& xa, const Vec3 tri[3], Vec3& n);

// time_of_impact with the fallback for a pair touching at the start, for the sides flagged in
// `core` (bit 0: A, bit 1: B; a side that is swept): such a side sweeps instead its core, a
// sphere of a quarter of its smallest width about its centre, against the other shape whole, so
// that a body already touching a thin wall or plate still cannot pass through it (a core arrives
// at most a quarter of the shape's width deep); and if the core touches too, its centre, which may
// approach the other shape by half its distance at the start but never cross it. Never returns
// `touching`: a pair touching at the start that no fallback stops is `separated` (the solver
// handles it). Against a triangle (tri_b) only A falls back, and only while its centre is in
// front of the triangle's plane (one-sided, as the narrow phase: sim/collision/narrow/triangles.cpp).
ToiOutput time_of_impact_guarded(const ToiInput& in, int core);

// The earliest time of impact of the swept convex shape in.a (on sweep in.sa; in.b and in.sb
// unused) with the triangles of the static triangle mesh `mesh` (CollideKind::mesh) at pose xm,
// among those whose boxes meet the world box [lo_W, hi_W] (the shape's box over its sweep),
// in the tree's fixed order. One-sided, as the narrow phase: a triangle the shape starts wholly
// behind is passed through. guarded: each triangle by time_of_impact_guarded (the continuous
// stage); else a triangle within target at the start makes the answer `touching` (the
// speculative manifold taken ahead then falls back to the usual one). `triangle`: the hit
// triangle's index in the mesh, or -1. Deterministic; allocates nothing.
ToiOutput mesh_time_of_impact(const ToiInput& in, const CollideShape& mesh, const Pose& xm, const Vec3& lo_W,
                              const Vec3& hi_W, bool guarded, int* triangle = nullptr);

}  // namespace simreel
