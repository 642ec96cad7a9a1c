#include <simreel/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "sim/geometry/convex_hull.hpp"
#include <simreel/error.hpp>
#include "sim/base/pair_key.hpp"
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {
constexpr EnumNames<MassMode, 3> kMassModes{{"solid", "shell", "hull"}};
static_assert(kMassModes.complete());
}  // namespace

const char* to_string(MassMode m) {
  return kMassModes(m);
}

std::optional<MassMode> mass_mode_from_name(std::string_view n) {
  return kMassModes.parse(n);
}

namespace {

using Tri = std::array<int, 3>;

std::string plural(long n, const char* word) {
  std::ostringstream os;
  const std::string w = word;
  os << n << " " << (n == 1 ? w : w == "vertex" ? "vertices" : w + "s");
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

// Mass properties take lengths to the 5th power (inertia ~ density L^5): sizes and coordinates out
// of 1e-60 .. 1e60 m overflow or underflow double precision, which would otherwise be reported as a
// flat, empty or single-point mesh. Says which, with the size.
void check_scale(const std::vector<Vec3>& v) {
  Vec3 lo = v[0], hi = v[0];
  for (const Vec3& p : v) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double far = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  const double size = (hi - lo).maxCoeff();  // inf when the span itself overflows
  char b[200];
  if (far > 1e60) {
    std::snprintf(b, sizeof b,
                  "mesh has coordinates up to %.3g m: its mass properties (lengths to the 5th power) would "
                  "overflow double precision; scale it into 1e-60 .. 1e60 m",
                  far);
    throw InputError(b);
  }
  if (size > 0 && size < 1e-60) {
    std::snprintf(b, sizeof b,
                  "mesh spans only %.3g m: its mass properties (lengths to the 5th power) would underflow "
                  "double precision; scale it into 1e-60 .. 1e60 m",
                  size);
    throw InputError(b);
  }
}

uint64_t edge_key(int a, int b) {
  return pair_key(a, b);
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

// "part 2 (480 faces, the first is face 12)": parts are numbered in the order of their first face;
// face numbers are those of the mesh as given.
std::string part_name(int c, const std::vector<int>& faces, const std::vector<int>& orig) {
  return "part " + std::to_string(c + 1) + " (" + plural((long)faces.size(), "face") +
         ", the first is face " + std::to_string(orig[faces.front()]) + ")";
}

// Generalized winding number of the closed surface `faces` about p (Jacobson, Kavan and
// Sorkine-Hornung 2013): the sum of the signed solid angles of its triangles over 4 pi, each by van
// Oosterom and Strackee's formula. For a closed, outward-wound surface it is 1 inside, 0 outside
// (an integer up to rounding for any point off the surface): a point-in-solid test that does not
// care how the surface is triangulated.
double winding_number(const TriangleMesh& m, const std::vector<int>& faces, const Vec3& p) {
  double sum = 0;
  for (int f : faces) {
    const Tri& t = m.triangles[f];
    const Vec3 a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * std::numbers::pi);
}

// Lists at most `limit` names, then "and N more".
std::string name_list(const std::vector<std::string>& names, size_t limit = 8) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < limit; ++i) s += (i ? "; " : "") + names[i];
  if (names.size() > limit) s += "; and " + std::to_string(names.size() - limit) + " more";
  return s;
}

// The surface as given, after welding: faces with a repeated corner are dropped (they add an edge
// and its reverse, so they change no edge count that matters), zero-area faces with three distinct
// corners (slivers, as at a T-junction) are kept for the topology and only marked in `sliver`, and
// the edge census fills closed, consistently_oriented and nonmanifold_edges. `orig` maps each kept
// face to its number in the input.
struct Surface {
  TriangleMesh m;
  std::vector<char> sliver;
  std::vector<int> orig;
  std::unordered_map<uint64_t, std::vector<int>> undirected;  ///< faces on each edge {min, max}
  long boundary = 0, unbalanced = 0;
  double diag = 0;
};

Surface surface(const TriangleMesh& in, MeshReport& rep) {
  validate(in);
  Surface s;
  TriangleMesh& m = s.m;
  m = weld(in, &rep.welded_vertices);
  check_scale(m.vertices);
  bbox_centre(m.vertices, &s.diag);
  if (!(s.diag > 0)) throw InputError("mesh is a single point (all vertices coincide)");

  // Degenerate faces: repeated corners, or an area below rounding level for this mesh's size.
  const double area_eps = 1e-13 * s.diag * s.diag;
  std::vector<Tri> kept;
  kept.reserve(m.triangles.size());
  long repeated = 0, slivers = 0;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    const Tri& t = m.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++repeated;
      continue;
    }
    const double area2 =
        (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
    const bool thin = !(0.5 * area2 > area_eps);
    slivers += thin;
    kept.push_back(t);
    s.sliver.push_back(thin);
    s.orig.push_back((int)f);
  }
  rep.degenerate_faces = (int)(repeated + slivers);
  if (rep.degenerate_faces) {
    std::string w =
        "skipped " + plural(rep.degenerate_faces, "degenerate face") + " (zero area) in the integrals";
    if (slivers)
      w += " (" + plural(slivers, "sliver") +
           " with three distinct corners, which still count for closedness" +
           (repeated ? ", and " + std::to_string(repeated) + " with a repeated corner)" : std::string(")"));
    rep.warnings.push_back(w);
  }
  m.triangles = std::move(kept);
  if (slivers == (long)m.triangles.size()) throw InputError("mesh has no face with a non-zero area");

  // Edge census. Balanced directed edges (count(a,b) == count(b,a)) make a closed, consistently
  // wound surface; an undirected edge with an odd number of faces is a hole (or a crack); an edge
  // whose directions differ by more than one has two faces that disagree on the winding (a
  // boundary edge has one face, so one direction, and agrees with everything).
  std::unordered_map<uint64_t, int> directed;
  directed.reserve(m.triangles.size() * 4);
  s.undirected.reserve(m.triangles.size() * 2);
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[f][k], b = m.triangles[f][(k + 1) % 3];
      ++directed[edge_key(a, b)];
      s.undirected[edge_key(std::min(a, b), std::max(a, b))].push_back((int)f);
    }
  long nonmanifold = 0, disagree = 0;
  for (const auto& [key, faces] : s.undirected) {
    if (faces.size() % 2) ++s.boundary;
    if (faces.size() > 2) ++nonmanifold;
    const int a = pair_first(key), b = pair_second(key);
    const auto ab = directed.find(edge_key(a, b)), ba = directed.find(edge_key(b, a));
    const int nab = ab == directed.end() ? 0 : ab->second, nba = ba == directed.end() ? 0 : ba->second;
    if (nab != nba) ++s.unbalanced;
    if (std::abs(nab - nba) > 1) ++disagree;
  }
  rep.closed = s.boundary == 0;
  rep.consistently_oriented = disagree == 0;
  rep.nonmanifold_edges = (int)nonmanifold;
  if (nonmanifold)
    rep.warnings.push_back(plural(nonmanifold, "edge") + (nonmanifold == 1 ? " is" : " are") +
                           " shared by more than two faces (non-manifold)");
  return s;
}

// All vertices within rounding of one plane?
bool coplanar(const std::vector<Vec3>& v, double diag) {
  const Vec3 o = v[0];
  size_t i1 = 0;
  for (size_t i = 1; i < v.size(); ++i)
    if ((v[i] - o).squaredNorm() > (v[i1] - o).squaredNorm()) i1 = i;
  const Vec3 d = (v[i1] - o).normalized();
  Vec3 n = Vec3::Zero();
  for (const Vec3& p : v) {
    const Vec3 c = d.cross(p - o);
    if (c.squaredNorm() > n.squaredNorm()) n = c;
  }
  if (!(n.norm() > 1e-12 * diag)) return true;  // collinear
  n.normalize();
  for (const Vec3& p : v)
    if (std::fabs(n.dot(p - o)) > 1e-12 * diag) return false;
  return true;
}

// Welds, makes the winding consistent and outward, then drops degenerate faces. With
// require_closed, an open surface, or one that encloses no volume, is an error (it cannot bound a
// solid).
TriangleMesh prepare(const TriangleMesh& in, MeshReport& rep, bool require_closed) {
  Surface s = surface(in, rep);
  TriangleMesh& m = s.m;
  auto drop_slivers = [&] {
    std::vector<Tri> kept;
    for (size_t f = 0; f < m.triangles.size(); ++f)
      if (!s.sliver[f]) kept.push_back(m.triangles[f]);
    m.triangles = std::move(kept);
  };
  if (!rep.closed) {
    if (require_closed)
      throw InputError(
          "mesh is open: " + plural(s.boundary, "edge") +
          " belong to a single face (a hole), so it does not enclose a volume; weigh it as a thin "
          "surface (shell mode) or as its convex hull (hull mode)");
    drop_slivers();
    return m;
  }
  double diag = 0;
  const Vec3 ref = bbox_centre(m.vertices, &diag);

  std::vector<int> comp;
  const int ncomp = components(m, s.undirected, &comp);

  // Inconsistent winding on a closed manifold surface: flip faces to agree with a neighbour,
  // breadth first from the lowest-numbered face of each part, which keeps its winding.
  if (s.unbalanced) {
    if (rep.nonmanifold_edges)
      throw InputError("mesh has " + plural(s.unbalanced, "edge") + " whose faces disagree on winding and " +
                       plural(rep.nonmanifold_edges, "edge") +
                       " shared by more than two faces; cannot repair it, "
                       "weigh its convex hull (hull mode) or fix the file");
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
          for (int g : s.undirected[edge_key(std::min(a, b), std::max(a, b))]) {
            if (g == f) continue;
            // g must traverse the edge as (b, a); if it traverses (a, b) it needs a flip.
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
      if (flip[f]) std::swap(m.triangles[f][1], m.triangles[f][2]);
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

  // Parts: volume (slivers add nothing), bounding box, and up to 9 probe points on the surface
  // (centroids of faces spread over the part) for the point-in-solid test.
  std::vector<std::vector<int>> faces_of(ncomp), solid_faces(ncomp);
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    faces_of[comp[f]].push_back((int)f);
    if (!s.sliver[f]) solid_faces[comp[f]].push_back((int)f);
  }
  std::vector<double> vol(ncomp, 0.0);
  std::vector<Vec3> lo(ncomp, Vec3::Constant(INFINITY)), hi(ncomp, Vec3::Constant(-INFINITY));
  std::vector<std::vector<Vec3>> probes(ncomp);
  for (int c = 0; c < ncomp; ++c) {
    vol[c] = solid_integrals(m, ref, &solid_faces[c]).vol;
    for (int f : faces_of[c])
      for (int v : m.triangles[f]) {
        lo[c] = lo[c].cwiseMin(m.vertices[v]);
        hi[c] = hi[c].cwiseMax(m.vertices[v]);
      }
    const size_t n = solid_faces[c].size(), step = std::max<size_t>(1, n / 9);
    for (size_t i = 0; i < n && probes[c].size() < 9; i += step) {
      const Tri& t = m.triangles[solid_faces[c][i]];
      probes[c].push_back((m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0);
    }
  }
  // Which larger, outward part (if any) holds each part: every probe has winding number 1 about
  // it (0 outside; about 1/2 on its surface, where parts touch, which decides nothing). Some
  // probes in and some out: the two surfaces cross. Only parts whose box holds this part's box
  // are tested.
  std::vector<int> holder(ncomp, -1), crossed(ncomp, -1);
  if (ncomp > 1)
    for (int c = 0; c < ncomp; ++c)
      for (int o = 0; o < ncomp && holder[c] < 0; ++o) {
        if (o == c || !(vol[o] > std::fabs(vol[c])) || !(lo[o].array() <= lo[c].array()).all() ||
            !(hi[o].array() >= hi[c].array()).all())
          continue;
        int in = 0, out = 0;
        for (const Vec3& p : probes[c]) {
          const double w = winding_number(m, solid_faces[o], p);
          in += w > 0.75;
          out += w < 0.25;
        }
        if (in && !out) holder[c] = o;
        if (in && out && crossed[c] < 0) crossed[c] = o;
      }
  // Inside-out parts: a part with negative volume is flipped, unless it lies inside a larger
  // outward part (then it is a cavity, which is legitimate). Both are named.
  std::vector<std::string> flipped_parts, cavities, overlaps, crossings;
  for (int c = 0; c < ncomp; ++c) {
    const std::string name = part_name(c, faces_of[c], s.orig);
    if (holder[c] < 0 && crossed[c] >= 0)
      crossings.push_back(name + " and " + part_name(crossed[c], faces_of[crossed[c]], s.orig));
    if (vol[c] >= 0) {
      if (holder[c] >= 0)
        overlaps.push_back(name + " inside " + part_name(holder[c], faces_of[holder[c]], s.orig));
      continue;
    }
    if (holder[c] >= 0) {
      cavities.push_back(name + " in " + part_name(holder[c], faces_of[holder[c]], s.orig));
      continue;
    }
    for (int f : faces_of[c]) std::swap(m.triangles[f][1], m.triangles[f][2]);
    flipped_parts.push_back(name);
  }
  if (!crossings.empty())
    rep.warnings.push_back(plural((long)crossings.size(), "part") +
                           " cut into a larger part (their surfaces cross), so the material they share is "
                           "counted twice: " +
                           name_list(crossings));
  if (!flipped_parts.empty()) {
    rep.inverted = true;
    rep.warnings.push_back(ncomp == 1
                               ? std::string("surface was inside-out (negative volume): flipped every face")
                               : "flipped " + plural((long)flipped_parts.size(), "inside-out part") +
                                     " (negative volume, inside no other part): " + name_list(flipped_parts));
  }
  if (!cavities.empty())
    rep.warnings.push_back(
        "took " + plural((long)cavities.size(), "inward-wound part") +
        " as a cavity (hollow) because it lies inside a larger part: " + name_list(cavities));
  if (!overlaps.empty())
    rep.warnings.push_back(
        plural((long)overlaps.size(), "outward part") +
        " lie inside another part, so their material is counted twice: " + name_list(overlaps));
  if (ncomp > 1)
    rep.warnings.push_back("mesh has " + std::to_string(ncomp) +
                           " separate closed parts; weighed as one body");

  drop_slivers();
  const double v = solid_integrals(m, ref).vol;
  if (!(std::fabs(v) > 1e-12 * diag * diag * diag)) {
    if (coplanar(m.vertices, diag))
      throw InputError(
          "mesh is flat (all its vertices lie in one plane), so it encloses no volume; weigh it as a thin "
          "surface (shell mode)");
    throw InputError(
        "mesh encloses no volume: its faces cancel out, as when a surface is given with both sides"
        " (each face twice, once per winding)" +
        (rep.nonmanifold_edges
             ? "; " + plural(rep.nonmanifold_edges, "edge") + " shared by more than two faces"
             : std::string()) +
        "; weigh it as a thin surface (shell mode)");
  }
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
      // A shell needs only a surface: no closedness, winding or volume checks.
      const Surface sf = surface(mesh, rep);
      const TriangleMesh& m = sf.m;
      double diag;
      const Vec3 ref = bbox_centre(m.vertices, &diag);
      double area = 0;
      Vec3 first = Vec3::Zero();
      Mat3 second = Mat3::Zero();
      for (size_t f = 0; f < m.triangles.size(); ++f) {
        if (sf.sliver[f]) continue;
        const Tri& t = m.triangles[f];
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
      check_scale(welded.vertices);
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
      // Asked for: no warning that the hull was weighed (it would read as a defect).
      break;
    }
  }
  // Never a non-finite (or vanished) result reported as a success: density and size together can
  // still overflow (1e300 kg/m^3) or underflow.
  const bool finite = std::isfinite(rep.volume) && std::isfinite(rep.area) && std::isfinite(rep.props.mass) &&
                      all_finite(rep.props.com) && rep.props.inertia.allFinite();
  if (!finite || !(rep.props.mass > 0)) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "mass properties %s double precision (mass %g kg, volume %g m^3, area %g m^2): the mesh's "
                  "size and the density are out of range together",
                  finite ? "underflow" : "overflow", rep.props.mass, rep.volume, rep.area);
    throw InputError(b);
  }
  const std::string bad = inertia_problem(rep.props.inertia, 1e-7);
  if (!bad.empty()) rep.warnings.push_back("computed inertia is not physically valid: " + bad);
  return rep;
}

}  // namespace simreel
