#include "sim/convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>

#include "sim/error.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace simreel {
namespace {

// qhull's options. 'Qs' searches all points for the initial simplex (robust for thin, nearly flat
// sets); merging is qhull's default for 3-d, 'C-0': a facet is merged into its neighbour whenever
// their convexity cannot be told apart from roundoff, so every facet qhull returns is clearly
// convex and planar to roundoff, and its vertices are input points (never moved, never jiggled:
// no 'QJ'). Not 'Qt': triangulating the merged facets would hide the coplanar faces that
// convex_polyhedron() needs whole. No randomisation ('QRn'): the result is deterministic.
constexpr const char* kQhullOptions = "qhull Qs";

struct RawFace {
  std::vector<int> loop;  // input point indices, counter-clockwise seen from outside
  Vec3 normal;            // outward unit normal (qhull's hyperplane)
  double offset;          // normal . v on the face
};

// The first line of qhull's message (qhull writes several paragraphs of advice after it).
std::string first_line(const std::string& s) {
  size_t a = s.find_first_not_of(" \n");
  if (a == std::string::npos) return "no message";
  size_t b = s.find('\n', a);
  return s.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

// Throws InputError unless the points can have a convex hull with volume: at least 4, finite, and
// not all on one plane (decided with a tolerance relative to the set's size; qhull decides nearly
// flat sets itself).
void check_points(const std::vector<Vec3>& pts) {
  const size_t n = pts.size();
  if (n < 4)
    throw InputError("convex hull needs at least 4 points (not all in one plane), got " + std::to_string(n));
  for (size_t i = 0; i < n; ++i)
    if (!pts[i].allFinite())
      throw InputError("convex hull: point " + std::to_string(i) + " has a coordinate that is not finite");
  Vec3 lo = pts[0], hi = pts[0];
  for (const Vec3& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double eps = 1e-13 * (hi - lo).norm();
  if (!((hi - lo).norm() > 0)) throw InputError("convex hull: all points coincide, they span no volume");
  // Furthest pair from the first point, then the point furthest from their line and plane.
  size_t a = 0, b = 0, c = n, d = n;
  double best = 0;
  for (size_t i = 0; i < n; ++i)
    if ((pts[i] - pts[a]).squaredNorm() > best) best = (pts[i] - pts[a]).squaredNorm(), b = i;
  const Vec3 u = (pts[b] - pts[a]).normalized();
  best = eps;
  for (size_t i = 0; i < n; ++i) {
    const double dist = (pts[i] - pts[a]).cross(u).norm();
    if (dist > best) best = dist, c = i;
  }
  if (c == n) throw InputError("convex hull: all points lie on one line, they span no volume");
  const Vec3 w = u.cross(pts[c] - pts[a]).normalized();
  best = eps;
  for (size_t i = 0; i < n; ++i) {
    const double dist = std::fabs(w.dot(pts[i] - pts[a]));
    if (dist > best) best = dist, d = i;
  }
  if (d == n)
    throw InputError(
        "convex hull: all points lie in one plane, they span no volume (a flat mesh: use `mode: shell`)");
}

// Copies qhull's facets out as vertex loops. qhull reports internal errors by longjmp to
// qh->errexit, so this frame holds only trivially destructible locals and calls qhull for nothing
// but reading; the vectors it fills belong to the caller. Returns qhull's exit code (0: success).
int collect_facets(qhT* qh, std::vector<RawFace>* out) {
  facetT* facet;
  vertexT *vertex, **vertexp;
  setT* vertices = nullptr;
  qh->NOerrexit = False;
  const int code = setjmp(qh->errexit);
  if (code) {
    qh->NOerrexit = True;
    return code;
  }
  FORALLfacets {
    // In 3-d qh_facet3vertex orders a facet's vertices around it (from ridges for a merged facet).
    vertices = qh_facet3vertex(qh, facet);
    out->emplace_back();
    RawFace& f = out->back();
    f.loop.reserve((size_t)qh_setsize(qh, vertices));
    FOREACHvertex_(vertices) f.loop.push_back(qh_pointid(qh, vertex->point));
    qh_settempfree(qh, &vertices);
    f.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]);
    f.offset = -facet->offset;  // qhull: normal . x + offset = 0 on the facet, < 0 inside
  }
  qh->NOerrexit = True;
  return 0;
}

// Runs qhull on the points; facets as loops of input indices, counter-clockwise from outside.
std::vector<RawFace> qhull_faces(const std::vector<Vec3>& pts) {
  check_points(pts);
  std::vector<coordT> coords(3 * pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = pts[i][k];

  // qhull never writes to stdout or stderr: its messages go to a memory stream, read on error.
  char* msg_buf = nullptr;
  size_t msg_len = 0;
  FILE* msg = open_memstream(&msg_buf, &msg_len);
  if (!msg) throw std::bad_alloc();
  auto qh = std::make_unique<qhT>();
  qh_zero(qh.get(), msg);
  struct Cleanup {
    qhT* qh;
    FILE* msg;
    char** buf;
    ~Cleanup() {
      qh_freeqhull(qh, !qh_ALL);
      int curlong = 0, totlong = 0;
      qh_memfreeshort(qh, &curlong, &totlong);
      if (msg) fclose(msg);
      free(*buf);
    }
  } cleanup{qh.get(), msg, &msg_buf};

  char options[64];
  std::snprintf(options, sizeof options, "%s", kQhullOptions);
  int code = qh_new_qhull(qh.get(), 3, (int)pts.size(), coords.data(), False, options, msg, msg);
  std::vector<RawFace> faces;
  if (!code) code = collect_facets(qh.get(), &faces);
  if (code) {
    fflush(msg);
    const std::string text(msg_buf ? msg_buf : "", msg_len);
    if (code == qh_ERRmem) throw std::bad_alloc();
    if (code == qh_ERRsingular)
      throw InputError("convex hull: the points span no volume (qhull: " + first_line(text) + ")");
    throw InputError("convex hull failed (qhull exit code " + std::to_string(code) + ": " + first_line(text) +
                     ")");
  }
  if (faces.size() < 4) throw InputError("convex hull: qhull returned fewer than 4 faces");
  // Orient each loop by its own area vector (qhull's vertex order is clockwise or not by facet).
  for (RawFace& f : faces) {
    if (f.loop.size() < 3) throw InputError("convex hull: qhull returned a face with fewer than 3 corners");
    Vec3 area = Vec3::Zero();
    const Vec3& o = pts[f.loop[0]];
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) area += (pts[f.loop[k]] - o).cross(pts[f.loop[k + 1]] - o);
    if (area.dot(f.normal) < 0) std::reverse(f.loop.begin(), f.loop.end());
  }
  return faces;
}

uint64_t key(int a, int b) {
  return (uint64_t)(uint32_t)a << 32 | (uint32_t)b;
}

}  // namespace

ConvexPolyhedron convex_polyhedron(const std::vector<Vec3>& pts) {
  std::vector<RawFace> faces = qhull_faces(pts);

  // A corner shared by only two faces lies on their common edge: not an extreme point (qhull keeps
  // such points when a merge leaves them there). Drop it from both loops.
  std::vector<int> degree(pts.size(), 0);
  for (const RawFace& f : faces)
    for (int v : f.loop) ++degree[v];
  for (RawFace& f : faces) {
    if (f.loop.size() <= 3) continue;
    std::vector<int> kept;
    kept.reserve(f.loop.size());
    for (int v : f.loop)
      if (degree[v] >= 3) kept.push_back(v);
    if (kept.size() >= 3) f.loop = std::move(kept);
  }

  // Vertices: the input points the faces use, in input order.
  ConvexPolyhedron p;
  std::vector<int> index(pts.size(), -1);
  for (const RawFace& f : faces)
    for (int v : f.loop) index[v] = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    if (index[i] == 0) {
      index[i] = (int)p.vertices.size();
      p.vertices.push_back(pts[i]);
    }

  // Half-edges: one per face corner; the half-edge a -> b and its twin b -> a share the pair
  // (2k, 2k+1), numbered in the order the edges are first met.
  size_t corners = 0;
  for (const RawFace& f : faces) corners += f.loop.size();
  p.edges.resize(corners);
  std::unordered_map<uint64_t, int> half;
  half.reserve(corners * 2);
  int next_pair = 0;
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    const std::vector<int>& loop = faces[fi].loop;
    const size_t m = loop.size();
    std::vector<int> ids(m);
    for (size_t k = 0; k < m; ++k) {
      const int a = index[loop[k]], b = index[loop[(k + 1) % m]];
      int id;
      if (auto it = half.find(key(b, a)); it != half.end()) {
        id = it->second ^ 1;
      } else {
        if (next_pair + 2 > (int)corners || half.count(key(a, b)))
          throw InputError("convex hull: qhull returned a surface that is not closed");
        id = next_pair;
        next_pair += 2;
      }
      if (!half.emplace(key(a, b), id).second)
        throw InputError("convex hull: qhull returned an edge used twice in one direction");
      ids[k] = id;
      p.edges[id].origin = a;
      p.edges[id].twin = id ^ 1;
      p.edges[id].face = (int)fi;
    }
    for (size_t k = 0; k < m; ++k) p.edges[ids[k]].next = ids[(k + 1) % m];
    ConvexPolyhedron::Face face;
    face.normal = faces[fi].normal;
    face.offset = faces[fi].offset;
    face.edge = ids[0];
    p.faces.push_back(face);
  }
  if (next_pair != (int)corners) throw InputError("convex hull: qhull returned a surface that is not closed");

  // Volume centroid from the faces fanned into tetrahedra about a point near the hull (keeps
  // precision far from the origin).
  Vec3 lo = p.vertices[0], hi = p.vertices[0];
  for (const Vec3& v : p.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec3 ref = 0.5 * (lo + hi);
  double vol6 = 0;
  Vec3 first24 = Vec3::Zero();
  for (const RawFace& f : faces) {
    const Vec3 a = pts[f.loop[0]] - ref;
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) {
      const Vec3 b = pts[f.loop[k]] - ref, c = pts[f.loop[k + 1]] - ref;
      const double d = a.dot(b.cross(c));
      vol6 += d;
      first24 += d * (a + b + c);
    }
  }
  if (!(vol6 > 0)) throw InputError("convex hull: the points span no volume");
  p.centroid = ref + first24 / (4 * vol6);
  p.inner_radius = INFINITY;
  for (const ConvexPolyhedron::Face& f : p.faces)
    p.inner_radius = std::min(p.inner_radius, f.offset - f.normal.dot(p.centroid));
  return p;
}

TriangleMesh convex_hull(const std::vector<Vec3>& pts) {
  const ConvexPolyhedron p = convex_polyhedron(pts);
  TriangleMesh out;
  out.vertices = p.vertices;
  out.triangles.reserve(p.edges.size() - 2 * p.faces.size());
  for (const ConvexPolyhedron::Face& f : p.faces) {
    const int e0 = f.edge, a = p.edges[e0].origin;
    for (int e = p.edges[e0].next; p.edges[e].next != e0; e = p.edges[e].next)
      out.triangles.push_back({a, p.edges[e].origin, p.edges[p.edges[e].next].origin});
  }
  return out;
}

}  // namespace simreel
