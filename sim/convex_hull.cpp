#include "sim/convex_hull.hpp"

#include <cmath>
#include <unordered_map>

#include "sim/error.hpp"

namespace simreel {
namespace {

struct Face {
  int a, b, c;
  Vec3 n;    // outward unit normal
  double d;  // plane offset: n.p = d on the face
  bool alive;
};

Face make_face(const std::vector<Vec3>& p, int a, int b, int c) {
  Face f{a, b, c, (p[b] - p[a]).cross(p[c] - p[a]), 0.0, true};
  const double len = f.n.norm();
  if (len > 0) f.n /= len;
  f.d = f.n.dot(p[a]);
  return f;
}

}  // namespace

TriangleMesh convex_hull(const std::vector<Vec3>& pts) {
  const int n = (int)pts.size();
  if (n < 4) throw InputError("convex hull needs at least 4 points, the mesh has " + std::to_string(n));
  // Initial tetrahedron from extreme points: furthest pair, furthest from their line, furthest
  // from their plane. Distances are compared against eps relative to the point set's size.
  Vec3 lo = pts[0], hi = pts[0];
  for (const Vec3& q : pts) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const double scale = (hi - lo).norm();
  const double eps = 1e-12 * scale;
  int i0 = 0, i1 = 0;
  for (int i = 0; i < n; ++i) {
    if (pts[i].x() < pts[i0].x()) i0 = i;
  }
  double best = -1;
  for (int i = 0; i < n; ++i)
    if ((pts[i] - pts[i0]).squaredNorm() > best) best = (pts[i] - pts[i0]).squaredNorm(), i1 = i;
  if (!(std::sqrt(best) > eps)) throw InputError("all points coincide: no convex hull");
  const Vec3 dir = (pts[i1] - pts[i0]).normalized();
  int i2 = -1;
  best = eps;
  for (int i = 0; i < n; ++i) {
    const double dist = (pts[i] - pts[i0]).cross(dir).norm();
    if (dist > best) best = dist, i2 = i;
  }
  if (i2 < 0) throw InputError("all points lie on a line: no convex hull");
  const Vec3 nrm = (pts[i1] - pts[i0]).cross(pts[i2] - pts[i0]).normalized();
  int i3 = -1;
  best = eps;
  for (int i = 0; i < n; ++i) {
    const double dist = std::fabs(nrm.dot(pts[i] - pts[i0]));
    if (dist > best) best = dist, i3 = i;
  }
  if (i3 < 0) throw InputError("all points lie in a plane: the convex hull is flat, use `mode: shell`");

  std::vector<Face> faces;
  if (nrm.dot(pts[i3] - pts[i0]) > 0) std::swap(i1, i2);  // i3 must be below face (i0,i1,i2)
  faces.push_back(make_face(pts, i0, i1, i2));
  faces.push_back(make_face(pts, i0, i3, i1));
  faces.push_back(make_face(pts, i1, i3, i2));
  faces.push_back(make_face(pts, i2, i3, i0));

  std::vector<char> used(n, 0);
  used[i0] = used[i1] = used[i2] = used[i3] = 1;
  std::unordered_map<uint64_t, int> edges;  // directed edge of a visible face -> count
  std::vector<std::pair<int, int>> horizon;
  std::vector<int> visible;
  for (int p = 0; p < n; ++p) {
    if (used[p]) continue;
    visible.clear();
    for (int f = 0; f < (int)faces.size(); ++f)
      if (faces[f].alive && faces[f].n.dot(pts[p]) - faces[f].d > eps) visible.push_back(f);
    if (visible.empty()) continue;  // inside the current hull
    // Horizon: edges of visible faces whose reverse edge is not on a visible face.
    edges.clear();
    auto key = [](int a, int b) { return (uint64_t)(uint32_t)a << 32 | (uint32_t)b; };
    for (int f : visible) {
      const Face& F = faces[f];
      edges[key(F.a, F.b)]++, edges[key(F.b, F.c)]++, edges[key(F.c, F.a)]++;
    }
    horizon.clear();
    for (int f : visible) {
      const Face& F = faces[f];
      const int v[3] = {F.a, F.b, F.c};
      for (int k = 0; k < 3; ++k)
        if (!edges.count(key(v[(k + 1) % 3], v[k]))) horizon.emplace_back(v[k], v[(k + 1) % 3]);
      faces[f].alive = false;
    }
    for (auto [a, b] : horizon) faces.push_back(make_face(pts, a, b, p));
    used[p] = 1;
  }
  // Compact: keep only vertices on live faces, in first-use order.
  TriangleMesh out;
  std::vector<int> remap(n, -1);
  for (const Face& F : faces) {
    if (!F.alive) continue;
    std::array<int, 3> t{F.a, F.b, F.c};
    for (int& v : t) {
      if (remap[v] < 0) {
        remap[v] = (int)out.vertices.size();
        out.vertices.push_back(pts[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace simreel
