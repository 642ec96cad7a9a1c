#include "app/import/mjcf.hpp"

#include "app/import/heightfield.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>

#include <simreel/error.hpp>
#include "app/import/xml_util.hpp"
#include "sim/geometry/convex_hull.hpp"

namespace simreel {

namespace fs = std::filesystem;
using namespace xml;
using tinyxml2::XMLElement;

namespace {

// Elements MuJoCo knows that describe no body, shape, joint or look simreel draws: skipped with
// one note each (what they drive: actuators, sensors, tendons, ...).
const std::set<std::string> kUnused = {
    "option",   "size",   "visual",   "statistic", "extension", "custom",     "contact",  "tendon",
    "actuator", "sensor", "keyframe", "light",     "camera",    "deformable", "flexcomp", "composite",
    "plugin",   "skin",   "hfield",   "numeric",   "text",      "tuple"};

// MJCF's attributes per element (MuJoCo 3.x): read here or knowingly unused. Anything else is a
// note (a typo, or an attribute newer than this list), never an error.
const std::map<std::string, std::set<std::string>> kAttributes = {
    {"body",
     {"name", "childclass", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mocap", "gravcomp",
      "user", "sleep"}},
    {"joint",
     {"name",
      "class",
      "type",
      "group",
      "pos",
      "axis",
      "springdamper",
      "solreflimit",
      "solimplimit",
      "solreffriction",
      "solimpfriction",
      "stiffness",
      "range",
      "limited",
      "actuatorfrclimited",
      "actuatorfrcrange",
      "actuatorgravcomp",
      "margin",
      "ref",
      "springref",
      "armature",
      "damping",
      "frictionloss",
      "user"}},
    {"freejoint", {"name", "group", "align"}},
    {"hfield", {"name", "content_type", "file", "nrow", "ncol", "elevation", "size"}},
    {"camera", {"name",   "class",      "mode",      "target",         "pos",          "quat", "axisangle",
                "xyaxes", "zaxis",      "euler",     "fovy",           "orthographic", "ipd",  "resolution",
                "focal",  "focalpixel", "principal", "principalpixel", "sensorsize",   "user"}},
    {"geom", {"name",         "class",    "type",       "contype",   "conaffinity", "condim", "group",
              "priority",     "size",     "material",   "rgba",      "friction",    "mass",   "density",
              "shellinertia", "solmix",   "solref",     "solimp",    "margin",      "gap",    "fromto",
              "pos",          "quat",     "axisangle",  "xyaxes",    "zaxis",       "euler",  "hfield",
              "mesh",         "fitscale", "fluidshape", "fluidcoef", "user"}},
    {"inertial",
     {"pos", "quat", "axisangle", "xyaxes", "zaxis", "euler", "mass", "diaginertia", "fullinertia"}},
};

struct MjMaterial {
  std::optional<std::array<float, 4>> rgba;
  std::string texture;      // texture asset name
  double texrepeat = 1;     // repeats of the texture image (along its first axis)
  bool texuniform = false;  // texrepeat per metre, not across the object
};
// A built-in 2D checker texture: a 2x2 image of squares in rgb1 and rgb2 (MuJoCo's `checker`).
struct MjChecker {
  std::array<float, 3> rgb1{0.8f, 0.8f, 0.8f}, rgb2{0.5f, 0.5f, 0.5f};
};
struct MjMesh {
  std::string file;  // resolved
  Vec3 scale = Vec3::Ones();
  std::shared_ptr<const TriangleMesh> inline_mesh;
};

class MjcfReader {
 public:
  MjcfReader(const std::string& path, const ImportPaths& paths) : path_(path), paths_(paths) {}

  Model read() {
    const std::string text = read_text(path_);
    parse_xml(doc_, text, path_);
    XMLElement* root = doc_.RootElement();
    if (!root || std::string(root->Name()) != "mujoco")
      throw InputError(path_ + ":" + std::to_string(root ? root->GetLineNum() : 1) +
                       ": expected a <mujoco> element at the top of an MJCF file, found <" +
                       (root ? root->Name() : "nothing") + ">");
    expand_includes(root, fs::path(path_).parent_path(), 0);
    m_.file = path_;
    m_.files.insert(m_.files.begin(), path_);
    m_.format = "mjcf";
    m_.name = attr_or(root, "model", fs::path(path_).stem().string());
    const fs::path dir = fs::path(path_).parent_path();
    meshdir_ = texturedir_ = dir;
    for (XMLElement* c = root->FirstChildElement("compiler"); c; c = c->NextSiblingElement("compiler"))
      compiler(c, dir);
    for (XMLElement* d = root->FirstChildElement("default"); d; d = d->NextSiblingElement("default"))
      defaults(d, "main", "");
    for (XMLElement* a = root->FirstChildElement("asset"); a; a = a->NextSiblingElement("asset")) assets(a);
    std::set<std::string> noted;
    for (XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "compiler" || tag == "default" || tag == "asset" || tag == "worldbody" ||
          tag == "equality" || tag == "contact" || tag == "actuator" || tag == "tendon")
        continue;
      if (tag == "option") {
        option(e);
        continue;
      }
      if (tag == "keyframe") {
        keyframe(e);
        continue;
      }
      if (noted.insert(tag).second)
        note(e, "<" + tag + "> is " +
                    (kUnused.count(tag) ? "not used by simreel" : "not an MJCF element simreel knows") +
                    "; ignored");
    }
    for (XMLElement* w = root->FirstChildElement("worldbody"); w; w = w->NextSiblingElement("worldbody"))
      worldbody(w);
    resolve_camera_targets();
    for (const auto& [link, e] : hfield_links_)  // every joint is read by now
      for (int l = link; l >= 0; l = link_parent_[l]) {
        // Welded to its parent (or to the world) or not: a free body has no joint of its own.
        const auto j = std::find_if(m_.joints.begin(), m_.joints.end(),
                                    [&](const ModelJoint& x) { return x.child == l && !x.loop; });
        if (j == m_.joints.end() || j->kind != ModelJoint::Kind::fixed)
          fail(e, "geom of body '" + m_.links[link].name + "'",
               "an hfield geom must be on a static body (MuJoCo's rule): '" + m_.links[l].name + "' moves");
      }
    for (XMLElement* q = root->FirstChildElement("equality"); q; q = q->NextSiblingElement("equality"))
      equality(q);
    for (XMLElement* q = root->FirstChildElement("contact"); q; q = q->NextSiblingElement("contact"))
      contact(q);
    for (XMLElement* t = root->FirstChildElement("tendon"); t; t = t->NextSiblingElement("tendon"))
      for (const XMLElement* e = t->FirstChildElement(); e; e = e->NextSiblingElement())
        for (const std::string& v : variants(e)) {
          suffix_ = v;
          tendon(e);
        }
    suffix_.clear();
    for (XMLElement* a = root->FirstChildElement("actuator"); a; a = a->NextSiblingElement("actuator"))
      actuators(a);
    return std::move(m_);
  }

 private:
  std::string path_;
  const ImportPaths& paths_;
  tinyxml2::XMLDocument doc_;
  std::vector<std::unique_ptr<tinyxml2::XMLDocument>> included_;
  std::map<const tinyxml2::XMLNode*, std::string> origin_;  // an included element: its file
  Model m_;
  bool degrees_ = true;
  std::string eulerseq_ = "xyz";
  fs::path meshdir_, texturedir_;
  // Default classes: parent class, and per element tag the prototype element.
  std::map<std::string, std::string> class_parent_;
  std::map<std::string, std::map<std::string, const XMLElement*>> class_proto_;
  std::map<std::string, MjMaterial> materials_;
  std::map<std::string, std::string> textures_;  // name -> resolved file
  std::map<std::string, MjChecker> checkers_;    // name -> built-in checker
  double plane_half_ = 0;                        // the plane geom being read: its size[0], m
  std::map<std::string, MjMesh> meshes_;
  std::map<std::string, int> body_index_;
  std::map<int, double> actuator_cap_;  // joint index: its actuatorfrcrange bound
  std::vector<int> link_parent_;        // per link: the link it hangs from (-1: the world)
  struct Site {
    int link = -1;
    ModelPose pose;  // in the link's frame
  };
  std::map<std::string, Site> sites_;
  // Per name defined inside a <replicate>: the copies' suffixes, in order (bodies, sites, joints).
  std::map<std::string, std::vector<std::string>> copies_;
  std::set<std::string> noted_;

  // ---- where things come from
  std::string file_of(const tinyxml2::XMLNode* e) const {
    for (const tinyxml2::XMLNode* n = e; n; n = n->Parent())
      if (auto it = origin_.find(n); it != origin_.end()) return it->second;
    return path_;
  }
  SourceRef src(const XMLElement* e, const std::string& what) const {
    return {file_of(e), e->GetLineNum(), what};
  }
  [[noreturn]] void fail(const XMLElement* e, const std::string& what, const std::string& msg) const {
    throw InputError(src(e, what).str() + ": " + msg);
  }
  // The entry `n` of a name map (bodies, sites), or an error naming the attribute `key` and the
  // nearest name the file defines.
  template <class Map>
  const typename Map::mapped_type& named(const XMLElement* e, const std::string& what, const Map& m,
                                         const char* key, const char* n, const char* kind) const {
    const auto it = m.find(n);
    if (it == m.end()) {
      std::vector<std::string> names;
      for (const auto& [k, v] : m) names.push_back(k);
      std::string msg = std::string(key) + " names " + kind + " '" + n + "', which the file does not define";
      if (auto sn = nearest_name(n, names)) msg += "; did you mean '" + *sn + "'?";
      fail(e, what, msg);
    }
    return it->second;
  }
  void note(const XMLElement* e, const std::string& msg, const std::string& what = "") {
    m_.notes.push_back(src(e, what).str() + ": " + msg);
  }
  void note_once(const XMLElement* e, const std::string& key, const std::string& msg) {
    if (noted_.insert(key).second) note(e, msg);
  }
  // An attribute MJCF does not have on this element: a note (once per element and attribute).
  void check_attributes(const XMLElement* e) {
    const auto known = kAttributes.find(e->Name());
    if (known == kAttributes.end()) return;
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
      if (!known->second.count(a->Name()))
        note_once(e, std::string(e->Name()) + "@" + a->Name(),
                  std::string("<") + e->Name() + "> has no attribute '" + a->Name() +
                      "' that simreel knows; ignored");
  }

  void expand_includes(XMLElement* parent, const fs::path& dir, int depth) {
    for (XMLElement* e = parent->FirstChildElement(); e;) {
      XMLElement* next = e->NextSiblingElement();
      if (std::string(e->Name()) == "include") {
        if (depth > 16) fail(e, "include", "includes nest more than 16 deep (a file including itself?)");
        const std::string f = attr_or(e, "file", "");
        if (f.empty()) fail(e, "include", "<include> needs a file");
        const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec))
          fail(e, "include",
               "file '" + f + "' not found (looked for " + fs::absolute(p, ec).lexically_normal().string() +
                   ")");
        auto doc = std::make_unique<tinyxml2::XMLDocument>();
        parse_xml(*doc, read_text(p.string()), p.string());
        m_.files.push_back(p.lexically_normal().string());
        XMLElement* inc_root = doc->RootElement();
        if (!inc_root || std::string(inc_root->Name()) != "mujoco")
          fail(e, "include", "'" + f + "' has no <mujoco> element at its top");
        expand_includes(inc_root, p.parent_path(), depth + 1);
        tinyxml2::XMLNode* after = e;
        for (XMLElement* c = inc_root->FirstChildElement(); c; c = c->NextSiblingElement()) {
          tinyxml2::XMLNode* copy = c->DeepClone(&doc_);
          parent->InsertAfterChild(after, copy);
          origin_[copy] = file_of(c) == path_ ? p.lexically_normal().string() : file_of(c);
          after = copy;
        }
        parent->DeleteChild(e);
        included_.push_back(std::move(doc));
      } else {
        expand_includes(e, dir, depth);
      }
      e = next;
    }
  }

  // <option>: its gravity is the model's (the scene's when the file is simulated directly);
  // simreel chooses its own steps and integrators, and has no medium (wind, density, viscosity).
  void option(const XMLElement* o) {
    if (auto g = vec<3>(o, "gravity", "", "option")) {
      if (!g->allFinite()) fail(o, "option", "gravity must be three finite numbers (m/s^2)");
      m_.gravity = *g;
    }
    for (const tinyxml2::XMLAttribute* a = o->FirstAttribute(); a; a = a->Next()) {
      const std::string n = a->Name();
      if (n == "gravity") continue;
      note(o, n == "timestep" || n == "integrator"
                  ? "<option " + n +
                        "> is not used: simreel takes its own steps (simulation.timestep, integrator)"
                  : "<option " + n + "> is not used by simreel; ignored");
    }
    if (o->FirstChildElement())
      note(o, "<option>'s <flag> and other children are not used by simreel; ignored");
  }

  // <keyframe>: each <key>'s qpos (MuJoCo's internal units: rad and m whatever the compiler's
  // angle), applied on import by name (imports: keyframe); its velocities, activations and
  // controls are notes.
  void keyframe(const XMLElement* k) {
    for (const XMLElement* e = k->FirstChildElement(); e; e = e->NextSiblingElement()) {
      if (std::string(e->Name()) != "key") {
        note(e, std::string("<") + e->Name() + "> in <keyframe> is not an MJCF key; ignored");
        continue;
      }
      Model::Key key;
      key.name = attr_or(e, "name", "key" + std::to_string(m_.keys.size()));
      key.src = src(e, "key '" + key.name + "'");
      if (auto q = nums(e, "qpos", "", "key '" + key.name + "'")) key.qpos = *q;
      for (const char* a : {"qvel", "act", "ctrl", "mpos", "mquat"})
        if (e->Attribute(a))
          note_once(e, std::string("key-") + a, std::string("a key's ") + a + " is not used (its qpos is)");
      m_.keys.push_back(std::move(key));
    }
  }

  void compiler(const XMLElement* c, const fs::path& dir) {
    const std::string angle = attr_or(c, "angle", "degree");
    if (angle != "degree" && angle != "radian")
      fail(c, "compiler", "angle must be degree or radian, got '" + angle + "'");
    degrees_ = angle == "degree";
    eulerseq_ = attr_or(c, "eulerseq", eulerseq_);
    if (eulerseq_.size() != 3 || eulerseq_.find_first_not_of("xyzXYZ") != std::string::npos)
      fail(c, "compiler",
           "eulerseq must be three of x, y, z (lower case: moving axes, upper: fixed), got '" + eulerseq_ +
               "'");
    const std::string asset = attr_or(c, "assetdir", "");
    if (!asset.empty()) meshdir_ = texturedir_ = dir / asset;
    if (c->Attribute("meshdir")) meshdir_ = dir / c->Attribute("meshdir");
    if (c->Attribute("texturedir")) texturedir_ = dir / c->Attribute("texturedir");
    for (const char* a : {"coordinate"})
      if (c->Attribute(a) && std::string(c->Attribute(a)) == "global")
        fail(c, "compiler",
             "coordinate=\"global\" (MuJoCo 1.x) is not read: convert the file to local coordinates");
  }

  // ---- default classes
  void defaults(const XMLElement* d, const std::string& name, const std::string& parent) {
    class_parent_[name] = parent;
    for (const XMLElement* c = d->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "default") {
        const std::string child = attr_or(c, "class", "");
        if (child.empty()) fail(c, "default", "a nested <default> needs a class name");
        defaults(c, child, name);
      } else {
        class_proto_[name][tag] = c;
      }
    }
  }
  // An attribute of `e` (tag `tag`): its own, else its class's default, else the class's parents'.
  // `tag`: the element whose defaults apply, when not e's own (a <spatial> tendon's are <tendon>).
  const char* get(const XMLElement* e, const char* key, const std::string& cls,
                  const char* tag = nullptr) const {
    if (const char* v = e->Attribute(key)) return v;
    for (std::string c = cls; !c.empty();) {
      const auto p = class_proto_.find(c);
      if (p != class_proto_.end()) {
        const auto t = p->second.find(tag ? tag : e->Name());
        if (t != p->second.end())
          if (const char* v = t->second->Attribute(key)) return v;
      }
      const auto up = class_parent_.find(c);
      c = up == class_parent_.end() ? "" : up->second;
    }
    return nullptr;
  }
  std::string class_of(const XMLElement* e, const std::string& childclass,
                       const std::string& what = "") const {
    if (const char* c = e->Attribute("class")) {
      if (!class_parent_.count(c)) {
        std::vector<std::string> names;
        for (const auto& [n, p] : class_parent_) names.push_back(n);
        std::string msg = std::string("class '") + c + "' is not defined";
        if (auto s = nearest_name(c, names)) msg += "; did you mean '" + *s + "'?";
        fail(e, what.empty() ? std::string(e->Name()) : what, msg);
      }
      return c;
    }
    return childclass.empty() ? "main" : childclass;
  }
  // Numbers of an attribute through the defaults; nullopt when absent.
  std::optional<std::vector<double>> nums(const XMLElement* e, const char* key, const std::string& cls,
                                          const std::string& what) const {
    const char* v = get(e, key, cls);
    if (!v) return std::nullopt;
    // The text may come from a default class: the message names this element's line.
    auto out = parse_numbers(v);
    if (!out) fail(e, what, std::string("<") + e->Name() + " " + key + "=\"" + v + "\">: expected numbers");
    return out;
  }
  template <int N>
  std::optional<Eigen::Matrix<double, N, 1>> vec(const XMLElement* e, const char* key, const std::string& cls,
                                                 const std::string& what) const {
    const auto v = nums(e, key, cls, what);
    if (!v) return std::nullopt;
    if ((int)v->size() != N)
      fail(e, what,
           std::string("<") + e->Name() + " " + key + ">: expected " + std::to_string(N) + " numbers, got " +
               std::to_string(v->size()));
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) out[i] = (*v)[i];
    return out;
  }
  double angle(double a) const { return degrees_ ? a * M_PI / 180 : a; }

  // A frame's orientation: quat, axisangle, euler, xyaxes or zaxis (at most one).
  Quat orientation(const XMLElement* e, const std::string& cls, const std::string& what) const {
    int given = 0;
    Quat q = Quat::Identity();
    if (auto v = vec<4>(e, "quat", cls, what)) {
      ++given;
      if (!(v->norm() > 0)) fail(e, what, "quat must not be zero");
      q = Quat((*v)[0], (*v)[1], (*v)[2], (*v)[3]).normalized();
    }
    if (auto v = vec<4>(e, "axisangle", cls, what)) {
      ++given;
      const Vec3 a = v->head<3>();
      if (!(a.norm() > 0)) fail(e, what, "axisangle's axis must not be zero");
      q = Quat(Eigen::AngleAxisd(angle((*v)[3]), a.normalized()));
    }
    if (auto v = vec<3>(e, "euler", cls, what)) {
      ++given;
      q = Quat::Identity();
      for (int i = 0; i < 3; ++i) {
        const char c = eulerseq_[i];
        const Vec3 axis = Vec3::Unit(std::tolower(c) - 'x');
        const Quat r(Eigen::AngleAxisd(angle((*v)[i]), axis));
        q = std::islower(c) ? q * r : r * q;  // moving axes: intrinsic; fixed axes: extrinsic
      }
    }
    if (auto v = nums(e, "xyaxes", cls, what)) {
      ++given;
      if (v->size() != 6) fail(e, what, "xyaxes needs 6 numbers");
      Vec3 x((*v)[0], (*v)[1], (*v)[2]), y((*v)[3], (*v)[4], (*v)[5]);
      if (!(x.norm() > 0)) fail(e, what, "xyaxes' x axis must not be zero");
      x.normalize();
      y -= x * x.dot(y);
      if (!(y.norm() > 1e-12)) fail(e, what, "xyaxes' y axis must not be parallel to x");
      y.normalize();
      Mat3 R;
      R << x, y, x.cross(y);
      q = Quat(R).normalized();
    }
    if (auto v = vec<3>(e, "zaxis", cls, what)) {
      ++given;
      if (!(v->norm() > 0)) fail(e, what, "zaxis must not be zero");
      q = Quat::FromTwoVectors(Vec3::UnitZ(), v->normalized());
    }
    if (given > 1) fail(e, what, "give one of quat, axisangle, euler, xyaxes, zaxis");
    return q;
  }
  ModelPose frame(const XMLElement* e, const std::string& cls, const std::string& what) const {
    ModelPose p;
    if (auto v = vec<3>(e, "pos", cls, what)) p.p = *v;
    p.q = orientation(e, cls, what);
    return p;
  }

  // ---- assets
  std::string asset_file(const XMLElement* e, const fs::path& dir, const char* what_kind) {
    const std::string f = attr_or(e, "file", "");
    return resolve_asset(f, dir.string(), file_of(e), paths_, src(e, std::string(what_kind)).str(), what_kind,
                         m_.notes);
  }
  void assets(const XMLElement* a) {
    for (const XMLElement* e = a->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      const std::string cls = class_of(e, "");
      if (tag == "mesh") {
        MjMesh mesh;
        std::string name = attr_or(e, "name", "");
        if (e->Attribute("file")) {
          mesh.file = asset_file(e, meshdir_, "mesh");
          if (name.empty()) name = fs::path(attr_or(e, "file", "")).stem().string();
        } else if (auto v = nums(e, "vertex", cls, "mesh '" + name + "'")) {
          if (v->size() % 3 != 0 || v->size() < 12)
            fail(e, "mesh '" + name + "'", "vertex needs at least 4 points (x y z each)");
          std::vector<Vec3> pts;
          for (size_t i = 0; i + 2 < v->size(); i += 3) pts.emplace_back((*v)[i], (*v)[i + 1], (*v)[i + 2]);
          if (auto s = vec<3>(e, "scale", cls, "mesh"))
            for (Vec3& p : pts) p = p.cwiseProduct(*s);
          if (auto f = nums(e, "face", cls, "mesh '" + name + "'")) {
            // Its own triangles (counter-clockwise from outside, as MuJoCo's): drawn and weighed as
            // the mesh they make; a moving body collides with their convex hull, as MuJoCo's does.
            if (f->empty() || f->size() % 3 != 0)
              fail(e, "mesh '" + name + "'", "face needs vertex indices in threes");
            TriangleMesh tm;
            tm.vertices = pts;
            for (size_t i = 0; i + 2 < f->size(); i += 3) {
              std::array<int, 3> t;
              for (int k = 0; k < 3; ++k) {
                const double x = (*f)[i + k];
                if (x != std::floor(x) || x < 0 || x >= (double)pts.size()) {
                  char num[32];
                  std::snprintf(num, sizeof num, "%g", x);
                  fail(e, "mesh '" + name + "'",
                       std::string("face index ") + num + " is not a vertex (0 to " +
                           std::to_string(pts.size() - 1) + ")");
                }
                t[k] = (int)x;
              }
              tm.triangles.push_back(t);
            }
            mesh.inline_mesh = std::make_shared<const TriangleMesh>(std::move(tm));
          } else {
            try {
              mesh.inline_mesh = std::make_shared<const TriangleMesh>(convex_hull(pts));
            } catch (const InputError& err) {
              fail(e, "mesh '" + name + "'", err.what());
            }
          }
        } else {
          note(e, "a mesh with neither file nor vertex is left out", "mesh '" + name + "'");
          continue;
        }
        if (!mesh.inline_mesh)
          if (auto s = vec<3>(e, "scale", cls, "mesh '" + name + "'")) mesh.scale = *s;
        meshes_[name] = mesh;
      } else if (tag == "texture") {
        const std::string name = attr_or(e, "name", "");
        const std::string type = attr_or(e, "type", "cube");
        const std::string builtin = attr_or(e, "builtin", "");
        // MuJoCo's defaults for a built-in texture's colours.
        auto rgb = [&](const char* key, std::array<float, 3> dflt) {
          if (auto v = vec<3>(e, key, "", "texture"))
            return std::array<float, 3>{(float)(*v)[0], (float)(*v)[1], (float)(*v)[2]};
          return dflt;
        };
        if (e->Attribute("file") && type == "2d") {
          try {
            textures_[name] = asset_file(e, texturedir_, "texture");
          } catch (const InputError& err) {
            m_.notes.push_back(std::string(err.what()) + "; its materials are drawn in their colour");
          }
        } else if (type == "2d" && builtin == "checker") {
          // Drawn where it lies on the floor plane (the scene's ground takes its colours); its
          // marks are lines simreel's ground does not draw.
          checkers_[name] = MjChecker{rgb("rgb1", {0.8f, 0.8f, 0.8f}), rgb("rgb2", {0.5f, 0.5f, 0.5f})};
          if (e->Attribute("mark") && attr_or(e, "mark", "none") != "none")
            note_once(e, "texture-mark", "a built-in texture's mark lines are not drawn");
        } else if (type == "skybox" && builtin == "gradient") {
          m_.sky = ModelSky{rgb("rgb1", {0.8f, 0.8f, 0.8f}), rgb("rgb2", {0.5f, 0.5f, 0.5f})};
        } else if (type == "skybox") {
          note_once(e, "texture-skybox", "a skybox other than a built-in gradient is not drawn");
        } else {
          note_once(
              e, "texture-" + type + (e->Attribute("builtin") ? "-builtin" : ""),
              std::string("a ") + (e->Attribute("builtin") ? "built-in " : "") + type +
                  " texture is not drawn (simreel lays 2D image files through a mesh's texture coordinates); "
                  "its materials are drawn in their colour");
        }
      } else if (tag == "material") {
        MjMaterial mat;
        if (auto v = vec<4>(e, "rgba", cls, "material"))
          mat.rgba = std::array<float, 4>{(float)(*v)[0], (float)(*v)[1], (float)(*v)[2], (float)(*v)[3]};
        if (const char* t = get(e, "texture", cls)) mat.texture = t;
        if (auto r = nums(e, "texrepeat", cls, "material"); r && !r->empty() && (*r)[0] > 0)
          mat.texrepeat = (*r)[0];
        if (const char* u = get(e, "texuniform", cls)) mat.texuniform = std::string(u) == "true";
        materials_[attr_or(e, "name", "")] = mat;
      } else if (tag == "hfield") {
        hfield(e, cls);
      } else if (tag != "skin" && tag != "model" && tag != "plugin") {
        note(e, "<" + tag + "> asset is not used; ignored");
      } else {
        note_once(e, "asset-" + tag, "<" + tag + "> assets are not used by simreel; ignored");
      }
    }
  }

  // A heightfield asset (size = x and y half-sizes, top, base): its elevations from a PNG (grey,
  // the image's top row at +y) or from nrow x ncol `elevation` numbers (MuJoCo 3; row 0 at -y),
  // made into the solid a static body's geom collides with (app/import/heightfield.hpp).
  void hfield(const XMLElement* e, const std::string& cls) {
    const std::string name = attr_or(e, "name", "");
    const std::string what = "hfield '" + name + "'";
    check_attributes(e);
    if (name.empty()) fail(e, "hfield", "needs a name (geoms refer to it)");
    const auto size = nums(e, "size", cls, what);
    if (!size || size->size() != 4) fail(e, what, "size needs 4 numbers (x and y half-sizes, top, base)");
    int nrow = 0, ncol = 0;
    std::vector<double> z;
    if (e->Attribute("file")) {
      const std::string f = asset_file(e, meshdir_, "hfield");
      const std::string ext = fs::path(f).extension().string();
      const bool png = ext == ".png" || ext == ".PNG";
      try {
        // MuJoCo reads a PNG by its extension and any other file as its binary format.
        z = png ? read_heightfield_png(f, nrow, ncol) : read_heightfield_bin(f, nrow, ncol);
      } catch (const InputError& err) {
        fail(e, what, err.what());
      }
    } else if (e->Attribute("elevation")) {
      const auto r = nums(e, "nrow", cls, what), c = nums(e, "ncol", cls, what);
      if (!r || !c || r->size() != 1 || c->size() != 1 || (*r)[0] != std::floor((*r)[0]) ||
          (*c)[0] != std::floor((*c)[0]) || (*r)[0] < 2 || (*c)[0] < 2 || (*r)[0] * (*c)[0] > 1e8)
        fail(e, what, "elevation needs whole nrow and ncol of at least 2");
      nrow = (int)(*r)[0];
      ncol = (int)(*c)[0];
      z = *nums(e, "elevation", cls, what);
    } else {
      note(e, "a heightfield with neither file nor elevation (filled in at run time) is left out", what);
      return;
    }
    try {
      hfields_[name] = std::make_shared<const TriangleMesh>(
          heightfield_mesh(nrow, ncol, z, (*size)[0], (*size)[1], (*size)[2], (*size)[3]));
    } catch (const InputError& err) {
      fail(e, what, err.what());
    }
  }
  std::map<std::string, std::shared_ptr<const TriangleMesh>> hfields_;

  // ---- bodies
  int add_link(const std::string& name, const XMLElement* e, const ModelPose& pose, int parent) {
    link_parent_.push_back(parent);
    ModelLink l;
    l.name = name;
    l.pose = pose;
    l.src = src(e, "body '" + name + "'");
    m_.links.push_back(std::move(l));
    return (int)m_.links.size() - 1;
  }

  // Where an element's children go: a frame inside their body (or the world) that <frame> and
  // <replicate> move them by, and the suffix <replicate> appends to the names they define.
  struct Place {
    ModelPose offset;
    std::string suffix;
  };

  void worldbody(const XMLElement* w) {
    int world_link = -1;  // geoms straight in the world: one static link, made at the first
    children(w, -1, "", Place{}, world_link);
  }

  // The children of the worldbody (link -1) or of a body's link: geoms, sites, bodies, and the
  // <frame>s and <replicate>s that place them (MuJoCo 3). A frame moves its children by its pose
  // (and may set their childclass); a replicate makes `count` copies, copy i moved by the step
  // (offset, euler) i times over, each taken in the previous copy's frame, and its names
  // suffixed with sep and i (as many digits as count - 1 has; an inner replicate's suffix
  // first), as MuJoCo does.
  void children(const XMLElement* parent, int link, const std::string& childclass, const Place& at,
                int& world_link) {
    for (const XMLElement* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "geom") {
        if (link < 0 && world_link < 0) {
          world_link = add_link("world", parent, ModelPose{}, -1);
          ModelJoint j;  // welded to the world
          j.name = "world";
          j.kind = ModelJoint::Kind::fixed;
          j.child = world_link;
          j.src = src(parent, "worldbody");
          m_.joints.push_back(j);
        }
        geom(e, link < 0 ? world_link : link, childclass, at.offset);
      } else if (tag == "body") {
        body(e, link, childclass, at);
      } else if (tag == "site") {
        site(e, link, childclass, at);
      } else if (tag == "camera") {
        camera(e, link, childclass, at);
      } else if (tag == "frame") {
        const std::string cc = e->Attribute("childclass") ? e->Attribute("childclass") : childclass;
        if (!cc.empty() && !class_parent_.count(cc))
          fail(e, "frame", "childclass '" + cc + "' is not defined");
        children(e, link, cc,
                 Place{at.offset * frame(e, class_of(e, childclass, "frame"), "frame"), at.suffix},
                 world_link);
      } else if (tag == "replicate") {
        const auto count = nums(e, "count", "main", "replicate");
        if (!count || count->size() != 1 || !((*count)[0] >= 1) || (*count)[0] != std::floor((*count)[0]))
          fail(e, "replicate", "count must be a positive whole number");
        const int n = (int)(*count)[0];
        ModelPose step;
        if (auto o = vec<3>(e, "offset", "main", "replicate")) step.p = *o;
        if (e->Attribute("euler")) step.q = orientation(e, "main", "replicate");
        const std::string sep = attr_or(e, "sep", "");
        const int digits = (int)std::to_string(n - 1).size();
        ModelPose copy;  // copy i's frame in the replicate's parent: step applied i times
        for (int i = 0; i < n; ++i) {
          std::string index = std::to_string(i);
          index.insert(0, digits - index.size(), '0');
          children(e, link, childclass, Place{at.offset * copy, sep + index + at.suffix}, world_link);
          copy = copy * step;
        }
      } else if (tag == "inertial" && link >= 0) {
        inertial(e, link, "body '" + m_.links[link].name + "'");
      } else if ((tag == "joint" || tag == "freejoint") && link >= 0) {
        continue;  // read with their body
      } else {
        note_once(e, (link < 0 ? "world-" : "body-") + tag, "<" + tag + "> is not used by simreel; ignored");
      }
    }
  }
  // The copies an element outside a <replicate> that names what it copies is made in (MuJoCo
  // copies such an element with them): the suffixes of the copied names it refers to, in its
  // attributes or its children's; one copy, with no suffix, when it names none.
  std::vector<std::string> variants(const XMLElement* e) {
    static const char* kKeys[] = {"body1",  "body2", "site1", "site2", "joint1",
                                  "joint2", "site",  "body",  "joint"};
    const std::vector<std::string>* found = nullptr;
    auto scan = [&](const XMLElement* x) {
      for (const char* k : kKeys) {
        const char* v = x->Attribute(k);
        if (!v || defined(v)) continue;
        const auto it = copies_.find(v);
        if (it == copies_.end()) continue;
        if (found && *found != it->second)
          fail(x, e->Name(),
               std::string("names '") + v + "', copied by another <replicate> than its other names");
        found = &it->second;
      }
    };
    scan(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) scan(c);
    return found ? *found : std::vector<std::string>{""};
  }
  bool defined(const std::string& n) const {
    if (body_index_.count(n) || sites_.count(n)) return true;
    for (const ModelJoint& j : m_.joints)
      if (j.name == n) return true;
    return false;
  }
  // A name an element refers to, in the copy variants() is on (suffix_).
  std::string ref(const char* n) const {
    if (!n) return "";
    return !suffix_.empty() && copies_.count(n) && !defined(n) ? n + suffix_ : std::string(n);
  }
  std::string suffix_;

  // A name a <replicate> copies: `name` and the copy's suffix, remembered so that what refers to
  // the name from outside (equality, exclude, tendon) is copied with it.
  std::string replicated(const std::string& name, const std::string& suffix) {
    if (suffix.empty() || name.empty()) return name;
    copies_[name].push_back(suffix);
    return name + suffix;
  }

  void body(const XMLElement* e, int parent, const std::string& parent_childclass, const Place& at) {
    std::string name = replicated(attr_or(e, "name", ""), at.suffix);
    if (name.empty()) name = "body" + std::to_string(m_.links.size());
    const std::string what = "body '" + name + "'";
    check_attributes(e);
    if (body_index_.count(name)) fail(e, what, "another body already has this name");
    const std::string childclass =
        e->Attribute("childclass") ? std::string(e->Attribute("childclass")) : parent_childclass;
    if (!childclass.empty() && !class_parent_.count(childclass))
      fail(e, what, "childclass '" + childclass + "' is not defined");
    const std::string cls = class_of(e, parent_childclass);
    const ModelPose pose = at.offset * frame(e, cls, what);
    // Its joints, in order.
    std::vector<const XMLElement*> joints;
    bool free = false;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "freejoint" || tag == "joint") check_attributes(c);
      if (tag == "freejoint")
        free = true;
      else if (tag == "joint") {
        const char* t = get(c, "type", class_of(c, childclass));
        if (t && std::string(t) == "free")
          free = true;
        else
          joints.push_back(c);
      }
    }
    if (free && (parent >= 0 || !joints.empty()))
      fail(e, what,
           parent >= 0 ? "a free joint is allowed only on a body in the worldbody"
                       : "a body with a free joint has no other joints");
    // A body with several joints: helper links carry all but the last (same frame, no offset).
    int prev = parent;
    ModelPose rel = pose;
    std::vector<int> helpers;
    for (size_t k = 0; k + 1 < joints.size(); ++k) {
      const int h = add_link(name + "#" + std::to_string(k + 1), e, rel, prev);
      helpers.push_back(h);
      joint(joints[k], prev, h, childclass, at.suffix);
      prev = h;
      rel = ModelPose{};
    }
    const int self = add_link(name, e, rel, prev);
    body_index_[name] = self;
    if (free) m_.qpos_layout.push_back(Model::QposSlot{-1, self, 7, 0.0});
    for (int h : helpers) m_.links[h].helper_of = self;
    if (!joints.empty()) {
      joint(joints.back(), prev, self, childclass, at.suffix);
    } else if (!free) {
      ModelJoint j;  // welded to its parent (or to the world)
      j.name = name + "/weld";
      j.kind = ModelJoint::Kind::fixed;
      j.parent = prev;
      j.child = self;
      j.src = src(e, what);
      m_.joints.push_back(j);
    }
    int unused = -1;
    children(e, self, childclass, Place{ModelPose{}, at.suffix}, unused);
  }

  // A site: a named frame on a body (equality constraints may join two). Sites have no physics.
  void site(const XMLElement* e, int link, const std::string& childclass, const Place& at) {
    const char* n = e->Attribute("name");
    if (!n) return;  // nothing can name it
    const std::string cls = class_of(e, childclass);
    sites_[replicated(n, at.suffix)] = {link, at.offset * frame(e, cls, std::string("site '") + n + "'")};
  }
  // A camera: its frame on the link (or the world), its vertical field of view and how it moves.
  // Its target is looked up once every body is read (cameras_target_).
  void camera(const XMLElement* e, int link, const std::string& childclass, const Place& at) {
    check_attributes(e);
    const std::string cls = class_of(e, childclass);
    ModelCamera c;
    c.name = e->Attribute("name") ? replicated(e->Attribute("name"), at.suffix)
                                  : "camera" + std::to_string(m_.cameras.size());
    const std::string what = "camera '" + c.name + "'";
    for (const ModelCamera& o : m_.cameras)
      if (o.name == c.name) fail(e, what, "another camera already has this name");
    c.link = link;
    c.pose = at.offset * frame(e, cls, what);
    if (auto f = nums(e, "fovy", cls, what)) {
      if (f->size() != 1 || !((*f)[0] > 0 && (*f)[0] < 180))
        fail(e, what, "fovy must be one angle in (0, 180) degrees");
      c.fovy = (*f)[0];
    }
    const std::string mode = attr_or(e, "mode", "fixed");
    using M = ModelCamera::Mode;
    static const std::map<std::string, M> kModes = {{"fixed", M::fixed},
                                                    {"track", M::track},
                                                    {"trackcom", M::trackcom},
                                                    {"targetbody", M::targetbody},
                                                    {"targetbodycom", M::targetbodycom}};
    const auto it = kModes.find(mode);
    if (it == kModes.end())
      fail(e, what, "mode '" + mode + "' is not fixed, track, trackcom, targetbody or targetbodycom");
    c.mode = it->second;
    if ((c.mode == M::targetbody || c.mode == M::targetbodycom)) {
      if (!e->Attribute("target")) fail(e, what, "mode " + mode + " needs a target body");
      cameras_target_.push_back({m_.cameras.size(), e->Attribute("target"), at.suffix, e});
    }
    if (e->Attribute("orthographic") && attr_or(e, "orthographic", "false") == "true")
      m_.notes.push_back(src(e, what).str() + ": an orthographic camera is drawn in perspective");
    c.src = src(e, what);
    m_.cameras.push_back(c);
  }
  struct CameraTarget {
    size_t camera;
    std::string body, suffix;  ///< a camera copied by a <replicate> looks at its own copy's body
    const XMLElement* e;
  };
  std::vector<CameraTarget> cameras_target_;
  std::vector<std::pair<int, const XMLElement*>> hfield_links_;  ///< links with an hfield geom
  void resolve_camera_targets() {
    for (const CameraTarget& t : cameras_target_) {
      auto it = body_index_.find(t.body + t.suffix);
      if (it == body_index_.end()) it = body_index_.find(t.body);
      if (it == body_index_.end())
        fail(t.e, "camera '" + m_.cameras[t.camera].name + "'",
             "target '" + t.body + "' is not a body of the file");
      m_.cameras[t.camera].target = it->second;
    }
  }

  // A link's frame in the world at the start (the poses compose from the root).
  ModelPose world_pose(int link) const {
    ModelPose x;
    for (int l = link; l >= 0; l = link_parent_[l]) x = m_.links[l].pose * x;
    return x;
  }

  void joint(const XMLElement* e, int parent, int child, const std::string& childclass,
             const std::string& suffix) {
    const std::string cls = class_of(e, childclass);
    ModelJoint j;
    j.name =
        e->Attribute("name") ? replicated(e->Attribute("name"), suffix) : m_.links[child].name + "/joint";
    const std::string what = "joint '" + j.name + "'";
    j.src = src(e, what);
    j.parent = parent;
    j.child = child;
    const std::string type = get(e, "type", cls) ? get(e, "type", cls) : "hinge";
    if (type == "hinge")
      j.kind = ModelJoint::Kind::continuous;
    else if (type == "slide")
      j.kind = ModelJoint::Kind::prismatic;
    else if (type == "ball")
      j.kind = ModelJoint::Kind::spherical;
    else
      fail(e, what, "unknown joint type '" + type + "' (hinge, slide, ball, free)");
    if (auto p = vec<3>(e, "pos", cls, what)) j.anchor = *p;
    if (auto a = vec<3>(e, "axis", cls, what)) {
      if (!(a->norm() > 0)) fail(e, what, "axis must not be zero");
      j.axis = a->normalized();
    } else {
      j.axis = Vec3::UnitZ();
    }
    const char* limited = get(e, "limited", cls);
    const auto range = vec<2>(e, "range", cls, what);
    const bool on = range && !(limited && std::string(limited) == "false") && (*range)[0] < (*range)[1];
    if (on && j.kind != ModelJoint::Kind::spherical) {
      const double s = j.kind == ModelJoint::Kind::continuous ? angle(1) : 1;
      j.limits = std::array<double, 2>{(*range)[0] * s, (*range)[1] * s};
      if (j.kind == ModelJoint::Kind::continuous) j.kind = ModelJoint::Kind::revolute;
    } else if (on) {
      // A ball joint's range bounds its rotation's angle from the reference pose: range[1] only.
      const double hi = (*range)[1] * angle(1);
      if ((*range)[0] != 0)
        note(e, "a ball joint's range uses only its second number (the first should be 0)", what);
      if (hi < std::numbers::pi)
        j.limits = std::array<double, 2>{0.0, hi};
      else
        note(e, "a ball joint's range of pi or more leaves it free", what);
    }
    if (auto d = nums(e, "damping", cls, what); d && !d->empty()) j.damping = (*d)[0];
    if (auto d = nums(e, "stiffness", cls, what); d && !d->empty()) j.stiffness = (*d)[0];
    if (auto d = nums(e, "frictionloss", cls, what); d && !d->empty()) j.friction = (*d)[0];
    if (auto d = nums(e, "springref", cls, what); d && !d->empty())
      j.rest = j.kind == ModelJoint::Kind::prismatic ? (*d)[0] : angle((*d)[0]);
    if (j.damping < 0 || j.stiffness < 0 || j.friction < 0)
      fail(e, what, "damping, stiffness and frictionloss must not be negative");
    // A ball joint's stiffness and damping are its spring (-k phi - c w, as MuJoCo's passive force
    // on the quaternion difference); its frictionloss bounds the torque about each of the child's
    // axes, as MuJoCo's one friction row per degree of freedom does.
    if (j.kind == ModelJoint::Kind::spherical) j.rest = 0;
    if (get(e, "armature", cls)) {
      const double a = nums(e, "armature", cls, what)->at(0);
      if (a < 0) fail(e, what, "armature must not be negative");
      if (a > 0 && j.kind == ModelJoint::Kind::spherical)
        note(e, "a ball joint's armature is not simulated", what);
      else
        j.armature = a;
    }
    if (auto r = nums(e, "actuatorfrcrange", cls, what); r && r->size() == 2) {
      const char* l = get(e, "actuatorfrclimited", cls);
      if (!(l && std::string(l) == "false"))
        actuator_cap_[(int)m_.joints.size()] = std::max(std::abs((*r)[0]), std::abs((*r)[1]));
    }
    // MuJoCo's qpos is ref in the file's pose: its range and springref are qpos values, simreel's
    // coordinates start at 0 there.
    double ref = 0;
    if (auto r = nums(e, "ref", cls, what); r && !r->empty() && j.kind != ModelJoint::Kind::spherical) {
      ref = j.kind == ModelJoint::Kind::prismatic ? (*r)[0] : angle((*r)[0]);
      if (j.limits) (*j.limits)[0] -= ref, (*j.limits)[1] -= ref;
      j.rest -= ref;
    }
    m_.qpos_layout.push_back(
        Model::QposSlot{(int)m_.joints.size(), -1, j.kind == ModelJoint::Kind::spherical ? 4 : 1, ref});
    m_.joints.push_back(j);
  }

  void inertial(const XMLElement* e, int link, const std::string& what) {
    check_attributes(e);
    ModelInertial I;
    I.src = src(e, what + ", inertial");
    const ModelPose p = frame(e, "main", what);
    const auto mass = nums(e, "mass", "main", what);
    if (!mass || mass->size() != 1 || !((*mass)[0] > 0)) fail(e, what, "<inertial> needs a positive mass");
    I.mass = (*mass)[0];
    Mat3 J = Mat3::Zero();
    if (auto d = vec<3>(e, "diaginertia", "main", what))
      J = d->asDiagonal();
    else if (auto f = nums(e, "fullinertia", "main", what)) {
      if (f->size() != 6) fail(e, what, "fullinertia needs 6 numbers (ixx iyy izz ixy ixz iyz)");
      const auto& v = *f;
      J << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
    } else {
      fail(e, what, "<inertial> needs diaginertia or fullinertia");
    }
    const Mat3 R = p.q.toRotationMatrix();
    I.inertia = R * J * R.transpose();
    I.com = p.p;
    m_.links[link].inertial = I;
  }

  void geom(const XMLElement* e, int link, const std::string& childclass, const ModelPose& offset) {
    ModelShape s;
    const std::string name = attr_or(e, "name", "");
    const std::string what =
        m_.links[link].name == "world"
            ? "worldbody geom" + (name.empty() ? "" : " '" + name + "'")
            : "body '" + m_.links[link].name + "', geom" + (name.empty() ? "" : " '" + name + "'");
    const std::string cls = class_of(e, childclass, what);
    check_attributes(e);
    s.src = src(e, what);
    const std::string type = get(e, "type", cls) ? get(e, "type", cls) : "sphere";
    const auto size = nums(e, "size", cls, what).value_or(std::vector<double>{});
    auto sz = [&](size_t i) {
      if (i >= size.size())
        fail(e, what, "a " + type + " needs size with at least " + std::to_string(i + 1) + " numbers");
      if (!(size[i] > 0) && type != "plane") fail(e, what, "size must be positive");
      return size[i];
    };
    using K = ModelShape::Kind;
    s.pose = frame(e, cls, what);
    const auto fromto = nums(e, "fromto", cls, what);
    if (fromto && fromto->size() != 6) fail(e, what, "fromto needs 6 numbers");
    double half = 0;
    if (fromto) {
      const Vec3 a((*fromto)[0], (*fromto)[1], (*fromto)[2]), b((*fromto)[3], (*fromto)[4], (*fromto)[5]);
      if (!((b - a).norm() > 0)) fail(e, what, "fromto's two points coincide");
      s.pose.p = 0.5 * (a + b);
      s.pose.q = Quat::FromTwoVectors(Vec3::UnitZ(), (b - a).normalized());
      half = 0.5 * (b - a).norm();
    }
    s.pose = offset * s.pose;
    if (type == "sphere") {
      s.kind = K::sphere;
      s.radius = sz(0);
    } else if (type == "capsule" || type == "cylinder") {
      s.kind = type == "capsule" ? K::capsule : K::cylinder;
      s.radius = sz(0);
      if (!fromto) half = sz(1);
      s.length = 2 * half + (s.kind == K::capsule ? 2 * s.radius : 0);
    } else if (type == "box") {
      s.kind = K::box;
      // With fromto, MuJoCo's box takes size[0] across and the segment's half-length along.
      s.size = fromto ? Vec3(2 * sz(0), 2 * sz(0), 2 * half) : Vec3(2 * sz(0), 2 * sz(1), 2 * sz(2));
    } else if (type == "ellipsoid") {
      s.kind = K::ellipsoid;
      s.radii = Vec3(sz(0), sz(1), sz(2));
    } else if (type == "plane") {
      s.kind = K::plane;
      plane_half_ = sz(0);
      if (m_.links[link].name != "world") fail(e, what, "a plane must be a geom of the worldbody");
    } else if (type == "mesh") {
      s.kind = K::mesh;
      const char* mn = get(e, "mesh", cls);
      if (!mn) fail(e, what, "a mesh geom needs mesh=\"NAME\"");
      const auto it = meshes_.find(mn);
      if (it == meshes_.end()) fail(e, what, std::string("mesh '") + mn + "' is not an asset");
      s.mesh_file = it->second.file;
      s.scale = it->second.scale;
      s.inline_mesh = it->second.inline_mesh;
    } else if (type == "hfield") {
      // MuJoCo's heightfields are static: a geom of the worldbody or of a body welded to it.
      s.kind = K::mesh;
      const char* hn = get(e, "hfield", cls);
      if (!hn) fail(e, what, "an hfield geom needs hfield=\"NAME\"");
      const auto it = hfields_.find(hn);
      if (it == hfields_.end()) fail(e, what, std::string("hfield '") + hn + "' is not an asset");
      s.inline_mesh = it->second;
      s.mesh_file = std::string("hfield ") + hn;
      hfield_links_.push_back({link, e});
    } else {
      note(
          e,
          "geom type '" + type +
              "' is not simulated (plane, sphere, capsule, ellipsoid, cylinder, box, mesh, hfield); left out",
          what);
      return;
    }
    // contype/conaffinity 0: drawn only. Groups 0-2 are drawn by MuJoCo's viewer by default, 3-5 hidden.
    const auto ct = nums(e, "contype", cls, what), ca = nums(e, "conaffinity", cls, what);
    const double contype = ct && !ct->empty() ? (*ct)[0] : 1, conaff = ca && !ca->empty() ? (*ca)[0] : 1;
    s.collision = contype != 0 || conaff != 0;
    if (s.collision && (contype != 1 || conaff != 1)) {
      s.group = (uint32_t)contype;
      s.mask = (uint32_t)conaff;
    }
    const auto group = nums(e, "group", cls, what);
    s.visual = !(group && !group->empty() && (*group)[0] >= 3);
    if (auto f = nums(e, "friction", cls, what); f && !f->empty()) s.friction = (*f)[0];
    // MuJoCo's contact is a spring and damper set by solref: (time constant, damping ratio z), or
    // (-stiffness, -damping). A linear spring-damper with z < 1 parts at exp(-pi z / sqrt(1 - z^2))
    // of its approach speed, none from z >= 1 (the default, z = 1); with no damping, all of it.
    // A negative pair with damping is a ratio that depends on the masses: a note, restitution 0.
    if (auto r = nums(e, "solref", cls, what); r && r->size() == 2) {
      const double a = (*r)[0], b = (*r)[1];
      if (a > 0 && b >= 0)
        s.restitution = b < 1 ? std::exp(-M_PI * b / std::sqrt(1 - b * b)) : 0.0;
      else if (a < 0 && b == 0)
        s.restitution = 1.0;
      else
        note_once(e, "solref-damped",
                  "a solref of stiffness and damping (" + std::to_string(a) + ", " + std::to_string(b) +
                      ") has no restitution of its own; 0 is used");
    }
    if (auto d = nums(e, "density", cls, what); d && !d->empty()) s.density = (*d)[0];
    if (auto mm = nums(e, "mass", cls, what); mm && !mm->empty()) s.mass = (*mm)[0];
    s.weighs = !(s.mass && *s.mass == 0) && !(s.density && *s.density == 0) && s.kind != K::plane;
    // Colour: rgba, else the material's; MuJoCo's default grey.
    std::optional<std::array<float, 4>> rgba;
    if (auto v = vec<4>(e, "rgba", cls, what))
      rgba = std::array<float, 4>{(float)(*v)[0], (float)(*v)[1], (float)(*v)[2], (float)(*v)[3]};
    if (const char* mat = get(e, "material", cls)) {
      const auto it = materials_.find(mat);
      if (it == materials_.end())
        note(e, std::string("material '") + mat + "' is not an asset; drawn in its colour", what);
      else {
        if (!e->Attribute("rgba") && it->second.rgba) rgba = it->second.rgba;
        if (!it->second.texture.empty()) {
          const auto t = textures_.find(it->second.texture);
          if (t != textures_.end()) s.texture = t->second;
          const auto c = checkers_.find(it->second.texture);
          if (c != checkers_.end() && s.kind == K::plane) {
            // The 2x2 image repeats texrepeat times a metre (texuniform), else across the plane's
            // width (2 size[0]; an infinite plane, size 0, is taken per metre).
            const MjMaterial& mt = it->second;
            const double across = mt.texuniform || !(plane_half_ > 0) ? 1.0 : 2 * plane_half_;
            s.checker = ModelChecker{c->second.rgb1, c->second.rgb2, across / (2 * mt.texrepeat)};
          }
        }
      }
    }
    if (rgba && (*rgba)[3] == 0) s.visual = false;  // fully transparent: not drawn
    if (rgba)
      s.color = std::array<float, 3>{(*rgba)[0], (*rgba)[1], (*rgba)[2]};
    else if (s.texture.empty())
      s.color = std::array<float, 3>{0.5f, 0.5f, 0.5f};
    if (!s.visual && !s.collision) return;  // neither drawn nor colliding: only its mass
    m_.links[link].shapes.push_back(std::move(s));
  }

  // <actuator>: no controller drives them here, but each bounds the force on its joint, which
  // `hold: true` gives the motor that holds the joint (URDF's <limit effort>): |gear| times the
  // actuator's force bound, its forcerange, or for a motor (force = ctrl) or a general actuator
  // without bias (force = gain ctrl) its ctrlrange times the gain; several on one joint add up,
  // and the joint's actuatorfrcrange caps the sum (MuJoCo's rules). Actuators on tendons, sites
  // or bodies are notes.
  void actuators(const XMLElement* a) {
    static const std::set<std::string> kKinds = {"motor",  "position", "velocity", "general",  "intvelocity",
                                                 "damper", "cylinder", "muscle",   "adhesion", "plugin"};
    std::map<std::string, int> joint_of;
    for (int k = 0; k < (int)m_.joints.size(); ++k) joint_of.emplace(m_.joints[k].name, k);
    for (const XMLElement* e = a->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      const std::string cls = class_of(e, "");
      const std::string what = "actuator '" + attr_or(e, "name", tag) + "'";
      if (!kKinds.count(tag)) {
        note_once(e, "actuator-" + tag, "<actuator><" + tag + "> is not an actuator simreel knows; ignored");
        continue;
      }
      const char* jn = e->Attribute("joint");
      if (!jn) {
        note_once(e, "actuator-transmission",
                  "actuators on tendons, sites and bodies are not used (simreel bounds a held joint's "
                  "motor by the actuators on that joint)");
        continue;
      }
      const auto it = joint_of.find(jn);
      if (it == joint_of.end())
        fail(e, what, std::string("drives joint '") + jn + "', which the file does not define");
      // A range is in force when `limited` says so, or (MuJoCo's "auto") when it is given.
      auto bound = [&](const char* range, const char* limited) -> double {
        const auto r = nums(e, range, cls, what);
        const char* l = get(e, limited, cls);
        if (!r || r->size() != 2 || (l && std::string(l) == "false")) return 0.0;
        return std::max(std::abs((*r)[0]), std::abs((*r)[1]));
      };
      double force = bound("forcerange", "forcelimited");
      if (force == 0 && (tag == "motor" || tag == "general")) {
        double gain = 1;
        if (tag == "general") {
          const char* bias = get(e, "biastype", cls);
          const auto g = nums(e, "gainprm", cls, what);
          if (bias && std::string(bias) != "none") gain = 0;  // a servo: unbounded without forcerange
          if (g && !g->empty()) gain *= (*g)[0];
        }
        force = std::abs(gain) * bound("ctrlrange", "ctrllimited");
      }
      const auto gear = nums(e, "gear", cls, what);
      const double G = gear && !gear->empty() ? std::abs((*gear)[0]) : 1.0;
      if (force == 0) {
        note(e, "no force bound (forcerange or ctrlrange): it gives its joint no effort for `hold`", what);
        continue;
      }
      ModelJoint& j = m_.joints[it->second];
      j.effort += G * force;
      const auto cap = actuator_cap_.find(it->second);
      if (cap != actuator_cap_.end()) j.effort = std::min(j.effort, cap->second);
    }
  }
  // <tendon><spatial> through two sites with a limited length: a rope between them (a string of
  // Newton's cradle), slack below the range's top, pulling at it (and pushing at its bottom when
  // that is above zero), exact where MuJoCo's limit is a soft spring. Tendons through more sites,
  // wrapping geoms, unlimited tendons (MuJoCo drives or senses them) and fixed tendons are notes.
  void tendon(const XMLElement* e) {
    const std::string tag = e->Name();
    const std::string name =
        e->Attribute("name") ? e->Attribute("name") + suffix_ : "tendon" + std::to_string(m_.ropes.size());
    const std::string what = "tendon '" + name + "'";
    if (tag == "fixed") {
      fixed_tendon(e, what);
      return;
    }
    if (tag != "spatial") {
      note(e, "<" + tag + "> tendons are not simulated; ignored", what);
      return;
    }
    // Attributes through the default classes, whose element is <tendon>.
    const std::string cls = class_of(e, "", what);
    auto attr = [&](const char* key) { return get(e, key, cls, "tendon"); };
    std::vector<const XMLElement*> sites;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::string(c->Name()) == "site") {
        sites.push_back(c);
      } else {
        note(c, "a tendon wrapping a geom or over a pulley is not simulated; tendon ignored", what);
        return;
      }
    }
    if (sites.size() != 2) {
      note(e,
           "a tendon through " + std::to_string(sites.size()) +
               " sites is not simulated (two: a rope); ignored",
           what);
      return;
    }
    // Its spring: -stiffness (L - springlength) - damping L'. One springlength (or two equal), or
    // a negative one (the default), is a rest length (the negative: the length in the file's pose,
    // MuJoCo's qpos0); two different values are a dead band, not simulated.
    std::optional<JointSpring> spring;
    {
      auto real = [&](const char* key) {
        const char* v = attr(key);
        if (!v) return 0.0;
        const auto n = parse_numbers(v);
        if (!n || n->size() != 1) fail(e, what, std::string(key) + " \"" + v + "\" must be one number");
        return (*n)[0];
      };
      const double k = real("stiffness"), c = real("damping");
      if (k < 0 || c < 0) fail(e, what, "stiffness and damping must not be negative");
      double rest = std::numeric_limits<double>::quiet_NaN();
      bool band = false;
      if (const char* sl = attr("springlength")) {
        const auto v = parse_numbers(sl);
        if (!v || v->empty() || v->size() > 2)
          fail(e, what, std::string("springlength \"") + sl + "\" must be one or two lengths");
        band = v->size() == 2 && (*v)[0] != (*v)[1];
        if (!band && (*v)[0] >= 0) rest = (*v)[0];
      }
      if (band && (k > 0 || c > 0))
        note(e, "a dead-band spring (two springlength values) is not simulated; its spring ignored", what);
      else if (k > 0 || c > 0)
        spring = JointSpring{k, c, rest};
    }
    const char* range_text = attr("range");
    const char* limited = attr("limited");
    const bool on = range_text && !(limited && std::string(limited) == "false");
    if (!on && !spring) {
      note(e,
           "a tendon without a limited length or a spring pulls nothing here (MuJoCo drives or senses it); "
           "ignored",
           what);
      return;
    }
    std::optional<std::vector<double>> range;
    if (on) {
      range = parse_numbers(range_text);
      if (!range || range->size() != 2 || !((*range)[1] > 0) || !((*range)[0] <= (*range)[1]))
        fail(e, what,
             std::string("range \"") + range_text + "\" must be two lengths, low to high, the high above 0");
    }
    auto site_of = [&](const XMLElement* c) -> const Site& {
      if (!c->Attribute("site")) fail(c, what, "a tendon's <site> needs site=\"NAME\"");
      return named(c, what, sites_, "site", ref(c->Attribute("site")).c_str(), "site");
    };
    const Site& a = site_of(sites[0]);
    const Site& b = site_of(sites[1]);
    if (const char* v = attr("frictionloss"); v && std::atof(v) != 0)
      note(e, "its frictionloss is not simulated", what);
    ModelRope r;
    r.name = name;
    r.link_a = a.link;
    r.point_a = a.pose.p;
    r.link_b = b.link;
    r.point_b = b.pose.p;
    if (range) {
      r.max_length = (*range)[1];
      if ((*range)[0] > 0) r.min_length = (*range)[0];
    }
    r.spring = spring;
    r.src = src(e, what);
    m_.ropes.push_back(r);
  }

  // <tendon><fixed> over two or more joints with a limited range: sum c_k q_k within [lo, hi] (a
  // hamstring spanning hip and knee) is the first joint's coupling to the others,
  // q1 - sum (-c_k / c1) q_k within [lo, hi] / c1, a stop on the combination. MuJoCo's coordinates
  // are ours where the joints' ref is 0 (the file's pose). No range, or a spring, are notes.
  void fixed_tendon(const XMLElement* e, const std::string& what) {
    const std::string cls = class_of(e, "", what);
    auto attr = [&](const char* key) { return get(e, key, cls, "tendon"); };
    std::vector<std::pair<int, double>> terms;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::string(c->Name()) != "joint") continue;
      if (!c->Attribute("joint")) fail(c, what, "a fixed tendon's <joint> needs joint=\"NAME\"");
      const std::string jn = ref(c->Attribute("joint"));
      int k = -1;
      for (int i = 0; i < (int)m_.joints.size(); ++i)
        if (m_.joints[i].name == jn) k = i;
      if (k < 0) fail(c, what, "names joint '" + jn + "', which the file does not define");
      const auto coef = parse_numbers(c->Attribute("coef") ? c->Attribute("coef") : "1");
      if (!coef || coef->size() != 1) fail(c, what, "coef must be one number");
      terms.emplace_back(k, (*coef)[0]);
    }
    for (const char* k : {"stiffness", "damping", "frictionloss"})
      if (const char* v = attr(k); v && std::atof(v) != 0)
        note(e, std::string("a fixed tendon's ") + k + " is not simulated", what);
    const char* range_text = attr("range");
    const char* limited = attr("limited");
    if (!range_text || (limited && std::string(limited) == "false")) {
      note(e, "a fixed tendon without a limited range is not simulated (MuJoCo drives or senses it); ignored",
           what);
      return;
    }
    bool usable = terms.size() >= 2;
    for (size_t a = 0; a < terms.size(); ++a) {
      usable = usable && terms[a].second != 0;
      for (size_t b = 0; b < a; ++b) usable = usable && terms[a].first != terms[b].first;
    }
    if (!usable) {
      note(e,
           "a fixed tendon is simulated over two or more distinct joints with nonzero coefficients; ignored",
           what);
      return;
    }
    const auto range = parse_numbers(range_text);
    if (!range || range->size() != 2 || !((*range)[0] < (*range)[1]))
      fail(e, what, std::string("range \"") + range_text + "\" must be two numbers, low to high");
    ModelJoint& j = m_.joints[terms[0].first];
    if (!j.coupled_joint.empty()) {
      note(e, "joint '" + j.name + "' already has a fixed tendon's limit; this one is ignored", what);
      return;
    }
    const double c1 = terms[0].second, c2 = terms[1].second;
    double lo = (*range)[0] / c1, hi = (*range)[1] / c1;
    if (lo > hi) std::swap(lo, hi);
    j.coupled_joint = m_.joints[terms[1].first].name;
    j.coupled_multiplier = -c2 / c1;
    for (size_t a = 2; a < terms.size(); ++a)
      j.coupled_more.emplace_back(m_.joints[terms[a].first].name, -terms[a].second / c1);
    j.coupled_range = {lo, hi};
    j.coupled_src = src(e, what);
  }

  // <contact><exclude body1 body2>: pairs that never collide; <pair> (explicit contacts) is a note.
  void contact(const XMLElement* q) {
    for (const XMLElement* e = q->FirstChildElement(); e; e = e->NextSiblingElement()) {
      if (std::string(e->Name()) != "exclude") {
        note_once(e, std::string("contact-") + e->Name(),
                  std::string("<contact><") + e->Name() + "> is not used; ignored");
        continue;
      }
      for (const std::string& v : variants(e)) {
        suffix_ = v;
        const std::string a = ref(e->Attribute("body1")), b = ref(e->Attribute("body2"));
        const auto ia = body_index_.find(a), ib = body_index_.find(b);
        if (ia == body_index_.end() || ib == body_index_.end())
          fail(e, "contact exclude",
               "names body '" + (ia == body_index_.end() ? a : b) + "', which the file does not define");
        m_.exclude.emplace_back(ia->second, ib->second);
      }
      suffix_.clear();
    }
  }

  // <equality><joint joint1 joint2 polycoef>: joint1 = c0 + c1 joint2 (+ c2 joint2^2 ...), from the
  // reference pose: a coupling of two coordinates, simreel's mimic (joint1 follows joint2 with
  // multiplier c1 and offset c0). Only the linear part is held; a curve's higher terms are a note,
  // and joint1 alone (locked at c0) is one too.
  void joint_equality(const XMLElement* e, const std::string& what) {
    if (!e->Attribute("joint1")) fail(e, what, "needs joint1");
    const std::string an = ref(e->Attribute("joint1")), bn = ref(e->Attribute("joint2"));
    const char* a = an.c_str();
    const char* b = e->Attribute("joint2") ? bn.c_str() : nullptr;
    int ia = -1, ib = -1;
    for (int k = 0; k < (int)m_.joints.size(); ++k) {
      if (m_.joints[k].name == a) ia = k;
      if (b && m_.joints[k].name == b) ib = k;
    }
    if (ia < 0 || (b && ib < 0))
      fail(e, what, std::string("names joint '") + (ia < 0 ? a : b) + "', which the file does not define");
    if (!b) {
      note(e, "a joint locked alone (no joint2) is not simulated; ignored", what);
      return;
    }
    std::vector<double> c = {0, 1, 0, 0, 0};
    if (auto p = nums(e, "polycoef", "main", what))
      for (size_t k = 0; k < p->size() && k < c.size(); ++k) c[k] = (*p)[k];
    if (c[2] != 0 || c[3] != 0 || c[4] != 0) note(e, "only the polynomial's linear part is held", what);
    ModelJoint& j = m_.joints[ia];
    j.mimic_joint = b;
    j.mimic_multiplier = c[1];
    j.mimic_offset = c[0];
  }

  void equality(const XMLElement* q) {
    for (const XMLElement* e = q->FirstChildElement(); e; e = e->NextSiblingElement())
      for (const std::string& v : variants(e)) {
        suffix_ = v;
        equality_one(e);
      }
    suffix_.clear();
  }
  void equality_one(const XMLElement* e) {
    {
      const std::string tag = e->Name();
      const std::string name =
          e->Attribute("name") ? e->Attribute("name") + suffix_ : tag + std::to_string(m_.joints.size());
      const std::string what = "equality " + tag + " '" + name + "'";
      if (tag == "joint") {
        if (!(e->Attribute("active") && std::string(e->Attribute("active")) == "false"))
          joint_equality(e, what);
        return;
      }
      if (tag != "connect" && tag != "weld") {
        note(e, "<" + tag + "> constraints are not simulated; ignored", what);
        return;
      }
      if (e->Attribute("active") && std::string(e->Attribute("active")) == "false") return;
      auto body_of = [&](const char* key, bool optional) -> int {
        if (!e->Attribute(key)) {
          if (optional) return -1;
          fail(e, what, std::string("needs ") + key);
        }
        const std::string n = ref(e->Attribute(key));
        if (n == "world") return -1;
        return named(e, what, body_index_, key, n.c_str(), "body");
      };
      ModelJoint j;
      j.name = name;
      j.loop = true;
      j.src = src(e, what);
      j.kind = tag == "connect" ? ModelJoint::Kind::spherical : ModelJoint::Kind::fixed;
      if (e->Attribute("site1") || e->Attribute("site2")) {
        // Two sites held together: connect, their origins; weld, their frames. Held as they are
        // at the start: sites apart there stay apart (MuJoCo's soft constraint would pull them
        // together), with a note.
        auto site_of = [&](const char* key) -> const Site& {
          if (!e->Attribute(key)) fail(e, what, std::string("needs ") + key + " (site1 and site2 together)");
          return named(e, what, sites_, key, ref(e->Attribute(key)).c_str(), "site");
        };
        const Site& s1 = site_of("site1");
        const Site& s2 = site_of("site2");
        if (s1.link == s2.link) {
          note(e, "both sites are on one body; nothing to hold", what);
          return;
        }
        const ModelPose w1 = world_pose(s1.link) * s1.pose, w2 = world_pose(s2.link) * s2.pose;
        const double apart = (w1.p - w2.p).norm();
        if (apart > 1e-6 || (tag == "weld" && w1.q.angularDistance(w2.q) > 1e-6))
          note(e, "its sites are apart at the start (" + std::to_string(apart) + " m): held as they are",
               what);
        j.child = s1.link;
        j.parent = s2.link;
        j.anchor = s1.pose.p;
        if (j.child < 0) {
          std::swap(j.child, j.parent);
          j.anchor = s2.pose.p;
        }
        m_.joints.push_back(j);
        return;
      }
      const int b1 = body_of("body1", false), b2 = body_of("body2", true);
      // simreel's child: body1 (the anchor is in its frame); the other body or the world the parent.
      j.child = b1;
      j.parent = b2;
      if (auto a = vec<3>(e, "anchor", "main", what))
        j.anchor = *a;
      else if (tag == "connect")
        fail(e, what, "connect needs an anchor (in body1's frame)");
      if (b1 < 0) {  // welded to the world: the body is the child (a weld's anchor only names a point)
        if (tag == "connect" || b2 < 0) fail(e, what, "body1 must be a body, not the world");
        std::swap(j.child, j.parent);
        j.anchor = Vec3::Zero();
      }
      if (tag == "weld" && (e->Attribute("relpose") || e->Attribute("torquescale")))
        note(e, "weld relpose and torquescale are not read: welded in the start pose", what);
      m_.joints.push_back(j);
    }
  }
};

}  // namespace

Model read_mjcf(const std::string& path, const ImportPaths& paths) {
  MjcfReader r(path, paths);
  Model m = r.read();
  return m;
}

}  // namespace simreel
