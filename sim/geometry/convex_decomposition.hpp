// An approximate convex decomposition of a closed triangle mesh, so that a concave body (a mug, a
// banana, an L-bracket) collides as itself rather than as its convex hull.
//
// The solid is split by axis-aligned planes into boxes (a k-d tree); each part is the convex hull
// of the solid inside its box: the mesh's triangles clipped to the box, and the box's corners that
// lie inside the solid. Those hulls are disjoint (each lies in its box) and each holds its piece,
// so together they cover the solid exactly and exceed it only by their pieces' concavity. The part
// whose hull stands off its piece's surface most is split next (then, once none stands off more
// than `max_concavity`, the one whose hull exceeds its piece most), at the plane that leaves the
// least hull volume, until the hulls' excess is under `max_excess` of the solid's volume and none
// stands off more than that, or there are `max_parts`.
// V-HACD works the same way on voxels and then fits hulls to voxel surfaces (half a voxel too
// large); clipping the triangles keeps every hull inside the true surface's hull.
//
// Deterministic: the same mesh and options give the same parts, bit for bit.
#pragma once
#include <memory>
#include <vector>

#include <simreel/mass_properties.hpp>
#include <simreel/mesh.hpp>
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

struct DecompositionOptions {
  int max_parts = 64;
  double max_excess = 0.02;  ///< the hulls' total volume over the solid's, minus 1, to stop at
  /// The most a part's hull may stand off the mesh's surface (the distance from a hull face's centre
  /// to the surface), as a fraction of the bounding box's diagonal: a bunny 0.2 m across, 1 mm.
  double max_concavity = 0.005;
  int resolution = 64;         ///< voxels along the longest side, for the pieces' volume estimates
  int candidates = 7;          ///< split planes tried per axis
  int max_hull_vertices = 64;  ///< each part's hull simplified to at most this many (0: none)
};

struct Decomposition {
  std::vector<std::shared_ptr<const ConvexPolyhedron>> parts;
  /// What each part is the hull of (convex_polyhedron(points[i], opt.max_hull_vertices) is
  /// parts[i], bit for bit): what a cache keeps.
  std::vector<std::vector<Vec3>> points;
  double solid_volume = 0;  ///< m^3, the mesh's (an open mesh's: its voxels', 64 along its longest side)
  bool closed = true;       ///< false: the mesh was open and read as the solid it nearly bounds
  double hull_volume = 0;   ///< m^3, the parts' together
  double excess() const { return solid_volume > 0 ? hull_volume / solid_volume - 1 : 0; }
};

// An open mesh (a scan with holes) is read as the solid it nearly bounds: a point is inside when two
// of three rays along the axes cross the surface an odd number of times, so a hole misleads only
// the rays through it. Throws InputError for a mesh with no faces or no volume.
Decomposition convex_decomposition(const TriangleMesh& mesh, const DecompositionOptions& opt = {});
// The parts' mass properties together at density 1 (mass = volume, m^3), in the mesh's frame: an
// open mesh's weight, read as the solid it nearly bounds.
MassProperties decomposition_mass(const Decomposition& d);

// The same decomposition rebuilt from its parts' points (a cache), with the solid's volume.
Decomposition decomposition_from_points(std::vector<std::vector<Vec3>> points, double solid_volume,
                                        int max_hull_vertices);

}  // namespace simreel
