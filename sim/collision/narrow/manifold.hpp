// The narrow phase's output: a contact manifold of up to four points between two convex shapes,
// with feature ids that stay the same while the same features touch (the solver warm-starts each
// point from the previous step's impulse by id, as Box2D v3 / Box3D do).
//
// Conventions:
//   - normal n points from shape A into shape B (world frame, unit);
//   - separation s of a point: signed distance between the surfaces along n, negative when they
//     overlap (m); points are reported while s <= speculative distance (speculative contacts);
//   - p_W is the midpoint between the two surfaces' points (A's point + (s/2) n);
//   - id: A's feature in the low 16 bits, B's in the high 16 bits, or any deterministic encoding
//     that is unique within the manifold and stable while the touching features stay the same.
#pragma once
#include <cstdint>

#include "sim/collision/narrow/geometry.hpp"

namespace simreel {

struct ManifoldPoint {
  Vec3 p_W = Vec3::Zero();  ///< m, world
  double separation = 0;    ///< m, negative = penetration
  uint32_t id = 0;          ///< feature pair id
};

struct Manifold {
  Vec3 normal_W = Vec3::UnitZ();  ///< from A to B
  int count = 0;                  ///< 0..4 points
  ManifoldPoint points[4];
};

// Per-pair state the narrow phase keeps between steps (a cached separating axis or feature for
// box and hull pairs, so a resting contact re-tests the same axis first). Default-initialised means
// "no cache". It is part of the saved world state (sim/world/snapshot), so a resumed run equals a
// straight one even where the cache decides between near-equal axes.
struct PairCache {
  uint8_t type = 0;        ///< 0 none; the rest is the pair function's own
  int32_t a = -1, b = -1;  ///< the cached feature indices (faces, edges or box axes)
};

// Collides A (at pose xa) with B (at pose xb). Fills `out` with the points whose separation is at
// most `speculative` (m) and returns out.count. The pair may come in either order: the function
// swaps internally and reports the normal from A to B. Deterministic: the same inputs (including
// the cache) give bit-identical output. Never allocates.
int collide(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, double speculative,
            PairCache& cache, Manifold& out);

}  // namespace simreel
