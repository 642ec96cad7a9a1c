#include "sim/geometry/convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>

#include <simreel/error.hpp>

extern "C" {
#include <libqhull_r/qhull_ra.h>
#include "sim/base/pair_key.hpp"
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
        "convex hull: all points lie in one plane, they span no volume (a flat mesh: weigh it as a thin "
        "surface, shell mode)");
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
// added > 0: qhull stops after adding that many points to its first simplex ('TA'), so the hull
// has at most added + 4 vertices, each the farthest point outside the hull so far (Quickhull's
// order; MuJoCo's maxhullvert is the same option).
std::vector<RawFace> qhull_faces(const std::vector<Vec3>& pts, int added = 0) {
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
  if (added > 0)
    std::snprintf(options, sizeof options, "%s TA%d", kQhullOptions, added);
  else
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
  return pair_key(a, b);
}

// A corner shared by only two faces lies on their common edge: not an extreme point (qhull can
// keep such a point when a merge leaves it there). Drops it from both loops; a vertex no face
// uses any more simply disappears.
void drop_edge_points(std::vector<RawFace>& faces, size_t npts) {
  std::vector<int> degree(npts, 0);
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
}

// qhull's faces, merged only where roundoff could not tell them apart: exact to rounding.
std::vector<RawFace> hull_faces(const std::vector<Vec3>& pts) {
  std::vector<RawFace> faces = qhull_faces(pts);
  drop_edge_points(faces, pts.size());
  return faces;
}

// Merges neighbouring faces that are coplanar to within what polyhedron_problem() calls coplanar
// (normals closer than 1 - 1e-12 in cosine, about 1.4e-6 rad), which qhull leaves apart when they
// are not coplanar to roundoff (a nearly flat part's rim, a CAD cap written with noisy decimals).
// A merge is made only if the merged face stays planar: every vertex within kPlanar (5e-10, half of
// polyhedron_problem()'s 1e-9) of the size from the merged plane (the outermost vertex on it); pairs are
// tried most coplanar first, so the result is deterministic. The merged face's corners that end up on only
// two faces are dropped by drop_edge_points(): they were extreme points by less than kPlanar, so the
// polyhedron may lie inside the exact hull by that much (contacts only; mass uses the unmerged hull_faces()).
std::vector<RawFace> merge_coplanar(std::vector<RawFace> faces, const std::vector<Vec3>& pts, double size) {
  constexpr double kCos = 1 - 2e-12, kPlanar = 5e-10;
  const int nf = (int)faces.size();
  std::unordered_map<uint64_t, int> face_of;  // directed edge -> face
  for (int f = 0; f < nf; ++f)
    for (size_t k = 0; k < faces[f].loop.size(); ++k)
      face_of[key(faces[f].loop[k], faces[f].loop[(k + 1) % faces[f].loop.size()])] = f;
  struct Pair {
    double cos;
    int f, g;
  };
  std::vector<Pair> pairs;
  for (int f = 0; f < nf; ++f)
    for (size_t k = 0; k < faces[f].loop.size(); ++k) {
      const auto it = face_of.find(key(faces[f].loop[(k + 1) % faces[f].loop.size()], faces[f].loop[k]));
      if (it == face_of.end() || it->second <= f) continue;
      const double c = faces[f].normal.dot(faces[it->second].normal);
      if (c > kCos) pairs.push_back({c, f, it->second});
    }
  if (pairs.empty()) return faces;
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.cos != b.cos ? a.cos > b.cos : (a.f != b.f ? a.f < b.f : a.g < b.g);
  });
  // Groups: union-find with each root's area-weighted normal and vertex list.
  std::vector<int> root(nf);
  std::iota(root.begin(), root.end(), 0);
  std::vector<Vec3> area(nf);
  std::vector<std::vector<int>> verts(nf);
  for (int f = 0; f < nf; ++f) {
    area[f] = Vec3::Zero();
    const Vec3& o = pts[faces[f].loop[0]];
    for (size_t k = 1; k + 1 < faces[f].loop.size(); ++k)
      area[f] += 0.5 * (pts[faces[f].loop[k]] - o).cross(pts[faces[f].loop[k + 1]] - o);
    verts[f] = faces[f].loop;
  }
  auto find = [&](int x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  const double tol = kPlanar * size;
  for (const Pair& pr : pairs) {
    const int a = find(pr.f), b = find(pr.g);
    if (a == b) continue;
    const Vec3 n = (area[a] + area[b]).normalized();
    double hi = -INFINITY, lo = INFINITY;
    for (const auto* vs : {&verts[a], &verts[b]})
      for (int v : *vs) hi = std::max(hi, n.dot(pts[v])), lo = std::min(lo, n.dot(pts[v]));
    if (hi - lo > tol) continue;
    root[b] = a;
    area[a] += area[b];
    verts[a].insert(verts[a].end(), verts[b].begin(), verts[b].end());
    verts[b].clear();
  }
  // Each group's boundary: its faces' directed edges whose reverse lies in another group, chained.
  std::vector<RawFace> out;
  std::vector<std::vector<std::pair<int, int>>> boundary(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& L = faces[f].loop;
    for (size_t k = 0; k < L.size(); ++k) {
      const int a = L[k], b = L[(k + 1) % L.size()];
      if (find(face_of.at(key(b, a))) != find(f)) boundary[find(f)].emplace_back(a, b);
    }
  }
  for (int r = 0; r < nf; ++r) {
    if (find(r) != r) continue;
    RawFace m;
    m.normal = area[r].normalized();
    if (boundary[r].size() == faces[r].loop.size() && verts[r].size() == faces[r].loop.size()) {
      out.push_back(faces[r]);  // not merged
      continue;
    }
    std::unordered_map<int, int> succ;
    for (auto [a, b] : boundary[r])
      if (!succ.emplace(a, b).second)
        throw InputError("convex hull: merged coplanar faces do not form a disc");
    int v = boundary[r][0].first;
    do {
      m.loop.push_back(v);
      v = succ.at(v);
    } while (v != boundary[r][0].first && m.loop.size() <= boundary[r].size());
    if (m.loop.size() != boundary[r].size())
      throw InputError("convex hull: merged coplanar faces do not form a disc");
    m.offset = -INFINITY;
    for (int u : m.loop) m.offset = std::max(m.offset, m.normal.dot(pts[u]));
    out.push_back(std::move(m));
  }
  drop_edge_points(out, pts.size());
  return out;
}

// Volume centroid from the faces fanned into tetrahedra about a point near the hull (keeps
// precision far from the origin).
Vec3 volume_centroid(const std::vector<RawFace>& faces, const std::vector<Vec3>& pts) {
  Vec3 lo = pts[faces[0].loop[0]], hi = lo;
  for (const RawFace& f : faces)
    for (int v : f.loop) lo = lo.cwiseMin(pts[v]), hi = hi.cwiseMax(pts[v]);
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
  return ref + first24 / (4 * vol6);
}

// The polyhedron on qhull's faces `exact` of the points.
ConvexPolyhedron polyhedron_from(const std::vector<RawFace>& exact, const std::vector<Vec3>& pts) {
  ConvexPolyhedron p;
  p.centroid = volume_centroid(exact, pts);
  double size = 0;
  for (const RawFace& f : exact)
    for (int v : f.loop) size = std::max(size, (pts[v] - p.centroid).norm());
  const std::vector<RawFace> faces = merge_coplanar(exact, pts, size);

  // Vertices: the input points the faces use, in input order.
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

  p.inner_radius = INFINITY;
  for (const ConvexPolyhedron::Face& f : p.faces)
    p.inner_radius = std::min(p.inner_radius, f.offset - f.normal.dot(p.centroid));
  // Never hand out a polyhedron that breaks its conventions. Only a nearly flat set gets here
  // (neighbouring faces closer than 1.4e-6 rad that are not planar to 5e-10 of the size together).
  // Offsets are absolute, so far from the origin planarity holds only to |position| * ulp: the
  // tolerance grows with distance/size (a collider's shape frame is centred, where it is 1e-9).
  double far = 0;
  for (const Vec3& v : p.vertices) far = std::max(far, v.norm());
  // Not refused: "joins two coplanar faces" alone. Real CAD hulls (the gear) have
  // neighbouring faces 1e-7 rad apart whose union is 1e-8 of the size off planar: no merge can
  // satisfy both of polyhedron_problem()'s rules there without moving vertices (reported upstream).
  const std::string bad = polyhedron_problem(p, 1e-9 * std::max(1.0, far / size));
  if (!bad.empty() && bad.find("joins two coplanar faces") == std::string::npos)
    throw InputError("convex hull: the points are too nearly flat for a valid collision polyhedron (" + bad +
                     ")");
  p.build_adjacency();
  return p;
}

}  // namespace

ConvexPolyhedron convex_polyhedron(const std::vector<Vec3>& pts, int max_vertices, HullReduction* reduction) {
  ConvexPolyhedron p = polyhedron_from(hull_faces(pts), pts);
  if (reduction) *reduction = HullReduction{(int)p.vertices.size(), (int)p.vertices.size(), 1.0};
  if (max_vertices < 4 || (int)p.vertices.size() <= max_vertices) return p;
  // The hull of the extreme points, stopped once it has max_vertices of them: an inner hull, its
  // volume a little less. Its own corners on an edge are dropped as in any hull.
  std::vector<RawFace> faces = qhull_faces(p.vertices, max_vertices - 4);
  drop_edge_points(faces, p.vertices.size());
  ConvexPolyhedron q = polyhedron_from(faces, p.vertices);
  if (reduction) {
    reduction->vertices = (int)q.vertices.size();
    reduction->volume_ratio = polyhedron_volume(q) / polyhedron_volume(p);
  }
  return q;
}

TriangleMesh convex_hull(const std::vector<Vec3>& pts) {
  // The unmerged faces: every extreme point qhull found stays a vertex, so the mass properties
  // are those of the exact hull to rounding.
  const std::vector<RawFace> faces = hull_faces(pts);
  TriangleMesh out;
  std::vector<int> index(pts.size(), -1);
  for (const RawFace& f : faces)
    for (int v : f.loop) index[v] = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    if (index[i] == 0) {
      index[i] = (int)out.vertices.size();
      out.vertices.push_back(pts[i]);
    }
  for (const RawFace& f : faces)
    for (size_t k = 1; k + 1 < f.loop.size(); ++k)
      out.triangles.push_back({index[f.loop[0]], index[f.loop[k]], index[f.loop[k + 1]]});
  return out;
}

}  // namespace simreel
