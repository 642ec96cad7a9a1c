// The collision hulls of a mesh collider on a moving body (convex hulls by qhull,
// sim/geometry/convex_hull.hpp). mesh_collider, which makes the whole collider with its exact mass
// properties, is public: include/simreel/body.hpp.
#pragma once
#include <memory>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/mesh.hpp>
#include "sim/geometry/convex_hull.hpp"
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

// Collision hulls of a mesh collider: the convex hull of all its vertices, or with `parts` one
// hull per connected part (triangles sharing a vertex position), in file order of each part's
// first triangle. max_vertices >= 4: each hull simplified to at most that many vertices
// (convex_polyhedron), how each went in `reductions` (if given, one per hull). Throws InputError
// when a part spans no volume.
std::vector<std::shared_ptr<const ConvexPolyhedron>> collision_hulls(
    const TriangleMesh& mesh, bool parts, int max_vertices = 0,
    std::vector<HullReduction>* reductions = nullptr);

}  // namespace simreel
