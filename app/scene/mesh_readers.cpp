// simreel's own double-precision readers for the common text and binary mesh formats.
//
// Why not assimp for these: its Debian build keeps coordinates in float32, so a cube written with
// "0.1" corners weighs 1e-8 wrong, not 1e-16. Numbers are parsed with std::from_chars (correctly
// rounded, locale independent). Formats: OBJ (Wavefront, with .mtl Kd colours), OFF (Princeton
// shape benchmark), STL (3D Systems, ASCII and binary), PLY (Turk 1994, ASCII and both binary
// byte orders, faces and triangle strips). Polygons are fanned when convex and ear-clipped in their
// plane otherwise, in double precision, so no file of these formats needs assimp.
#include <algorithm>
#include <bit>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/mesh_import.hpp"

namespace simreel::detail {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError("cannot open mesh '" + path + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) throw InputError("cannot read mesh '" + path + "'");
  return ss.str();
}

[[noreturn]] void fail(const std::string& path, long line, const std::string& what) {
  throw InputError(path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
}

// A double for a message, whatever it holds (never cast to an integer: NaN or 1e300 would be UB).
std::string show(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// Whitespace-separated tokens of one line, comments (from `comment` on) removed.
std::vector<std::string_view> tokens(std::string_view line, char comment = '#') {
  if (comment) {
    const size_t c = line.find(comment);
    if (c != std::string_view::npos) line = line.substr(0, c);
  }
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace((unsigned char)line[i])) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace((unsigned char)line[j])) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

// OFF's first keyword: [ST][C][N][4][n]OFF (letters in any case).
bool is_off_keyword(std::string_view h) {
  if (h.size() < 3 || h.size() > 9) return false;
  for (size_t i = 0; i < h.size(); ++i) {
    const char c = (char)std::toupper((unsigned char)h[i]);
    if (i + 3 >= h.size() ? c != "OFF"[i + 3 - h.size()]
                          : std::string_view("STCN4").find(c) == std::string_view::npos)
      return false;
  }
  return true;
}

// Lines with their 1-based numbers; handles \n and \r\n.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    size_t e = text_.find('\n', pos_);
    if (e == std::string_view::npos) e = text_.size();
    *line = text_.substr(pos_, e - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = e + 1;
    ++number_;
    return true;
  }
  long number() const { return number_; }
  size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  long number_ = 0;
};

// A whole token as a T (double or long): from_chars, with the leading '+' files have and it refuses.
template <typename T>
T parse(std::string_view t, const std::string& path, long line, const char* what) {
  T v{};
  const char* b = t.data() + (!t.empty() && t[0] == '+');
  const auto r = std::from_chars(b, t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size())
    fail(path, line, "'" + std::string(t) + "' is not " + what);
  return v;
}

double number(std::string_view t, const std::string& path, long line) {
  const double v = parse<double>(t, path, line, "a number");
  if (!std::isfinite(v)) fail(path, line, "coordinate '" + std::string(t) + "' is not finite");
  return v;
}

long integer(std::string_view t, const std::string& path, long line) {
  return parse<long>(t, path, line, "an integer");
}

// Twice the signed area of the 2-D triangle (a, b, c).
double orient2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

}  // namespace

// Appends a polygon as triangles, in double precision. A convex polygon is fanned from its first
// corner; any other is ear-clipped in its plane (the coordinate along which Newell's normal is
// largest dropped, which is exact), trying ears in corner order, so a convex polygon gets the fan
// too. A corner in line with its neighbours is never an ear tip, so collinear corners (a T-junction
// along an edge) make no zero-area triangles unless nothing else is left. Polygons with fewer than
// three corners are lines or points: counted, skipped.
void add_polygon(RawMesh& m, const std::vector<int>& v, const std::vector<int>& vn, int material,
                 const std::vector<int>& vt) {
  const size_t n = v.size();
  if (n < 3) {
    ++m.points_and_lines;
    return;
  }
  auto emit = [&](size_t i, size_t j, size_t k) {
    m.triangles.push_back({v[i], v[j], v[k]});
    if (!vn.empty()) m.triangle_normals.push_back({vn[i], vn[j], vn[k]});
    if (!vt.empty()) m.triangle_uvs.push_back({vt[i], vt[j], vt[k]});
    m.triangle_material.push_back(material);
  };
  bool convex = true;
  Vec3 nn = Vec3::Zero();
  if (n > 3) {
    // Newell's normal of the polygon; every turn must agree with it for a fan to be exact.
    double scale2 = 0;
    for (size_t i = 0; i < n; ++i) {
      const Vec3& a = m.vertices[v[i]];
      const Vec3& b = m.vertices[v[(i + 1) % n]];
      nn += (a - b).cross(a + b);
      scale2 = std::max(scale2, (b - a).squaredNorm());
    }
    for (size_t i = 0; i < n && convex; ++i) {
      const Vec3& a = m.vertices[v[i]];
      const Vec3& b = m.vertices[v[(i + 1) % n]];
      const Vec3& c = m.vertices[v[(i + 2) % n]];
      if ((b - a).cross(c - b).dot(nn) < -1e-12 * scale2 * nn.norm()) convex = false;
    }
  }
  if (convex) {
    for (size_t i = 1; i + 1 < n; ++i) emit(0, i, i + 1);
    return;
  }
  int ax = 0;
  nn.cwiseAbs().maxCoeff(&ax);
  int u = (ax + 1) % 3, w = (ax + 2) % 3;
  if (nn[ax] < 0) std::swap(u, w);  // counter-clockwise in the (u, w) plane
  std::vector<Eigen::Vector2d> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = Eigen::Vector2d(m.vertices[v[i]][u], m.vertices[v[i]][w]);
  std::vector<size_t> idx(n);
  for (size_t i = 0; i < n; ++i) idx[i] = i;
  while (idx.size() > 3) {
    const size_t k = idx.size();
    size_t best = k;
    double most = -INFINITY;
    size_t most_at = 1;
    for (size_t t = 0; t < k && best == k; ++t) {
      const size_t s = (t + 1) % k;
      const size_t i0 = idx[(s + k - 1) % k], i1 = idx[s], i2 = idx[(s + 1) % k];
      const double o = orient2(p[i0], p[i1], p[i2]);
      if (o > most) {
        most = o;
        most_at = s;
      }
      if (!(o > 0)) continue;  // reflex or in line: not an ear tip
      bool empty = true;
      for (size_t j : idx) {
        if (j == i0 || j == i1 || j == i2 || p[j] == p[i0] || p[j] == p[i1] || p[j] == p[i2]) continue;
        if (orient2(p[i0], p[i1], p[j]) >= 0 && orient2(p[i1], p[i2], p[j]) >= 0 &&
            orient2(p[i2], p[i0], p[j]) >= 0) {
          empty = false;
          break;
        }
      }
      if (empty) best = s;
    }
    if (best == k) best = most_at;  // no clean ear (a self-touching polygon): the most convex corner
    emit(idx[(best + k - 1) % k], idx[best], idx[(best + 1) % k]);
    idx.erase(idx.begin() + (long)best);
  }
  emit(idx[0], idx[1], idx[2]);
}

// ---- OBJ ------------------------------------------------------------------------------------

namespace {

struct MtlEntry {
  std::optional<std::array<float, 3>> kd;
  std::string map_kd;  ///< the base-colour image as written, options removed
};

// The image file of a "map_Kd [options] FILE" line: the options (-o u [v [w]], -s, -t take up to
// three numbers, -mm two, the rest one) are skipped and the rest of the line, spaces included, is
// the file name.
std::string map_file(std::string_view line) {
  const auto t = tokens(line);
  size_t i = 1;
  auto is_number = [](std::string_view x) {
    double d;
    const char* b = x.data() + (!x.empty() && x[0] == '+');
    const auto r = std::from_chars(b, x.data() + x.size(), d);
    return r.ec == std::errc() && r.ptr == x.data() + x.size();
  };
  while (i < t.size() && t[i].size() > 1 && t[i][0] == '-' && !is_number(t[i])) {
    const std::string_view o = t[i++];
    const size_t most = (o == "-o" || o == "-s" || o == "-t") ? 3 : o == "-mm" ? 2 : 1;
    for (size_t k = 0; k < most && i < t.size(); ++k) {
      if (most == 3 && k > 0 && !is_number(t[i])) break;
      ++i;
    }
  }
  if (i >= t.size()) return "";
  const char* b = t[i].data();
  const char* e = t.back().data() + t.back().size();
  return std::string(b, (size_t)(e - b));
}

// "Kd r g b" and "map_Kd FILE" of every "newmtl" in a material library.
void read_mtl(const std::string& path, std::map<std::string, MtlEntry>& out) {
  const std::string text = slurp(path);
  Lines lines(text);
  std::string_view line;
  std::string current;
  while (lines.next(&line)) {
    const auto t = tokens(line);
    if (t.size() >= 2 && t[0] == "newmtl") {
      current = std::string(t[1]);
      out[current];
    }
    if (current.empty()) continue;
    if (t.size() >= 4 && t[0] == "Kd") {
      std::array<float, 3> c;
      for (int k = 0; k < 3; ++k) c[k] = (float)std::clamp(number(t[1 + k], path, lines.number()), 0.0, 1.0);
      out[current].kd = c;
    } else if (t.size() >= 2 && t[0] == "map_Kd") {
      out[current].map_kd = map_file(line);
    }
  }
}

}  // namespace

RawMesh parse_obj(std::string_view text, const std::string& path) {
  RawMesh m;
  std::vector<std::string> libraries;
  std::vector<std::string> material_names;
  int material = -1;
  bool every_corner_has_normal = true;
  Lines lines(text);
  std::string_view line;
  std::vector<int> v, vn, vt;
  bool every_corner_has_uv = true;
  while (lines.next(&line)) {
    const long ln = lines.number();
    const auto t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "v") {
      if (t.size() < 4) fail(path, ln, "a vertex needs x y z");
      Vec3 p(number(t[1], path, ln), number(t[2], path, ln), number(t[3], path, ln));
      if (t.size() == 5) {  // x y z w: homogeneous
        const double w = number(t[4], path, ln);
        if (w == 0) fail(path, ln, "vertex has w = 0 (a point at infinity)");
        p /= w;
        if (!all_finite(p)) fail(path, ln, "vertex x/w, y/w, z/w overflows (w = " + std::string(t[4]) + ")");
      }
      if (t.size() >= 7) {  // x y z r g b: a vertex colour (MeshLab, ZBrush), display values in [0, 1]
        std::array<float, 3> c;
        for (int k = 0; k < 3; ++k)
          c[k] = srgb_to_linear((float)std::clamp(number(t[4 + k], path, ln), 0.0, 1.0));
        m.colors.resize(m.vertices.size(), {-1.f, -1.f, -1.f});
        m.colors.push_back(c);
      }
      m.vertices.push_back(p);
    } else if (t[0] == "vt") {
      if (t.size() < 2) fail(path, ln, "a texture coordinate needs u [v]");
      m.uvs.emplace_back((float)number(t[1], path, ln), t.size() > 2 ? (float)number(t[2], path, ln) : 0.f);
    } else if (t[0] == "vn") {
      if (t.size() < 4) fail(path, ln, "a normal needs x y z");
      m.normals.emplace_back((float)number(t[1], path, ln), (float)number(t[2], path, ln),
                             (float)number(t[3], path, ln));
    } else if (t[0] == "f" || t[0] == "fo") {
      v.clear();
      vn.clear();
      vt.clear();
      bool normals_here = true, uvs_here = true;
      for (size_t i = 1; i < t.size(); ++i) {
        // v, v/vt, v//vn or v/vt/vn; negative indices count back from the latest.
        const std::string_view tok = t[i];
        const size_t s1 = tok.find('/');
        const long raw = integer(tok.substr(0, s1), path, ln);
        const long nv = (long)m.vertices.size();
        const long vi = raw < 0 ? nv + raw : raw - 1;
        if (raw == 0 || vi < 0 || vi >= nv)
          fail(path, ln,
               "face refers to vertex " + std::to_string(raw) + " but " + std::to_string(nv) +
                   " are defined before it");
        v.push_back((int)vi);
        const size_t s2 = s1 == std::string_view::npos ? s1 : tok.find('/', s1 + 1);
        const size_t t_end = s2 == std::string_view::npos ? tok.size() : s2;
        if (s1 != std::string_view::npos && t_end > s1 + 1) {
          const long rt = integer(tok.substr(s1 + 1, t_end - s1 - 1), path, ln);
          const long nt = (long)m.uvs.size();
          const long ti = rt < 0 ? nt + rt : rt - 1;
          if (rt == 0 || ti < 0 || ti >= nt)
            fail(path, ln,
                 "face refers to texture coordinate " + std::to_string(rt) + " that does not exist");
          vt.push_back((int)ti);
        } else {
          uvs_here = false;
        }
        if (s2 != std::string_view::npos && s2 + 1 < tok.size()) {
          const long rn = integer(tok.substr(s2 + 1), path, ln);
          const long nn = (long)m.normals.size();
          const long ni = rn < 0 ? nn + rn : rn - 1;
          if (rn == 0 || ni < 0 || ni >= nn)
            fail(path, ln, "face refers to normal " + std::to_string(rn) + " that does not exist");
          vn.push_back((int)ni);
        } else {
          normals_here = false;
        }
      }
      if (!normals_here) {
        every_corner_has_normal = false;
        vn.clear();
      }
      if (!uvs_here) {
        every_corner_has_uv = false;
        vt.clear();
      }
      add_polygon(m, v, vn, material, vt);
    } else if (t[0] == "l" || t[0] == "p") {
      ++m.points_and_lines;
    } else if (t[0] == "mtllib") {
      for (size_t i = 1; i < t.size(); ++i) libraries.emplace_back(t[i]);
    } else if (t[0] == "usemtl" && t.size() >= 2) {
      const std::string name(t[1]);
      auto it = std::find(material_names.begin(), material_names.end(), name);
      material = (int)(it - material_names.begin());
      if (it == material_names.end()) material_names.push_back(name);
    }
  }
  if (!every_corner_has_normal) m.triangle_normals.clear();
  if (!every_corner_has_uv || m.triangle_uvs.size() != m.triangles.size()) {
    m.triangle_uvs.clear();
    m.uvs.clear();
  }
  // Vertex colours only where every vertex has one: a partial list is no colouring.
  if (!m.colors.empty()) {
    m.colors.resize(m.vertices.size(), {-1.f, -1.f, -1.f});
    if (std::any_of(m.colors.begin(), m.colors.end(), [](const auto& c) { return c[0] < 0; })) {
      m.notes.push_back("only some vertices have a colour: vertex colours left out");
      m.colors.clear();
    }
  }
  // Materials: colours and images from the libraries beside the OBJ file.
  std::map<std::string, MtlEntry> kd;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const std::string& lib : libraries) {
    // Any name a file gives: too long, a symlink loop, a folder, a FIFO. None of that stops the
    // mesh from loading; the note says why the colours are not the file's.
    std::string why;
    try {
      const std::filesystem::path p = dir / lib;
      std::error_code ec;
      const auto st = std::filesystem::status(p, ec);
      if (ec || !std::filesystem::exists(st))
        why = ec && ec != std::errc::no_such_file_or_directory ? ec.message() : "not found";
      else if (!std::filesystem::is_regular_file(st))
        why = "not a regular file";
      else
        read_mtl(p.string(), kd);
    } catch (const InputError& e) {
      why = e.what();
    } catch (const std::exception& e) {  // filesystem_error, bad_alloc on a path: a note, not a failure
      why = e.what();
    }
    if (!why.empty())
      m.notes.push_back("material library '" + lib + "' could not be opened (" + why +
                        "); colours from the scene");
  }
  m.materials.assign(material_names.size(), {-1.f, -1.f, -1.f});  // -1: no Kd known
  m.material_names = material_names;
  m.material_textures.assign(material_names.size(), "");
  for (size_t i = 0; i < material_names.size(); ++i) {
    const auto it = kd.find(material_names[i]);
    if (it == kd.end()) continue;
    if (it->second.kd) m.materials[i] = *it->second.kd;
    m.material_textures[i] = it->second.map_kd;
  }
  return m;
}

// ---- OFF ------------------------------------------------------------------------------------

RawMesh parse_off(std::string_view text, const std::string& path) {
  Lines lines(text);
  std::string_view line;
  RawMesh m;
  auto next_tokens = [&](std::vector<std::string_view>* t) {
    while (lines.next(&line)) {
      *t = tokens(line);
      if (!t->empty()) return true;
    }
    return false;
  };
  std::vector<std::string_view> t;
  if (!next_tokens(&t)) fail(path, 0, "empty file");
  // Header: [ST][C][N][4][n]OFF, possibly followed by the counts on the same line.
  const std::string_view head = t[0];
  if (!is_off_keyword(head)) fail(path, lines.number(), "not an OFF file (no OFF header)");
  if (head.find('4') != std::string_view::npos || head.find('n') != std::string_view::npos)
    fail(path, lines.number(), "only 3-dimensional OFF files are supported");
  t.erase(t.begin());
  if (t.empty() && !next_tokens(&t)) fail(path, lines.number(), "missing vertex and face counts");
  if (t.size() < 2) fail(path, lines.number(), "expected 'vertices faces edges' counts");
  const long nv = integer(t[0], path, lines.number()), nf = integer(t[1], path, lines.number());
  if (nv < 0 || nf < 0) fail(path, lines.number(), "negative count");
  if (nv > INT_MAX) fail(path, lines.number(), "more than 2147483647 vertices");
  // The body as a stream of tokens: a vertex or face may run over several lines (some writers
  // wrap long faces). What follows a record on its last line (colours, normals) is skipped.
  size_t ti = t.size();
  auto token = [&](std::string_view* tok) {
    while (ti >= t.size()) {
      if (!lines.next(&line)) return false;
      t = tokens(line);
      ti = 0;
    }
    *tok = t[ti++];
    return true;
  };
  std::string_view tok;
  // Never sized by the claim alone: a vertex takes at least 6 bytes ("0 0 0\n"). A claim the file
  // cannot hold ends in "file ends after N of M".
  m.vertices.reserve(std::min((size_t)nv, (text.size() - std::min(text.size(), lines.offset())) / 6 + 1));
  for (long i = 0; i < nv; ++i) {
    double c[3];
    for (int k = 0; k < 3; ++k) {
      if (!token(&tok))
        fail(path, lines.number(),
             "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
      c[k] = number(tok, path, lines.number());
    }
    m.vertices.emplace_back(c[0], c[1], c[2]);
    ti = t.size();
  }
  std::vector<int> v;
  for (long f = 0; f < nf; ++f) {
    auto ends = [&] {
      fail(path, lines.number(),
           "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    };
    if (!token(&tok)) ends();
    const long k = integer(tok, path, lines.number());
    if (k < 0) fail(path, lines.number(), "face has a negative count " + std::to_string(k));
    v.clear();
    for (long i = 0; i < k; ++i) {
      if (!token(&tok)) ends();
      const long ln = lines.number();
      const long vi = integer(tok, path, ln);
      if (vi < 0 || vi >= nv)
        fail(path, ln, "face refers to vertex " + std::to_string(vi) + " of " + std::to_string(nv));
      v.push_back((int)vi);
    }
    ti = t.size();
    add_polygon(m, v, {}, -1);
  }
  return m;
}

// ---- STL ------------------------------------------------------------------------------------

RawMesh parse_stl(std::string_view text, const std::string& path, std::string* kind) {
  RawMesh m;
  // Binary: 80-byte header, uint32 count, 50 bytes a triangle. Many binary files also begin with
  // "solid", so the size decides.
  uint32_t n = 0;
  if (text.size() >= 84) {
    std::memcpy(&n, text.data() + 80, 4);
    if (84 + 50ull * n == text.size()) {
      m.vertices.reserve(3ull * n);
      m.triangles.reserve(n);
      *kind = "stl-binary";
      for (uint32_t f = 0; f < n; ++f) {
        const char* rec = text.data() + 84 + 50ull * f + 12;  // skip the facet normal
        std::array<int, 3> tri;
        for (int k = 0; k < 3; ++k) {
          float c[3];
          std::memcpy(c, rec + 12 * k, 12);  // little-endian IEEE float32, as the format defines
          for (float x : c)
            if (!std::isfinite(x))
              fail(path, 0, "triangle " + std::to_string(f) + " has a non-finite coordinate");
          tri[k] = (int)m.vertices.size();
          m.vertices.emplace_back(c[0], c[1], c[2]);
        }
        m.triangles.push_back(tri);
      }
      return m;
    }
  }
  // A binary STL whose count is wrong is not text: a NUL or control byte says so.
  const std::string claim =
      text.size() >= 84
          ? "binary STL whose header claims " + std::to_string(n) + " triangles (84 + 50 x " +
                std::to_string(n) + " = " + std::to_string(84 + 50ull * n) + " bytes) but the file has " +
                std::to_string(text.size()) + " bytes: the triangle count is wrong or the file is cut short"
          : std::string();
  const bool binary_bytes = std::any_of(text.begin(), text.end(), [](char ch) {
    const unsigned char u = (unsigned char)ch;
    return u < 0x20 && u != '\t' && u != '\n' && u != '\r' && u != '\f' && u != '\v';
  });
  {
    const auto first = tokens(text.substr(0, 512), 0);
    if (first.empty() || first[0] != "solid")
      fail(path, 0,
           !claim.empty() && binary_bytes
               ? "not ASCII STL (no 'solid'); read as a " + claim
               : "neither ASCII STL (no 'solid') nor binary STL (size " + std::to_string(text.size()) +
                     " bytes does not match 84 + 50 x its triangle count)");
  }

  *kind = "stl-ascii";
  Lines lines(text);
  std::string_view line;
  std::vector<int> loop;
  while (lines.next(&line)) {
    const auto t = tokens(line, 0);
    if (t.empty()) continue;
    const long ln = lines.number();
    if (t[0] == "vertex") {
      if (t.size() < 4) fail(path, ln, "a vertex needs x y z");
      loop.push_back((int)m.vertices.size());
      m.vertices.emplace_back(number(t[1], path, ln), number(t[2], path, ln), number(t[3], path, ln));
    } else if (t[0] == "outer") {
      loop.clear();
    } else if (t[0] == "endloop") {
      if (loop.size() < 3)
        fail(path, ln, "a facet loop needs 3 vertices, found " + std::to_string(loop.size()));
      add_polygon(m, loop, {}, -1);
      loop.clear();
    }
  }
  if (m.triangles.empty() && binary_bytes && !claim.empty())
    fail(path, 0, "begins with 'solid' but holds binary data and no facets; read as a " + claim);
  return m;
}

// ---- PLY ------------------------------------------------------------------------------------

namespace {

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<PlyType> ply_type(std::string_view s) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},
      {"uint8", PlyType::u8},   {"short", PlyType::i16},   {"int16", PlyType::i16},
      {"ushort", PlyType::u16}, {"uint16", PlyType::u16},  {"int", PlyType::i32},
      {"int32", PlyType::i32},  {"uint", PlyType::u32},    {"uint32", PlyType::u32},
      {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64},
      {"float64", PlyType::f64}};
  for (const auto& [n, t] : names)
    if (s == n) return t;
  return std::nullopt;
}

int ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8:
    case PlyType::u8:
      return 1;
    case PlyType::i16:
    case PlyType::u16:
      return 2;
    case PlyType::i32:
    case PlyType::u32:
    case PlyType::f32:
      return 4;
    case PlyType::f64:
      return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  PlyType type;
  bool is_list = false;
  PlyType count_type = PlyType::u8;
};

struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> props;
};

// Values of the body, in ASCII or binary, as doubles (integers up to 2^32 are exact).
class PlyReader {
 public:
  PlyReader(std::string_view text, size_t start, long first_line, int format, const std::string& path)
      : text_(text), pos_(std::min(start, text.size())), format_(format), path_(path), line_(first_line) {}

  double read(PlyType t) {
    if (format_ == 0) return ascii();
    const int n = ply_size(t);
    if (pos_ + n > text_.size()) fail(path_, 0, "binary data ends early" + where());
    unsigned char b[8];
    std::memcpy(b, text_.data() + pos_, n);
    pos_ += n;
    const bool little = format_ == 1;
    if (little != (std::endian::native == std::endian::little)) std::reverse(b, b + n);
    switch (t) {
      case PlyType::i8:
        return (double)(int8_t)b[0];
      case PlyType::u8:
        return (double)b[0];
      case PlyType::i16: {
        int16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case PlyType::u16: {
        uint16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case PlyType::i32: {
        int32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::u32: {
        uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::f32: {
        float v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::f64: {
        double v;
        std::memcpy(&v, b, 8);
        return v;
      }
    }
    return 0;
  }
  long line() const { return line_; }
  size_t remaining() const { return text_.size() - pos_; }
  void set_element(const PlyElement* e) { element_ = e; }
  void set_record(long k) { record_ = k; }

 private:
  double ascii() {
    while (pos_ < text_.size() && std::isspace((unsigned char)text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    size_t e = pos_;
    while (e < text_.size() && !std::isspace((unsigned char)text_[e])) ++e;
    if (e == pos_) fail(path_, line_, "data ends early" + where());
    const std::string_view tok(text_.data() + pos_, e - pos_);
    pos_ = e;
    return number(tok, path_, line_);
  }
  std::string_view text_;
  size_t pos_;
  int format_;  // 0 ascii, 1 little endian, 2 big endian
  std::string where() const {
    if (!element_) return "";
    return " (in " + element_->name + " " + std::to_string(record_ + 1) + " of the " +
           std::to_string(element_->count) + " the header claims)";
  }
  const std::string& path_;
  long line_;  // of the next token, ASCII only
  const PlyElement* element_ = nullptr;
  long record_ = 0;
};

}  // namespace

RawMesh parse_ply(std::string_view text, const std::string& path, std::string* kind) {
  Lines lines(text);
  std::string_view line;
  if (!lines.next(&line) || tokens(line, 0) != std::vector<std::string_view>{"ply"})
    fail(path, 1, "not a PLY file (first line is not 'ply')");
  int format = -1;
  std::vector<PlyElement> elements;
  std::string texture_file;
  bool ended = false;
  while (lines.next(&line)) {
    const long ln = lines.number();
    const auto t = tokens(line, 0);
    // "comment TextureFile NAME": the image the vertices' texture coordinates index (MeshLab).
    if (t.size() >= 3 && t[0] == "comment" && t[1] == "TextureFile") {
      const char* b = t[2].data();
      texture_file = std::string(b, (size_t)(t.back().data() + t.back().size() - b));
    }
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      // Alone on its line: the body starts after its newline (a file without one has no body).
      if (t.size() != 1) fail(path, ln, "end_header must be alone on its line");
      ended = true;
      break;
    }
    if (t[0] == "format") {
      if (t.size() < 2) fail(path, ln, "format needs a name");
      format = t[1] == "ascii"                  ? 0
               : t[1] == "binary_little_endian" ? 1
               : t[1] == "binary_big_endian"    ? 2
                                                : -2;
      if (format == -2) fail(path, ln, "unknown PLY format '" + std::string(t[1]) + "'");
    } else if (t[0] == "element") {
      if (t.size() != 3) fail(path, ln, "element needs a name and a count");
      const long n = integer(t[2], path, ln);
      if (n < 0) fail(path, ln, "negative element count");
      for (const PlyElement& e : elements)
        if (e.name == t[1]) fail(path, ln, "a second element named '" + e.name + "'");
      elements.push_back({std::string(t[1]), n, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) fail(path, ln, "property before any element");
      PlyProperty p;
      if (t.size() >= 2 && t[1] == "list") {
        if (t.size() != 5) fail(path, ln, "a list property needs a count type, an item type and a name");
        const auto ct = ply_type(t[2]), it = ply_type(t[3]);
        if (!ct || !it) fail(path, ln, "unknown property type");
        if (*ct == PlyType::f32 || *ct == PlyType::f64)
          fail(path, ln, "a list's count type must be an integer type, not '" + std::string(t[2]) + "'");
        p = {std::string(t[4]), *it, true, *ct};
      } else if (t.size() == 3) {
        const auto ty = ply_type(t[1]);
        if (!ty) fail(path, ln, "unknown property type '" + std::string(t[1]) + "'");
        p = {std::string(t[2]), *ty};
      } else {
        fail(path, ln, "property needs a type and a name");
      }
      for (const PlyProperty& q : elements.back().props)
        if (q.name == p.name)
          fail(path, ln,
               "element '" + elements.back().name + "' has a second property named '" + p.name + "'");
      elements.back().props.push_back(p);
    }
    // Anything else is a line real exporters write without "comment" (Blender 2.4x: "Created by
    // Blender3D ..."): nothing to read in it.
  }
  if (!ended) fail(path, 0, "header has no end_header");
  if (format < 0) fail(path, 0, "header has no format line");
  *kind = format == 0 ? "ply-ascii" : "ply-binary";
  RawMesh m;
  PlyReader r(text, lines.offset(), lines.number() + 1, format, path);
  long nv = -1, strip_triangles = 0, strip_joins = 0;
  std::vector<int> v;
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_strip = e.name == "tristrips";
    const bool is_face = e.name == "face" || is_strip;
    int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iface = -1;
    int ic[3] = {-1, -1, -1}, iu = -1, iv = -1;  // colour (red green blue), texture coordinates
    bool colour_bytes = true;                    // uchar colours (0-255) rather than floats (0-1)
    for (int i = 0; i < (int)e.props.size(); ++i) {
      const std::string& n = e.props[i].name;
      const bool scalar = !e.props[i].is_list;
      if (is_vertex && !scalar && (n == "x" || n == "y" || n == "z"))
        fail(path, 0, "vertex property '" + n + "' is a list, not a number");
      if (scalar && n == "x") ix = i;
      if (scalar && n == "y") iy = i;
      if (scalar && n == "z") iz = i;
      if (scalar && n == "nx") inx = i;
      if (scalar && n == "ny") iny = i;
      if (scalar && n == "nz") inz = i;
      for (int k = 0; k < 3; ++k)
        if (scalar && (n == std::array{"red", "green", "blue"}[k] ||
                       n == std::array{"diffuse_red", "diffuse_green", "diffuse_blue"}[k])) {
          ic[k] = i;
          colour_bytes = e.props[i].type != PlyType::f32 && e.props[i].type != PlyType::f64;
        }
      if (scalar && (n == "s" || n == "u" || n == "texture_u" || n == "texture_s")) iu = i;
      if (scalar && (n == "t" || n == "v" || n == "texture_v" || n == "texture_t")) iv = i;
      if ((n == "vertex_indices" || n == "vertex_index") && e.props[i].is_list) iface = i;
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) fail(path, 0, "vertex element has no x, y and z");
    if (is_face && iface < 0) fail(path, 0, "face element has no vertex_indices list");
    const bool normals = is_vertex && inx >= 0 && iny >= 0 && inz >= 0;
    const bool colours = is_vertex && ic[0] >= 0 && ic[1] >= 0 && ic[2] >= 0;
    const bool uvs = is_vertex && iu >= 0 && iv >= 0;
    if (is_vertex) {
      if (e.count > INT_MAX) fail(path, 0, "more than 2147483647 vertices");
      nv = e.count;
    }
    // Elements with no properties take no bytes: skipped whatever their count (no loop over 2^63).
    if (e.props.empty()) continue;
    // A record takes at least its scalars' sizes and its lists' count sizes (binary), or two bytes
    // a value (ASCII): memory is never sized beyond what the bytes left can hold. A claim the file
    // cannot hold ends in "data ends early".
    size_t least = 0;
    for (const PlyProperty& p : e.props)
      least += format == 0 ? 2 : ply_size(p.is_list ? p.count_type : p.type);
    if (is_vertex) m.vertices.reserve(std::min((size_t)e.count, r.remaining() / least + 1));
    r.set_element(&e);
    std::vector<double> vals(e.props.size());
    for (long k = 0; k < e.count; ++k) {
      r.set_record(k);
      v.clear();
      for (int i = 0; i < (int)e.props.size(); ++i) {
        const PlyProperty& p = e.props[i];
        if (!p.is_list) {
          vals[i] = r.read(p.type);
          continue;
        }
        const double cnt = r.read(p.count_type);
        // Never convert before checking: NaN or 1e300 to an integer is undefined.
        if (!(cnt >= 0 && cnt <= 2147483647.0) || cnt != std::floor(cnt) ||
            cnt * (format == 0 ? 2 : ply_size(p.type)) > (double)r.remaining() + (format == 0 ? 1 : 0))
          fail(path, format == 0 ? r.line() : 0,
               "list length " + show(cnt) + " is not a whole number the rest of the file can hold");
        for (long j = 0; j < (long)cnt; ++j) {
          const double x = r.read(p.type);
          if (i == iface) {
            if (nv < 0) fail(path, 0, "faces come before vertices");
            if (is_strip && x == -1) {  // restarts the strip
              v.push_back(-1);
              continue;
            }
            if (!(x >= 0 && x < (double)nv) || x != std::floor(x))
              fail(
                  path, format == 0 ? r.line() : 0,
                  "face " + std::to_string(k) + " refers to vertex " + show(x) + " of " + std::to_string(nv));
            v.push_back((int)x);
          }
        }
      }
      if (is_vertex) {
        const Vec3 p(vals[ix], vals[iy], vals[iz]);
        if (!all_finite(p))
          fail(path, format == 0 ? r.line() : 0,
               "vertex " + std::to_string(k) + " has a non-finite coordinate");
        m.vertices.push_back(p);
        if (normals) m.normals.emplace_back((float)vals[inx], (float)vals[iny], (float)vals[inz]);
        if (colours) {
          std::array<float, 3> c;
          for (int j = 0; j < 3; ++j) {
            const double x = vals[ic[j]] / (colour_bytes ? 255.0 : 1.0);
            c[j] = srgb_to_linear((float)(x >= 0 ? std::min(x, 1.0) : 0.0));  // NaN to 0
          }
          m.colors.push_back(c);
        }
        if (uvs) m.uvs.emplace_back((float)vals[iu], (float)vals[iv]);
      }
      if (is_strip) {
        // Triangle strips: every three consecutive indices make a triangle, the winding
        // alternating; -1 starts a new strip. Triangles with a repeated corner join strips and
        // are not part of the surface.
        size_t start = 0;
        for (size_t i = 0; i <= v.size(); ++i) {
          if (i < v.size() && v[i] >= 0) continue;
          for (size_t j = start; j + 2 < i; ++j) {
            const int a = v[j], b = v[j + 1], c = v[j + 2];
            if (a == b || b == c || a == c) {
              ++strip_joins;
              continue;
            }
            if ((j - start) % 2 == 0)
              m.triangles.push_back({a, b, c});
            else
              m.triangles.push_back({b, a, c});
            m.triangle_material.push_back(-1);
            ++strip_triangles;
          }
          start = i + 1;
        }
      } else if (is_face) {
        add_polygon(m, v, {}, -1);
      }
    }
  }
  // A texture file makes one material, used by every face (PLY has no material per face).
  if (!texture_file.empty() && !m.uvs.empty()) {
    m.materials.push_back({-1.f, -1.f, -1.f});
    m.material_names.push_back("");
    m.material_textures.push_back(texture_file);
    std::fill(m.triangle_material.begin(), m.triangle_material.end(), 0);
  }
  if (strip_triangles)
    m.notes.push_back("read " + std::to_string(strip_triangles) + " triangles from triangle strips" +
                      (strip_joins ? " (left out " + std::to_string(strip_joins) +
                                         " with a repeated corner, which only join strips)"
                                   : std::string()));
  return m;
}

std::string read_file(const std::string& path) {
  return slurp(path);
}

std::string native_format(std::string_view head, uint64_t size) {
  head = head.substr(0, 512);
  if (head.starts_with("ply\n") || head.starts_with("ply\r\n")) return "ply";
  const auto t = tokens(head, 0);
  if (!t.empty() && t[0] == "ply") return "ply";  // after blank lines: refused by the PLY reader
  if (!t.empty() && is_off_keyword(t[0])) return "off";
  if (!t.empty() && t[0] == "solid" && head.find("facet") != std::string_view::npos) return "stl";
  if (head.size() >= 84 && size >= 84) {
    uint32_t n;
    std::memcpy(&n, head.data() + 80, 4);
    if (84 + 50ull * n == size) return "stl";
  }
  return "";
}

}  // namespace simreel::detail
