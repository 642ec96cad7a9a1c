// Exact references for convex hull tests: rational arithmetic (GMP's mpq_class) on the exact
// double coordinates, so the reference itself has no rounding at all.
//   - exact_solid(): volume, centroid and inertia of a closed triangle surface;
//   - hull_containment(): whether every point is inside or on every hull triangle's plane, by an
//     exact orientation predicate (a floating-point filter decides the clear cases, mpq the rest).
// Together they bound how far a hull's mass properties can be from the exact hull's: a hull whose
// vertices are input points and which contains every input point IS the exact hull; points
// outside by at most delta make the exact hull larger by at most about delta * area in volume.
#pragma once
#include <gmpxx.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include <simreel/mesh.hpp>

namespace simreel::test {

struct ExactSolid {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();  ///< about the centroid, density 1
};

// Divergence theorem over tetrahedra with apex at the origin, all in rationals; rounded to double
// only at the end (each output is the exact value correctly rounded, up to mpq -> double rounding).
inline ExactSolid exact_solid(const TriangleMesh& m) {
  mpq_class vol6 = 0, first[3] = {0, 0, 0}, second[3][3];
  for (auto& row : second)
    for (auto& x : row) x = 0;
  for (const auto& t : m.triangles) {
    mpq_class p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) p[k][i] = m.vertices[t[k]][i];
    const auto &a = p[0], &b = p[1], &c = p[2];
    const mpq_class d = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                        a[2] * (b[0] * c[1] - b[1] * c[0]);
    vol6 += d;
    mpq_class s[3];
    for (int i = 0; i < 3; ++i) {
      s[i] = a[i] + b[i] + c[i];
      first[i] += d * s[i];
    }
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) second[i][j] += d * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
  }
  // vol = vol6/6, first moment = sum d s / 24, C = sum d (...) / 120.
  const mpq_class vol = vol6 / 6;
  mpq_class com[3];
  for (int i = 0; i < 3; ++i) com[i] = first[i] / 24 / vol;
  mpq_class C[3][3];  // covariance about the centroid
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      C[i][j] = second[i][j] / 120 - vol * com[i] * com[j];
      C[j][i] = C[i][j];
    }
  const mpq_class tr = C[0][0] + C[1][1] + C[2][2];
  ExactSolid r;
  r.volume = vol.get_d();
  for (int i = 0; i < 3; ++i) {
    r.centroid[i] = com[i].get_d();
    for (int j = 0; j < 3; ++j) r.inertia(i, j) = mpq_class((i == j ? tr : mpq_class(0)) - C[i][j]).get_d();
  }
  return r;
}

// Sign of det[a - p, b - p, c - p]: negative when p is outside (above) the counter-clockwise
// triangle a, b, c, zero when on its plane. Exact.
inline int orient_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const Vec3 ad = a - p, bd = b - p, cd = c - p;
  const double det = ad.dot(bd.cross(cd));
  const Vec3 A = ad.cwiseAbs(), B = bd.cwiseAbs(), C = cd.cwiseAbs();
  const double perm = A.x() * (B.y() * C.z() + B.z() * C.y()) + A.y() * (B.x() * C.z() + B.z() * C.x()) +
                      A.z() * (B.x() * C.y() + B.y() * C.x());
  // Generous static filter (Shewchuk's bound for this form is about 7.8e-16 * perm).
  if (det > 1e-14 * perm) return 1;
  if (det < -1e-14 * perm) return -1;
  mpq_class q[4][3];
  const Vec3* v[4] = {&a, &b, &c, &p};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) q[k][i] = (*v[k])[i];
  mpq_class x[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) x[k][i] = q[k][i] - q[3][i];
  const mpq_class e = x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) -
                      x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
                      x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
  return sgn(e);
}

struct Containment {
  long outside = 0;         ///< (point, triangle) pairs with the point strictly above the plane
  double max_distance = 0;  ///< m, the largest such height (approximate: double)
};

// Every point against every triangle's plane: for a convex hull, inside-or-on everywhere.
inline Containment hull_containment(const TriangleMesh& hull, const std::vector<Vec3>& pts) {
  Containment r;
  for (const auto& t : hull.triangles) {
    const Vec3 &a = hull.vertices[t[0]], &b = hull.vertices[t[1]], &c = hull.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double nn = n.norm(), lab = (b - a).norm() * (c - a).norm();
    for (const Vec3& p : pts) {
      // Quick reject: clearly inside by a margin far above the rounding of n and s (a few ulps
      // of |b - a| |c - a| |p - a|, however thin the triangle).
      const double s = n.dot(p - a);
      if (s < -1e-12 * lab * (p - a).norm()) continue;
      if (orient_exact(a, b, c, p) < 0) {
        ++r.outside;
        r.max_distance = std::max(r.max_distance, nn > 0 ? s / nn : 0.0);
      }
    }
  }
  return r;
}

// The exact convex hull of the points (every predicate exact: orient_exact), by the plain
// incremental algorithm: a point strictly outside some faces replaces them by a cone to their
// horizon. O(n F); for references on a few thousand points (pass only the points that may be on the
// hull). Faces counter-clockwise from outside; coplanar faces stay separate triangles.
inline TriangleMesh exact_hull(const std::vector<Vec3>& pts) {
  const int n = (int)pts.size();
  int i1 = -1, i2 = -1, i3 = -1;
  double best = 0;
  for (int i = 1; i < n; ++i)
    if ((pts[i] - pts[0]).squaredNorm() > best) best = (pts[i] - pts[0]).squaredNorm(), i1 = i;
  best = 0;
  for (int i = 1; i < n; ++i) {
    const double a = (pts[i1] - pts[0]).cross(pts[i] - pts[0]).squaredNorm();
    if (a > best) best = a, i2 = i;
  }
  best = 0;
  for (int i = 1; i < n; ++i) {
    const double v = std::fabs((pts[i1] - pts[0]).cross(pts[i2] - pts[0]).dot(pts[i] - pts[0]));
    if (v > best) best = v, i3 = i;
  }
  if (i1 < 0 || i2 < 0 || i3 < 0 || orient_exact(pts[0], pts[i1], pts[i2], pts[i3]) == 0)
    throw std::runtime_error("exact_hull: flat input");
  std::vector<std::array<int, 3>> tris;
  if (orient_exact(pts[0], pts[i1], pts[i2], pts[i3]) < 0) std::swap(i1, i2);  // i3 below (0, i1, i2)
  tris = {{0, i1, i2}, {0, i3, i1}, {i1, i3, i2}, {i2, i3, 0}};
  std::vector<char> alive(4, 1);
  auto key = [](int a, int b) { return (uint64_t)(uint32_t)a << 32 | (uint32_t)b; };
  std::vector<int> visible;
  std::unordered_set<uint64_t> vis_edges;
  for (int p = 1; p < n; ++p) {
    if (p == i1 || p == i2 || p == i3) continue;
    visible.clear();
    for (int f = 0; f < (int)tris.size(); ++f)
      if (alive[f] && orient_exact(pts[tris[f][0]], pts[tris[f][1]], pts[tris[f][2]], pts[p]) < 0)
        visible.push_back(f);
    if (visible.empty()) continue;
    vis_edges.clear();
    for (int f : visible)
      for (int k = 0; k < 3; ++k) vis_edges.insert(key(tris[f][k], tris[f][(k + 1) % 3]));
    for (int f : visible) {
      alive[f] = 0;
      for (int k = 0; k < 3; ++k) {
        const int a = tris[f][k], b = tris[f][(k + 1) % 3];
        if (!vis_edges.count(key(b, a))) {
          tris.push_back({a, b, p});
          alive.push_back(1);
        }
      }
    }
  }
  TriangleMesh m;
  m.vertices = pts;
  for (size_t f = 0; f < tris.size(); ++f)
    if (alive[f]) m.triangles.push_back(tris[f]);
  return m;
}

}  // namespace simreel::test
