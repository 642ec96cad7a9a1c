// Triangle meshes from files through assimp (OBJ, STL, PLY, OFF, glTF 2.0, ...).
#pragma once
#include <string>

#include "sim/mesh_mass.hpp"

namespace simreel {

// Node transforms applied, polygons triangulated, points and lines dropped, each vertex scaled by
// `scale` (per axis). Vertices are not welded here: analyze_mesh welds by exact position.
// Throws InputError naming the file for unreadable, empty or broken files.
TriangleMesh import_mesh(const std::string& path, const Vec3& scale = Vec3::Ones());

}  // namespace simreel
