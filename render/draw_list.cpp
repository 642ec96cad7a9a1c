#include "render/draw_list.hpp"

#include <sys/resource.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

namespace simreel {

size_t available_memory() {
  size_t avail = SIZE_MAX;
  long vm_size = -1, vm_data = -1;  // kB
  auto field = [](const std::string& line, const char* name, long& out) {
    if (line.rfind(name, 0) == 0) out = std::atol(line.c_str() + std::strlen(name));
  };
  {
    std::ifstream in("/proc/meminfo");
    long kb = -1;
    for (std::string line; std::getline(in, line);) field(line, "MemAvailable:", kb);
    if (kb >= 0) avail = (size_t)kb * 1024;
  }
  {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);) {
      field(line, "VmSize:", vm_size);
      field(line, "VmData:", vm_data);
    }
  }
  auto limit = [&](int resource, long used_kb) {
    rlimit r{};
    if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY || used_kb < 0) return;
    const size_t used = (size_t)used_kb * 1024;
    avail = std::min(avail, r.rlim_cur > used ? (size_t)(r.rlim_cur - used) : 0);
  };
  limit(RLIMIT_AS, vm_size);
  limit(RLIMIT_DATA, vm_data);
  return avail;
}

SceneMeshes::SceneMeshes(const World& w, const SceneStyles& styles, size_t budget) {
  auto style = [&](int i, size_t k) {
    return (size_t)i < styles.size() && k < styles[i].size() ? styles[i][k] : ColliderStyle{};
  };
  // First the distinct meshes and what they will need, so that a scene that cannot be drawn
  // says so before anything is made.
  std::map<RenderMeshKey, int> index;
  size_t need = 0;
  for (int i = 0; i < w.body_count(); ++i) {
    const std::vector<Collider>& cols = w.def(i).colliders;
    for (size_t k = 0; k < cols.size(); ++k) {
      const ColliderStyle st = style(i, k);
      if (st.drawn &&
          index.try_emplace(render_mesh_key(cols[k], st.plane_size, st.normals, st.look), -1).second)
        need += render_mesh_bytes(cols[k], st.look != nullptr);
    }
  }
  if (need > budget / 2) {
    char msg[400];
    std::snprintf(msg, sizeof msg,
                  "drawing this scene needs %.3g GB for its %zu distinct render meshes (%.3g GB, held twice: "
                  "here and in the GL), more than the %.3g GB this process can still allocate; colliders "
                  "share one render mesh when they are the same mesh file at the same scale, or primitives "
                  "of the same size",
                  2e-9 * (double)need, index.size(), 1e-9 * (double)need, 1e-9 * (double)budget);
    throw std::runtime_error(msg);
  }
  // Each distinct image decoded once (a file by its path, an embedded image by its bytes), and per
  // look the slot of each of its images; one that cannot be decoded leaves its faces in their
  // material's colour, with a note.
  std::map<std::pair<std::string, const void*>, int> image_slot;
  std::map<const MeshAppearance*, std::vector<int>> slots_of;
  auto slots = [&](const MeshAppearance& look) -> const std::vector<int>& {
    auto [it, fresh] = slots_of.try_emplace(&look);
    if (!fresh) return it->second;
    for (const TextureSource& t : look.textures) {
      const auto key = std::make_pair(t.file, (const void*)t.bytes.get());
      auto [s, made] = image_slot.try_emplace(key, -1);
      if (made) {
        try {
          TextureImage im = t.bytes ? decode_image(*t.bytes, t.name) : read_image(t.file);
          // A frame never shows more of an image than a few thousand texels across: larger ones
          // are halved (in linear light) to 4096 a side, 64 MB at most, not the 1 GB of 16384^2.
          if (im.width > kMaxTextureSide || im.height > kMaxTextureSide) {
            const int w = im.width, h = im.height;
            shrink_image(im, kMaxTextureSide);
            notes.push_back("image '" + t.name + "' (" + std::to_string(w) + "x" + std::to_string(h) +
                            " px) halved to " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                            " px for drawing");
          }
          s->second = (int)textures.size();
          bytes += im.rgba.size();
          textures.push_back(std::move(im));
        } catch (const std::exception& e) {
          notes.push_back(std::string(e.what()) + ": drawn in its material's colour");
        }
      }
      it->second.push_back(s->second);
    }
    return it->second;
  };
  mesh_of.resize(w.body_count());
  color_of.resize(w.body_count());
  for (int i = 0; i < w.body_count(); ++i) {
    const std::vector<Collider>& cols = w.def(i).colliders;
    for (size_t k = 0; k < cols.size(); ++k) {
      const ColliderStyle st = style(i, k);
      color_of[i].push_back(st.color);
      if (!st.drawn) {
        mesh_of[i].push_back(-1);
        continue;
      }
      int& m = index.at(render_mesh_key(cols[k], st.plane_size, st.normals, st.look));
      if (m < 0) {
        m = (int)meshes.size();
        meshes.push_back(tessellate_collider(cols[k], st.plane_size, st.normals));
        if (st.look && cols[k].shape == ShapeKind::mesh)
          apply_appearance(meshes.back(), *st.look, slots(*st.look));
        bytes += meshes.back().bytes();
      }
      mesh_of[i].push_back(m);
    }
  }
}

void build_draw_list(const World& w, const SceneMeshes& sm, const CameraView& cam, int follow,
                     DrawList& out) {
  out.items.clear();
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (int i = 0; i < w.body_count(); ++i) {
    Eigen::Isometry3d T_WB = Eigen::Isometry3d::Identity();
    T_WB.linear() = w.rotation(i);
    T_WB.translation() = w.origin_position(i);
    const BodyDef& d = w.def(i);
    for (size_t k = 0; k < d.colliders.size(); ++k) {
      const int mesh = sm.mesh_of[i][k];
      if (mesh < 0) continue;
      const Collider& c = d.colliders[k];
      Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
      T_BC.linear() = c.q_BC.toRotationMatrix();
      T_BC.translation() = c.p_BC;
      const Eigen::Isometry3d T = T_WB * T_BC;
      DrawItem it;
      it.mesh = mesh;
      it.model = T.matrix().cast<float>();
      it.color = sm.color_of[i][k];
      out.items.push_back(it);
      const double r = sm.meshes[it.mesh].radius;
      lo = lo.cwiseMin(T.translation() - Vec3::Constant(r));
      hi = hi.cwiseMax(T.translation() + Vec3::Constant(r));
    }
  }
  if (out.items.empty()) lo = hi = Vec3::Zero();  // nothing drawn (a ground alone)
  out.bounds_center = 0.5 * (lo + hi);
  out.bounds_radius = std::max(0.5 * (hi - lo).norm(), 1e-3);
  out.camera = cam;
  if (follow >= 0) {
    const Vec3 c = w.centroid(follow);
    out.camera.eye = cam.eye + (c - cam.target);
    out.camera.target = c;
  }
}

}  // namespace simreel
