#include "app/scene/mesh_library.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/mesh_import.hpp"

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

std::vector<std::string> MeshLibrary::files() const {
  std::vector<std::string> out;
  for (const auto& [k, m] : files_) {
    const std::string path = k.substr(0, k.rfind('|'));
    if (out.empty() || out.back() != path) out.push_back(path);
    if (m && m->appearance)  // the images its materials name (an MTL's map_Kd, a glTF's files)
      for (const TextureSource& t : m->appearance->textures)
        if (!t.file.empty()) out.push_back(t.file);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
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

namespace {

// FNV-1a, 64 bits: a cache key, not a security boundary.
uint64_t fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ull) {
  const unsigned char* p = (const unsigned char*)data;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

std::filesystem::path cache_dir() {
  if (const char* d = std::getenv("SIMREEL_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::filesystem::path(d) / "simreel";
  if (const char* d = std::getenv("HOME"); d && *d) return std::filesystem::path(d) / ".cache" / "simreel";
  return {};
}

constexpr char kMagic[8] = {'S', 'R', 'D', 'E', 'C', '0', '1', 0};

}  // namespace

const Decomposition& MeshLibrary::decomposition(const std::string& path, const Vec3& scale, int cap) {
  const int vertices = cap > 0 ? cap : 64;
  const std::string k = key(path, scale) + "|" + std::to_string(vertices);
  if (auto it = decompositions_.find(k); it != decompositions_.end()) return it->second;
  const TriangleMesh& mesh = file(path, scale)->mesh;
  DecompositionOptions opt;
  opt.max_hull_vertices = vertices;
  // The key: the file's bytes, the scale, the options and the format's version.
  std::string bytes = detail::read_file(path);
  uint64_t h = fnv1a(bytes.data(), bytes.size());
  h = fnv1a(scale.data(), sizeof(double) * 3, h);
  const double params[] = {(double)opt.max_parts, opt.max_excess, (double)opt.resolution,
                           (double)opt.candidates, (double)opt.max_hull_vertices};
  h = fnv1a(params, sizeof params, h);
  h = fnv1a(kMagic, sizeof kMagic, h);
  char name[40];
  std::snprintf(name, sizeof name, "%016llx.decomposition", (unsigned long long)h);
  const std::filesystem::path dir = cache_dir() / "decompose";
  const std::filesystem::path cached = dir / name;
  std::optional<Decomposition> d;
  MeshMassOptions unit;
  unit.density = 1;
  {
    std::ifstream in(cached, std::ios::binary);
    std::error_code size_ec;
    uint64_t left = in ? (uint64_t)std::filesystem::file_size(cached, size_ec) : 0;
    if (in && !size_ec) {
      // magic, solid volume, part count, then per part its point count and points (doubles).
      char magic[8];
      double volume = 0;
      uint64_t parts = 0;
      std::vector<std::vector<Vec3>> points;
      bool ok = in.read(magic, 8) && std::memcmp(magic, kMagic, 8) == 0 &&
                in.read((char*)&volume, sizeof volume) && in.read((char*)&parts, sizeof parts) &&
                parts < 100000;
      for (uint64_t p = 0; ok && p < parts; ++p) {
        uint64_t n = 0;
        ok = in.read((char*)&n, sizeof n) && n >= 4 && n <= left / sizeof(Vec3);  // never sized past the file
        if (!ok) break;
        std::vector<Vec3> pts(n);
        ok = (bool)in.read((char*)pts.data(), (std::streamsize)(n * sizeof(Vec3)));
        points.push_back(std::move(pts));
      }
      if (ok) {
        try {
          d = decomposition_from_points(std::move(points), volume, opt.max_hull_vertices);
        } catch (const InputError&) {
          d.reset();  // a damaged cache file: made again below
        }
      }
    }
  }
  if (!d) {
    d = convex_decomposition(mesh, opt);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::filesystem::path tmp = cached.string() + ".tmp" + std::to_string((long)getpid());
    std::ofstream out(tmp, std::ios::binary);
    if (!ec && out) {
      const uint64_t parts = d->points.size();
      out.write(kMagic, 8);
      out.write((const char*)&d->solid_volume, sizeof(double));
      out.write((const char*)&parts, sizeof parts);
      for (const auto& pts : d->points) {
        const uint64_t n = pts.size();
        out.write((const char*)&n, sizeof n);
        out.write((const char*)pts.data(), (std::streamsize)(n * sizeof(Vec3)));
      }
      out.close();
      if (out) std::filesystem::rename(tmp, cached, ec);  // whole or not at all
      if (!out || ec) std::filesystem::remove(tmp, ec);
    }
  }
  return decompositions_.emplace(k, std::move(*d)).first->second;
}

}  // namespace simreel
