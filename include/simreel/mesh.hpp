// Exact mass properties of triangle meshes, with the checks a user needs to trust them.
//
// Solid: divergence theorem over signed tetrahedra (apex at a reference point near the mesh),
//   vol = sum d/6, first moment = sum d/24 (a+b+c), second moment
//   C = sum d/120 (a a^T + b b^T + c c^T + s s^T), s = a+b+c, d = a.(b x c),
// from the canonical tetrahedron covariance (Blow & Binstock, "How to find the inertia tensor (or
// other mass properties) of a 3D solid body represented by a triangle mesh", 2004; equivalent to
// Mirtich 1996 and Eberly's polyhedral mass properties). Then I = tr(C) 1 - C, shifted to the
// centroid. Working about a reference point near the mesh keeps full precision far from the origin.
// Shell: the same with area-weighted triangle moments, C = A/12 (a a^T + b b^T + c c^T + s s^T).
// Hull: the solid formula on the convex hull of the vertices.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <simreel/mass_properties.hpp>

namespace simreel {

struct TriangleMesh {
  std::vector<Vec3> vertices;                 ///< m (after any scale)
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise seen from outside
};

enum class MassMode { solid, shell, hull };
const char* to_string(MassMode m);
std::optional<MassMode> mass_mode_from_name(std::string_view name);  ///< solid, shell, hull

struct MeshReport {
  MassProperties props;  ///< at the requested density; com and inertia in mesh axes
  double volume = 0.0;   ///< m^3 of the solid (of the hull in hull mode; 0 for a shell)
  double area = 0.0;     ///< m^2 of the surface used
  bool closed = false;   ///< every edge has an even number of faces (after welding)
  /// Every edge's faces agree on the winding (as loaded): an edge is walked as often in one
  /// direction as in the other, give or take one (a boundary edge has one face and always agrees).
  bool consistently_oriented = false;
  int welded_vertices = 0;    ///< duplicate positions merged (STL stores one set per face)
  int degenerate_faces = 0;   ///< zero-area faces skipped in the integrals (not in the closedness check)
  int nonmanifold_edges = 0;  ///< edges shared by more than two faces
  int reoriented_faces = 0;   ///< faces flipped to agree with their neighbours
  bool inverted = false;      ///< the whole surface was inside-out and was flipped
  std::vector<std::string> warnings;  ///< one sentence per defect and what was done about it
};

struct MeshMassOptions {
  MassMode mode = MassMode::solid;
  double density = 1000.0;   ///< kg/m^3
  double thickness = 0.001;  ///< m, shell mode only: mass = density * thickness * area
};

// Throws InputError for meshes that cannot be a solid of the requested mode (no faces,
// non-finite coordinates, bad indices, open or flat surface for `solid`, ...).
MeshReport analyze_mesh(const TriangleMesh& mesh, const MeshMassOptions& opt);

// Solid mode checks the surface as given (zero-area slivers that close a T-junction count), flips
// inside-out parts unless they lie inside a larger part (a cavity, by a winding-number
// point-in-solid test) and names both in the warnings. Shell mode needs only a surface.

// The mesh after welding, dropping degenerate faces and fixing orientation: what analyze_mesh
// integrated over in solid mode (useful to render exactly what was weighed).
TriangleMesh repaired_mesh(const TriangleMesh& mesh, MeshReport* report = nullptr);

}  // namespace simreel
