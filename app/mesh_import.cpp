#include "app/mesh_import.hpp"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <filesystem>

#include "sim/error.hpp"

namespace simreel {
namespace {

// Everything else assimp reads. Node transforms are baked in by PreTransformVertices.
detail::RawMesh read_with_assimp(const std::string& path) {
  Assimp::Importer imp;
  // Keep points and lines out of the triangle lists; we report files that have nothing else.
  imp.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
  const aiScene* sc = imp.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                             aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!sc || !sc->mRootNode)
    throw InputError("cannot read mesh '" + path + "': " + std::string(imp.GetErrorString()));
  detail::RawMesh out;
  bool all_normals = true;
  for (unsigned mi = 0; mi < sc->mNumMeshes; ++mi) {
    const aiMesh* m = sc->mMeshes[mi];
    const int base = (int)out.vertices.size();
    bool any = false;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) {
        ++out.points_and_lines;
        continue;
      }
      any = true;
      std::array<int, 3> t;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= m->mNumVertices)
          throw InputError("mesh '" + path + "': face refers to a vertex that does not exist");
        t[k] = base + (int)face.mIndices[k];
      }
      out.triangles.push_back(t);
      out.triangle_material.push_back((int)m->mMaterialIndex);
    }
    if (!any) continue;
    all_normals = all_normals && m->HasNormals();
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
      out.normals.emplace_back(m->HasNormals()
                                   ? Eigen::Vector3f(m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z)
                                   : Eigen::Vector3f::Zero());
    }
  }
  if (!all_normals) out.normals.clear();
  for (unsigned i = 0; i < sc->mNumMaterials; ++i) {
    aiColor4D c;
    const aiMaterial* mat = sc->mMaterials[i];
    if (mat->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || mat->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
      out.materials.push_back(
          {std::clamp(c.r, 0.f, 1.f), std::clamp(c.g, 0.f, 1.f), std::clamp(c.b, 0.f, 1.f)});
    else
      out.materials.push_back({-1.f, -1.f, -1.f});
  }
  return out;
}

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& ch : e) ch = (char)std::tolower((unsigned char)ch);
  return e;
}

}  // namespace

ImportedMesh import_mesh(const std::string& path, const Vec3& scale) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("mesh file '" + path + "' does not exist");
  ImportedMesh out;
  const std::string ext = lower_extension(path);
  std::optional<detail::RawMesh> raw;
  if (ext == ".obj") {
    raw = detail::read_obj(path);
    out.reader = "obj";
  } else if (ext == ".off") {
    raw = detail::read_off(path);
    out.reader = "off";
  } else if (ext == ".stl") {
    raw = detail::read_stl(path, &out.reader);
  } else if (ext == ".ply") {
    raw = detail::read_ply(path, &out.reader);
  }
  if (!raw) {
    raw = read_with_assimp(path);
    out.reader = "assimp";
  }
  detail::RawMesh& r = *raw;
  out.notes.insert(out.notes.end(), r.notes.begin(), r.notes.end());
  if (r.points_and_lines)
    out.notes.push_back("skipped " + std::to_string(r.points_and_lines) +
                        " points or lines (only triangles have volume)");
  if (r.triangles.empty())
    throw InputError("mesh '" + path + "' has no triangles" +
                     (r.points_and_lines
                          ? " (only " + std::to_string(r.points_and_lines) + " points or lines)"
                          : std::string()));
  // Only the vertices faces use, in first-use order (a hull must not see stray points).
  std::vector<int> remap(r.vertices.size(), -1);
  TriangleMesh& m = out.mesh;
  for (const auto& t : r.triangles) {
    std::array<int, 3> u;
    for (int k = 0; k < 3; ++k) {
      int& id = remap[t[k]];
      if (id < 0) {
        id = (int)m.vertices.size();
        m.vertices.push_back(r.vertices[t[k]].cwiseProduct(scale));
      }
      u[k] = id;
    }
    m.triangles.push_back(u);
  }
  for (const Vec3& v : m.vertices)
    if (!all_finite(v))
      throw InputError("mesh '" + path + "' has a vertex with a NaN or infinite coordinate");
  // Shading normals: per corner (OBJ) or per vertex (PLY, assimp). A scale s maps normals by s^-1.
  const bool per_corner = !r.triangle_normals.empty();
  const bool per_vertex = !per_corner && !r.normals.empty() && r.normals.size() == r.vertices.size();
  if (per_corner || per_vertex) {
    const Eigen::Vector3f inv = scale.cwiseInverse().cast<float>();
    for (size_t f = 0; f < r.triangles.size(); ++f) {
      std::array<Eigen::Vector3f, 3> c;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f n =
            r.normals[per_corner ? r.triangle_normals[f][k] : r.triangles[f][k]].cwiseProduct(inv);
        c[k] = n.norm() > 0 && n.allFinite() ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f::Zero();
      }
      out.corner_normals.push_back(c);
    }
  }
  // The colour of the material most faces use, if the file gives it one.
  if (!r.materials.empty() && r.triangle_material.size() == r.triangles.size()) {
    std::vector<long> uses(r.materials.size(), 0);
    for (int mat : r.triangle_material)
      if (mat >= 0 && mat < (int)uses.size()) ++uses[mat];
    const size_t best = std::max_element(uses.begin(), uses.end()) - uses.begin();
    if (uses[best] > 0 && r.materials[best][0] >= 0) out.color = r.materials[best];
  }
  return out;
}

}  // namespace simreel
