// Triangle meshes for the static-mesh tests and benchmark: grids (flat, or any height field)
// triangulated with alternating diagonals, a bowl, and a closed cuboid.
#pragma once
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/mesh.hpp>

namespace simreel::trimesh_test {

// A surface P(u, v) sampled on nu x nv cells of [u0, u1] x [v0, v1], front side along
// P_u x P_v; each cell's diagonal alternates (a checkerboard), so edges run in three directions.
inline std::shared_ptr<TriangleMesh> param_grid(int nu, int nv, double u0, double u1, double v0, double v1,
                                                const std::function<Vec3(double, double)>& P) {
  auto m = std::make_shared<TriangleMesh>();
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) m->vertices.push_back(P(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv));
  auto at = [&](int i, int j) { return j * (nu + 1) + i; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2 == 0) {
        m->triangles.push_back({a, b, c});
        m->triangles.push_back({a, c, d});
      } else {
        m->triangles.push_back({a, b, d});
        m->triangles.push_back({b, c, d});
      }
    }
  return m;
}

// nx x ny square cells of side h from (x0, y0), z = height(x, y) (0 without), front side up.
inline std::shared_ptr<TriangleMesh> grid(int nx, int ny, double h, double x0, double y0,
                                          const std::function<double(double, double)>& height = nullptr) {
  return param_grid(nx, ny, x0, x0 + nx * h, y0, y0 + ny * h,
                    [&](double x, double y) { return Vec3(x, y, height ? height(x, y) : 0.0); });
}

// A static body whose only collider is the mesh (massless: static).
inline BodyDef mesh_body(std::shared_ptr<const TriangleMesh> mesh, double friction = 0.6,
                         const Quat& q_WB = Quat::Identity(), const Vec3& p_WB = Vec3::Zero()) {
  BodyDef b;
  b.name = "mesh";
  b.type = BodyType::static_body;
  b.q_WB = q_WB;
  b.p_WB = p_WB;
  Collider c;
  c.shape = ShapeKind::mesh;
  c.mesh = std::move(mesh);
  c.props_C.mass = 0;
  c.props_C.com = Vec3::Zero();
  c.props_C.inertia = Mat3::Zero();
  c.friction = friction;
  b.add_collider(c);
  return b;
}

}  // namespace simreel::trimesh_test

namespace simreel::trimesh_test {

// The lower half of a sphere of radius R centred at (0, 0, R) (bottom at the origin, rim at
// z = R), front side inward: n_theta rings from the bottom to the rim, n_phi segments around,
// the seam and the pole shared (welded exactly).
inline std::shared_ptr<TriangleMesh> bowl(double R, int n_theta, int n_phi) {
  auto m = std::make_shared<TriangleMesh>();
  m->vertices.emplace_back(0, 0, 0);  // the pole
  for (int i = 1; i <= n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const double th = 0.5 * M_PI * i / n_theta, ph = 2 * M_PI * j / n_phi;
      m->vertices.emplace_back(R * std::sin(th) * std::cos(ph), R * std::sin(th) * std::sin(ph),
                               R - R * std::cos(th));
    }
  auto at = [&](int i, int j) { return i == 0 ? 0 : 1 + (i - 1) * n_phi + (j % n_phi); };
  for (int i = 0; i < n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      // Inward front: (theta, phi) increasing is counter-clockwise seen from inside.
      m->triangles.push_back({a, b, c});
      if (i > 0) m->triangles.push_back({a, c, d});
    }
  return m;
}

}  // namespace simreel::trimesh_test

namespace simreel::trimesh_test {

// A closed cuboid of half extents h centred at the origin, each face a grid of cells (n[axis]
// cells along each axis), counter-clockwise about the outward normal. Every coordinate along an
// axis comes from one table, so the faces' shared vertices weld exactly.
inline std::shared_ptr<TriangleMesh> cuboid(const Vec3& h, const int n[3]) {
  auto m = std::make_shared<TriangleMesh>();
  std::vector<double> coord[3];
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i <= n[a]; ++i) coord[a].push_back(i == n[a] ? h[a] : -h[a] + 2.0 * h[a] * i / n[a]);
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
      const int base = (int)m->vertices.size();
      for (int j = 0; j <= n[v]; ++j)
        for (int i = 0; i <= n[u]; ++i) {
          Vec3 p;
          p[a] = s == 0 ? -h[a] : h[a];
          p[u] = coord[u][i];
          p[v] = coord[v][j];
          m->vertices.push_back(p);
        }
      auto at = [&](int i, int j) { return base + j * (n[u] + 1) + i; };
      for (int j = 0; j < n[v]; ++j)
        for (int i = 0; i < n[u]; ++i) {
          const int p0 = at(i, j), p1 = at(i + 1, j), p2 = at(i + 1, j + 1), p3 = at(i, j + 1);
          if (s == 1) {  // +e_a outward: counter-clockwise in (u, v)
            m->triangles.push_back({p0, p1, p2});
            m->triangles.push_back({p0, p2, p3});
          } else {
            m->triangles.push_back({p0, p2, p1});
            m->triangles.push_back({p0, p3, p2});
          }
        }
    }
  return m;
}

}  // namespace simreel::trimesh_test
