// Convex hull of a point set (incremental algorithm, deterministic: points are inserted in input
// order). Faces are counter-clockwise seen from outside.
#pragma once
#include "sim/mesh_mass.hpp"
#include "sim/polyhedron.hpp"

namespace simreel {

// Throws InputError when the points span no volume (fewer than 4 points, or all coplanar).
TriangleMesh convex_hull(const std::vector<Vec3>& points);
// The hull with adjacency (sim/polyhedron.hpp), for collision.
ConvexPolyhedron convex_polyhedron(const std::vector<Vec3>& points);

}  // namespace simreel
