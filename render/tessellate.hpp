// Render meshes: positions and normals for GL, made once per collider in the collider frame.
#pragma once
#include <array>
#include <compare>
#include <cstdint>
#include <vector>

#include <simreel/body.hpp>
#include "render/material.hpp"

namespace simreel {

struct RenderMesh {
  std::vector<float> vertices;    ///< interleaved x y z nx ny nz
  std::vector<uint32_t> indices;  ///< triangles
  float radius = 0;               ///< m, bounding sphere about the collider origin
  // Drawn without back-face culling, lit on the side seen. Set for meshes from files, whose winding
  // may be inside-out or open (shells): they must look the same as the repaired solid was weighed.
  bool two_sided = false;
  // A convex solid (the primitives: box, sphere, cylinder, capsule, ellipsoid): it casts no shadow
  // on itself where it faces the light, so the renderer leaves it out of the shadow map unless it
  // can shadow another body (render/renderer.cpp, classify_shadows).
  bool convex = false;

  // A mesh file's look (render/material.hpp), for meshes that have one: per vertex r g b a u v,
  // where a = 1 takes the vertex's colour (material x vertex colour) and a = 0 the item's (a face
  // whose material gives no colour); and the index ranges drawn with one texture each.
  std::vector<float> extras;
  struct Part {
    uint32_t first = 0, count = 0;  ///< indices
    int texture = -1;               ///< SceneMeshes::textures, or -1 (none)
  };
  std::vector<Part> parts;  ///< empty unless `extras` is set; then they cover `indices`

  size_t bytes() const {
    return (vertices.size() + indices.size() + extras.size()) * 4;
  }  ///< vertex and index data
};

RenderMesh tessellate_box(const Vec3& size);
RenderMesh tessellate_sphere(double r, int rings = 24);
RenderMesh tessellate_cylinder(double r, double h, int segments = 48);
RenderMesh tessellate_cone(double r, double h, int segments = 48);  ///< base disk at z = 0, tip at z = h
RenderMesh tessellate_capsule(double r, double h, int segments = 48);
RenderMesh tessellate_plane(double size);  ///< square in z = 0, normal +z, centred on the origin
// The unit sphere's mesh scaled by the semi-axes r: positions diag(r) p, normals diag(1/r) n
// normalised (the inverse transpose of the scaling).
RenderMesh tessellate_ellipsoid(const Vec3& r, int rings = 24);
// A plane collider drawn as a finite square of side `size`, seen from both sides.
RenderMesh tessellate_plane_collider(double size);
// Triangle mesh with normals split at edges sharper than crease_deg (smooth elsewhere), two-sided.
// Every normal points to the side the triangle's winding calls front (a file normal that points
// the other way is turned round), so the renderer's "flip for back faces" lights the seen side.
// `normals`: the file's shading normals per triangle corner (used where given), else crease normals.
using CornerNormals = std::vector<std::array<Eigen::Vector3f, 3>>;
RenderMesh tessellate_mesh(const TriangleMesh& m, const CornerNormals* normals = nullptr,
                           double crease_deg = 35.0);
// plane_size: m, the side of the square drawn for a plane collider (planes are infinite).
RenderMesh tessellate_collider(const Collider& c, double plane_size = 10,
                               const CornerNormals* normals = nullptr);

// Lays a mesh file's look over a tessellate_mesh result of the same mesh (three vertices per
// triangle, in triangle order): the vertices' extras, and the triangles regrouped (stably) into one
// part per texture. texture_slot maps the look's textures to SceneMeshes::textures (-1: an image
// that could not be decoded, drawn in its material's colour).
void apply_appearance(RenderMesh& m, const MeshAppearance& look, const std::vector<int>& texture_slot);

// Everything tessellate_collider reads from its arguments: colliders with equal keys have the
// same render mesh, bit for bit, so one copy serves them all. A mesh's surface and normals count
// by identity (the scene loader shares one imported mesh per file and scale), not by content.
struct RenderMeshKey {
  ShapeKind shape = ShapeKind::box;
  std::array<double, 3> dims{};   ///< m: the sizes the shape's tessellation reads, zero elsewhere
  const void* mesh = nullptr;     ///< mesh shapes: the surface...
  const void* normals = nullptr;  ///< ...and the file's shading normals (nullptr: crease normals)
  const void* look = nullptr;     ///< ...and its materials, if drawn with them
  auto operator<=>(const RenderMeshKey&) const = default;
};
RenderMeshKey render_mesh_key(const Collider& c, double plane_size = 10,
                              const CornerNormals* normals = nullptr, const MeshAppearance* look = nullptr);
// RenderMesh::bytes() of tessellate_collider(c) without making it: what a scene's meshes will
// need, checked before any is made.
size_t render_mesh_bytes(const Collider& c, bool with_look = false);

}  // namespace simreel
