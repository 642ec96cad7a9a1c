// The body of each libFuzzer harness, shared with the replay test (tests/fuzz/replay_test.cpp) that
// runs every input ever found through the same code in the default build.
//
// Each calls simreel's code on the input. An InputError is the right answer to bad input; any
// other exception escapes (libFuzzer reports it: std::terminate aborts), and a result reported as a
// success with a non-finite mass, volume or inertia, or an index out of range, aborts in finding().
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "app/scene/mesh_import.hpp"
#include "app/scene/scene.hpp"
#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include <simreel/mesh.hpp>

namespace simreel::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FINDING: %s\n", what.c_str());
  std::abort();
}

// Every triangle's indices in range and every vertex finite (what import_mesh relies on).
inline void check_raw(const detail::RawMesh& m) {
  for (const auto& t : m.triangles)
    for (int i : t)
      if (i < 0 || (size_t)i >= m.vertices.size()) finding("triangle index out of range");
  for (const auto& t : m.triangle_normals)
    for (int i : t)
      if (i < 0 || (size_t)i >= m.normals.size()) finding("normal index out of range");
  for (const Vec3& v : m.vertices)
    if (!all_finite(v)) finding("non-finite vertex accepted");
  if (m.points_and_lines < 0) finding("negative point count");
}

inline void check_report(const MeshReport& r) {
  if (!std::isfinite(r.volume) || !std::isfinite(r.area) || !std::isfinite(r.props.mass) ||
      !all_finite(r.props.com) || !r.props.inertia.allFinite())
    finding("non-finite mass properties reported as a success");
  if (!(r.props.mass > 0)) finding("non-positive mass reported as a success");
}

// The mesh a reader returned, weighed as a solid the way import_mesh and analyze_mesh would.
inline void weigh(const detail::RawMesh& m) {
  if (m.triangles.empty() || m.triangles.size() > 20000) return;  // big meshes: the reader was the point
  TriangleMesh t;
  t.vertices = m.vertices;
  t.triangles = m.triangles;
  try {
    check_report(analyze_mesh(t, MeshMassOptions{}));
  } catch (const InputError&) {
  }
}

// Where the harnesses pretend their input lives: a folder that does not exist, so that an OBJ's
// mtllib or a scene's mesh file names nothing on this machine (unless absolute).
inline const char* kFakeDir = "/nonexistent-simreel-fuzz";

// The readers: `format` is "obj", "off", "stl" or "ply".
inline void reader(const char* format, const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string path = std::string(kFakeDir) + "/in." + format;
  std::string kind;
  try {
    const std::string_view f = format;
    const detail::RawMesh m = f == "obj"   ? detail::parse_obj(text, path)
                              : f == "off" ? detail::parse_off(text, path)
                              : f == "stl" ? detail::parse_stl(text, path, &kind)
                                           : detail::parse_ply(text, path, &kind);
    check_raw(m);
    weigh(m);
  } catch (const InputError&) {
  }
}

// Mass properties of arbitrary triangle meshes (sim/mass/mesh_mass.cpp), every mode.
//
// Input: byte 0 picks the mode (solid, shell, hull) and how coordinates are coded, byte 1 a
// binary exponent for the coordinates (-128 .. 127, times 8: sizes from 1e-308 to 1e308), byte 2
// the vertex count; then the vertices (3 int16 each, times 2^exponent, or 3 raw doubles), then
// triangles as byte triples (indices modulo the vertex count) to the end.
inline void mass(const uint8_t* data, size_t size) {
  if (size < 3) return;
  const int mode = data[0] % 3;
  const bool raw = (data[0] / 3) % 4 == 0;
  const int exponent = 8 * (int)(int8_t)data[1];
  const int nv = data[2];
  size_t at = 3;
  TriangleMesh m;
  for (int i = 0; i < nv; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      if (raw) {
        if (at + 8 > size) return;
        std::memcpy(&p[k], data + at, 8);
        at += 8;
      } else {
        if (at + 2 > size) return;
        int16_t q;
        std::memcpy(&q, data + at, 2);
        at += 2;
        p[k] = std::ldexp((double)q, exponent);
      }
    }
    m.vertices.push_back(p);
  }
  for (; at + 3 <= size; at += 3)
    if (nv > 0) m.triangles.push_back({data[at] % nv, data[at + 1] % nv, data[at + 2] % nv});
  MeshMassOptions opt;
  opt.mode = mode == 0 ? MassMode::solid : mode == 1 ? MassMode::shell : MassMode::hull;
  try {
    fuzz::check_report(analyze_mesh(m, opt));
  } catch (const InputError&) {
  }
}

// The scene loader on arbitrary text, as if the file were `scene.yaml` in the working directory. A
// scene that loads must give every body a finite, positive mass and a finite, physical inertia:
// the world would refuse it otherwise, without naming file and line.
inline void scene(const uint8_t* data, size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  try {
    const Scene s = load_scene_text(yaml, "scene.yaml");
    for (const BodyDef& b : s.bodies) {
      bool massive = false;
      bool trimesh = false;  // a static body's mesh collides as its triangles and weighs nothing
      for (const Collider& c : b.colliders) {
        massive = massive || c.shape != ShapeKind::plane;
        trimesh = trimesh || (c.shape == ShapeKind::mesh && b.type == BodyType::static_body);
      }
      if (!massive || trimesh) continue;
      const MassProperties& mp = b.mass_B();
      if (!std::isfinite(mp.mass) || !(mp.mass > 0) || !all_finite(mp.com) || !mp.inertia.allFinite())
        finding("a body with a non-finite or non-positive mass or inertia was loaded");
      if (!inertia_problem(mp.inertia, 1e-7).empty()) finding("a body with an unphysical inertia was loaded");
    }
  } catch (const InputError&) {
  }
}

}  // namespace simreel::fuzz
