#include "sim/geometry/polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace simreel {

namespace {
// The 26 seed directions: every sign pattern (-1, 0, 1)^3 but zero, unnormalised.
Vec3 seed_direction(int k) {
  const int c = k < 13 ? k : k + 1;  // skip 13, the centre (0, 0, 0)
  return Vec3(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
}
}  // namespace

int ConvexPolyhedron::support(const Vec3& d) const {
  const int n = (int)vertices.size();
  if (n <= kScanVertices || vertex_edge.empty()) {
    int best = 0;
    double best_dot = -INFINITY;
    for (int i = 0; i < n; ++i) {
      const double s = d.dot(vertices[i]);
      if (s > best_dot) best_dot = s, best = i;
    }
    return best;
  }
  int v = seeds[0];
  double best = d.dot(vertices[v]);
  for (size_t k = 1; k < seeds.size(); ++k) {
    const double s = d.dot(vertices[seeds[k]]);
    if (s > best) best = s, v = seeds[k];
  }
  for (;;) {
    // Around v: each leaving half-edge's far end; the next leaving edge is the twin's next.
    int to = -1;
    const int first = vertex_edge[v];
    int e = first;
    do {
      const int w = edges[e ^ 1].origin;
      const double s = d.dot(vertices[w]);
      if (s > best) best = s, to = w;
      e = edges[e ^ 1].next;
    } while (e != first);
    if (to < 0) return v;
    v = to;
  }
}

void ConvexPolyhedron::build_adjacency() {
  face_begin.assign(1, 0);
  face_edges.clear();
  for (const Face& f : faces) {
    int e = f.edge;
    do face_edges.push_back(e), e = edges[e].next;
    while (e != f.edge);
    face_begin.push_back((int)face_edges.size());
  }
  vertex_edge.assign(vertices.size(), -1);
  for (int e = 0; e < (int)edges.size(); ++e)
    if (vertex_edge[edges[e].origin] < 0) vertex_edge[edges[e].origin] = e;
  seeds.clear();
  for (int k = 0; k < 26; ++k) {
    const Vec3 d = seed_direction(k);
    int best = 0;
    double best_dot = -INFINITY;
    for (int i = 0; i < (int)vertices.size(); ++i) {
      const double s = d.dot(vertices[i]);
      if (s > best_dot) best_dot = s, best = i;
    }
    seeds.push_back(best);
  }
  // And every k-th vertex, about 2 sqrt(n) of them: a climb along a long flat-sided rim (a
  // cylinder's cap of 1,500 points) walks one vertex a step, and from the nearest of 26 extremes
  // that was ~60 steps; from the nearest of ~110 seeds it is a few.
  const int n = (int)vertices.size();
  const int stride = std::max(1, n / std::max(1, (int)(2 * std::sqrt((double)n))));
  for (int i = 0; i < n; i += stride) seeds.push_back(i);
}

double polyhedron_volume(const ConvexPolyhedron& p) {
  double v6 = 0;
  for (const ConvexPolyhedron::Face& f : p.faces) {
    const Vec3 a = p.vertices[p.edges[f.edge].origin] - p.centroid;
    for (int e = p.edges[f.edge].next; p.edges[e].next != f.edge; e = p.edges[e].next) {
      const Vec3 b = p.vertices[p.edges[e].origin] - p.centroid;
      const Vec3 c = p.vertices[p.edges[p.edges[e].next].origin] - p.centroid;
      v6 += a.dot(b.cross(c));
    }
  }
  return v6 / 6.0;
}

ConvexPolyhedron make_box_polyhedron(const Vec3& h) {
  ConvexPolyhedron p;
  // Vertex i has coordinate signs from its bits: x from bit 0, y from bit 1, z from bit 2.
  for (int i = 0; i < 8; ++i)
    p.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Faces as vertex loops, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
  const int loops[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const Vec3 normals[6] = {-Vec3::UnitX(), Vec3::UnitX(),  -Vec3::UnitY(),
                           Vec3::UnitY(),  -Vec3::UnitZ(), Vec3::UnitZ()};
  // Half-edges: one per face corner; twins found by the reversed vertex pair, stored as (2k, 2k+1).
  int he_of[8][8];
  for (auto& row : he_of)
    for (int& x : row) x = -1;
  p.edges.resize(24);
  int next_edge = 0;
  for (int f = 0; f < 6; ++f) {
    for (int k = 0; k < 4; ++k) {
      const int a = loops[f][k], b = loops[f][(k + 1) % 4];
      int idx;
      if (he_of[b][a] >= 0) {
        idx = he_of[b][a] ^ 1;
      } else {
        idx = next_edge;
        next_edge += 2;
      }
      he_of[a][b] = idx;
      p.edges[idx].origin = a;
      p.edges[idx].twin = idx ^ 1;
      p.edges[idx].face = f;
    }
    for (int k = 0; k < 4; ++k) {
      const int a = loops[f][k], b = loops[f][(k + 1) % 4], c = loops[f][(k + 2) % 4];
      p.edges[he_of[a][b]].next = he_of[b][c];
    }
    ConvexPolyhedron::Face face;
    face.normal = normals[f];
    face.offset = std::fabs(normals[f].dot(h));
    face.edge = he_of[loops[f][0]][loops[f][1]];
    p.faces.push_back(face);
  }
  p.centroid = Vec3::Zero();
  p.inner_radius = h.minCoeff();
  p.build_adjacency();
  return p;
}

std::string polyhedron_problem(const ConvexPolyhedron& p, double tol) {
  std::ostringstream os;
  const int nv = (int)p.vertices.size(), ne = (int)p.edges.size(), nf = (int)p.faces.size();
  if (nv < 4 || nf < 4 || ne < 12 || ne % 2) return "too few vertices, faces or half-edges";
  double size = 0;
  for (const Vec3& v : p.vertices) size = std::max(size, (v - p.centroid).norm());
  const double eps = tol * std::max(size, 1e-300);
  // Euler's formula for a convex polyhedron: V - E + F = 2.
  if (nv - ne / 2 + nf != 2) {
    os << "V - E + F = " << nv - ne / 2 + nf << ", not 2";
    return os.str();
  }
  std::vector<int> face_edges(nf, 0), vertex_used(nv, 0);
  for (int e = 0; e < ne; ++e) {
    const auto& h = p.edges[e];
    if (h.twin != (e ^ 1)) return "half-edge " + std::to_string(e) + ": twin is not e ^ 1";
    if (h.origin < 0 || h.origin >= nv || h.next < 0 || h.next >= ne || h.face < 0 || h.face >= nf)
      return "half-edge " + std::to_string(e) + ": index out of range";
    if (p.edges[h.next].face != h.face) return "half-edge " + std::to_string(e) + ": next is on another face";
    if (p.edges[h.next].origin != p.edges[h.twin].origin)
      return "half-edge " + std::to_string(e) + ": next does not start where this one ends";
    vertex_used[h.origin] = 1;
    face_edges[h.face]++;
  }
  for (int v = 0; v < nv; ++v)
    if (!vertex_used[v]) return "vertex " + std::to_string(v) + " is on no edge";
  for (int f = 0; f < nf; ++f) {
    const auto& F = p.faces[f];
    if (std::fabs(F.normal.norm() - 1) > 1e-9) return "face " + std::to_string(f) + ": normal is not unit";
    if (F.edge < 0 || F.edge >= ne || p.edges[F.edge].face != f)
      return "face " + std::to_string(f) + ": its edge is not on it";
    // Walk the loop: it must return to the start after as many half-edges as the face owns.
    int e = F.edge, steps = 0;
    do {
      const Vec3& v = p.vertices[p.edges[e].origin];
      if (std::fabs(F.normal.dot(v) - F.offset) > eps)
        return "face " + std::to_string(f) + ": a vertex is off its plane";
      // Convex corner: the turn at each vertex agrees with the outward normal.
      const Vec3& a = p.vertices[p.edges[e].origin];
      const Vec3& b = p.vertices[p.edges[p.edges[e].next].origin];
      const Vec3& c = p.vertices[p.edges[p.edges[p.edges[e].next].next].origin];
      if ((b - a).cross(c - b).dot(F.normal) <= -eps * size)
        return "face " + std::to_string(f) + ": not convex";
      e = p.edges[e].next;
      if (++steps > ne) return "face " + std::to_string(f) + ": its loop does not close";
    } while (e != F.edge);
    if (steps != face_edges[f]) return "face " + std::to_string(f) + ": loop misses some of its half-edges";
    for (int v = 0; v < nv; ++v)
      if (F.normal.dot(p.vertices[v]) - F.offset > eps)
        return "face " + std::to_string(f) + ": vertex " + std::to_string(v) + " is outside its plane";
    // Adjacent faces must not be coplanar (they should have been merged).
  }
  for (int e = 0; e < ne; e += 2) {
    const auto& n1 = p.faces[p.edges[e].face].normal;
    const auto& n2 = p.faces[p.edges[e + 1].face].normal;
    if (n1.dot(n2) > 1 - 1e-12) return "edge " + std::to_string(e / 2) + " joins two coplanar faces";
  }
  return {};
}

}  // namespace simreel
