// The URDF reader. Written on tinyxml2 rather than Debian's liburdfdom 3.0.1, measured on the
// corpus: liburdfdom rejects a whole file for one element it does not know (Bullet's hinge.urdf
// for its `spherical` joint, any file with a `capsule`), reports through console_bridge without a
// line number, and drops what it skips without saying so. Here every element keeps its line, an
// unknown one is a note, and the format's 15 elements take about 400 lines.
#include "app/import/urdf.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <simreel/error.hpp>
#include "app/import/xml_util.hpp"

namespace simreel {

namespace fs = std::filesystem;
using namespace xml;

std::string SourceRef::str() const {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  if (!what.empty()) s += ": " + what;
  return s;
}

namespace {

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// `package://NAME` in one folder: the folder is the package, or holds it.
std::optional<fs::path> in_package_dir(const fs::path& dir, const std::string& pkg, const std::string& rest) {
  if (dir.filename() == pkg && is_file(dir / rest)) return dir / rest;
  if (is_file(dir / pkg / rest)) return dir / pkg / rest;
  return std::nullopt;
}

}  // namespace

std::string resolve_asset(const std::string& raw, const std::string& base_dir, const std::string& file,
                          const ImportPaths& paths, const std::string& where, const char* what,
                          std::vector<std::string>& notes) {
  std::vector<std::string> tried;
  auto attempt = [&](const fs::path& p) -> std::optional<std::string> {
    if (is_file(p)) return p.lexically_normal().string();
    std::error_code ec;
    tried.push_back(fs::absolute(p, ec).lexically_normal().string());
    return std::nullopt;
  };
  const std::string package = "package://";
  if (raw.rfind(package, 0) == 0) {
    const std::string tail = raw.substr(package.size());
    const size_t slash = tail.find('/');
    const std::string pkg = tail.substr(0, slash),
                      rest = slash == std::string::npos ? "" : tail.substr(slash + 1);
    std::vector<fs::path> dirs(paths.package_paths.begin(), paths.package_paths.end());
    // The command line's --package-path first (app/cli/run_options.cpp), then ROS's.
    for (const char* var : {"SIMREEL_PACKAGE_PATH", "ROS_PACKAGE_PATH"})
      if (const char* env = std::getenv(var)) {
        std::stringstream ss(env);
        for (std::string d; std::getline(ss, d, ':');)
          if (!d.empty()) dirs.emplace_back(d);
      }
    // The file's folder and its ancestors: a URDF inside its package (urdf/robot.urdf) finds it.
    for (fs::path d = fs::absolute(fs::path(base_dir)); !d.empty(); d = d.parent_path()) {
      dirs.push_back(d);
      if (d == d.parent_path()) break;
    }
    for (const fs::path& d : dirs)
      if (auto p = in_package_dir(d, pkg, rest)) return p->lexically_normal().string();
    std::string msg = where + ": " + what + " '" + raw + "': package '" + pkg +
                      "' not found; give its folder in the import's `package_paths` (or the folder "
                      "holding it), --package-path, or ROS_PACKAGE_PATH (looked in";
    size_t shown = 0;
    for (const fs::path& d : dirs)
      if (shown++ < 8) msg += (shown > 1 ? ", " : " ") + d.string();
    if (dirs.size() > 8) msg += ", ...";
    throw InputError(msg + ")");
  }
  std::string p = raw;
  if (p.rfind("file://", 0) == 0) p = p.substr(7);
  // A Windows path (C:\..., E:/..., \\server\...) or a backslashed relative one.
  const bool windows =
      (p.size() > 2 && std::isalpha((unsigned char)p[0]) && p[1] == ':') || p.find('\\') != std::string::npos;
  std::string unixy = p;
  std::replace(unixy.begin(), unixy.end(), '\\', '/');
  if (!windows) {
    const fs::path fp(p);
    if (auto r = attempt(fp.is_absolute() ? fp : fs::path(base_dir) / fp)) return *r;
  } else if (!(p.size() > 2 && p[1] == ':') && unixy.rfind("//", 0) != 0) {
    if (auto r = attempt(fs::path(base_dir) / unixy)) return *r;
  }
  // From another machine: by its file name beside the file that names it.
  const std::string name = fs::path(unixy).filename().string();
  if (!name.empty() && (windows || fs::path(p).is_absolute()))
    if (auto r = attempt(fs::path(base_dir) / name)) {
      notes.push_back(where + ": " + what + " '" + raw + "' is a path on another machine; using " + *r +
                      " (the same file name beside " + fs::path(file).filename().string() + ")");
      return *r;
    }
  std::string msg = where + ": " + what + " '" + raw + "' not found (looked for";
  for (size_t i = 0; i < tried.size(); ++i) msg += (i ? ", " : " ") + tried[i];
  throw InputError(msg + ")");
}

namespace {

struct UrdfMaterial {
  std::optional<std::array<float, 3>> color;
  std::string texture;  // resolved
};

class UrdfReader {
 public:
  UrdfReader(const std::string& path, const ImportPaths& paths)
      : path_(path), dir_(fs::path(path).parent_path().string()), paths_(paths) {}

  Model read() {
    std::string ext = fs::path(path_).extension().string();
    for (char& c : ext) c = (char)std::tolower((unsigned char)c);
    const std::string text = read_text(path_);
    if (ext == ".xacro" || text.find("<xacro:") != std::string::npos)
      throw InputError(path_ +
                       ": a xacro file (macros, not a robot): expand it first with xacro, e.g. "
                       "`xacro " +
                       fs::path(path_).filename().string() +
                       " > robot.urdf` (package ros-*-xacro), and load the result");
    tinyxml2::XMLDocument doc;
    parse_xml(doc, text, path_);
    const tinyxml2::XMLElement* robot = doc.RootElement();
    if (!robot || std::string(robot->Name()) != "robot")
      throw InputError(path_ + ":" + std::to_string(robot ? robot->GetLineNum() : 1) +
                       ": expected a <robot> element at the top of a URDF file, found <" +
                       (robot ? robot->Name() : "nothing") + ">");
    m_.file = path_;
    m_.files = {path_};
    m_.format = "urdf";
    m_.name = attr_or(robot, "name", fs::path(path_).stem().string());
    // Named materials first: a visual may use one defined after it, at the top level or inside
    // another visual (r2d2 defines "white" in its first visual and names it in the others).
    for (auto* e = robot->FirstChildElement("material"); e; e = e->NextSiblingElement("material")) {
      const std::string name = attr_or(e, "name", "");
      if (name.empty()) {
        note(e, "a top-level <material> without a name is never used");
        continue;
      }
      materials_[name] = material(e, true);
    }
    for (auto* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
      for (auto* v = l->FirstChildElement("visual"); v; v = v->NextSiblingElement("visual"))
        if (auto* e = v->FirstChildElement("material"); e && e->FirstChildElement()) {
          const std::string name = attr_or(e, "name", "");
          if (!name.empty() && !materials_.count(name)) materials_[name] = material(e, true);
        }
    std::set<std::string> noted;
    for (auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "link")
        link(e);
      else if (tag == "joint" || tag == "material")
        continue;
      else if (noted.insert(tag).second)
        note(e,
             "<" + tag + "> is not used by simreel (" +
                 (tag == "gazebo" || tag == "transmission" ? std::string("simulator and controller settings")
                                                           : std::string("unknown element")) +
                 "); ignored");
    }
    for (auto* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) joint(e);
    check_tree();
    expand_planar();
    return std::move(m_);
  }

 private:
  std::string path_, dir_;
  const ImportPaths& paths_;
  Model m_;
  std::map<std::string, UrdfMaterial> materials_;
  std::map<std::string, int> link_index_;

  SourceRef src(const tinyxml2::XMLElement* e, const std::string& what) const {
    return {path_, e->GetLineNum(), what};
  }
  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& what,
                         const std::string& msg) const {
    throw InputError(src(e, what).str() + ": " + msg);
  }
  void note(const tinyxml2::XMLElement* e, const std::string& msg, const std::string& what = "") {
    m_.notes.push_back(src(e, what).str() + ": " + msg);
  }
  ModelPose origin(const tinyxml2::XMLElement* parent, const std::string& what) const {
    ModelPose p;
    const auto* o = parent->FirstChildElement("origin");
    if (!o) return p;
    if (o->Attribute("xyz")) p.p = numbers<3>(o, "xyz", path_, what);
    if (o->Attribute("rpy")) p.q = rpy_quat(numbers<3>(o, "rpy", path_, what));
    return p;
  }

  UrdfMaterial material(const tinyxml2::XMLElement* e, bool top) {
    UrdfMaterial mat;
    const std::string name = attr_or(e, "name", "");
    const std::string what = "material '" + name + "'";
    if (const auto* c = e->FirstChildElement("color")) {
      const auto v = numbers<4>(c, "rgba", path_, what);
      for (int i = 0; i < 4; ++i)
        if (!(v[i] >= 0 && v[i] <= 1)) fail(c, what, "rgba components must be in [0, 1]");
      mat.color = std::array<float, 3>{(float)v[0], (float)v[1], (float)v[2]};
    }
    if (const auto* t = e->FirstChildElement("texture")) {
      const std::string f = attr_or(t, "filename", "");
      if (!f.empty()) {
        try {
          mat.texture = resolve_asset(f, dir_, path_, paths_, src(t, what).str(), "texture", m_.notes);
        } catch (const InputError& err) {  // a missing image costs the look, not the robot
          m_.notes.push_back(std::string(err.what()) + "; drawn in the material's colour");
        }
      }
    }
    if (!top && !mat.color && mat.texture.empty() && !name.empty()) {
      const auto it = materials_.find(name);
      if (it == materials_.end())
        note(e, "material '" + name + "' is not defined at the top level; drawn in the default colour");
      else
        mat = it->second;
    }
    return mat;
  }

  // False (with a note) for a geometry simreel does not know; InputError for a broken one.
  bool geometry(const tinyxml2::XMLElement* owner, ModelShape& s, const std::string& what, const char* tag) {
    const auto* g = owner->FirstChildElement("geometry");
    if (!g) fail(owner, what, "has no <geometry>");
    const auto* e = g->FirstChildElement();
    if (!e) fail(g, what, "<geometry> is empty (box, cylinder, sphere, capsule or mesh)");
    const std::string t = e->Name();
    using K = ModelShape::Kind;
    if (t == "box") {
      s.kind = K::box;
      s.size = numbers<3>(e, "size", path_, what);
      for (int i = 0; i < 3; ++i)
        if (!(s.size[i] > 0)) fail(e, what, "box size must be positive");
    } else if (t == "sphere") {
      s.kind = K::sphere;
      s.radius = positive_attr(e, "radius", path_, what);
    } else if (t == "cylinder" || t == "capsule") {
      s.kind = t == "cylinder" ? K::cylinder : K::capsule;
      s.radius = positive_attr(e, "radius", path_, what);
      s.length = positive_attr(e, "length", path_, what);
      // URDF's capsule (Gazebo, Bullet): `length` between the caps' centres.
      if (s.kind == K::capsule) s.length += 2 * s.radius;
    } else if (t == "mesh") {
      s.kind = K::mesh;
      const std::string f = attr_or(e, "filename", "");
      if (f.empty()) fail(e, what, "<mesh> needs a filename");
      s.mesh_file = resolve_asset(f, dir_, path_, paths_, src(e, what).str(), "mesh", m_.notes);
      if (e->Attribute("scale")) {
        const std::string sc = e->Attribute("scale");
        s.scale = std::count(sc.begin(), sc.end(), ' ') == 0 && sc.find_first_not_of(" ") != std::string::npos
                      ? Vec3::Constant(numbers<1>(e, "scale", path_, what)[0])
                      : numbers<3>(e, "scale", path_, what);
        for (int i = 0; i < 3; ++i)
          if (!(s.scale[i] > 0)) fail(e, what, "mesh scale factors must be positive");
      }
    } else {
      // A shape the file names but no reader here knows (Bullet's .cdf) loses that shape, not the robot.
      note(e,
           "unknown geometry <" + t + "> (box, cylinder, sphere, capsule, mesh)" +
               (t == "cdf" ? "; Bullet's .cdf collision files are not a mesh format" : "") + "; this " + tag +
               " is left out",
           what);
      return false;
    }
    return true;
  }

  void link(const tinyxml2::XMLElement* e) {
    ModelLink l;
    l.name = attr_or(e, "name", "");
    if (l.name.empty()) fail(e, "link", "a <link> needs a name");
    const std::string what = "link '" + l.name + "'";
    if (link_index_.count(l.name)) fail(e, what, "another link already has this name");
    l.src = src(e, what);
    if (const auto* in = e->FirstChildElement("inertial")) {
      ModelInertial I;
      I.src = src(in, what + ", inertial");
      const ModelPose o = origin(in, what);
      if (const auto* m = in->FirstChildElement("mass"))
        I.mass = number_attr(m, "value", path_, what);
      else
        note(in, "<inertial> has no <mass>: mass 0", what);
      if (!(I.mass >= 0)) fail(in, what, "mass must not be negative");
      Mat3 J = Mat3::Zero();
      if (const auto* t = in->FirstChildElement("inertia")) {
        const char* k[6] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
        double v[6];
        for (int i = 0; i < 6; ++i) v[i] = t->Attribute(k[i]) ? number_attr(t, k[i], path_, what) : 0.0;
        J << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
      }
      // The tensor is given in the inertial's own frame: rotated into the link frame here (the rotation
      // several loaders drop).
      const Mat3 R = o.q.toRotationMatrix();
      I.inertia = R * J * R.transpose();
      I.com = o.p;
      l.inertial = I;
    }
    auto shapes = [&](const char* tag, bool visual) {
      int k = 0;
      for (auto* v = e->FirstChildElement(tag); v; v = v->NextSiblingElement(tag), ++k) {
        ModelShape s;
        const std::string sw = what + ", " + tag + " " + std::to_string(k);
        s.src = src(v, sw);
        s.visual = visual;
        s.collision = !visual;
        s.weighs = !visual;
        s.pose = origin(v, sw);
        if (!geometry(v, s, sw, tag)) continue;
        if (visual)
          if (const auto* mat = v->FirstChildElement("material")) {
            const UrdfMaterial um = material(mat, false);
            s.color = um.color;
            s.texture = um.texture;
          }
        l.shapes.push_back(std::move(s));
      }
    };
    shapes("visual", true);
    shapes("collision", false);
    link_index_[l.name] = (int)m_.links.size();
    m_.links.push_back(std::move(l));
  }

  void joint(const tinyxml2::XMLElement* e) {
    ModelJoint j;
    j.name = attr_or(e, "name", "");
    if (j.name.empty()) fail(e, "joint", "a <joint> needs a name");
    const std::string what = "joint '" + j.name + "'";
    j.src = src(e, what);
    const std::string type = attr_or(e, "type", "");
    using K = ModelJoint::Kind;
    static const std::map<std::string, K> kinds = {{"revolute", K::revolute},   {"continuous", K::continuous},
                                                   {"prismatic", K::prismatic}, {"fixed", K::fixed},
                                                   {"floating", K::floating},   {"planar", K::planar},
                                                   {"spherical", K::spherical}};
    const auto it = kinds.find(type);
    if (it == kinds.end())
      fail(e, what,
           "unknown joint type '" + type +
               "' (revolute, continuous, prismatic, fixed, floating, planar, spherical)");
    j.kind = it->second;
    auto link_of = [&](const char* tag) {
      const auto* x = e->FirstChildElement(tag);
      if (!x) fail(e, what, std::string("needs a <") + tag + " link=\"...\"/>");
      const std::string n = attr_or(x, "link", "");
      const auto f = link_index_.find(n);
      if (f == link_index_.end()) {
        std::vector<std::string> names;
        for (const auto& l : m_.links) names.push_back(l.name);
        std::string msg = std::string("<") + tag + "> names link '" + n + "', which the file does not define";
        if (auto s = nearest_name(n, names)) msg += "; did you mean '" + *s + "'?";
        fail(x, what, msg);
      }
      return f->second;
    };
    j.parent = link_of("parent");
    j.child = link_of("child");
    if (j.parent == j.child) fail(e, what, "joins link '" + m_.links[j.child].name + "' to itself");
    m_.links[j.child].pose = origin(e, what);
    if (const auto* a = e->FirstChildElement("axis")) {
      j.axis = numbers<3>(a, "xyz", path_, what);
      if (!(j.axis.norm() > 1e-12)) fail(a, what, "the axis must not be zero");
      j.axis.normalize();
    }
    if (const auto* l = e->FirstChildElement("limit")) {
      if (l->Attribute("effort")) j.effort = number_attr(l, "effort", path_, what);
      if (l->Attribute("velocity")) j.velocity = number_attr(l, "velocity", path_, what);
      if (j.kind == K::revolute || j.kind == K::prismatic) {
        const double lo = l->Attribute("lower") ? number_attr(l, "lower", path_, what) : 0.0;
        const double hi = l->Attribute("upper") ? number_attr(l, "upper", path_, what) : 0.0;
        if (lo > hi) fail(l, what, "limit lower is above upper");
        if (lo < hi)
          j.limits = std::array<double, 2>{lo, hi};
        else
          note(l, "equal lower and upper limits: the joint is locked (held as a fixed joint)", what);
        if (lo == hi) j.kind = K::fixed;
      }
    } else if (j.kind == K::revolute || j.kind == K::prismatic) {
      fail(e, what,
           "a " + type + " joint needs a <limit> (URDF requires one; a hinge without stops is 'continuous')");
    }
    if (const auto* d = e->FirstChildElement("dynamics")) {
      if (d->Attribute("damping")) j.damping = number_attr(d, "damping", path_, what);
      if (d->Attribute("friction")) j.friction = number_attr(d, "friction", path_, what);
      if (j.damping < 0 || j.friction < 0) fail(d, what, "damping and friction must not be negative");
    }
    if (const auto* mm = e->FirstChildElement("mimic")) {
      const char* leader = mm->Attribute("joint");
      if (!leader) fail(mm, what, "<mimic> needs joint=\"NAME\" (the joint it follows)");
      j.mimic_joint = leader;
      if (mm->Attribute("multiplier")) j.mimic_multiplier = number_attr(mm, "multiplier", path_, what);
      if (mm->Attribute("offset")) j.mimic_offset = number_attr(mm, "offset", path_, what);
    }
    m_.joints.push_back(std::move(j));
  }

  // A planar joint (two translations in the plane normal to its axis, one rotation about it) as
  // simreel's joints allow: two sliders and a hinge through two helper links of 1e-9 of the
  // child's mass (named CHILD#1, CHILD#2), the hinge's at the child's origin.
  void expand_planar() {
    const size_t joints = m_.joints.size();
    for (size_t k = 0; k < joints; ++k) {
      if (m_.joints[k].kind != ModelJoint::Kind::planar) continue;
      const ModelJoint planar = m_.joints[k];
      const int child = planar.child;
      const Vec3 n = planar.axis;
      const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
      int prev = planar.parent;
      ModelPose rel = m_.links[child].pose;
      for (int h = 0; h < 2; ++h) {
        ModelLink helper;
        helper.name = m_.links[child].name + "#" + std::to_string(h + 1);
        helper.pose = rel;
        helper.src = m_.links[child].src;
        helper.helper_of = child;
        m_.links.push_back(helper);
        ModelJoint slide = planar;
        slide.name = planar.name + (h ? "/y" : "/x");
        slide.kind = ModelJoint::Kind::prismatic;
        slide.axis = h ? v : u;
        slide.parent = prev;
        slide.child = (int)m_.links.size() - 1;
        slide.limits.reset();
        if (planar.limits) slide.limits = planar.limits;
        m_.joints.push_back(slide);
        prev = slide.child;
        rel = ModelPose{};
      }
      m_.links[child].pose = ModelPose{};
      ModelJoint& hinge = m_.joints[k];
      hinge.kind = ModelJoint::Kind::continuous;
      hinge.parent = prev;
      hinge.limits.reset();
      m_.notes.push_back(planar.src.str() + ": planar: two prismatic joints (" + planar.name + "/x, " +
                         planar.name + "/y) and a hinge about its axis, through two helper links");
    }
  }

  void check_tree() {
    std::vector<int> parent_joint(m_.links.size(), -1);
    for (size_t k = 0; k < m_.joints.size(); ++k) {
      const ModelJoint& j = m_.joints[k];
      if (parent_joint[j.child] >= 0)
        throw InputError(j.src.str() + ": link '" + m_.links[j.child].name +
                         "' already has a parent (joint '" + m_.joints[parent_joint[j.child]].name +
                         "'); URDF describes trees: a link has at most one parent joint");
      parent_joint[j.child] = (int)k;
    }
    std::vector<int> roots;
    for (size_t i = 0; i < m_.links.size(); ++i)
      if (parent_joint[i] < 0) roots.push_back((int)i);
    if (roots.empty()) throw InputError(path_ + ": the joints form a loop: no link is the root");
    if (roots.size() > 1) {
      std::string msg =
          path_ + ": " + std::to_string(roots.size()) + " links have no parent joint (URDF has one root): ";
      for (size_t i = 0; i < roots.size() && i < 6; ++i)
        msg += (i ? ", '" : "'") + m_.links[roots[i]].name + "'";
      throw InputError(msg);
    }
    // Every link reaches the root (no cycle hiding beside it).
    for (size_t i = 0; i < m_.links.size(); ++i) {
      size_t hops = 0;
      for (int l = (int)i; parent_joint[l] >= 0; l = m_.joints[parent_joint[l]].parent)
        if (++hops > m_.links.size())
          throw InputError(m_.links[i].src.str() + ": the joints above this link form a loop");
    }
  }
};

}  // namespace

Model read_urdf(const std::string& path, const ImportPaths& paths) {
  return UrdfReader(path, paths).read();
}

}  // namespace simreel
