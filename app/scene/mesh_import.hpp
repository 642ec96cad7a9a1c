// Triangle meshes from files.
//
// OBJ, OFF, STL (ASCII and binary) and PLY (ASCII and binary; faces and triangle strips) are read
// by simreel's own readers in double precision, polygons of any shape included, so a coordinate written "0.1"
// is 0.1 to the last bit and mass properties stay exact to rounding. Everything else assimp reads (glTF 2.0,
// COLLADA, 3MF, FBX, ...) goes through assimp, whose Debian build stores coordinates in single precision
// (about 6e-8 relative; glTF positions are float32 in the file anyway). Node transforms are applied.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <simreel/mesh.hpp>
#include "render/material.hpp"

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
  /// Materials per triangle, texture coordinates, vertex colours and images (render/material.hpp)
  /// when the file has more than one colour to give; null otherwise. Drawing only.
  std::shared_ptr<const MeshAppearance> appearance;
  std::vector<std::string> notes;  ///< what the reader did that the user should know
};

// Polygons triangulated, points and lines dropped (counted in a note), each vertex scaled by
// `scale` (per axis). Vertices are not welded here: analyze_mesh welds by exact position.
// Throws InputError naming the file (and the line for text formats) for unreadable, empty or
// broken files. The extension picks simreel's reader; a file whose first bytes announce PLY, OFF or
// STL goes to simreel's reader whatever its name. Everything else goes to assimp in a child process
// (detail::contained_read): a crash there is an InputError "assimp could not read 'FILE' (crashed:
// SIGBUS)".
ImportedMesh import_mesh(const std::string& path, const Vec3& scale = Vec3::Ones());

namespace detail {
// The native readers. They triangulate every polygon themselves (fan when convex, ear clipping in
// the polygon's plane otherwise), so they always return a mesh or throw InputError. They never size
// memory by a count a header claims before checking that the bytes left can hold it.
struct RawMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3f> normals;  ///< per vertex (PLY, assimp) or the OBJ vn list
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> triangle_normals;  ///< indices into normals, OBJ only
  std::vector<int> triangle_material;                ///< index into materials (OBJ, assimp)
  std::vector<std::array<float, 3>> materials;       ///< linear RGB base colour; -1 where none is known
  std::vector<std::string> material_names;           ///< parallel to materials ("" unnamed)
  /// Parallel to materials: the base-colour image as the file names it ("" none; "*N" the N-th
  /// embedded image, as assimp names them).
  std::vector<std::string> material_textures;
  std::vector<std::string> embedded;             ///< embedded images' encoded bytes (glb)
  std::vector<Eigen::Vector2f> uvs;              ///< per vertex (PLY, assimp) or the OBJ vt list
  std::vector<std::array<int, 3>> triangle_uvs;  ///< indices into uvs, OBJ only
  std::vector<std::array<float, 3>> colors;      ///< per vertex, linear RGB (PLY, assimp, OBJ v x y z r g b)
  long points_and_lines = 0;
  std::vector<std::string> notes;
};
// Each reads a file's bytes; `path` names the file in messages (and OBJ's material libraries are
// looked up beside it). `kind` gets the variant read ("stl-ascii", "ply-binary", ...).
RawMesh parse_obj(std::string_view text, const std::string& path);
RawMesh parse_off(std::string_view text, const std::string& path);
RawMesh parse_stl(std::string_view text, const std::string& path, std::string* kind);
RawMesh parse_ply(std::string_view text, const std::string& path, std::string* kind);
std::string read_file(const std::string& path);  ///< the whole file; InputError if unreadable
// The native format a file's first bytes (up to 512) and size announce whatever its name ("ply",
// "off", "stl"), or "": a PLY, OFF or STL file never goes to assimp.
std::string native_format(std::string_view head, uint64_t size);

// Appends a polygon (indices into m.vertices) as triangles; fewer than 3 corners counts a point
// or line.
// `vn` and `vt`: the corners' normal and texture-coordinate indices (OBJ), or empty.
void add_polygon(RawMesh& m, const std::vector<int>& v, const std::vector<int>& vn, int material,
                 const std::vector<int>& vt = {});

// assimp in this process (what the child of read_with_assimp runs): no post-processing but
// validation; node transforms and triangulation are simreel's own.
RawMesh assimp_read(const std::string& path);

// Runs `read` in a forked child process that sends the mesh back over a pipe, so that a crash,
// hang or memory blow-up in third-party code becomes an InputError "WHO could not read PATH
// (crashed: SIGBUS)" (or "(gave up after N s)", ...). InputError thrown in the child is rethrown
// with its message. The reply is checked (sizes never trusted, indices in range).
RawMesh contained_read(const std::string& path, const char* who, const std::function<RawMesh()>& read,
                       double seconds = 120);
// The wire format of contained_read, exposed for tests: encode_mesh(m) decodes to m.
std::string encode_mesh(const RawMesh& m);
RawMesh decode_mesh(std::string_view bytes, const std::string& path, const char* who);
}  // namespace detail

}  // namespace simreel
