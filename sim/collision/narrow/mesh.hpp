// Contacts between a static triangle mesh (CollideKind::mesh, sim/geometry/trimesh.hpp) and a convex shape.
// Design (docs/collision.md, "Static triangle meshes"): the triangles whose boxes overlap the shape's
// box, from the mesh's tree; each triangle against the shape (closed form for spheres and
// capsules; GJK/EPA, then face clipping, for the others); internal-edge handling on each result;
// the results grouped by normal into at most kMaxMeshManifolds manifolds of up to four points.
#pragma once
#include "sim/collision/narrow/manifold.hpp"

namespace simreel {

constexpr int kMaxMeshManifolds = 4;

// Contacts between the static triangle mesh `mesh` at pose xm and the convex shape b at pose xb,
// among the triangles whose boxes overlap the world box [lo_W, hi_W] (the shape's box, grown as
// the broad phase grows it). Each manifold's normal points from the mesh into b; its points are
// within `speculative` (m). Writes up to kMaxMeshManifolds manifolds into out and returns how
// many. Deterministic (triangles in the tree's fixed order), allocation-free.
int collide_mesh(const CollideShape& mesh, const Pose& xm, const CollideShape& b, const Pose& xb,
                 const Vec3& lo_W, const Vec3& hi_W, double speculative, Manifold out[kMaxMeshManifolds]);

}  // namespace simreel
