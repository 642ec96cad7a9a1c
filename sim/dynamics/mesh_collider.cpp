#include "sim/dynamics/mesh_collider.hpp"

#include <algorithm>
#include <string>

#include <simreel/error.hpp>
#include "sim/geometry/convex_hull.hpp"

namespace simreel {

// Collision hulls of a mesh collider: the convex hull of all its vertices, or with `parts` one hull
// per connected part (triangles sharing a vertex position), in file order of each part's first
// triangle. Throws InputError when a part spans no volume.
std::vector<std::shared_ptr<const ConvexPolyhedron>> collision_hulls(const TriangleMesh& mesh, bool parts,
                                                                     int max_vertices,
                                                                     std::vector<HullReduction>* reductions) {
  std::vector<std::shared_ptr<const ConvexPolyhedron>> out;
  if (reductions) reductions->clear();
  auto hull = [&](const std::vector<Vec3>& pts) {
    HullReduction r;
    out.push_back(std::make_shared<const ConvexPolyhedron>(convex_polyhedron(pts, max_vertices, &r)));
    if (reductions) reductions->push_back(r);
  };
  if (!parts) {
    hull(mesh.vertices);
    return out;
  }
  const TriangleMesh m = repaired_mesh(mesh);  // welded: shared positions are shared indices
  std::vector<int> root(m.vertices.size());
  for (size_t i = 0; i < root.size(); ++i) root[i] = (int)i;
  auto find = [&](int x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const auto& t : m.triangles)
    for (int k = 1; k < 3; ++k) {
      const int a = find(t[0]), b = find(t[k]);
      if (a != b) root[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> part_of(m.vertices.size(), -1);
  std::vector<std::vector<Vec3>> points;
  for (const auto& t : m.triangles) {
    const int r = find(t[0]);
    if (part_of[r] < 0) {
      part_of[r] = (int)points.size();
      points.emplace_back();
    }
  }
  std::vector<char> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (int v : t)
      if (!used[v]) {
        used[v] = 1;
        points[part_of[find(v)]].push_back(m.vertices[v]);
      }
  for (size_t p = 0; p < points.size(); ++p) {
    try {
      hull(points[p]);
    } catch (const InputError& e) {
      throw InputError("part " + std::to_string(p + 1) + " of " + std::to_string(points.size()) + ": " +
                       e.what());
    }
  }
  return out;
}

Collider mesh_collider(std::shared_ptr<const TriangleMesh> mesh, double density, bool parts,
                       MeshReport* report, int hull_vertices) {
  MeshMassOptions opt;
  opt.density = density;
  const MeshReport rep = analyze_mesh(*mesh, opt);
  if (!(rep.props.mass > 0)) throw InputError("the mesh encloses no volume, so it has no mass");
  Collider c;
  c.shape = ShapeKind::mesh;
  c.props_C = rep.props;
  c.hulls = collision_hulls(*mesh, parts, hull_vertices);
  c.mesh = std::move(mesh);
  if (report) *report = rep;
  return c;
}

}  // namespace simreel
