// Shared by the libFuzzer harnesses: what counts as a finding.
//
// A harness calls simreel's code on the input. An InputError is the right answer to bad input;
// any other exception escapes (libFuzzer reports it as a crash: std::terminate aborts), and a
// result reported as a success with a non-finite mass, volume or inertia, or with an index out of
// range, aborts through finding().
#pragma once
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/mesh_import.hpp"
#include "sim/error.hpp"
#include "sim/mesh_mass.hpp"

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

}  // namespace simreel::fuzz
