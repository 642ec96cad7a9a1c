// Meshes with closed-form mass properties, built in code so every reference value is exact.
#pragma once
#include <cmath>
#include <numbers>

#include <simreel/mesh.hpp>

namespace simreel::test {

// Axis-aligned box [lo, lo + size], 8 vertices, 12 outward triangles.
inline TriangleMesh box_mesh(const Vec3& size, const Vec3& lo = Vec3::Zero()) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(lo + Vec3((i & 1) ? size.x() : 0, (i & 2) ? size.y() : 0, (i & 4) ? size.z() : 0));
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

// Tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): volume 1/6, centroid (1/4, 1/4, 1/4).
inline TriangleMesh unit_tetrahedron() {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// Extrusion along z (height h) of a simple counter-clockwise polygon in the xy plane; the caps are
// fanned from vertex 0, which is valid for the star-shaped L used here.
inline TriangleMesh prism(const std::vector<Eigen::Vector2d>& poly, double h) {
  TriangleMesh m;
  const int n = (int)poly.size();
  for (const auto& p : poly) m.vertices.push_back(Vec3(p.x(), p.y(), 0));
  for (const auto& p : poly) m.vertices.push_back(Vec3(p.x(), p.y(), h));
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});          // bottom, facing -z
    m.triangles.push_back({n, n + i, n + i + 1});  // top, facing +z
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  return m;
}

// L-shaped prism: the unit-thickness (along z) union of [0,2]x[0,1] and [0,1]x[1,2].
inline TriangleMesh l_prism() {
  return prism({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 1.0);
}

// UV sphere of radius r with `n` latitude bands and 2n longitude segments.
inline TriangleMesh uv_sphere(double r, int n) {
  TriangleMesh m;
  const double pi = std::numbers::pi;
  m.vertices.push_back(Vec3(0, 0, r));
  for (int i = 1; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double th = pi * i / n, ph = pi * j / n;
      m.vertices.push_back(r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  m.vertices.push_back(Vec3(0, 0, -r));
  const int south = (int)m.vertices.size() - 1;
  auto ring = [n](int i, int j) { return 1 + (i - 1) * 2 * n + (j % (2 * n)); };
  for (int j = 0; j < 2 * n; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  for (int j = 0; j < 2 * n; ++j) m.triangles.push_back({south, ring(n - 1, j + 1), ring(n - 1, j)});
  return m;
}

inline double rel_err(const Mat3& a, const Mat3& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace simreel::test
