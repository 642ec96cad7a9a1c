// A static triangle mesh as a collider: the surface exactly as given (open or closed, any number
// of parts), for static bodies (terrain, a bowl, a half-pipe). Built once at load: vertices
// welded by exact position, degenerate triangles dropped, each edge's neighbour found, and each
// edge and vertex marked active or not for internal-edge handling (docs/collision.md, "Internal
// edges"); a bounding-volume tree (sim/geometry/bvh.hpp) over the triangles.
//
// One-sided: a triangle's front is the side its vertices wind counter-clockwise around (the
// outward side of a closed mesh), and contacts push shapes out of the front.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/geometry/bvh.hpp"
#include <simreel/mesh.hpp>

namespace simreel {

struct MeshTriangle {
  int v[3] = {0, 0, 0};         ///< vertex indices, counter-clockwise seen from the front
  Vec3 normal = Vec3::UnitZ();  ///< unit, front side, shape frame
  // Per edge k (v[k] -> v[k+1]): the unit vector in the neighbour's plane, perpendicular to the
  // edge, pointing from the neighbour across the edge (zero for a boundary edge). A contact
  // normal nu at this edge with nu . out_nb[k] < 0 points into the neighbour's own face region,
  // where the neighbour's face contact stands for it.
  Vec3 out_nb[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  uint8_t active = 0;  ///< bit k: edge k is active; bit 3 + k: vertex k is active
};

struct TriMeshShape {
  std::vector<Vec3> vertices;  ///< m, shape frame, welded
  std::vector<MeshTriangle> triangles;
  Bvh bvh;                                    ///< over the triangles' boxes
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< m, bounds in the shape frame
  int dropped = 0;                            ///< degenerate triangles (zero area) left out
};

// Edges bent convex by more than this are active (Jolt's default active-edge threshold is 5
// degrees too): a contact there keeps its own normal; at a flatter, or a concave, edge it takes
// the triangle's face normal.
constexpr double kActiveEdgeAngle = 5.0 * 3.14159265358979323846 / 180.0;

// Builds the collider from a mesh (any winding is kept as given: it decides the front side).
// Throws InputError when no triangle has an area.
TriMeshShape make_trimesh_shape(const TriangleMesh& mesh, double active_edge_angle = kActiveEdgeAngle);

}  // namespace simreel
