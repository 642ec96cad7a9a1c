// A convex polyhedron with adjacency (half-edge structure): what a mesh collider on a dynamic body
// collides as, and what the narrow phase's separating-axis and face-clipping code reads. Built by
// convex_hull() (sim/geometry/convex_hull.hpp) from any point set, or by make_box_polyhedron() for a box.
//
// Conventions (checked by polyhedron_problem()):
//   - faces are planar convex polygons, coplanar hull triangles merged into one face; each face's
//     outward unit normal n and offset d satisfy n . v = d for its vertices, n . v <= d for all;
//   - half-edges come in twin pairs at indices 2k and 2k+1 (edge k joins them: edges[2k].origin ->
//     edges[2k+1].origin); `next` walks a face's boundary counter-clockwise seen from outside;
//   - vertices are exactly the hull's extreme points (no interior or mid-edge points).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

struct ConvexPolyhedron {
  struct HalfEdge {
    int origin = -1;  ///< vertex index this half-edge starts at
    int twin = -1;    ///< the opposite half-edge (index ^ 1)
    int next = -1;    ///< next half-edge around the same face, counter-clockwise from outside
    int face = -1;    ///< face on this half-edge's left (seen from outside)
  };
  struct Face {
    Vec3 normal = Vec3::Zero();  ///< outward unit normal, shape frame
    double offset = 0;           ///< m, normal . v for every vertex v of the face
    int edge = -1;               ///< one half-edge of the face
  };
  std::vector<Vec3> vertices;   ///< m, shape frame
  std::vector<HalfEdge> edges;  ///< twin pairs (2k, 2k+1)
  std::vector<Face> faces;
  Vec3 centroid = Vec3::Zero();  ///< m, volume centroid (a point well inside, for SAT and GJK seeds)
  double inner_radius = 0;       ///< m, distance from centroid to the nearest face plane

  // Per vertex, one half-edge leaving it; and the seeds support() climbs from on a hull of more
  // than kScanVertices vertices: the vertices extreme along 26 fixed directions (the faces, edges
  // and corners of a cube) and every k-th vertex, about 2 sqrt(n) of them. Every builder of a
  // polyhedron with edges calls build_adjacency(); without it support() scans.
  std::vector<int> vertex_edge, seeds;
  // Each face's half-edges in loop order from Face::edge: face f's are face_edges[face_begin[f] ..
  // face_begin[f + 1]) (a detailed face's every k-th corner without walking it). Empty until
  // build_adjacency().
  std::vector<int> face_begin, face_edges;

  int edge_count() const { return (int)edges.size() / 2; }
  // Index of a vertex maximising d . v. Up to kScanVertices vertices (or without adjacency): a
  // scan, ties to the lowest index. Beyond: from the seed nearest d, to the neighbour that gains
  // most until none gains (a local maximum of a linear function on a convex polyhedron is the
  // maximum): about sqrt(n) steps where a scan costs n (3,000 vertices: ~60 against 3,000).
  int support(const Vec3& d) const;
  static constexpr int kScanVertices = 48;
  void build_adjacency();  ///< vertex_edge, seeds and the face loops, from vertices, edges and faces
};

// m^3, the enclosed volume (faces fanned from their first vertex, tetrahedra from the centroid).
double polyhedron_volume(const ConvexPolyhedron& p);

// A box with half extents h (> 0), centred on the origin: 8 vertices, 6 faces, 12 edges.
ConvexPolyhedron make_box_polyhedron(const Vec3& h);

// Empty when `p` satisfies every convention above (to a relative tolerance `tol` of its size),
// otherwise the first violation found. For tests and for checking hulls as they are built.
std::string polyhedron_problem(const ConvexPolyhedron& p, double tol = 1e-9);

}  // namespace simreel
