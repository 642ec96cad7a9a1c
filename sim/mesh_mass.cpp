#include "sim/mesh_mass.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "sim/convex_hull.hpp"
#include "sim/error.hpp"

namespace simreel {

const char* to_string(MassMode m) {
  switch (m) {
    case MassMode::solid:
      return "solid";
    case MassMode::shell:
      return "shell";
    case MassMode::hull:
      return "hull";
  }
  return "?";
}

std::optional<MassMode> mass_mode_from_name(std::string_view n) {
  for (MassMode m : {MassMode::solid, MassMode::shell, MassMode::hull})
    if (n == to_string(m)) return m;
  return std::nullopt;
}

namespace {

using Tri = std::array<int, 3>;

std::string plural(long n, const char* word) {
  std::ostringstream os;
  os << n << " " << word << (n == 1 ? "" : "s");
  return os.str();
}

void validate(const TriangleMesh& m) {
  if (m.vertices.empty()) throw InputError("mesh has no vertices");
  if (m.triangles.empty())
    throw InputError("mesh has " + plural((long)m.vertices.size(), "vertex") +
                     " but no faces (a point cloud or line set is not a surface)");
  for (size_t i = 0; i < m.vertices.size(); ++i)
    if (!all_finite(m.vertices[i]))
      throw InputError("vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
  const long n = (long)m.vertices.size();
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (m.triangles[f][k] < 0 || m.triangles[f][k] >= n)
        throw InputError("face " + std::to_string(f) + " refers to vertex " +
                         std::to_string(m.triangles[f][k]) + ", but the mesh has " + plural(n, "vertex"));
}

struct BitsHash {
  size_t operator()(const std::array<uint64_t, 3>& k) const {
    uint64_t h = 1469598103934665603ull;
    for (uint64_t x : k) h = (h ^ x) * 1099511628211ull ^ (x >> 29);
    return (size_t)h;
  }
};

// Merges vertices with bit-identical coordinates; indices are assigned in first-seen order, so
// the result does not depend on the hash table.
TriangleMesh weld(const TriangleMesh& in, int* merged) {
  TriangleMesh out;
  std::unordered_map<std::array<uint64_t, 3>, int, BitsHash> index;
  index.reserve(in.vertices.size() * 2);
  std::vector<int> remap(in.vertices.size());
  for (size_t i = 0; i < in.vertices.size(); ++i) {
    std::array<uint64_t, 3> key;
    for (int k = 0; k < 3; ++k) {
      const double c = in.vertices[i][k] + 0.0;  // -0.0 becomes +0.0
      std::memcpy(&key[k], &c, sizeof c);
    }
    auto [it, fresh] = index.emplace(key, (int)out.vertices.size());
    if (fresh) out.vertices.push_back(in.vertices[i]);
    remap[i] = it->second;
  }
  *merged = (int)(in.vertices.size() - out.vertices.size());
  out.triangles.reserve(in.triangles.size());
  for (const Tri& t : in.triangles) out.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  return out;
}

Vec3 bbox_centre(const std::vector<Vec3>& v, double* diag) {
  Vec3 lo = v[0], hi = v[0];
  for (const Vec3& p : v) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  *diag = (hi - lo).norm();
  return 0.5 * (lo + hi);
}

uint64_t edge_key(int a, int b) {
  return (uint64_t)(uint32_t)a << 32 | (uint32_t)b;
}

// Signed volume integrals of a closed surface about `ref` (density 1).
struct SolidIntegrals {
  double vol = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
};
SolidIntegrals solid_integrals(const TriangleMesh& m, const Vec3& ref,
                               const std::vector<int>* faces = nullptr) {
  SolidIntegrals s;
  auto add = [&](const Tri& t) {
    const Vec3 a = m.vertices[t[0]] - ref, b = m.vertices[t[1]] - ref, c = m.vertices[t[2]] - ref;
    const double d = a.dot(b.cross(c));  // 6 x signed volume of tetrahedron (ref, a, b, c)
    const Vec3 sum = a + b + c;
    s.vol += d / 6.0;
    s.first += d / 24.0 * sum;
    s.second +=
        d / 120.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  };
  if (faces)
    for (int f : *faces) add(m.triangles[f]);
  else
    for (const Tri& t : m.triangles) add(t);
  return s;
}

// Mass properties from volume (or area) integrals C about ref: density rho, centroid first/vol,
// covariance shifted to the centroid, I = tr(C) 1 - C.
MassProperties from_integrals(double measure, const Vec3& first, const Mat3& second, const Vec3& ref,
                              double rho) {
  MassProperties mp;
  const Vec3 c = first / measure;
  const Mat3 C = rho * (second - measure * c * c.transpose());
  mp.mass = rho * measure;
  mp.com = ref + c;
  mp.inertia = C.trace() * Mat3::Identity() - C;
  mp.inertia = 0.5 * (mp.inertia + mp.inertia.transpose()).eval();
  return mp;
}

// Faces connected through shared edges, each a component; returns component id per face.
int components(const TriangleMesh& m, const std::unordered_map<uint64_t, std::vector<int>>& edge_faces,
               std::vector<int>* comp) {
  std::vector<int> parent(m.triangles.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [key, faces] : edge_faces)
    for (size_t i = 1; i < faces.size(); ++i) {
      const int a = find(faces[0]), b = find(faces[i]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  comp->assign(m.triangles.size(), -1);
  int n = 0;
  std::vector<int> id(m.triangles.size(), -1);
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    const int r = find((int)f);
    if (id[r] < 0) id[r] = n++;
    (*comp)[f] = id[r];
  }
  return n;
}

// Welds, drops degenerate faces, makes the winding consistent and outward. With require_closed,
// an open or flat surface is an error (it cannot bound a solid).
TriangleMesh prepare(const TriangleMesh& in, MeshReport& rep, bool require_closed) {
  validate(in);
  TriangleMesh m = weld(in, &rep.welded_vertices);
  double diag = 0;
  const Vec3 ref = bbox_centre(m.vertices, &diag);
  if (!(diag > 0)) throw InputError("mesh is a single point (all vertices coincide)");

  // Degenerate faces: repeated corners or an area below rounding level for this mesh's size.
  const double area_eps = 1e-13 * diag * diag;
  std::vector<Tri> kept;
  kept.reserve(m.triangles.size());
  for (const Tri& t : m.triangles) {
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    const double area2 =
        (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
    if (repeated || !(0.5 * area2 > area_eps))
      ++rep.degenerate_faces;
    else
      kept.push_back(t);
  }
  if (rep.degenerate_faces)
    rep.warnings.push_back("skipped " + plural(rep.degenerate_faces, "degenerate face") + " (zero area)");
  m.triangles = std::move(kept);
  if (m.triangles.empty()) throw InputError("mesh has no face with a non-zero area");

  // Edge census. Balanced directed edges (count(a,b) == count(b,a)) make a closed, consistently
  // wound surface; an undirected edge with an odd number of faces is a hole (or a crack).
  std::unordered_map<uint64_t, int> directed;
  std::unordered_map<uint64_t, std::vector<int>> undirected;
  directed.reserve(m.triangles.size() * 4);
  undirected.reserve(m.triangles.size() * 2);
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[f][k], b = m.triangles[f][(k + 1) % 3];
      ++directed[edge_key(a, b)];
      undirected[edge_key(std::min(a, b), std::max(a, b))].push_back((int)f);
    }
  long boundary = 0, nonmanifold = 0, unbalanced = 0;
  for (const auto& [key, faces] : undirected) {
    if (faces.size() % 2) ++boundary;
    if (faces.size() > 2) ++nonmanifold;
    const int a = (int)(key >> 32), b = (int)(key & 0xffffffffu);
    const auto ab = directed.find(edge_key(a, b)), ba = directed.find(edge_key(b, a));
    if ((ab == directed.end() ? 0 : ab->second) != (ba == directed.end() ? 0 : ba->second)) ++unbalanced;
  }
  rep.closed = boundary == 0;
  rep.consistently_oriented = unbalanced == 0;
  if (!rep.closed) {
    if (require_closed)
      throw InputError("mesh is open: " + plural(boundary, "edge") +
                       " belong to a single face (a hole), so it does not enclose a volume; use "
                       "`mode: shell` to weigh it as a thin surface, or `mode: hull` for its convex hull");
    return m;
  }

  std::vector<int> comp;
  const int ncomp = components(m, undirected, &comp);

  // Inconsistent winding on a closed manifold surface: flip faces to agree with a neighbour,
  // breadth first from the lowest-numbered face of each part, which keeps its winding.
  if (unbalanced) {
    if (nonmanifold)
      throw InputError("mesh has " + plural(unbalanced, "edge") + " whose faces disagree on winding and " +
                       plural(nonmanifold, "edge") +
                       " shared by more than two faces; cannot repair it, "
                       "use `mode: hull` or fix the file");
    std::vector<int> flip(m.triangles.size(), -1);
    std::vector<int> queue;
    for (size_t seed = 0; seed < m.triangles.size(); ++seed) {
      if (flip[seed] >= 0) continue;
      flip[seed] = 0;
      queue.assign(1, (int)seed);
      for (size_t qi = 0; qi < queue.size(); ++qi) {
        const int f = queue[qi];
        for (int k = 0; k < 3; ++k) {
          int a = m.triangles[f][k], b = m.triangles[f][(k + 1) % 3];
          if (flip[f]) std::swap(a, b);  // the edge as f will be traversed after its own flip
          for (int g : undirected[edge_key(std::min(a, b), std::max(a, b))]) {
            if (g == f) continue;
            // g traverses (a, b) too when a follows... find g's direction on this edge.
            const Tri& t = m.triangles[g];
            bool same = false;
            for (int j = 0; j < 3; ++j)
              if (t[j] == a && t[(j + 1) % 3] == b) same = true;
            const int want = same ? 1 : 0;
            if (flip[g] < 0) {
              flip[g] = want;
              queue.push_back(g);
            } else if (flip[g] != want) {
              throw InputError(
                  "mesh surface is not orientable (like a Moebius strip); it cannot bound a solid");
            }
          }
        }
      }
    }
    for (size_t f = 0; f < m.triangles.size(); ++f)
      if (flip[f]) {
        std::swap(m.triangles[f][1], m.triangles[f][2]);
        ++rep.reoriented_faces;
      }
    // Keep the majority winding of each part (the BFS kept the seed's).
    std::vector<long> flipped(ncomp, 0), total(ncomp, 0);
    for (size_t f = 0; f < m.triangles.size(); ++f) {
      ++total[comp[f]];
      flipped[comp[f]] += flip[f];
    }
    for (size_t f = 0; f < m.triangles.size(); ++f)
      if (2 * flipped[comp[f]] > total[comp[f]]) std::swap(m.triangles[f][1], m.triangles[f][2]);
    rep.reoriented_faces = 0;
    for (size_t f = 0; f < m.triangles.size(); ++f)
      rep.reoriented_faces += (2 * flipped[comp[f]] > total[comp[f]]) ? 1 - flip[f] : flip[f];
    rep.warnings.push_back("flipped " + plural(rep.reoriented_faces, "face") +
                           " whose winding disagreed with their neighbours");
  }

  // Inside-out parts: a part with negative volume is flipped, unless it sits inside a larger
  // positive part (then it is a cavity, which is legitimate).
  std::vector<std::vector<int>> faces_of(ncomp);
  for (size_t f = 0; f < m.triangles.size(); ++f) faces_of[comp[f]].push_back((int)f);
  std::vector<double> vol(ncomp);
  std::vector<Vec3> lo(ncomp, Vec3::Constant(INFINITY)), hi(ncomp, Vec3::Constant(-INFINITY));
  for (int c = 0; c < ncomp; ++c) {
    vol[c] = solid_integrals(m, ref, &faces_of[c]).vol;
    for (int f : faces_of[c])
      for (int v : m.triangles[f]) {
        lo[c] = lo[c].cwiseMin(m.vertices[v]);
        hi[c] = hi[c].cwiseMax(m.vertices[v]);
      }
  }
  int inverted_parts = 0;
  for (int c = 0; c < ncomp; ++c) {
    if (vol[c] >= 0) continue;
    bool cavity = false;
    for (int o = 0; o < ncomp; ++o)
      if (o != c && vol[o] > -vol[c] && (lo[o].array() <= lo[c].array()).all() &&
          (hi[o].array() >= hi[c].array()).all())
        cavity = true;
    if (cavity) continue;
    for (int f : faces_of[c]) std::swap(m.triangles[f][1], m.triangles[f][2]);
    ++inverted_parts;
  }
  if (inverted_parts) {
    rep.inverted = true;
    rep.warnings.push_back(
        ncomp == 1 ? std::string("surface was inside-out (negative volume): flipped every face")
                   : "flipped " + plural(inverted_parts, "inside-out part") + " of " + std::to_string(ncomp));
  }
  if (ncomp > 1)
    rep.warnings.push_back("mesh has " + std::to_string(ncomp) +
                           " separate closed parts; weighed as one body");

  const double v = solid_integrals(m, ref).vol;
  if (!(std::fabs(v) > 1e-12 * diag * diag * diag))
    throw InputError("mesh is flat (it encloses no volume); use `mode: shell` to weigh it as a thin surface");
  return m;
}

// Volume, area and mass properties of a closed, outward-wound surface, into rep.
void weigh_solid(const TriangleMesh& m, double rho, MeshReport& rep) {
  double diag;
  const Vec3 ref = bbox_centre(m.vertices, &diag);
  const SolidIntegrals s = solid_integrals(m, ref);
  rep.volume = s.vol;
  for (const Tri& t : m.triangles)
    rep.area += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  rep.props = from_integrals(s.vol, s.first, s.second, ref, rho);
}

}  // namespace

TriangleMesh repaired_mesh(const TriangleMesh& mesh, MeshReport* report) {
  MeshReport local;
  return prepare(mesh, report ? *report : local, true);
}

MeshReport analyze_mesh(const TriangleMesh& mesh, const MeshMassOptions& opt) {
  if (!(opt.density > 0) || !std::isfinite(opt.density))
    throw InputError("density must be a positive number");
  MeshReport rep;
  switch (opt.mode) {
    case MassMode::solid: {
      const TriangleMesh m = prepare(mesh, rep, true);
      weigh_solid(m, opt.density, rep);
      break;
    }
    case MassMode::shell: {
      if (!(opt.thickness > 0) || !std::isfinite(opt.thickness))
        throw InputError("thickness must be a positive number");
      const TriangleMesh m = prepare(mesh, rep, false);
      double diag;
      const Vec3 ref = bbox_centre(m.vertices, &diag);
      double area = 0;
      Vec3 first = Vec3::Zero();
      Mat3 second = Mat3::Zero();
      for (const Tri& t : m.triangles) {
        const Vec3 a = m.vertices[t[0]] - ref, b = m.vertices[t[1]] - ref, c = m.vertices[t[2]] - ref;
        const double A = 0.5 * (b - a).cross(c - a).norm();
        const Vec3 s = a + b + c;
        area += A;
        first += A / 3.0 * s;
        second += A / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
      }
      rep.area = area;
      rep.volume = 0.0;
      rep.props = from_integrals(area, first, second, ref, opt.density * opt.thickness);
      break;
    }
    case MassMode::hull: {
      validate(mesh);
      TriangleMesh welded = weld(mesh, &rep.welded_vertices);
      // Closed and outward by construction: not through prepare(), whose sliver rule would drop a
      // thin hull triangle and then call the hull open.
      const TriangleMesh m = convex_hull(welded.vertices);
      // Report the input's own topology; the hull is closed by construction.
      MeshReport topo;
      try {
        prepare(mesh, topo, false);
      } catch (const InputError&) {
      }
      rep.closed = topo.closed;
      rep.consistently_oriented = topo.consistently_oriented;
      weigh_solid(m, opt.density, rep);
      rep.warnings.push_back("weighed the convex hull (" + plural((long)m.triangles.size(), "face") +
                             ") of " + plural((long)welded.vertices.size(), "vertex"));
      break;
    }
  }
  const std::string bad = inertia_problem(rep.props.inertia, 1e-7);
  if (!bad.empty()) rep.warnings.push_back("computed inertia is not physically valid: " + bad);
  return rep;
}

}  // namespace simreel
