// Contacts kept across steps: one record per pair of shapes whose bounding boxes overlap, with its
// manifold and the impulses the solver accumulated on each point, matched by feature id so the
// next step starts from them (warm starting). Part of the saved world state (sim/world/snapshot.hpp).
#pragma once
#include <cstdint>

#include "sim/collision/narrow/manifold.hpp"
#include "sim/base/pair_key.hpp"

namespace simreel {

struct ContactPoint {
  uint32_t id = 0;            ///< feature pair (sim/collision/narrow/manifold.hpp)
  Vec3 p_W = Vec3::Zero();    ///< m, world, when collided
  double separation = 0;      ///< m, negative = overlap, when collided
  double normal_impulse = 0;  ///< N s, accumulated over the last step (>= 0)
  /// m, B's anchor minus A's across the normal (zero but for a fast pair's manifold taken ahead,
  /// sim/world/continuous.cpp: there the two surface points meet only at the time of impact). Made afresh
  /// by every collide; not saved.
  Vec3 offset_W = Vec3::Zero();
};

struct Contact {
  int shape_a = -1, shape_b = -1;  ///< shape_a < shape_b (ShapeTable indices)
  int body_a = -1, body_b = -1;
  Vec3 normal_W = Vec3::UnitZ();  ///< from A to B
  int count = 0;                  ///< points in use (0: boxes overlap, shapes do not touch)
  ContactPoint points[4];
  PairCache cache;                         ///< narrow-phase cache (separating axis)
  Vec3 friction_impulse_W = Vec3::Zero();  ///< N s, at the manifold's centre, world (warm start)
  double twist_impulse = 0;                ///< N m s, about the normal
  Vec3 rolling_impulse = Vec3::Zero();     ///< N m s
  double friction = 0;                     ///< mixed: sqrt(f_a f_b)
  double restitution = 0;                  ///< mixed: max(e_a, e_b)
  uint64_t key() const { return pair_key(shape_a, shape_b); }
};

}  // namespace simreel
