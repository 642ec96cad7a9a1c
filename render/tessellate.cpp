#include "render/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace simreel {
namespace {

constexpr double kPi = std::numbers::pi;

void push(RenderMesh& m, const Vec3& p, const Vec3& n) {
  for (double v : {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()}) m.vertices.push_back((float)v);
  m.radius = std::max(m.radius, (float)p.norm());
}
uint32_t count(const RenderMesh& m) {
  return (uint32_t)(m.vertices.size() / 6);
}

// A surface of revolution about z from a profile (radius, z, normal in the rz plane).
struct ProfilePoint {
  double r, z, nr, nz;
};
void revolve(RenderMesh& m, const std::vector<ProfilePoint>& prof, int seg) {
  const uint32_t base = count(m);
  for (const ProfilePoint& p : prof)
    for (int j = 0; j <= seg; ++j) {
      const double a = 2 * kPi * j / seg, c = std::cos(a), s = std::sin(a);
      push(m, Vec3(p.r * c, p.r * s, p.z), Vec3(p.nr * c, p.nr * s, p.nz));
    }
  for (size_t i = 0; i + 1 < prof.size(); ++i)
    for (int j = 0; j < seg; ++j) {
      const uint32_t a = base + (uint32_t)(i * (seg + 1) + j), b = a + seg + 1;
      m.indices.insert(m.indices.end(), {a, a + 1, b + 1, a, b + 1, b});
    }
}

void disk(RenderMesh& m, double r, double z, double nz, int seg) {
  const uint32_t c = count(m);
  push(m, Vec3(0, 0, z), Vec3(0, 0, nz));
  for (int j = 0; j <= seg; ++j) {
    const double a = 2 * kPi * j / seg;
    push(m, Vec3(r * std::cos(a), r * std::sin(a), z), Vec3(0, 0, nz));
  }
  for (int j = 0; j < seg; ++j) {
    const uint32_t a = c + 1 + j;
    if (nz > 0)
      m.indices.insert(m.indices.end(), {c, a, a + 1});
    else
      m.indices.insert(m.indices.end(), {c, a + 1, a});
  }
}

}  // namespace

RenderMesh tessellate_box(const Vec3& s) {
  RenderMesh m;
  const Vec3 h = 0.5 * s;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      Vec3 n = Vec3::Zero();
      n[axis] = sign;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const uint32_t b = count(m);
      for (int k = 0; k < 4; ++k) {
        Vec3 p;
        p[axis] = sign * h[axis];
        p[u] = ((k == 1 || k == 2) ? 1 : -1) * h[u];
        p[v] = (k >= 2 ? 1 : -1) * h[v];
        push(m, p, n);
      }
      if (sign > 0)
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
      else
        m.indices.insert(m.indices.end(), {b, b + 2, b + 1, b, b + 3, b + 2});
    }
  return m;
}

RenderMesh tessellate_sphere(double r, int rings) {
  RenderMesh m;
  std::vector<ProfilePoint> prof;
  for (int i = 0; i <= rings; ++i) {
    const double th = kPi * i / rings;  // from the south pole up
    prof.push_back({r * std::sin(th), -r * std::cos(th), std::sin(th), -std::cos(th)});
  }
  revolve(m, prof, 2 * rings);
  return m;
}

RenderMesh tessellate_cylinder(double r, double h, int seg) {
  RenderMesh m;
  revolve(m, {{r, -h / 2, 1, 0}, {r, h / 2, 1, 0}}, seg);
  disk(m, r, h / 2, 1, seg);
  disk(m, r, -h / 2, -1, seg);
  return m;
}

RenderMesh tessellate_cone(double r, double h, int seg) {
  RenderMesh m;
  const double l = std::hypot(r, h), nr = h / l, nz = r / l;
  revolve(m, {{r, 0, nr, nz}, {0, h, nr, nz}}, seg);
  disk(m, r, 0, -1, seg);
  return m;
}

RenderMesh tessellate_capsule(double r, double h, int seg) {
  RenderMesh m;
  const double half = h / 2 - r;  // centre of each hemisphere
  std::vector<ProfilePoint> prof;
  const int q = seg / 4;
  for (int i = 0; i <= q; ++i) {
    const double th = kPi / 2 * i / q;
    prof.push_back({r * std::sin(th), -half - r * std::cos(th), std::sin(th), -std::cos(th)});
  }
  for (int i = 0; i <= q; ++i) {
    const double th = kPi / 2 + kPi / 2 * i / q;
    prof.push_back({r * std::sin(th), half - r * std::cos(th), std::sin(th), -std::cos(th)});
  }
  revolve(m, prof, seg);
  return m;
}

RenderMesh tessellate_plane(double size) {
  RenderMesh m;
  const double h = size / 2;
  push(m, Vec3(-h, -h, 0), Vec3::UnitZ());
  push(m, Vec3(h, -h, 0), Vec3::UnitZ());
  push(m, Vec3(h, h, 0), Vec3::UnitZ());
  push(m, Vec3(-h, h, 0), Vec3::UnitZ());
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

RenderMesh tessellate_ellipsoid(const Vec3& r, int rings) {
  RenderMesh unit = tessellate_sphere(1.0, rings);
  RenderMesh m;
  m.indices = std::move(unit.indices);
  for (size_t v = 0; v + 5 < unit.vertices.size(); v += 6) {
    const Vec3 p(unit.vertices[v], unit.vertices[v + 1], unit.vertices[v + 2]);
    const Vec3 n(unit.vertices[v + 3], unit.vertices[v + 4], unit.vertices[v + 5]);
    push(m, p.cwiseProduct(r), n.cwiseQuotient(r).normalized());
  }
  return m;
}

RenderMesh tessellate_plane_collider(double size) {
  RenderMesh m = tessellate_plane(size);
  m.two_sided = true;  // a slope is seen from below as often as from above
  return m;
}

RenderMesh tessellate_mesh(const TriangleMesh& tm, const CornerNormals* normals, double crease_deg) {
  // Each corner gets the area-weighted average of the normals of the faces around its vertex that
  // lie within crease_deg of its own face normal: smooth curved surfaces, sharp edges kept.
  RenderMesh m;
  m.two_sided = true;
  const size_t nf = tm.triangles.size();
  const bool from_file = normals && normals->size() == nf;
  std::vector<Vec3> fn(nf);
  std::vector<std::vector<int>> around(from_file ? 0 : tm.vertices.size());  // only for crease normals
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = tm.triangles[f];
    fn[f] = (tm.vertices[t[1]] - tm.vertices[t[0]]).cross(tm.vertices[t[2]] - tm.vertices[t[0]]);
    if (!from_file)
      for (int k = 0; k < 3; ++k) around[t[k]].push_back((int)f);
  }
  const double cos_crease = std::cos(crease_deg * kPi / 180);
  for (size_t f = 0; f < nf; ++f) {
    const Vec3 own = fn[f].normalized();
    if (from_file) {  // the file's own shading normals, where it gives a usable one
      for (int k = 0; k < 3; ++k) {
        const Vec3 n = (*normals)[f][k].cast<double>();
        push(m, tm.vertices[tm.triangles[f][k]], n.squaredNorm() > 0.5 ? (n.dot(own) < 0 ? -n : n) : own);
        m.indices.push_back(count(m) - 1);
      }
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int v = tm.triangles[f][k];
      Vec3 n = Vec3::Zero();
      for (int g : around[v])
        if (fn[g].normalized().dot(own) >= cos_crease) n += fn[g];
      push(m, tm.vertices[v], n.norm() > 0 ? Vec3(n.normalized()) : own);
      m.indices.push_back(count(m) - 1);
    }
  }
  return m;
}

RenderMesh tessellate_collider(const Collider& c, double plane_size, const CornerNormals* normals) {
  auto solid = [](RenderMesh m) {
    m.convex = true;
    return m;
  };
  switch (c.shape) {
    case ShapeKind::box:
      return solid(tessellate_box(c.size));
    case ShapeKind::sphere:
      return solid(tessellate_sphere(c.radius));
    case ShapeKind::cylinder:
      return solid(tessellate_cylinder(c.radius, c.height));
    case ShapeKind::capsule:
      return solid(tessellate_capsule(c.radius, c.height));
    case ShapeKind::mesh:
      return tessellate_mesh(*c.mesh, normals);
    case ShapeKind::ellipsoid:
      return solid(tessellate_ellipsoid(c.radii));
    case ShapeKind::plane:
      return tessellate_plane_collider(plane_size);
  }
  return {};
}

void apply_appearance(RenderMesh& m, const MeshAppearance& look, const std::vector<int>& texture_slot) {
  const size_t nt = m.indices.size() / 3;
  if (m.vertices.size() != 6 * 3 * nt || look.triangle_material.size() != nt) return;  // not this mesh's
  m.extras.assign(6 * 3 * nt, 0.0f);
  std::vector<int> slot_of(nt, -1);
  for (size_t f = 0; f < nt; ++f) {
    const int mat = look.triangle_material[f];
    const SurfaceMaterial* sm = mat >= 0 && mat < (int)look.materials.size() ? &look.materials[mat] : nullptr;
    const bool known = sm && sm->color[0] >= 0;
    if (sm && sm->texture >= 0 && sm->texture < (int)texture_slot.size() && !look.corner_uv.empty())
      slot_of[f] = texture_slot[sm->texture];
    for (int k = 0; k < 3; ++k) {
      float* e = &m.extras[6 * (3 * f + k)];
      std::array<float, 3> c = known ? sm->color : std::array<float, 3>{1, 1, 1};
      if (!look.corner_color.empty())
        for (int j = 0; j < 3; ++j) c[j] *= look.corner_color[f][k][j];
      const bool own = known || !look.corner_color.empty();
      e[0] = c[0], e[1] = c[1], e[2] = c[2], e[3] = own ? 1.0f : 0.0f;
      if (slot_of[f] >= 0) e[4] = look.corner_uv[f][k].x(), e[5] = look.corner_uv[f][k].y();
    }
  }
  // Triangles grouped by texture (untextured first), each group in triangle order.
  std::vector<uint32_t> order(nt);
  for (size_t f = 0; f < nt; ++f) order[f] = (uint32_t)f;
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return slot_of[a] < slot_of[b]; });
  std::vector<uint32_t> idx(3 * nt);
  m.parts.clear();
  for (size_t i = 0; i < nt; ++i) {
    const uint32_t f = order[i];
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = m.indices[3 * f + k];
    if (m.parts.empty() || m.parts.back().texture != slot_of[f])
      m.parts.push_back({(uint32_t)(3 * i), 0, slot_of[f]});
    m.parts.back().count += 3;
  }
  m.indices = std::move(idx);
}

RenderMeshKey render_mesh_key(const Collider& c, double plane_size, const CornerNormals* normals,
                              const MeshAppearance* look) {
  RenderMeshKey k;
  k.shape = c.shape;
  switch (c.shape) {
    case ShapeKind::box:
      k.dims = {c.size.x(), c.size.y(), c.size.z()};
      break;
    case ShapeKind::sphere:
      k.dims = {c.radius, 0, 0};
      break;
    case ShapeKind::cylinder:
    case ShapeKind::capsule:
      k.dims = {c.radius, c.height, 0};
      break;
    case ShapeKind::mesh:
      k.mesh = c.mesh.get();
      k.normals = normals;
      k.look = look;
      break;
    case ShapeKind::ellipsoid:
      k.dims = {c.radii.x(), c.radii.y(), c.radii.z()};
      break;
    case ShapeKind::plane:
      k.dims = {plane_size, 0, 0};
      break;
  }
  return k;
}

size_t render_mesh_bytes(const Collider& c, bool with_look) {
  // Floats per vertex, and per shape its vertices and indices as the functions above make them:
  // revolve() makes (profile points) x (segments + 1) vertices and 6 indices per quad; disk() 2 +
  // segments vertices and 3 indices per segment. The tests compare with the meshes themselves.
  auto bytes = [](size_t vertices, size_t indices) { return (6 * vertices + indices) * 4; };
  constexpr size_t rings = 24, seg = 48;  // the defaults of the tessellate_ functions
  const size_t sphere = bytes((rings + 1) * (2 * rings + 1), rings * 2 * rings * 6);
  switch (c.shape) {
    case ShapeKind::box:
      return bytes(24, 36);
    case ShapeKind::sphere:
    case ShapeKind::ellipsoid:
      return sphere;
    case ShapeKind::cylinder:
      return bytes(2 * (seg + 1) + 2 * (seg + 2), seg * 6 + 2 * seg * 3);
    case ShapeKind::capsule:
      return bytes((2 * (seg / 4 + 1)) * (seg + 1), (2 * (seg / 4 + 1) - 1) * seg * 6);
    case ShapeKind::mesh:
      return c.mesh ? bytes(3 * c.mesh->triangles.size(), 3 * c.mesh->triangles.size()) +
                          (with_look ? 6 * 4 * 3 * c.mesh->triangles.size() : 0)
                    : 0;
    case ShapeKind::plane:
      return bytes(4, 6);
  }
  return 0;
}

}  // namespace simreel
