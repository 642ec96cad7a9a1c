// Collision geometry as the narrow phase reads it: one flat record per collider shape, in the
// collider's own frame C (include/simreel/math.hpp), and a rigid pose C -> world. Mass properties are not
// here: include/simreel/body.hpp's Collider holds them, and a collider may collide as a simpler shape than it
// weighs (a mesh weighs as the exact mesh, collides as its convex hull).
#pragma once
#include <cstdint>

#include "sim/geometry/polyhedron.hpp"
#include <simreel/math.hpp>

namespace simreel {

struct TriMeshShape;

// Narrow-phase shape kinds, in the order the pair dispatch table uses.
// `mesh` (a static triangle mesh, sim/geometry/trimesh.hpp) pairs through collide_mesh() (sim/collision/narrow/mesh.hpp),
// not collide(): it gives several manifolds.
enum class CollideKind : uint8_t { plane, sphere, capsule, cylinder, ellipsoid, box, hull, mesh, count };
const char* to_string(CollideKind k);

struct CollideShape {
  CollideKind kind = CollideKind::sphere;
  // plane: the plane z = 0 of frame C, solid below (normal +z_C); static bodies only.
  double radius = 0;                       ///< m: sphere; capsule and cylinder (around z_C)
  double half_length = 0;                  ///< m: capsule, half the segment between its sphere centres (z_C);
                                           ///<    cylinder, half its height (z_C)
  Vec3 half_extents = Vec3::Zero();        ///< m: box
  Vec3 radii = Vec3::Zero();               ///< m: ellipsoid semi-axes along x_C, y_C, z_C
  const ConvexPolyhedron* hull = nullptr;  ///< hull (and box: make_box_polyhedron, owned elsewhere)
  const TriMeshShape* mesh = nullptr;      ///< mesh: the triangles and their tree (owned elsewhere)
  double bounding_radius = 0;              ///< m, about C's origin (planes: 0, unbounded)
};

// Rigid transform from a shape frame C to the world: p_W = R p_C + p.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();  ///< m
  Vec3 apply(const Vec3& x) const { return R * x + p; }
  Vec3 apply_inverse(const Vec3& x) const { return R.transpose() * (x - p); }
};

}  // namespace simreel
