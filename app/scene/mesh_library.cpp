#include "app/scene/mesh_library.hpp"

#include <cstdio>

#include "sim/dynamics/mesh_collider.hpp"

namespace simreel {

namespace {
std::string exact(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%a", v);
  return b;
}
}  // namespace

std::string MeshLibrary::key(const std::string& file, const Vec3& scale) {
  return file + "|" + exact(scale.x()) + "," + exact(scale.y()) + "," + exact(scale.z());
}

std::shared_ptr<const ImportedMesh> MeshLibrary::file(const std::string& path, const Vec3& scale) {
  auto& m = files_[key(path, scale)];
  if (!m) {
    auto read = std::make_shared<const ImportedMesh>(import_mesh(path, scale));
    for (const std::string& w : read->notes) notes_.push_back(path + ": " + w);
    m = std::move(read);
  }
  return m;
}

std::shared_ptr<const TriangleMesh> MeshLibrary::surface(const std::string& path, const Vec3& scale) {
  const std::shared_ptr<const ImportedMesh> m = file(path, scale);
  return std::shared_ptr<const TriangleMesh>(m, &m->mesh);
}

const MeshReport& MeshLibrary::analysis(const std::string& path, const Vec3& scale,
                                        const MeshMassOptions& opt) {
  const std::string k = key(path, scale) + "|" + std::to_string((int)opt.mode) + "," + exact(opt.thickness);
  auto it = reports_.find(k);
  if (it == reports_.end()) {
    MeshMassOptions unit = opt;
    unit.density = 1.0;
    it = reports_.emplace(k, analyze_mesh(file(path, scale)->mesh, unit)).first;
  }
  return it->second;
}

const MeshLibrary::Hulls& MeshLibrary::hulls(const std::string& path, const Vec3& scale, bool parts, int cap,
                                             std::vector<HullReduction>* reductions) {
  const std::string k = key(path, scale) + (parts ? "|parts" : "|hull") + "|" + std::to_string(cap);
  auto it = hulls_.find(k);
  if (it == hulls_.end())
    it = hulls_.emplace(k, collision_hulls(file(path, scale)->mesh, parts, cap, reductions)).first;
  return it->second;
}

}  // namespace simreel
