// The scene's `forces:` list. Its small value readers repeat app/scene/scene.cpp's (which keeps them
// file-local): the same "FILE:LINE:COL: KEY: what" messages, without a shared header between the
// two loaders.
#include "app/scene/scene_forces.hpp"

#include "app/scene/scene_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {

// The readers every part of the scene format shares (app/scene/scene_yaml.hpp).
using namespace scene_yaml;

Vec3 vec3(const YAML::Node& n, const Ctx& c) {
  return vec<3>(n, c);
}

// check_keys for one force type: the message names the type and lists its keys.
void check_keys_of(const YAML::Node& map, const Ctx& c, const std::vector<std::string>& known,
                   const std::string& type) {
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), k) != known.end()) continue;
    std::string msg = "unknown key '" + k + "' for type " + type;
    if (auto s = nearest(k, known)) msg += "; did you mean '" + *s + "'?";
    std::string list;
    for (const std::string& s : known) list += (list.empty() ? "" : ", ") + s;
    c.child(k).fail(kv.first, msg + " (keys: " + list + ")");
  }
}

constexpr EnumNames<ForceKind, 6> kForceTypes{
    {"force", "torque", "impulse", "angular_impulse", "spring", "drag"}};
static_assert(kForceTypes.complete());

constexpr EnumNames<ForceFrame, 2> kForceFrames{{"world", "body"}};
static_assert(kForceFrames.complete());

// The keys each type takes.
std::vector<std::string> keys_of(ForceKind k) {
  switch (k) {
    case ForceKind::force:
      return {"type", "body", "bodies", "vector", "frame", "at", "from", "to"};
    case ForceKind::torque:
      return {"type", "body", "bodies", "vector", "frame", "from", "to"};
    case ForceKind::impulse:
      return {"type", "body", "bodies", "vector", "frame", "at", "time"};
    case ForceKind::angular_impulse:
      return {"type", "body", "bodies", "vector", "frame", "time"};
    case ForceKind::spring:
      return {"type",      "body",        "bodies",  "point", "points", "anchor",
              "stiffness", "rest_length", "damping", "from",  "to"};
    case ForceKind::drag:
      return {"type", "body", "bodies", "linear", "quadratic", "from", "to"};
  }
  return {};
}

class Reader {
 public:
  Reader(const std::string& file, const std::vector<BodyDef>& bodies, double duration,
         std::vector<std::string>& notes)
      : file_(file), bodies_(bodies), duration_(duration), notes_(notes) {
    for (const BodyDef& b : bodies) names_.push_back(b.name);
  }

  void entry(const YAML::Node& n, const Ctx& c, std::vector<ForceDef>& out) {
    if (!n.IsMap())
      c.fail(n, "expected a mapping like { type: force, body: NAME, vector: [x, y, z] }, got " + show(n));
    if (!n["type"]) {
      c.fail(n, "missing key 'type' (force, torque, impulse, angular_impulse, spring or drag)");
    }
    const std::string type = text(n["type"], c.child("type"));
    const std::optional<ForceKind> kind = kForceTypes.parse(type);
    if (!kind) {
      const std::vector<std::string> names(kForceTypes.names.begin(), kForceTypes.names.end());
      std::string msg =
          "unknown force type '" + type + "' (force, torque, impulse, angular_impulse, spring, drag)";
      if (auto s = nearest(type, names)) msg += "; did you mean '" + *s + "'?";
      c.child("type").fail(n["type"], msg);
    }
    check_keys_of(n, c, keys_of(*kind), type);
    ForceDef f;
    f.kind = *kind;
    const bool has_body = (bool)n["body"], has_bodies = (bool)n["bodies"];
    if (has_body && has_bodies)
      c.child("bodies").fail(n["bodies"], "give either 'body' (one name) or 'bodies' (a list), not both");

    // Common values.
    if (n["frame"]) {
      const Ctx fc = c.child("frame");
      const std::string fr = text(n["frame"], fc);
      if (const auto frame = kForceFrames.parse(fr)) {
        f.frame = *frame;
      } else {
        std::string msg = "unknown frame '" + fr + "' (world or body)";
        if (auto s = nearest(fr, {"world", "body"})) msg += "; did you mean '" + *s + "'?";
        fc.fail(n["frame"], msg);
      }
    }
    const bool vectorial = f.kind == ForceKind::force || f.kind == ForceKind::torque || is_impulse(f.kind);
    if (vectorial) {
      if (!n["vector"]) c.fail(n, type + " needs 'vector' ([x, y, z] in " + unit(f.kind) + ")");
      f.vector = vec3(n["vector"], c.child("vector"));
    }
    if (n["at"]) {
      f.at_B = vec3(n["at"], c.child("at"));
      f.at_centroid = false;
    }
    if (n["from"]) f.from = number(n["from"], c.child("from"));
    if (n["to"]) f.to = number(n["to"], c.child("to"));
    if (f.from > f.to)
      c.child("from").fail(n["from"], "the window starts after it ends (from " + n["from"].Scalar() +
                                          " s, to " + n["to"].Scalar() + " s)");
    if (is_impulse(f.kind)) {
      if (!n["time"]) c.fail(n, type + " needs 'time' (s: when it is applied, once)");
      f.time = non_negative(n["time"], c.child("time"));
      if (f.time > duration_)
        notes_.push_back(c.child("time").where(n["time"]) + ": " + type + " at " + n["time"].Scalar() +
                         " s comes after the end of the run (" + fmt(duration_) + " s): it is never applied");
    }

    if (f.kind == ForceKind::spring) {
      spring(n, c, f, has_body, has_bodies, out);
      return;
    }
    if (f.kind == ForceKind::drag) {
      if (!n["linear"] && !n["quadratic"])
        c.fail(n, "drag needs 'linear' (N per m/s) or 'quadratic' (N per (m/s)^2), or both");
      if (n["linear"]) f.linear = non_negative(n["linear"], c.child("linear"));
      if (n["quadratic"]) f.quadratic = non_negative(n["quadratic"], c.child("quadratic"));
      if (!has_body && !has_bodies) {  // every dynamic body
        for (size_t i = 0; i < bodies_.size(); ++i)
          if (bodies_[i].type == BodyType::dynamic) {
            f.body = (int)i;
            out.push_back(f);
          }
        return;
      }
    }
    if (!has_body && !has_bodies)
      c.fail(n, type + " needs 'body' (a body's name) or 'bodies' (a list of names)");
    for (int i : targets(n, c, has_body)) {
      f.body = i;
      out.push_back(f);
    }
  }

 private:
  static const char* unit(ForceKind k) {
    switch (k) {
      case ForceKind::force:
        return "N";
      case ForceKind::torque:
        return "N m";
      case ForceKind::impulse:
        return "N s";
      case ForceKind::angular_impulse:
        return "N m s";
      default:
        return "";
    }
  }
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  int body_index(const YAML::Node& n, const Ctx& c, bool must_be_dynamic) {
    const std::string name = text(n, c);
    const auto it = std::find(names_.begin(), names_.end(), name);
    if (it == names_.end()) {
      std::string msg = "no body is named '" + name + "'";
      if (auto s = nearest(name, names_)) msg += "; did you mean '" + *s + "'?";
      c.fail(n, msg);
    }
    const int i = (int)(it - names_.begin());
    if (must_be_dynamic && bodies_[i].type != BodyType::dynamic)
      c.fail(n, "body '" + name + "' is " + to_string(bodies_[i].type) +
                    ": forces act on dynamic bodies only (a spring may end on any body)");
    return i;
  }

  std::vector<int> targets(const YAML::Node& n, const Ctx& c, bool has_body) {
    if (has_body) return {body_index(n["body"], c.child("body"), true)};
    const YAML::Node l = n["bodies"];
    const Ctx lc = c.child("bodies");
    if (!l.IsSequence() || l.size() == 0)
      lc.fail(l, "expected a non-empty list of body names, got " + show(l));
    std::vector<int> out;
    for (size_t k = 0; k < l.size(); ++k) {
      const int i = body_index(l[k], lc.index(k), true);
      if (std::find(out.begin(), out.end(), i) != out.end())
        lc.index(k).fail(l[k], "names body '" + names_[i] + "' twice");
      out.push_back(i);
    }
    return out;
  }

  // World position of a body point at the start (for a spring's default rest length).
  Vec3 start_point(int i, bool centroid, const Vec3& p_B) const {
    const BodyDef& b = bodies_[i];
    return b.p_WB + b.q_WB.normalized() * (centroid ? b.mass_B().com : p_B);
  }

  void spring(const YAML::Node& n, const Ctx& c, ForceDef& f, bool has_body, bool has_bodies,
              std::vector<ForceDef>& out) {
    if (!has_body && !has_bodies)
      c.fail(n,
             "spring needs 'body' with 'anchor' (a fixed world point) or 'bodies: [a, b]' (between two "
             "bodies)");
    if (!n["stiffness"]) c.fail(n, "spring needs 'stiffness' (N/m)");
    f.stiffness = non_negative(n["stiffness"], c.child("stiffness"));
    if (n["damping"]) f.damping = non_negative(n["damping"], c.child("damping"));
    if (has_body) {
      if (!n["anchor"])
        c.fail(n,
               "spring on one body needs 'anchor' (a fixed world point [x, y, z], m); for a spring "
               "between two bodies give 'bodies: [a, b]'");
      if (n["points"])
        c.child("points").fail(n["points"], "a spring on one body takes 'point', not 'points'");
      f.body = body_index(n["body"], c.child("body"), true);
      f.anchor_W = vec3(n["anchor"], c.child("anchor"));
      if (n["point"]) {
        f.at_B = vec3(n["point"], c.child("point"));
        f.at_centroid = false;
      }
    } else {
      const YAML::Node l = n["bodies"];
      const Ctx lc = c.child("bodies");
      if (!l.IsSequence() || l.size() != 2)
        lc.fail(l, "a spring joins two bodies: expected [a, b], got " +
                       (l.IsSequence() ? "a list of " + std::to_string(l.size()) : show(l)));
      if (n["anchor"])
        c.child("anchor").fail(n["anchor"],
                               "a spring has one fixed anchor or a second body, not both (drop 'anchor' or "
                               "use 'body')");
      if (n["point"])
        c.child("point").fail(n["point"],
                              "a spring between two bodies takes 'points: [[x, y, z], [x, y, z]]'");
      int ia = body_index(l[0], lc.index(0), false), ib = body_index(l[1], lc.index(1), false);
      if (ia == ib) lc.fail(l, "a spring needs two different bodies");
      bool ca = true, cb = true;
      Vec3 pa = Vec3::Zero(), pb = Vec3::Zero();
      if (const YAML::Node p = n["points"]) {
        const Ctx pc = c.child("points");
        if (!p.IsSequence() || p.size() != 2)
          pc.fail(p, "expected two points [[x, y, z], [x, y, z]] (one per body), got " +
                         (p.IsSequence() ? "a list of " + std::to_string(p.size()) : show(p)));
        pa = vec3(p[0], pc.index(0));
        pb = vec3(p[1], pc.index(1));
        ca = cb = false;
      }
      const bool da = bodies_[ia].type == BodyType::dynamic, db = bodies_[ib].type == BodyType::dynamic;
      if (!da && !db)
        lc.fail(l, "neither '" + names_[ia] + "' nor '" + names_[ib] +
                       "' is dynamic: a spring must move at least one body");
      if (!da) {  // the dynamic end first
        std::swap(ia, ib);
        std::swap(ca, cb);
        std::swap(pa, pb);
      }
      f.body = ia;
      f.body_b = ib;
      f.at_centroid = ca;
      f.at_B = pa;
      f.at_b_centroid = cb;
      f.at_b_B = pb;
    }
    if (n["rest_length"]) {
      f.rest_length = non_negative(n["rest_length"], c.child("rest_length"));
    } else {
      const Vec3 a = start_point(f.body, f.at_centroid, f.at_B);
      const Vec3 b = f.body_b >= 0 ? start_point(f.body_b, f.at_b_centroid, f.at_b_B) : f.anchor_W;
      f.rest_length = (a - b).norm();  // unstretched at the start
    }
    out.push_back(f);
  }

  std::string file_;
  const std::vector<BodyDef>& bodies_;
  double duration_;
  std::vector<std::string>& notes_;
  std::vector<std::string> names_;
};

}  // namespace

std::vector<ForceDef> load_forces(const YAML::Node& list, const std::string& file,
                                  const std::vector<BodyDef>& bodies, double duration,
                                  std::vector<std::string>& notes) {
  const Ctx c(file, "forces");
  if (list.IsNull()) return {};
  if (!list.IsSequence())
    c.fail(list,
           "expected a list of forces (- { type: force, body: NAME, vector: [x, y, z] }), got " + show(list));
  Reader r(file, bodies, duration, notes);
  std::vector<ForceDef> out;
  for (size_t k = 0; k < list.size(); ++k) r.entry(list[k], c.index(k), out);
  return out;
}

}  // namespace simreel
