#include "app/mesh_import.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>

#include "sim/error.hpp"

namespace simreel {

TriangleMesh import_mesh(const std::string& path, const Vec3& scale) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("mesh file '" + path + "' does not exist");
  Assimp::Importer imp;
  // Keep points and lines out of the triangle lists; we report files that have nothing else.
  imp.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
  const aiScene* sc = imp.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                             aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!sc || !sc->mRootNode)
    throw InputError("cannot read mesh '" + path + "': " + std::string(imp.GetErrorString()));
  TriangleMesh out;
  long points = 0;
  for (unsigned mi = 0; mi < sc->mNumMeshes; ++mi) {
    const aiMesh* m = sc->mMeshes[mi];
    const int base = (int)out.vertices.size();
    bool any = false;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) {
        ++points;
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
    }
    if (!any) continue;
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      out.vertices.push_back(Vec3(p.x, p.y, p.z).cwiseProduct(scale));
    }
  }
  if (out.triangles.empty())
    throw InputError("mesh '" + path + "' has no triangles" +
                     (points ? " (only " + std::to_string(points) + " points or lines)" : std::string()));
  for (const Vec3& v : out.vertices)
    if (!all_finite(v))
      throw InputError("mesh '" + path + "' has a vertex with a NaN or infinite coordinate");
  return out;
}

}  // namespace simreel
