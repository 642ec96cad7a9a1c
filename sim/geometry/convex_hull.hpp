// Convex hull of a point set, by Debian's qhull (libqhull_r, the reentrant C library: each call has
// its own qhT, so hulls may be built on several threads at once). Deterministic: the same points in
// the same order give the same hull, bit for bit.
//
// Robustness: qhull merges facets whose coplanarity is decided by roundoff ('C-0', its default in
// 3-d), so near-coplanar CAD points (a gear's flat caps written with a few ulps of noise) come out
// as one planar convex facet instead of a knot of slivers. Every hull vertex is one of the input
// points, unchanged; a point qhull leaves out lies within a few ulps of the hull's surface.
#pragma once
#include <simreel/mesh.hpp>
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

// The hull as triangles, counter-clockwise seen from outside (each hull face fanned from one of its
// corners). Throws InputError when the points span no volume (fewer than 4 points, all coincident,
// collinear or coplanar) or a coordinate is not finite.
TriangleMesh convex_hull(const std::vector<Vec3>& points);
// The hull with adjacency (sim/geometry/polyhedron.hpp): coplanar triangles merged into one convex polygon
// face, only extreme points as vertices, outward unit normals, volume centroid and inner radius.
// Throws InputError like convex_hull().
//
// max_vertices >= 4: a hull with more vertices than that is simplified to the hull of at most that
// many of them, each added where the hull so far is farthest from the points (qhull's 'TA', as
// MuJoCo's maxhullvert): an inner hull, a little smaller. `reduction` (if given) says how it went.
struct HullReduction {
  int vertices_before = 0, vertices = 0;
  double volume_ratio = 1;  ///< the hull's volume over the full hull's
};
ConvexPolyhedron convex_polyhedron(const std::vector<Vec3>& points, int max_vertices = 0,
                                   HullReduction* reduction = nullptr);

}  // namespace simreel
