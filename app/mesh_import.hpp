// Triangle meshes from files.
//
// OBJ, OFF, STL (ASCII and binary) and PLY (ASCII and binary; faces and triangle strips) are read
// by simreel's own readers in double precision, polygons of any shape included, so a coordinate written "0.1"
// is 0.1 to the last bit and mass properties stay exact to rounding. Everything else assimp reads (glTF 2.0,
// COLLADA, 3MF, FBX, ...) goes through assimp, whose Debian build stores coordinates in single precision
// (about 6e-8 relative; glTF positions are float32 in the file anyway). Node transforms are applied.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "sim/mesh_mass.hpp"

namespace simreel {

struct ImportedMesh {
  TriangleMesh mesh;   ///< vertices in m after `scale`; only vertices that faces use
  std::string reader;  ///< "obj", "off", "stl-ascii", "stl-binary", "ply-ascii", "ply-binary", "assimp"
  /// False when the coordinates passed through assimp's float32.
  bool double_precision() const { return reader != "assimp"; }
  std::optional<std::array<float, 3>> color;  ///< diffuse colour of the material most faces use
  /// Shading normals per triangle corner of `mesh` (unit, mesh axes) when the file gives them;
  /// empty otherwise. Drawing only (appearance stays out of sim/).
  std::vector<std::array<Eigen::Vector3f, 3>> corner_normals;
  std::vector<std::string> notes;  ///< what the reader did that the user should know
};

// Polygons triangulated, points and lines dropped (counted in a note), each vertex scaled by
// `scale` (per axis). Vertices are not welded here: analyze_mesh welds by exact position.
// Throws InputError naming the file (and the line for text formats) for unreadable, empty or
// broken files.
ImportedMesh import_mesh(const std::string& path, const Vec3& scale = Vec3::Ones());

namespace detail {
// The native readers. They triangulate every polygon themselves (fan when convex, ear clipping in
// the polygon's plane otherwise), so they always return a mesh or throw; optional is kept for a
// reader that hands a file on to assimp.
struct RawMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3f> normals;  ///< per vertex (PLY) or the OBJ vn list
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> triangle_normals;  ///< indices into normals, OBJ only
  std::vector<int> triangle_material;                ///< index into materials, OBJ only
  std::vector<std::array<float, 3>> materials;
  long points_and_lines = 0;
  std::vector<std::string> notes;
};
std::optional<RawMesh> read_obj(const std::string& path);
std::optional<RawMesh> read_off(const std::string& path);
std::optional<RawMesh> read_stl(const std::string& path, std::string* kind);
std::optional<RawMesh> read_ply(const std::string& path, std::string* kind);
}  // namespace detail

}  // namespace simreel
