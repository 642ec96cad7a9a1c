#include "sim/geometry/trimesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include <simreel/error.hpp>

namespace simreel {

TriMeshShape make_trimesh_shape(const TriangleMesh& mesh, double active_edge_angle) {
  TriMeshShape s;
  // Weld by exact position (files often repeat a vertex per face for its normals or UVs).
  std::map<std::tuple<double, double, double>, int> index;
  std::vector<int> remap(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    const auto [it, added] = index.try_emplace({v.x(), v.y(), v.z()}, (int)s.vertices.size());
    if (added) s.vertices.push_back(v);
    remap[i] = it->second;
  }
  double size = 0;
  for (const Vec3& v : s.vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  for (const auto& t : mesh.triangles) {
    MeshTriangle m;
    for (int k = 0; k < 3; ++k) m.v[k] = remap[t[k]];
    const Vec3 &a = s.vertices[m.v[0]], &b = s.vertices[m.v[1]], &c = s.vertices[m.v[2]];
    const Vec3 n = (b - a).cross(c - a);
    // Zero area, to rounding of the coordinates' size (includes repeated vertices).
    if (!(n.norm() > 1e-12 * std::max(1.0, size * size))) {
      ++s.dropped;
      continue;
    }
    m.normal = n.normalized();
    s.triangles.push_back(m);
  }
  if (s.triangles.empty()) throw InputError("the mesh has no triangle with an area");
  // Edge adjacency: an edge used by exactly two triangles joins them; by one (or by three or
  // more: not a surface there) it is a boundary edge.
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;  // (lo, hi) -> (tri, k)
  for (int t = 0; t < (int)s.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = s.triangles[t].v[k], b = s.triangles[t].v[(k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({t, k});
    }
  const double sin_active = std::sin(active_edge_angle);
  for (const auto& [key, uses] : edges) {
    if (uses.size() != 2) {
      for (const auto& [t, k] : uses) s.triangles[t].active |= (uint8_t)(1u << k);
      continue;
    }
    for (int side = 0; side < 2; ++side) {
      MeshTriangle& T = s.triangles[uses[side].first];
      const int k = uses[side].second;
      const MeshTriangle& N = s.triangles[uses[1 - side].first];
      const int kn = uses[1 - side].second;
      const Vec3& e0 = s.vertices[T.v[k]];
      const Vec3 e = (s.vertices[T.v[(k + 1) % 3]] - e0).normalized();
      const Vec3& w = s.vertices[N.v[(kn + 2) % 3]];  // the neighbour's vertex off the edge
      Vec3 perp = (w - e0) - e.dot(w - e0) * e;       // in N's plane, from the edge to w
      const double len = perp.norm();
      perp /= len;
      T.out_nb[k] = -perp;
      // Bent convex by more than the threshold: N falls away below T's plane.
      if (-T.normal.dot(perp) > sin_active) T.active |= (uint8_t)(1u << k);
    }
  }
  // A vertex is active when one of its two edges in the triangle is.
  for (MeshTriangle& T : s.triangles)
    for (int k = 0; k < 3; ++k)
      if (T.active & ((1u << k) | (1u << ((k + 2) % 3)))) T.active |= (uint8_t)(1u << (3 + k));
  std::vector<Vec3> lo(s.triangles.size()), hi(s.triangles.size());
  s.lo = Vec3::Constant(INFINITY);
  s.hi = Vec3::Constant(-INFINITY);
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const MeshTriangle& T = s.triangles[t];
    lo[t] = s.vertices[T.v[0]].cwiseMin(s.vertices[T.v[1]]).cwiseMin(s.vertices[T.v[2]]);
    hi[t] = s.vertices[T.v[0]].cwiseMax(s.vertices[T.v[1]]).cwiseMax(s.vertices[T.v[2]]);
    s.lo = s.lo.cwiseMin(lo[t]);
    s.hi = s.hi.cwiseMax(hi[t]);
  }
  s.bvh.build(lo, hi);
  return s;
}

}  // namespace simreel
