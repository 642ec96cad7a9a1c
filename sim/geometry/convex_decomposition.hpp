// An approximate convex decomposition of a closed triangle mesh, so that a concave body (a mug, a
// banana, an L-bracket) collides as itself rather than as its convex hull.
//
// The solid is split by axis-aligned planes into boxes (a k-d tree); each part is the convex hull
// of the solid inside its box: the mesh's triangles clipped to the box, and the box's corners that
// lie inside the solid. Those hulls are disjoint (each lies in its box) and each holds its piece,
// so together they cover the solid exactly and exceed it only by their pieces' concavity. The part
// whose hull exceeds its piece most is split next, at the plane that leaves the least hull volume,
// until the hulls' excess is under `max_excess` of the solid's volume or there are `max_parts`.
// V-HACD works the same way on voxels and then fits hulls to voxel surfaces (half a voxel too
// large); clipping the triangles keeps every hull inside the true surface's hull.
//
// Deterministic: the same mesh and options give the same parts, bit for bit.
#pragma once
#include <memory>
#include <vector>

#include <simreel/mesh.hpp>
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

struct DecompositionOptions {
  int max_parts = 32;
  double max_excess = 0.02;    ///< the hulls' total volume over the solid's, minus 1, to stop at
  int resolution = 64;         ///< voxels along the longest side, for the pieces' volume estimates
  int candidates = 7;          ///< split planes tried per axis
  int max_hull_vertices = 64;  ///< each part's hull simplified to at most this many (0: none)
};

struct Decomposition {
  std::vector<std::shared_ptr<const ConvexPolyhedron>> parts;
  /// What each part is the hull of (convex_polyhedron(points[i], opt.max_hull_vertices) is
  /// parts[i], bit for bit): what a cache keeps.
  std::vector<std::vector<Vec3>> points;
  double solid_volume = 0;  ///< m^3, the mesh's
  double hull_volume = 0;   ///< m^3, the parts' together
  double excess() const { return solid_volume > 0 ? hull_volume / solid_volume - 1 : 0; }
};

// Throws InputError for a mesh that is not a closed solid (analyze_mesh's rules) or spans no volume.
Decomposition convex_decomposition(const TriangleMesh& mesh, const DecompositionOptions& opt = {});
// The same decomposition rebuilt from its parts' points (a cache), with the solid's volume.
Decomposition decomposition_from_points(std::vector<std::vector<Vec3>> points, double solid_volume,
                                        int max_hull_vertices);

}  // namespace simreel
