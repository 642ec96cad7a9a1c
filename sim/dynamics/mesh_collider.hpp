// A collider from a triangle mesh, for programs that build worlds in C++ (the scene loader in
// app/ does the same from a file): mass properties from the mesh's geometry (sim/mass/mesh_mass.hpp)
// and the convex hulls it collides as (sim/geometry/convex_hull.hpp).
#pragma once
#include <memory>
#include <vector>

#include "sim/dynamics/body.hpp"
#include "sim/mass/mesh_mass.hpp"
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

// Collision hulls of a mesh collider: the convex hull of all its vertices, or with `parts` one
// hull per connected part (triangles sharing a vertex position), in file order of each part's
// first triangle. Throws InputError when a part spans no volume.
std::vector<std::shared_ptr<const ConvexPolyhedron>> collision_hulls(const TriangleMesh& mesh, bool parts);

// A mesh collider of uniform density (kg/m^3): mass, centroid and inertia exactly from the mesh
// (after welding and orientation repairs, which `report` describes when given), colliding as its
// convex hull, or as one hull per connected part with `parts`. Collider frame = mesh axes at the
// body origin. Throws InputError for a mesh with no volume.
Collider mesh_collider(std::shared_ptr<const TriangleMesh> mesh, double density, bool parts = false,
                       MeshReport* report = nullptr);

}  // namespace simreel
