#include "app/scene/scene.hpp"

#include "app/scene/scene_yaml.hpp"

#include "app/scene/frame_plan.hpp"

#include <yaml-cpp/anchor.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "app/scene/mesh_import.hpp"
#include "app/scene/mesh_library.hpp"
#include "app/scene/scene_camera.hpp"
#include "app/scene/scene_forces.hpp"
#include "app/scene/scene_imports.hpp"
#include "app/scene/scene_joints.hpp"
#include "app/scene/scene_place.hpp"
#include "app/scene/scene_repeat.hpp"
#include "sim/base/enum_names.hpp"
#include "sim/dynamics/mesh_collider.hpp"
#include "sim/geometry/convex_decomposition.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "sim/mass/primitives.hpp"

namespace simreel {

using namespace scene_yaml;

namespace fs = std::filesystem;

std::optional<std::string> nearest(const std::string& w, const std::vector<std::string>& cands) {
  auto dist = [](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t prev = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t cur = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
        prev = cur;
      }
    }
    return row[b.size()];
  };
  std::optional<std::string> best;
  size_t bd = std::max<size_t>(2, w.size() / 3) + 1;
  for (const std::string& c : cands) {
    const size_t d = dist(w, c);
    if (d < bd) bd = d, best = c;
  }
  return best;
}

namespace {

// What yaml-cpp's loader lets through silently, checked on the event stream before it builds the
// tree: a second document, a duplicate key (the loader keeps the first), a key that is not a plain
// name (a list or mapping as a key: "bad conversion" later), and aliases that expand to more nodes
// than any scene needs (a few KB of nested aliases can stand for billions). Throws InputError
// "FILE:LINE:COL: KEY: what".
class StrictYaml : public YAML::EventHandler {
 public:
  static constexpr uint64_t kMaxNodes = 2000000;  ///< nodes after expanding aliases
  explicit StrictYaml(const std::string& file) : file_(file) {}
  void OnDocumentStart(const YAML::Mark& m) override {
    if (++documents_ > 1)
      fail(m, "", "a scene file holds one YAML document; a second one starts here (after '---' or '...')");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t a) override { item(m, nullptr, a, 1); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t a) override {
    if (!stack_.empty() && stack_.back().map && stack_.back().want_key)
      fail(m, stack_.back().path, "a key must be a plain name, not an alias");
    const auto it = sizes_.find(a);
    item(m, nullptr, 0, it == sizes_.end() ? 1 : it->second, true);
  }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t a, const std::string& v) override {
    item(m, &v, a, 1);
  }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a,
                       YAML::EmitterStyle::value) override {
    open(m, false, a);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a,
                  YAML::EmitterStyle::value) override {
    open(m, true, a);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Frame {
    bool map = false;
    YAML::anchor_t anchor = 0;
    std::string path;
    bool want_key = true;              // map: the next node is a key
    size_t index = 0;                  // sequence: of the next item
    std::string key;                   // map: the key of the value now being read
    uint64_t size = 1;                 // nodes so far, aliases expanded
    std::map<std::string, int> lines;  // map: keys seen, with their lines
  };
  [[noreturn]] void fail(const YAML::Mark& m, const std::string& key, const std::string& what) const {
    std::ostringstream os;
    os << file_ << ":" << m.line + 1 << ":" << m.column + 1 << ": " << (key.empty() ? "scene" : key) << ": "
       << what;
    throw InputError(os.str());
  }
  std::string child_path() const {
    if (stack_.empty()) return "";
    const Frame& f = stack_.back();
    if (!f.map) return f.path + "[" + std::to_string(f.index) + "]";
    return f.path.empty() ? f.key : f.path + "." + f.key;
  }
  void count(const YAML::Mark& m, uint64_t n) {
    total_ = std::min(total_ + n, kMaxNodes + 1);
    if (total_ > kMaxNodes)
      fail(m, child_path(),
           "the scene expands to more than " + std::to_string(kMaxNodes) +
               " YAML nodes (through aliases); that is no scene simreel can run");
  }
  // A finished node (scalar, null, alias, or a closed list or mapping) in the frame on top.
  void item(const YAML::Mark& m, const std::string* scalar, YAML::anchor_t anchor, uint64_t size,
            bool alias = false) {
    if (anchor) sizes_[anchor] = size;
    if (stack_.empty()) return;
    Frame& f = stack_.back();
    if (f.map && f.want_key) {
      if (!scalar) fail(m, f.path, alias ? "a key must be a plain name, not an alias" : "a key is empty");
      const auto it = f.lines.find(*scalar);
      f.key = *scalar;
      if (it != f.lines.end())
        fail(m, child_path(),
             "duplicate key '" + *scalar + "' (first on line " + std::to_string(it->second) +
                 "); YAML would keep only one of them");
      f.lines[*scalar] = m.line + 1;
      f.want_key = false;
    } else if (f.map) {
      f.want_key = true;
    } else {
      ++f.index;
    }
    f.size = std::min(f.size + size, kMaxNodes + 1);
    count(m, size);
  }
  void open(const YAML::Mark& m, bool map, YAML::anchor_t anchor) {
    if (!stack_.empty() && stack_.back().map && stack_.back().want_key)
      fail(m, stack_.back().path,
           std::string("a key must be a plain name, not a ") + (map ? "mapping" : "list"));
    Frame f;
    f.map = map;
    f.anchor = anchor;
    f.path = child_path();
    stack_.push_back(std::move(f));
  }
  void close() {
    const Frame f = std::move(stack_.back());
    stack_.pop_back();
    if (f.anchor) sizes_[f.anchor] = f.size;
    if (stack_.empty()) return;
    Frame& p = stack_.back();
    if (p.map)
      p.want_key = true;
    else
      ++p.index;
    p.size = std::min(p.size + f.size, kMaxNodes + 1);
  }

  std::string file_;
  int documents_ = 0;
  std::vector<Frame> stack_;
  std::map<YAML::anchor_t, uint64_t> sizes_;
  uint64_t total_ = 0;
};

std::array<float, 3> color(const YAML::Node& n, const Ctx& c) {
  const Vec3 v = vec<3>(n, c);
  for (int i = 0; i < 3; ++i)
    if (v[i] < 0 || v[i] > 1) c.index(i).fail(n[i], "colour components must lie in [0, 1]");
  return {(float)v[0], (float)v[1], (float)v[2]};
}

int whole(const YAML::Node& n, const Ctx& c, int lo, int hi) {
  const double v = number(n, c);
  if (v != std::floor(v) || v < lo || v > hi)
    c.fail(n, "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " +
                  show(n));
  return (int)v;
}

// A mesh collider's hull beyond this many vertices gets a note suggesting `hull_vertices`.
constexpr int kLargeHull = 1000;
constexpr EnumNames<AntiAliasing, 4> kAntiAliasings{{"none", "fxaa", "msaa2", "msaa4"}};
static_assert(kAntiAliasings.complete());

// A body's `type:`, named as BodyType's to_string names it.
constexpr EnumNames<BodyType, 3> kBodyTypes{{"static", "kinematic", "dynamic"}};
static_assert(kBodyTypes.complete());

}  // namespace

const char* to_string(AntiAliasing a) {
  return kAntiAliasings(a);
}

std::optional<AntiAliasing> antialiasing_from_name(const std::string& name) {
  return kAntiAliasings.parse(name);
}

namespace {

// The area of the hull's base when it rests on its side facing d: its faces facing d (within 8
// degrees) that lie in the extreme plane along d (within 1% of the hull's size), m^2. Summed, as
// qhull may leave a flat base as several coplanar faces.
double base_area(const ConvexPolyhedron& h, const Vec3& d) {
  double far = -std::numeric_limits<double>::infinity(), size = 0;
  for (const Vec3& v : h.vertices)
    far = std::max(far, v.dot(d)), size = std::max(size, (v - h.centroid).norm());
  double area = 0;
  for (size_t f = 0; f < h.faces.size(); ++f) {
    if (h.faces[f].normal.dot(d) < std::cos(8 * M_PI / 180)) continue;
    Vec3 sum = Vec3::Zero();
    const int first = h.face_begin[f], last = h.face_begin[f + 1];
    const Vec3& a = h.vertices[h.edges[h.face_edges[first]].origin];
    if (a.dot(d) < far - 0.01 * size) continue;
    for (int k = first + 1; k + 1 < last; ++k)
      sum += (h.vertices[h.edges[h.face_edges[k]].origin] - a)
                 .cross(h.vertices[h.edges[h.face_edges[k + 1]].origin] - a);
    area += 0.5 * sum.norm();
  }
  return area;
}

// What a downloaded mesh's shape says about how it was authored: a file tens of metres across is
// likely in millimetres; one that stands on a flat base at its lowest y but has none at its lowest
// z (the bunny, the teapot, spot) was authored y-up and lies on its side in simreel's z-up world.
// "" when nothing stands out.
std::string authoring_hint(const TriangleMesh& m, const ConvexPolyhedron* hull, bool scaled, bool up_given) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec3 e = hi - lo;
  if (!scaled && e.maxCoeff() > 50) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "is %.4g m across: if the file is in millimetres, give the collider `scale: 0.001`",
                  e.maxCoeff());
    return b;
  }
  if (hull && !up_given && e.minCoeff() > 0) {
    const double fy = base_area(*hull, -Vec3::UnitY()) / (e.x() * e.z());
    const double fz = base_area(*hull, -Vec3::UnitZ()) / (e.x() * e.y());
    if (fy > 0.05 && fz < 0.01)
      return "stands on a flat base at its lowest y and has none at its lowest z: it was probably authored "
             "y-up and "
             "will lie on its side; `up_axis: y` stands it up";
  }
  return "";
}

struct Loader {
  Scene& scene;
  fs::path dir;
  fs::path assets;
  MeshLibrary& library;                  // files, analyses, hulls
  std::vector<std::string> mesh_errors;  // meshes that cannot be weighed, reported together
  std::set<std::string> hinted;          // files whose authoring hint was given
  std::map<std::string, std::shared_ptr<const MeshAppearance>> textured_looks;  // by mesh key + image

  // A mesh collider's `texture: IMAGE`: every face drawn with that image through the file's texture
  // coordinates, tinted by the collider's (or body's) colour if it has one (MuJoCo's way: the mug
  // of its model gallery is an OBJ with UVs and a PNG named in the XML). One look per mesh and
  // image, shared by the colliders that use them.
  std::shared_ptr<const MeshAppearance> textured(const std::shared_ptr<const MeshAppearance>& file_look,
                                                 const std::string& mkey, const YAML::Node& n, const Ctx& c,
                                                 const std::string& mesh_file) {
    const std::string image = resolve(n, c, "image");
    scene.inputs.push_back(image);
    auto& out = textured_looks[mkey + "|" + image];
    if (out) return out;
    if (!file_look || file_look->corner_uv.empty())
      c.fail(n, "mesh '" + mesh_file + "' has no texture coordinates to lay an image on");
    out = image_on_uvs(*file_look, image);
    return out;
  }
  std::string resolve(const YAML::Node& n, const Ctx& c, const std::string& what = "mesh file") {
    const std::string f = text(n, c);
    std::vector<fs::path> tried;
    for (const fs::path& base : {dir, assets, fs::path(".")}) {
      const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : base / f;
      std::error_code ec;
      const fs::file_status st = fs::status(p, ec);
      if (fs::is_regular_file(st)) return p.lexically_normal().string();
      if (fs::exists(st))
        c.fail(n,
               what + " '" + p.lexically_normal().string() + "' is " +
                   (fs::is_directory(st) ? "a directory" : "not a regular file (a FIFO, socket or device)"));
      // Absolute, each once (the scene's folder, assets/ and the working folder may coincide).
      const fs::path abs = fs::absolute(p, ec).lexically_normal();
      if (std::find(tried.begin(), tried.end(), abs) == tried.end()) tried.push_back(abs);
      if (fs::path(f).is_absolute()) break;
    }
    std::string msg = what + " '" + f + "' not found (looked in";
    for (size_t i = 0; i < tried.size(); ++i) msg += (i ? ", " : " ") + tried[i].string();
    c.fail(n, msg + ")");
  }

  // A collider's mass properties, checked here so that the error names file, line and key (the
  // world would only say "body 0: mass must be positive"): `unit` at density 1 (its volume), `mp`
  // at density `rho`. A mass the shape turns into an infinite or vanishing density, or sizes whose
  // volume or inertia leave double precision, are errors at the key that caused them.
  void check_mass(const MassProperties& unit, const MassProperties& mp, double rho, const YAML::Node& n,
                  const Ctx& c) {
    std::string size_key = "size";
    for (const char* k : {"file", "size", "radius", "radii", "height", "scale"})
      if (n[k]) {
        size_key = k;
        break;
      }
    const char* value_key = n["mass"] ? "mass" : n["density"] ? "density" : nullptr;
    auto blame = [&](const std::string& k) { return n[k] ? c.child(k) : c; };
    auto node = [&](const std::string& k) { return n[k] ? n[k] : n; };
    char b[300];
    if (!std::isfinite(unit.mass) || !(unit.mass > 0)) {
      std::snprintf(b, sizeof b, "gives a volume of %g m^3, out of the range of double precision", unit.mass);
      blame(size_key).fail(node(size_key), b);
    }
    if (!std::isfinite(rho) || !(rho > 0)) {
      std::snprintf(b, sizeof b,
                    "over a volume of %g m^3 is a density of %g kg/m^3: out of the range of double precision",
                    unit.mass, rho);
      blame("mass").fail(node("mass"), b);
    }
    const std::string k = value_key ? value_key : size_key;
    if (!std::isfinite(mp.mass) || !(mp.mass > 0) || !all_finite(mp.com) || !mp.inertia.allFinite()) {
      std::snprintf(
          b, sizeof b,
          "gives a mass of %g kg and an inertia of up to %g kg m^2 (density %g kg/m^3, volume %g m^3): "
          "out of the range of double precision",
          mp.mass, mp.inertia.cwiseAbs().maxCoeff(), rho, unit.mass);
      blame(k).fail(node(k), b);
    }
    const std::string bad = inertia_problem(mp.inertia, 1e-7);
    if (!bad.empty()) blame(k).fail(node(k), bad);
  }

  // A mesh collider's `center: com | bbox`: the collider placed so that its mesh's centre of mass
  // (or bounding-box centre) sits at `position`, not the file's origin (downloads are often
  // modelled far from their origin: Suzanne's 3 m offset).
  void center(Collider& col, const YAML::Node& n, const Ctx& c, const MassProperties& props) {
    if (!n["center"]) return;
    const std::string how = text(n["center"], c.child("center"));
    Vec3 o;
    if (how == "com") {
      if (!(props.mass > 0))
        c.child("center").fail(n["center"], "a static body's mesh has no mass: use `center: bbox`");
      o = props.com;
    } else if (how == "bbox") {
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const Vec3& v : col.mesh->vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      o = 0.5 * (lo + hi);
    } else {
      c.child("center").fail(n["center"], "expected com or bbox, got '" + how + "'");
    }
    col.p_BC -= col.q_BC * o;
  }

  Collider collider(const YAML::Node& n, const Ctx& c, const std::string& body, BodyType type,
                    ColliderLook& look) {
    check_keys(n, c,
               {"shape",      "size",          "radius",      "height",  "radii",    "file",        "scale",
                "mode",       "thickness",     "density",     "mass",    "position", "orientation", "euler",
                "axis_angle", "friction",      "restitution", "collide", "group",    "mask",        "color",
                "up_axis",    "hull_vertices", "texture",     "center"});
    Collider col;
    const char* kShapes = "box, sphere, cylinder, capsule, mesh, plane or ellipsoid";
    if (!n["shape"]) c.fail(n, std::string("missing key 'shape' (") + kShapes + ")");
    const std::string shape = text(n["shape"], c.child("shape"));
    // In ShapeKind's order.
    const std::vector<std::string> shapes = {"box",  "sphere", "cylinder", "capsule",
                                             "mesh", "plane",  "ellipsoid"};
    const auto it = std::find(shapes.begin(), shapes.end(), shape);
    if (it == shapes.end()) {
      std::string msg = "unknown shape '" + shape + "' (" + kShapes + ")";
      if (auto s = nearest(shape, shapes)) msg += "; did you mean '" + *s + "'?";
      c.child("shape").fail(n["shape"], msg);
    }
    col.shape = (ShapeKind)(it - shapes.begin());
    auto need = [&](const char* k) {
      if (!n[k]) c.fail(n, std::string("a ") + shape + " needs '" + k + "'");
      return n[k];
    };
    auto forbid = [&](std::initializer_list<const char*> keys) {
      for (const char* k : keys)
        if (n[k]) c.child(k).fail(n[k], std::string("does not apply to a ") + shape);
    };
    if (n["position"]) col.p_BC = vec<3>(n["position"], c.child("position"));
    orientation(n, c, col.q_BC);
    if (n["up_axis"] && col.shape != ShapeKind::mesh)
      c.child("up_axis").fail(n["up_axis"], "applies to mesh colliders only");
    if (n["texture"] && col.shape != ShapeKind::mesh)
      c.child("texture").fail(
          n["texture"],
          "applies to mesh colliders only (the image is laid on by the file's texture coordinates)");
    if (n["center"] && col.shape != ShapeKind::mesh)
      c.child("center").fail(n["center"], "applies to mesh colliders only");
    if (n["hull_vertices"] && col.shape != ShapeKind::mesh)
      c.child("hull_vertices").fail(n["hull_vertices"], "applies to mesh colliders only");
    if (n["hull_vertices"] && type == BodyType::static_body)
      c.child("hull_vertices")
          .fail(n["hull_vertices"], "a static body's mesh collides as its triangles, not a hull");
    if (n["friction"]) col.friction = non_negative(n["friction"], c.child("friction"));
    if (n["restitution"]) col.restitution = unit_interval(n["restitution"], c.child("restitution"));
    if (n["collide"]) col.collide = boolean(n["collide"], c.child("collide"));
    if (n["color"]) look.color = color(n["color"], c.child("color"));
    if (n["group"]) col.group = bits(n["group"], c.child("group"));
    if (n["mask"]) col.mask = bits(n["mask"], c.child("mask"));
    if (col.shape == ShapeKind::plane) {
      if (type != BodyType::static_body)
        c.child("shape").fail(n["shape"],
                              std::string("a plane may only be a collider of a static body (body '") + body +
                                  "' is " + to_string(type) + "; give it 'type: static')");
      forbid({"radius", "height", "radii", "file", "scale", "mode", "thickness"});
      for (const char* k : {"density", "mass"})
        if (n[k]) c.child(k).fail(n[k], "a plane has no mass (it belongs to a static body)");
      if (n["size"]) look.plane_size = positive(n["size"], c.child("size"));
      col.props_C.mass = 0;  // infinite and massless: only its static body holds it
      col.props_C.inertia = Mat3::Zero();
      col.label = "plane";
      return col;
    }
    if (n["density"] && n["mass"])
      c.child("mass").fail(n["mass"], "give either 'density' or 'mass', not both");
    const double density = n["density"] ? positive(n["density"], c.child("density")) : 1000.0;
    switch (col.shape) {
      case ShapeKind::box:
        forbid({"radius", "height", "radii", "file", "scale", "mode", "thickness"});
        col.size = vec<3>(need("size"), c.child("size"));
        for (int i = 0; i < 3; ++i)
          if (!(col.size[i] > 0)) c.child("size").index(i).fail(n["size"][i], "must be positive");
        break;
      case ShapeKind::sphere:
        forbid({"size", "height", "radii", "file", "scale", "mode", "thickness"});
        col.radius = positive(need("radius"), c.child("radius"));
        break;
      case ShapeKind::cylinder:
      case ShapeKind::capsule:
        forbid({"size", "radii", "file", "scale", "mode", "thickness"});
        col.radius = positive(need("radius"), c.child("radius"));
        col.height = positive(need("height"), c.child("height"));
        if (col.shape == ShapeKind::capsule && col.height < 2 * col.radius)
          c.child("height").fail(n["height"],
                                 "a capsule's height (tip to tip) must be at least twice its radius");
        break;
      case ShapeKind::ellipsoid:
        forbid({"size", "radius", "height", "file", "scale", "mode", "thickness"});
        col.radii = vec<3>(need("radii"), c.child("radii"));
        for (int i = 0; i < 3; ++i)
          if (!(col.radii[i] > 0)) c.child("radii").index(i).fail(n["radii"][i], "must be positive");
        break;
      case ShapeKind::plane:  // returned above
        break;
      case ShapeKind::mesh: {
        forbid({"size", "radius", "height", "radii"});
        const std::string file = resolve(need("file"), c.child("file"));
        // Meshes authored y-up (glTF by its specification, most DCC tools) stand up in simreel's
        // z-up world when turned +90 degrees about x (mesh +y becomes +z), after the collider's
        // own orientation.
        std::string up = "z";
        if (n["up_axis"]) {
          up = text(n["up_axis"], c.child("up_axis"));
          if (up != "y" && up != "z")
            c.child("up_axis").fail(n["up_axis"], "expected y or z, got '" + up + "'");
        }
        if (up == "y") col.q_BC = col.q_BC * Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()));
        {
          std::string ext = std::filesystem::path(file).extension().string();
          for (char& ch : ext) ch = (char)std::tolower((unsigned char)ch);
          if ((ext == ".gltf" || ext == ".glb") && !n["up_axis"])
            scene.notes.push_back(
                where(n["file"], c.child("file")) + ": " + file +
                " is glTF, which is y-up by its specification: add `up_axis: y` if it lies on "
                "its side (simreel is z-up)");
        }
        Vec3 scale = Vec3::Ones();
        if (n["scale"]) {
          scale = n["scale"].IsSequence() ? vec<3>(n["scale"], c.child("scale"))
                                          : Vec3::Constant(positive(n["scale"], c.child("scale")));
          for (int i = 0; i < 3; ++i)
            if (!(scale[i] > 0)) c.child("scale").fail(n["scale"], "scale factors must be positive");
        }
        MeshMassOptions opt;
        opt.density = 1.0;
        bool parts = false;      // collide as one convex hull per connected part, weigh as the solid
        bool decompose = false;  // collide as an approximate convex decomposition, weigh as the solid
        if (n["mode"]) {
          const std::string m = text(n["mode"], c.child("mode"));
          const auto mode = m == "parts" || m == "decompose" ? std::optional<MassMode>(MassMode::solid)
                                                             : mass_mode_from_name(m);
          if (!mode) {
            std::string msg = "unknown mode '" + m + "' (solid, shell, hull, parts or decompose)";
            if (auto sug = nearest(m, {"solid", "shell", "hull", "parts", "decompose"}))
              msg += "; did you mean '" + *sug + "'?";
            c.child("mode").fail(n["mode"], msg);
          }
          opt.mode = *mode;
          parts = m == "parts";
          decompose = m == "decompose";
        }
        if (n["thickness"]) {
          if (opt.mode != MassMode::shell)
            c.child("thickness").fail(n["thickness"], "applies to mode: shell only");
          opt.thickness = positive(n["thickness"], c.child("thickness"));
        }
        const std::string mkey = MeshLibrary::key(file, scale);
        // The file read once per scale for the whole scene (its notes once), and this collider's
        // share of it: the surface, the file's colour unless the scene gives one, its shading normals.
        std::shared_ptr<const ImportedMesh> read;
        auto import_once = [&] { read = library.file(file, scale); };
        auto use_mesh = [&] {
          col.mesh = library.surface(file, scale);
          const std::shared_ptr<const MeshAppearance>& file_look = read->appearance;
          if (n["texture"]) {
            look.appearance = textured(file_look, mkey, n["texture"], c.child("texture"), file);
            if (!n["color"]) look.color = Rgb{1, 1, 1};  // the image as it is, unless a colour tints it
          } else if (!n["color"]) {
            look.color = read->color;
            // Shared by every collider of this file; only when the file has more than one colour.
            if (file_look && file_look->varies) look.appearance = file_look;
          }
          if (!read->corner_normals.empty())
            look.normals = std::shared_ptr<const std::vector<std::array<Eigen::Vector3f, 3>>>(
                read, &read->corner_normals);
        };
        if (type == BodyType::static_body) {
          // A static body's mesh collides as its triangles, as given (open surfaces too: terrain, a
          // bowl), and weighs nothing (sim/geometry/trimesh.hpp).
          for (const char* k : {"mode", "thickness", "density", "mass"})
            if (n[k])
              c.child(k).fail(n[k], "a static body's mesh collides as its triangles and has no mass: '" +
                                        std::string(k) + "' does not apply");
          try {
            import_once();
          } catch (const InputError& e) {
            c.child("file").fail(n["file"], e.what());
          }
          use_mesh();
          col.props_C.mass = 0;
          col.props_C.inertia = Mat3::Zero();
          col.label = file;
          center(col, n, c, MassProperties{});
          return col;
        }
        MeshReport rep;
        try {
          import_once();
          try {
            rep = library.analysis(file, scale, opt);
          } catch (const InputError& e) {
            if (!decompose || std::string(e.what()).find("mesh is open") == std::string::npos) throw;
            // A scan with holes: decomposed as the solid it nearly bounds, and weighed as that
            // (the parts are disjoint convex polyhedra, within a few percent of the solid).
            rep.props = decomposition_mass(library.decomposition(file, scale, 0));
            rep.volume = rep.props.mass;
            std::ostringstream os;
            os << c.file() << ": body '" << body << "', " << c.key() << " (" << file
               << "): the mesh is open (" << e.what()
               << "); it is weighed as its decomposition, as the solid it nearly bounds";
            scene.notes.push_back(os.str());
          }
        } catch (const InputError& e) {
          // Every mesh that cannot be weighed is reported at once, each with its fix (five open
          // downloads took five runs to find one at a time): a stand-in lets loading go on, and the
          // scene is refused after its bodies.
          std::string msg = e.what();
          if (msg.find("(shell mode)") != std::string::npos)
            msg += " (on this collider: `mode: shell`, or `mode: hull`)";
          mesh_errors.push_back(c.child("file").message(n["file"], msg));
          Collider stand_in = sphere_collider(0.1, 1000.0);
          stand_in.label = file;
          return stand_in;
        }
        use_mesh();
        for (const std::string& w : rep.warnings)
          scene.notes.push_back(c.file() + ": body '" + body + "', " + c.key() + " (" + file + "): " + w);
        // Mass properties at density 1, then scaled: by the density, or to the requested mass.
        const double rho = n["mass"] ? positive(n["mass"], c.child("mass")) / rep.props.mass : density;
        col.props_C = rep.props;
        col.props_C.mass *= rho;
        col.props_C.inertia *= rho;
        check_mass(rep.props, col.props_C, rho, n, c);
        center(col, n, c, rep.props);
        col.label = file;
        if (col.collide) {
          int cap = 0;
          if (n["hull_vertices"]) cap = whole(n["hull_vertices"], c.child("hull_vertices"), 4, 1000000);
          std::vector<HullReduction> reductions;
          if (decompose) {
            // Concave meshes collide as themselves: disjoint convex parts covering the solid.
            const Decomposition& d = library.decomposition(file, scale, cap);
            col.hulls = d.parts;
            std::ostringstream os;
            os << c.file() << ": body '" << body << "', " << c.key() << " (" << file << "): decomposed into "
               << d.parts.size() << " convex parts whose hulls hold " << std::setprecision(3)
               << 100 * std::fabs(d.excess()) << "% " << (d.excess() >= 0 ? "more" : "less")
               << " volume than the mesh (its mass properties are the mesh's)";
            if (!hinted.count("decompose|" + file)) scene.notes.push_back(os.str());
            hinted.insert("decompose|" + file);
          } else
            try {
              col.hulls = library.hulls(file, scale, parts, cap, &reductions);
            } catch (const InputError& e) {
              c.child("file").fail(n["file"], std::string("cannot build its collision hull: ") + e.what());
            }
          // What a cap did, and where a large hull would gain from one (its pairs take GJK and EPA,
          // a few microseconds; a capped hull is faster still and a little smaller).
          for (size_t h = 0; h < reductions.size(); ++h) {
            const HullReduction& r = reductions[h];
            std::ostringstream os;
            os << c.file() << ": body '" << body << "', " << c.key() << " (" << file << ")";
            if (reductions.size() > 1) os << ", hull " << h + 1 << " of " << reductions.size();
            if (r.vertices < r.vertices_before) {
              os << ": collision hull simplified from " << r.vertices_before << " to " << r.vertices
                 << " vertices (hull_vertices: " << cap << "), " << std::setprecision(3)
                 << 100 * (1 - r.volume_ratio) << "% less volume";
              scene.notes.push_back(os.str());
            } else if (!cap && r.vertices_before > kLargeHull) {
              os << ": its collision hull has " << r.vertices_before
                 << " vertices; `hull_vertices: 64` (or another cap) makes its contacts cheaper for a "
                    "little volume (the note then says how much)";
              scene.notes.push_back(os.str());
            }
          }
          // A mesh collides as its convex hull: say so when that is visibly more than the mesh.
          if (!parts && !decompose && opt.mode != MassMode::shell && rep.volume > 0) {
            const double hv = polyhedron_volume(*col.hulls[0]);
            if (hv > rep.volume * (1 + 1e-3)) {
              std::ostringstream os;
              os << c.file() << ": body '" << body << "', " << c.key() << " (" << file
                 << "): the mesh is not convex; it collides as its convex hull, " << std::setprecision(3)
                 << 100 * (hv / rep.volume - 1)
                 << "% larger in volume (its mass properties are the mesh's; `mode: decompose` collides as "
                    "the mesh itself, `mode: parts` as one hull per connected part)";
              scene.notes.push_back(os.str());
            }
          }
        }
        if (hinted.insert(file).second) {
          const std::string h =
              authoring_hint(*col.mesh, col.hulls.size() == 1 ? col.hulls[0].get() : nullptr,
                             (bool)n["scale"], (bool)n["up_axis"]);
          if (!h.empty()) scene.notes.push_back(where(n["file"], c.child("file")) + ": " + file + " " + h);
        }
        return col;
      }
    }
    const MassProperties unit = primitive_mass(col, 1.0);
    const double rho = n["mass"] ? positive(n["mass"], c.child("mass")) / unit.mass : density;
    col.props_C = primitive_mass(col, rho);
    check_mass(unit, col.props_C, rho, n, c);
    col.label = shape;
    return col;
  }

  // `mass_properties: { mass, center_of_mass, inertia }`: stated, not drawn. The inertia is about
  // the centre of mass in the body frame, a 3x3 list of rows or [3] for a diagonal tensor.
  MassProperties mass_properties(const YAML::Node& n, const Ctx& c) {
    if (!n.IsMap()) c.fail(n, "expected a mapping { mass, center_of_mass, inertia }, got " + show(n));
    check_keys(n, c, {"mass", "center_of_mass", "inertia"});
    for (const char* k : {"mass", "center_of_mass", "inertia"})
      if (!n[k])
        c.fail(n, std::string("needs '") + k + "' (mass, center_of_mass and inertia are all required)");
    MassProperties mp;
    mp.mass = positive(n["mass"], c.child("mass"));
    mp.com = vec<3>(n["center_of_mass"], c.child("center_of_mass"));
    const YAML::Node in = n["inertia"];
    const Ctx ic = c.child("inertia");
    if (in.IsSequence() && in.size() == 3 && in[0].IsSequence()) {
      for (int r = 0; r < 3; ++r) mp.inertia.row(r) = vec<3>(in[r], ic.index(r)).transpose();
    } else if (in.IsSequence() && in.size() == 3) {
      mp.inertia = vec<3>(in, ic).asDiagonal();
    } else {
      ic.fail(in,
              "expected a 3x3 tensor (three rows of three numbers, kg m^2) or [3] principal moments, got " +
                  show(in));
    }
    const double scale = mp.inertia.cwiseAbs().maxCoeff();
    if ((mp.inertia - mp.inertia.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale)
      ic.fail(in, "the inertia tensor must be symmetric (row i, column j equal to row j, column i)");
    if (const std::string bad = mass_problem(mp, 1e-9); !bad.empty()) {
      const Vec3 m = principal_axes(mp.inertia).moments;
      if (!(m[0] > 0)) ic.fail(in, bad + ": the inertia tensor must be positive definite");
      ic.fail(in, bad + ": no rigid body has these (the largest moment is at most the sum of the other two)");
    }
    return mp;
  }

  BodyDef body(const YAML::Node& n, const Ctx& c, size_t i, BodyLook& look) {
    check_keys(n, c,
               {"name", "position", "orientation", "euler", "axis_angle", "linear_velocity",
                "angular_velocity", "angular_velocity_body", "type", "static", "color", "integrator",
                "colliders", "show", "ghost", "mass_properties", "bullet", "place"});
    BodyDef b;
    b.name = n["name"] ? text(n["name"], c.child("name")) : "body" + std::to_string(i);
    if (n["position"]) b.p_WB = vec<3>(n["position"], c.child("position"));
    orientation(n, c, b.q_WB);
    if (n["linear_velocity"]) b.v_W = vec<3>(n["linear_velocity"], c.child("linear_velocity"));
    if (n["angular_velocity"] && n["angular_velocity_body"])
      c.child("angular_velocity_body")
          .fail(n["angular_velocity_body"],
                "give the angular velocity once: in the world or in the body frame");
    if (n["angular_velocity"]) b.w_W = vec<3>(n["angular_velocity"], c.child("angular_velocity"));
    // In the body frame (a top spun about its own axis, whatever its tilt): w_W = R_WB w_B.
    if (n["angular_velocity_body"])
      b.w_W = b.q_WB * vec<3>(n["angular_velocity_body"], c.child("angular_velocity_body"));
    if (n["type"]) {
      const Ctx tc = c.child("type");
      const std::string t = text(n["type"], tc);
      if (const auto type = kBodyTypes.parse(t)) {
        b.type = *type;
      } else {
        std::string msg = "unknown body type '" + t + "' (dynamic, static or kinematic)";
        if (auto sug = nearest(t, {"dynamic", "static", "kinematic"}))
          msg += "; did you mean '" + *sug + "'?";
        tc.fail(n["type"], msg);
      }
    }
    if (n["static"]) {  // the older shorthand: must agree with `type` when both are given
      const bool st = boolean(n["static"], c.child("static"));
      if (n["type"] && st != (b.type == BodyType::static_body))
        c.child("static").fail(n["static"], std::string("static: ") + (st ? "true" : "false") +
                                                " contradicts type: " + to_string(b.type));
      if (st) b.type = BodyType::static_body;
    }
    if (b.type == BodyType::static_body) {  // a static body never moves, whatever is set
      for (const char* k : {"linear_velocity", "angular_velocity", "angular_velocity_body"})
        if (n[k] && (k[0] == 'l' ? b.v_W : b.w_W).squaredNorm() > 0)
          scene.notes.push_back(where(n[k], c.child(k)) + ": body '" + b.name +
                                "' is static: its velocity is ignored (a static body never moves)");
      b.v_W.setZero();
      b.w_W.setZero();
    }
    if (n["color"]) look.color = color(n["color"], c.child("color"));
    if (n["integrator"]) b.integrator = integrator(n["integrator"], c.child("integrator"));
    // `bullet`: swept every step it moves (docs/continuous-collision.md)
    if (n["bullet"]) b.bullet = boolean(n["bullet"], c.child("bullet"));
    if (n["ghost"]) look.ghost = parse_ghost(n["ghost"], c.child("ghost"));
    const YAML::Node cols = n["colliders"];
    if (!cols) c.fail(n, "body '" + b.name + "' needs 'colliders' (a list of shapes)");
    if (!cols.IsSequence() || cols.size() == 0)
      c.child("colliders").fail(cols, "expected a non-empty list of colliders, got " + show(cols));
    for (size_t k = 0; k < cols.size(); ++k) {
      ColliderLook cl;
      Collider col = collider(cols[k], c.child("colliders").index(k), b.name, b.type, cl);
      // The scene's body colour wins over the file's material; the collider's own colour over both.
      if (n["color"] && !cols[k]["color"]) cl.color.reset();
      if (n["color"] && !cols[k]["texture"]) cl.appearance.reset();
      look.colliders.push_back(cl);
      b.append_collider(std::move(col));  // composed once, when the body is done
    }
    if (n["mass_properties"])
      b.mass_override = mass_properties(n["mass_properties"], c.child("mass_properties"));
    // The body as a whole (colliders far apart: the parallel-axis terms can overflow).
    bool massive = false;
    for (const Collider& col : b.colliders)  // planes and a static body's meshes weigh nothing
      massive = massive || !(col.shape == ShapeKind::plane ||
                             (b.type == BodyType::static_body && col.shape == ShapeKind::mesh));
    if (massive && !b.mass_override) {
      const MassProperties& mp = b.mass_B();
      std::string bad;
      if (!std::isfinite(mp.mass) || !(mp.mass > 0) || !all_finite(mp.com) || !mp.inertia.allFinite()) {
        char buf[200];
        std::snprintf(
            buf, sizeof buf,
            "the body's mass (%g kg) or inertia about its centre of mass (up to %g kg m^2) is out of the "
            "range of double precision",
            mp.mass, mp.inertia.cwiseAbs().maxCoeff());
        bad = buf;
      } else {
        bad = inertia_problem(mp.inertia, 1e-7);
      }
      if (!bad.empty()) c.child("colliders").fail(cols, "body '" + b.name + "': " + bad);
    }
    return b;
  }
};

}  // namespace

Scene load_scene(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw InputError(path + ": scene file: " + ec.message());
  if (!fs::exists(st)) throw InputError(path + ": scene file does not exist");
  if (fs::is_directory(st)) throw InputError(path + ": is a directory, not a scene file");
  if (!fs::is_regular_file(st))
    throw InputError(path + ": scene file is not a regular file (a FIFO, socket or device)");
  std::ifstream f(path, std::ios::binary);
  std::ostringstream text;
  text << f.rdbuf();
  if (!f || f.bad()) throw InputError(path + ": cannot read the scene file");
  // A robot file alone: placed on a ground before an automatic camera (app/scene/scene_imports.hpp).
  if (is_model_file(path)) return load_scene_text(scene_for_model_file(path), path);
  return load_scene_text(text.str(), path);
}

Scene load_scene_text(const std::string& yaml, const std::string& path) {
  Scene s;
  s.path = path;
  s.name = fs::path(path).stem().string();
  std::error_code ec;
  YAML::Node root;
  try {
    std::istringstream in(yaml);
    YAML::Parser parser(in);
    StrictYaml strict(path);
    while (parser.HandleNextDocument(strict)) {
    }
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    std::ostringstream os;
    os << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": YAML syntax error: " << e.msg;
    throw InputError(os.str());
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": YAML: " << e.msg;
    throw InputError(os.str());
  }
  const Ctx top(path, "");
  if (!root.IsMap())
    top.fail(root, "a scene is a mapping with keys simulation, video, camera, render, ground, bodies");
  expand_repeats(root, path);
  check_keys(root, top,
             {"simulation", "video", "camera", "render", "ground", "bodies", "test", "forces", "joints",
              "overlays", "time", "panes", "variants", "imports"});

  if (const YAML::Node sim = root["simulation"]) {
    const Ctx c = top.child("simulation");
    check_keys(
        sim, c,
        {"duration", "timestep", "integrator", "gravity", "contacts", "ignore_pairs", "sleep", "joints"});
    if (const YAML::Node jn = sim["joints"]) {
      const Ctx jc = c.child("joints");
      if (!jn.IsMap())
        jc.fail(jn, "expected { integrator: dopri5, tolerance: 1e-10, max_steps: 100000 }, got " + show(jn));
      check_keys(jn, jc, {"integrator", "tolerance", "max_steps", "substeps"});
      if (const YAML::Node in = jn["integrator"]) {
        const std::string name = in.IsScalar() ? in.as<std::string>() : "";
        if (name == "dopri5")
          s.joint_settings.integrator = JointIntegrator::dopri5;
        else if (name == "verlet")
          s.joint_settings.integrator = JointIntegrator::verlet;
        else
          jc.child("integrator").fail(in, "expected dopri5 or verlet, got " + show(in));
      }
      if (jn["substeps"]) {
        const double n = positive(jn["substeps"], jc.child("substeps"));
        if (n != std::floor(n) || n > 1e6)
          jc.child("substeps").fail(jn["substeps"], "must be a whole number");
        if (s.joint_settings.integrator != JointIntegrator::verlet)
          jc.child("substeps")
              .fail(jn["substeps"], "is verlet's (dopri5 chooses its steps by the tolerance)");
        s.joint_settings.substeps = (int)n;
      }
      if (jn["tolerance"]) {
        s.joint_settings.tolerance = positive(jn["tolerance"], jc.child("tolerance"));
        if (s.joint_settings.tolerance >= 1e-2)
          jc.child("tolerance")
              .fail(jn["tolerance"], "must be below 0.01 (a relative error per internal step)");
      }
      if (jn["max_steps"]) {
        const double m = positive(jn["max_steps"], jc.child("max_steps"));
        if (m != std::floor(m) || m > 1e9)
          jc.child("max_steps").fail(jn["max_steps"], "must be a whole number");
        s.joint_settings.max_steps = (int)m;
      }
    }
    if (sim["sleep"]) s.contacts.sleep = boolean(sim["sleep"], c.child("sleep"));
    if (const YAML::Node k = sim["contacts"]) {
      const Ctx kc = c.child("contacts");
      check_keys(
          k, kc,
          {"substeps", "iterations", "passes", "contact_hertz", "damping_ratio", "max_push_out",
           "restitution_threshold", "speculative_distance", "linear_slop", "rolling_resistance", "slip_speed",
           "rolling", "rolling_tolerance", "sleep_speed", "sleep_time", "continuous", "compound_shapes"});
      ContactSettings& cs = s.contacts;
      if (k["substeps"]) cs.substeps = whole(k["substeps"], kc.child("substeps"), 0, 1000);  // 0: automatic
      if (k["iterations"]) cs.iterations = whole(k["iterations"], kc.child("iterations"), 1, 1000);
      if (k["passes"]) cs.passes = whole(k["passes"], kc.child("passes"), 1, 32);
      if (k["contact_hertz"]) cs.contact_hertz = positive(k["contact_hertz"], kc.child("contact_hertz"));
      if (k["damping_ratio"]) cs.damping_ratio = non_negative(k["damping_ratio"], kc.child("damping_ratio"));
      if (k["max_push_out"]) cs.max_push_out = non_negative(k["max_push_out"], kc.child("max_push_out"));
      if (k["restitution_threshold"]) {
        cs.restitution_threshold =
            non_negative(k["restitution_threshold"], kc.child("restitution_threshold"));
        s.restitution_threshold_given = true;
      }
      if (k["speculative_distance"])
        cs.speculative_distance = non_negative(k["speculative_distance"], kc.child("speculative_distance"));
      if (k["linear_slop"]) cs.linear_slop = non_negative(k["linear_slop"], kc.child("linear_slop"));
      if (k["rolling_resistance"])
        cs.rolling_resistance = non_negative(k["rolling_resistance"], kc.child("rolling_resistance"));
      if (k["slip_speed"]) cs.slip_speed = non_negative(k["slip_speed"], kc.child("slip_speed"));
      if (k["rolling"]) cs.rolling = boolean(k["rolling"], kc.child("rolling"));
      if (k["rolling_tolerance"]) {
        cs.rolling_tolerance = positive(k["rolling_tolerance"], kc.child("rolling_tolerance"));
        if (cs.rolling_tolerance >= 1e-2)
          kc.child("rolling_tolerance").fail(k["rolling_tolerance"], "must be below 0.01");
      }
      if (k["sleep_speed"]) cs.sleep_speed = non_negative(k["sleep_speed"], kc.child("sleep_speed"));
      if (k["sleep_time"]) cs.sleep_time = non_negative(k["sleep_time"], kc.child("sleep_time"));
      if (k["continuous"]) cs.continuous = boolean(k["continuous"], kc.child("continuous"));
      if (k["compound_shapes"])
        cs.compound_shapes = whole(k["compound_shapes"], kc.child("compound_shapes"), 0, 1000000000);
    }
    if (sim["duration"]) s.duration = positive(sim["duration"], c.child("duration"));
    if (sim["timestep"]) s.timestep = positive(sim["timestep"], c.child("timestep"));
    if (sim["gravity"]) s.gravity = vec<3>(sim["gravity"], c.child("gravity")), s.gravity_given = true;
    if (sim["integrator"]) s.integrator = integrator(sim["integrator"], c.child("integrator"));
    if (s.timestep > s.duration) c.child("timestep").fail(sim["timestep"], "is longer than the duration");
    // The step count must be a number a run can count to (4.9e-324 made it infinite: zero steps).
    if (!(s.duration / s.timestep < 9007199254740992.0))
      c.child("timestep")
          .fail(sim["timestep"] ? sim["timestep"] : sim,
                "makes duration / timestep = " + std::to_string(s.duration / s.timestep) +
                    " steps, more than any run can count (2^53)");
  }
  if (const YAML::Node v = root["video"]) {
    const Ctx c = top.child("video");
    check_keys(v, c, {"width", "height", "fps"});
    if (v["width"]) s.video.width = whole(v["width"], c.child("width"), 16, 16384);
    if (v["height"]) s.video.height = whole(v["height"], c.child("height"), 16, 16384);
    if (v["fps"]) s.video.fps = positive(v["fps"], c.child("fps"));
  }
  if (const YAML::Node cam = root["camera"]) {
    const Ctx c = top.child("camera");
    s.camera_given = true;
    check_keys(cam, c,
               {"position", "look_at", "up", "fov", "follow", "auto", "frame", "path", "orbit", "aim"});
    if (cam["auto"]) s.camera.fit = boolean(cam["auto"], c.child("auto"));
    if (cam["position"]) s.camera.position = vec<3>(cam["position"], c.child("position"));
    if (cam["look_at"]) s.camera.look_at = vec<3>(cam["look_at"], c.child("look_at"));
    if (cam["up"]) s.camera.up = vec<3>(cam["up"], c.child("up"));
    if (cam["fov"]) {
      s.camera.fov = positive(cam["fov"], c.child("fov"));
      if (s.camera.fov >= 179) c.child("fov").fail(cam["fov"], "must be below 179 degrees");
    }
    if (cam["follow"])
      s.camera.follow = camera_follow(cam["follow"], c.child("follow"), s.camera.follow_damping);
    if (cam["frame"]) s.camera.frame_body = camera_frame_body(cam["frame"], c.child("frame"));
    if (!s.camera.follow.empty() && !s.camera.frame_body.empty())
      c.child("follow").fail(cam["follow"],
                             "a camera riding in a body's frame does not also follow one: give one");
    if (const YAML::Node a = cam["aim"]) {
      const Ctx ca = c.child("aim");
      if (a.IsScalar()) {
        s.camera.aim.push_back(text(a, ca));
      } else if (a.IsSequence() && a.size() > 0) {
        for (size_t i = 0; i < a.size(); ++i) s.camera.aim.push_back(text(a[i], ca.index(i)));
      } else {
        ca.fail(a, "expected a body name or a list of them, got " + show(a));
      }
      if (!s.camera.follow.empty())
        ca.fail(a,
                "a camera that follows a body moves with it; one that aims turns to it from where it is: "
                "give one");
      if (s.camera.fit) ca.fail(a, "camera.auto places a still camera aimed at everything: give one");
    }
    if (s.camera.fit && !s.camera.frame_body.empty())
      c.child("auto").fail(
          cam["auto"], "camera.auto frames the world: a camera riding in a body's frame is placed by hand");
    if ((s.camera.position - s.camera.look_at).norm() == 0)
      c.child("look_at").fail(cam["look_at"], "coincides with the camera position");
    if (s.camera.up.cross(s.camera.position - s.camera.look_at).norm() == 0)
      c.child("up").fail(cam["up"] ? cam["up"] : cam, "is parallel to the viewing direction (or zero)");
  }
  // The drawn ground's look, from `ground:` or `render.ground:`: a checker colour pair, or an image
  // (beside the scene, or as given) repeating every `texture_size` m.
  auto ground_look = [&](const YAML::Node& g, const Ctx& gc) {
    if (g["colors"] || g["texture"] || g["tile"]) s.look_given = true;
    if (const YAML::Node cs = g["colors"]) {
      const Ctx cc = gc.child("colors");
      if (!cs.IsSequence() || cs.size() != 2)
        cc.fail(cs, "expected two colours [[r, g, b], [r, g, b]] (the checker's two tiles), got " + show(cs));
      s.render.ground_color = color(cs[0], cc.index(0));
      s.render.ground_color2 = color(cs[1], cc.index(1));
    }
    if (g["texture"]) {
      const std::string f = text(g["texture"], gc.child("texture"));
      const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : fs::path(path).parent_path() / f;
      std::error_code ec;
      if (!fs::is_regular_file(p, ec))
        gc.child("texture").fail(g["texture"], "image '" + f + "' not found (looked for " +
                                                   fs::absolute(p, ec).lexically_normal().string() + ")");
      s.render.ground_texture = p.lexically_normal().string();
      s.inputs.push_back(s.render.ground_texture);
    }
    if (g["texture_size"]) {
      if (!g["texture"]) gc.child("texture_size").fail(g["texture_size"], "applies with 'texture' only");
      s.render.ground_texture_size = positive(g["texture_size"], gc.child("texture_size"));
    }
  };
  if (const YAML::Node r = root["render"]) {
    const Ctx c = top.child("render");
    check_keys(
        r, c,
        {"shadows", "antialiasing", "background", "horizon", "sky", "quality", "ground", "motion_blur"});
    if (r["motion_blur"]) s.motion_blur = motion_blur(r["motion_blur"], c.child("motion_blur"));
    if (r["sky"] || r["background"] || r["horizon"]) s.look_given = true;
    if (r["sky"]) {
      const std::string k = text(r["sky"], c.child("sky"));
      if (k != "gradient" && k != "flat")
        c.child("sky").fail(r["sky"], "unknown sky '" + k + "' (gradient, flat)");
      s.render.sky_gradient = k == "gradient";
    }
    if (r["horizon"]) s.render.horizon = color(r["horizon"], c.child("horizon"));
    if (r["quality"]) {
      const std::string q = text(r["quality"], c.child("quality"));
      if (q != "standard" && q != "high")
        c.child("quality").fail(r["quality"], "unknown quality '" + q + "' (standard, high)");
      s.render.quality = q == "high" ? RenderQuality::high : RenderQuality::standard;
    }
    if (r["shadows"]) s.render.shadows = boolean(r["shadows"], c.child("shadows"));
    if (r["antialiasing"]) {
      const Ctx ac = c.child("antialiasing");
      const std::string name = text(r["antialiasing"], ac);
      const auto a = antialiasing_from_name(name);
      if (!a) ac.fail(r["antialiasing"], "unknown anti-aliasing '" + name + "' (fxaa, msaa2, msaa4, none)");
      s.render.antialiasing = *a;
    }
    if (r["background"]) s.render.background = color(r["background"], c.child("background"));
    if (const YAML::Node g = r["ground"]) {
      const Ctx gc = c.child("ground");
      if (root["ground"])
        gc.fail(g,
                "the top-level 'ground' already draws the ground (and collides): give one of them, "
                "'ground' for a floor things land on, 'render.ground' for a drawing only");
      if (g.IsScalar()) {
        s.render.ground = boolean(g, gc);
      } else {
        check_keys(g, gc, {"height", "size", "tile", "colors", "texture", "texture_size"});
        ground_look(g, gc);
        s.render.ground = true;
        if (g["height"]) s.render.ground_height = number(g["height"], gc.child("height"));
        if (g["size"]) s.render.ground_size = positive(g["size"], gc.child("size"));
        if (g["tile"]) s.render.ground_tile = positive(g["tile"], gc.child("tile"));
      }
    }
  }
  if (const YAML::Node g = root["ground"]) {
    const Ctx gc = top.child("ground");
    bool on = true;
    GroundSpec gs;
    if (g.IsScalar()) {
      on = boolean(g, gc);
    } else {
      check_keys(g, gc,
                 {"height", "friction", "restitution", "size", "tile", "colors", "texture", "texture_size"});
      ground_look(g, gc);
      if (g["height"]) gs.height = number(g["height"], gc.child("height"));
      if (g["friction"]) gs.friction = non_negative(g["friction"], gc.child("friction"));
      if (g["restitution"]) gs.restitution = unit_interval(g["restitution"], gc.child("restitution"));
      if (g["size"]) gs.size = positive(g["size"], gc.child("size"));
      if (g["tile"]) gs.tile = positive(g["tile"], gc.child("tile"));
    }
    if (on) {
      s.ground = gs;
      s.render.ground = true;
      s.render.ground_height = gs.height;
      s.render.ground_size = gs.size;
      s.render.ground_tile = gs.tile;
    }
  }
  // `bodies` may be left out (or empty) when `imports` places the bodies.
  const YAML::Node bodies = root["bodies"]    ? root["bodies"]
                            : root["imports"] ? YAML::Node(YAML::NodeType::Sequence)
                                              : root["bodies"];
  if (!bodies) top.fail(root, "missing key 'bodies' (a list of bodies) or 'imports' (robot files)");
  if (!bodies.IsSequence() || (bodies.size() == 0 && !root["imports"]))
    top.child("bodies").fail(bodies, "expected a non-empty list of bodies, got " + show(bodies));
  MeshLibrary library(s.notes);
  Loader L{s, fs::path(path).parent_path(), fs::path("assets"), library, {}, {}, {}};
  // Assets next to the scene's folder (scenes/../assets) as well as the working directory's.
  const fs::path up_assets = fs::path(path).parent_path().parent_path() / "assets";
  if (fs::is_directory(up_assets, ec)) L.assets = up_assets;
  // Limits of one scene, named in the message (a scene past them is a mistake or an attack: a
  // 64 KB file of YAML aliases could stand for millions of bodies).
  constexpr size_t kMaxBodies = 100000, kMaxColliders = 1000000;
  if (bodies.size() > kMaxBodies)
    top.child("bodies").fail(bodies, std::to_string(bodies.size()) + " bodies: a scene holds at most " +
                                         std::to_string(kMaxBodies));
  size_t colliders = 0;
  for (size_t i = 0; i < bodies.size(); ++i)
    if (const YAML::Node cs = bodies[i].IsMap() ? bodies[i]["colliders"] : YAML::Node();
        cs && cs.IsSequence()) {
      colliders += cs.size();
      if (colliders > kMaxColliders)
        top.child("bodies")
            .index(i)
            .child("colliders")
            .fail(cs, "more than " + std::to_string(kMaxColliders) +
                          " colliders in the scene: a scene holds at most " + std::to_string(kMaxColliders));
    }
  std::set<std::string> names;
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Ctx c = top.child("bodies").index(i);
    s.looks.emplace_back();
    s.bodies.push_back(L.body(bodies[i], c, i, s.looks.back()));
    if (!names.insert(s.bodies.back().name).second)
      c.child("name").fail(bodies[i]["name"], "another body is already named '" + s.bodies.back().name + "'");
  }
  if (L.mesh_errors.size() == 1) throw InputError(L.mesh_errors[0]);
  if (!L.mesh_errors.empty()) {
    std::string msg = std::to_string(L.mesh_errors.size()) + " meshes cannot be weighed as they are:";
    for (const std::string& e : L.mesh_errors) msg += "\n  " + e;
    throw InputError(msg);
  }
  // Imported robots and rigs after the scene's own bodies (app/scene/scene_imports.cpp).
  if (root["imports"]) {
    load_imports(root["imports"], path, s, library);
    for (size_t i = bodies.size(); i < s.bodies.size(); ++i) names.insert(s.bodies[i].name);
    // A file whose contacts bounce (MJCF's solref) was written for an engine that bounces at any
    // speed; below the default threshold (1 m/s) a cradle's 0.6 m/s impacts would stick. Unless the
    // scene sets its own, the threshold drops to what the cradle demos use.
    constexpr double kImportedThreshold = 0.05;  // m/s
    bool bounces = false;
    for (size_t i = bodies.size(); i < s.bodies.size(); ++i)
      for (const Collider& col : s.bodies[i].colliders)
        bounces = bounces || (col.collide && col.restitution > 0);
    if (bounces && !s.restitution_threshold_given && s.contacts.restitution_threshold > kImportedThreshold) {
      s.contacts.restitution_threshold = kImportedThreshold;
      s.notes.push_back(
          "simulation.contacts.restitution_threshold set to 0.05 m/s: an imported file's contacts bounce "
          "(restitution from solref), at any speed in the engine it was written for; set the key to choose");
    }
  }
  if (s.ground) {  // the ground body comes last: the scene's own bodies keep their indices
    if (names.count("ground")) {
      for (size_t i = 0; i < bodies.size(); ++i)
        if (s.bodies[i].name == "ground")
          top.child("bodies").index(i).child("name").fail(
              bodies[i]["name"],
              "the top-level 'ground' makes a static body named 'ground': rename this one");
      top.child("imports").fail(root["imports"],
                                "an imported link is named 'ground', as the top-level 'ground' body is: "
                                "give the import a `name`");
    }
    names.insert("ground");
    BodyDef g;
    g.name = "ground";
    g.type = BodyType::static_body;
    Collider plane;
    plane.shape = ShapeKind::plane;
    plane.p_BC = Vec3(0, 0, s.ground->height);
    plane.friction = s.ground->friction;
    plane.restitution = s.ground->restitution;
    plane.props_C.mass = 0;
    plane.props_C.inertia = Mat3::Zero();
    plane.label = "plane (ground)";
    g.add_collider(std::move(plane));
    s.bodies.push_back(std::move(g));
    BodyLook look;
    look.drawn = false;  // the renderer's checkered ground draws it
    look.colliders.resize(1);
    s.looks.push_back(look);
  }
  apply_placements(bodies, path, s, s.gravity);
  if (root["simulation"] && root["simulation"]["ignore_pairs"]) {
    const YAML::Node ip = root["simulation"]["ignore_pairs"];
    const Ctx c = top.child("simulation").child("ignore_pairs");
    if (!ip.IsSequence())
      c.fail(ip, "expected a list of body name pairs like [[a, b], [c, d]], got " + show(ip));
    std::vector<std::string> all;
    for (const BodyDef& b : s.bodies) all.push_back(b.name);
    for (size_t k = 0; k < ip.size(); ++k) {
      const Ctx pc = c.index(k);
      const YAML::Node p = ip[k];
      if (!p.IsSequence() || p.size() != 2)
        pc.fail(p, "expected a pair of body names [a, b], got " +
                       (p.IsSequence() ? "a list of " + std::to_string(p.size()) : show(p)));
      int idx[2];
      for (int j = 0; j < 2; ++j) {
        const std::string name = text(p[j], pc.index(j));
        const auto f = std::find(all.begin(), all.end(), name);
        if (f == all.end()) {
          std::string msg = "no body is named '" + name + "'";
          if (auto sug = nearest(name, all)) msg += "; did you mean '" + *sug + "'?";
          pc.index(j).fail(p[j], msg);
        }
        idx[j] = (int)(f - all.begin());
      }
      if (idx[0] == idx[1]) pc.fail(p, "names the same body twice (a body never collides with itself)");
      s.ignore_pairs.emplace_back(std::min(idx[0], idx[1]), std::max(idx[0], idx[1]));
    }
  }
  if (root["forces"]) s.forces = load_forces(root["forces"], path, s.bodies, s.duration, s.notes);
  if (root["joints"]) s.joints = load_joints(root["joints"], path, s.bodies, s.notes);
  if (!s.camera.follow.empty() && !names.count(s.camera.follow))
    top.child("camera").child("follow").fail(root["camera"]["follow"],
                                             "no body is named '" + s.camera.follow + "'");
  for (size_t i = 0; i < s.camera.aim.size(); ++i)
    if (!names.count(s.camera.aim[i])) {
      const YAML::Node a = root["camera"]["aim"];
      const Ctx ca = top.child("camera").child("aim");
      if (a.IsSequence())
        ca.index(i).fail(a[i], "no body is named '" + s.camera.aim[i] + "'");
      else
        ca.fail(a, "no body is named '" + s.camera.aim[i] + "'");
    }
  if (!s.camera.frame_body.empty() && !names.count(s.camera.frame_body))
    top.child("camera").child("frame").child("body").fail(root["camera"]["frame"],
                                                          "no body is named '" + s.camera.frame_body + "'");
  // app/scene/scene_camera.cpp: camera.path and camera.orbit, once the bodies are known
  load_camera_motion(root, path, s);
  check_ghosts(root, path, s);  // app/scene/ghost.cpp: only where a closed form exists
  load_time(root, path, s);     // app/scene/scene_time.cpp
  load_views(root, path, s);    // app/scene/scene_views.cpp: variants and panes
  if (const YAML::Node t = root["test"]) {
    const Ctx c = top.child("test");
    check_keys(t, c, {"frames", "width", "height"});
    if (t["width"]) s.test.width = whole(t["width"], c.child("width"), 16, 16384);
    if (t["height"]) s.test.height = whole(t["height"], c.child("height"), 16, 16384);
    if (t["frames"]) {
      s.test.frames = text(t["frames"], c.child("frames"));
      try {
        parse_frame_spec(s.test.frames, plan_frames(s.duration, s.timestep, s.video.fps), s.video.fps,
                         s.timestep, s.duration);
      } catch (const std::invalid_argument& e) {
        c.child("frames").fail(t["frames"], e.what());
      }
    }
  }
  load_overlays(root, path, s);  // bodies' show: and overlays: (app/scene/scene_overlays.cpp)
  for (const std::string& f : library.files()) s.inputs.push_back(f);
  std::sort(s.inputs.begin(), s.inputs.end());
  s.inputs.erase(std::unique(s.inputs.begin(), s.inputs.end()), s.inputs.end());
  return s;
}

}  // namespace simreel
