// The contact solver's wide path: four manifolds of one colour solved at once, one per lane of
// a four-double vector (Box2D v3 / Box3D solve a colour's contacts in SIMD bundles the same way:
// Catto, "Solver2D" and Box2D's contact_solver.c, "wide" float lanes; here doubles).
//
// Which manifolds. Within a colour no two manifolds share a moving body (sim/solver/constraint_graph.hpp),
// so four of them are four independent solves. A lane does exactly what ManifoldSolve
// (contact_solver.cpp) does for a plain manifold, the same algorithm in the same order: the block
// solve of the resting points, the passes where it does not apply (every lane runs them, masked,
// until its own manifold has converged), friction at the centre, twist. Manifolds that need more
// stay on the scalar path: a tracked point, rolling resistance, restitution, regularised Coulomb
// friction (contacts.slip_speed), and the graph's overflow set (solved in sequence). Bundles are
// made per colour in slot order, so they, and every result, are the same for any thread count;
// a lane's arithmetic depends on nothing in the other lanes.
//
// Why. The large pyramid's sweeps streamed 1.4 KB per manifold (its 15,000 manifolds, 21 MB,
// three times a substep, from the shared cache): the warm start ran at the cache's bandwidth and
// the solve had half of it again as arithmetic on one lane. A lane here is 0.65 KB: the lever
// arms r x n and the inertia products I^-1 (r x n) are made in the sweep from the anchors and the
// bodies (in the 1st-level cache), not stored, nor is what is cheap to make (a point's normal
// mass 1/K_ii, the second tangent n x t0, the softness), and an impulse's angular part is summed
// over the points before one product with I^-1 (warm start, block solve, friction).
#pragma once
#include <cstdint>

#include "sim/solver/contact_settings.hpp"
#include <simreel/math.hpp>

namespace simreel {

struct SolverBody;
struct ContactConstraint;
struct BodyImpulse;

// The block solve's regularisation of rigid rows: K + eps diag(K) for the singular K of a face on a
// face (four points on three degrees of freedom): velocities off by a relative 1e-8, far inside the
// passes' tolerance (1e-4), and the matrix well enough conditioned (1e8) for double.
constexpr double kBlockRegularisation = 1e-8;

namespace wide {

constexpr int kLanes = 4;  // (eight lanes of AVX-512 measured no faster: the sweeps wait on memory)
using Real = double __attribute__((vector_size(8 * kLanes)));        ///< a double per lane
using Mask = std::int64_t __attribute__((vector_size(8 * kLanes)));  ///< per lane: -1 true, 0 false

struct Vec {
  Real x, y, z;
};

// One point of each lane's manifold (a lane with fewer points: zeros). Its normal mass is 1 / K_ii
// (Bundle::K), taken where the passes need it, not stored.
struct Point {
  Vec cA, cB;                ///< m, each surface's centre of curvature from its centre of mass (world)
  Real adjusted_separation;  ///< m, separation - n.(cB - cA) at the step's start
  Real lever;                ///< m, distance from the friction centre (twist limit)
  Real normal_impulse;       ///< N s, accumulated (per substep)
};

// kLanes manifolds of one colour (an empty lane: bodies 0 and 0, no points). Only what the sweeps
// cannot make cheaply from the rest: they wait on memory as much as on arithmetic (the large
// pyramid streams its bundles, 9 MB, three times a substep).
struct alignas(64) Bundle {
  int a[kLanes], b[kLanes];  ///< solver bodies (0: the static body, never written)
  int count[kLanes];         ///< points, 0 to 4
  int contact[kLanes];       ///< index into the contact list (-1: an empty lane)
  // Each side's world inverse inertia R I^-1 R^T (xx, xy, xz, yy, yz, zz) at the step's start,
  // copied from its body (read from the body, it was two more cache lines of each of eight bodies
  // read at random); the step's start is also what K and the tangent mass are made with (a
  // tracked body's inertia, refreshed within the step, is not followed: like the scalar path's
  // constraints other than the tracked one).
  Real inv_IA[6], inv_IB[6];  ///< 1/(kg m^2)
  Vec n, t0;                  ///< normal (A to B) and first tangent, world (the second: n x t0)
  Real friction;              ///< dimensionless
  Real tangent_mass[3];       ///< kg, the 2x2 tangent mass at the centre, symmetric: 00, 01, 11
  Real twist_mass;            ///< kg m^2
  Vec fA, fB;                 ///< m, the friction centre from each centre of mass
  Real tangent_impulse0, tangent_impulse1, twist_impulse;  ///< N s, N s, N m s
  Point p[4];
  // The points' coupling K = J M^-1 J^T (K_ij: point i's normal velocity per unit impulse at
  // point j; symmetric, positive semi-definite), lower triangle row by row; an absent point's row
  // and column are the identity's. For the block solve (contact_wide.cpp).
  Real K[10];
  Mask touched;  ///< a point held an impulse at some time this step (ContactSolver::finish)
};

void clear_lane(Bundle& k, int lane);
// A lane from a constraint's full record (ContactSolver::make_constraint), its points' coupling K
// (10 values, as Bundle::K) and its bodies' world inverse inertia.
void set_lane(Bundle& k, int lane, const ContactConstraint& f, const double* K, const Mat3& inv_IA,
              const Mat3& inv_IB);

struct SolveParams {
  double inv_h, max_push, slop, apart;  ///< 1/s, m/s, m, m (as ManifoldSolve's)
  // The softness (Softness) of a pair of moving bodies [0] and of one with a static or kinematic
  // body [1] (ContactSolver::make_constraint's choice, made here from the bodies' masses), and
  // d = impulse_scale / mass_scale of each.
  double bias_rate[2], mass_scale[2], impulse_scale[2], d[2];  ///< 1/s, -, -, -
  int resting_passes;                                          ///< contacts.passes
  bool use_bias;                                               ///< solve (true) or relax (false)
  const BodyImpulse* start;  ///< per solver body, its velocities before the substep's impulses
};

// The warm start: each lane's accumulated impulses applied to its bodies.
void warm_start(const Bundle& k, SolverBody* sb);
// One Gauss-Seidel visit of each lane's manifold; returns whether one was struck (kImpactSpeed).
bool solve(Bundle& k, SolverBody* sb, const SolveParams& q);

}  // namespace wide
}  // namespace simreel
