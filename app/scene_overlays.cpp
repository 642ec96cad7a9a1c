#include "app/scene_overlays.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/scene.hpp"
#include "app/scene_yaml.hpp"
#include "sim/error.hpp"

namespace simreel {

namespace {

// The readers every part of the scene format shares (app/scene_yaml.hpp): values are read, and
// refused, as strictly here as in the rest of the scene.
using namespace scene_yaml;

double in_range(const YAML::Node& n, const Ctx& w, double lo, double hi, bool open_lo = false) {
  const double v = number(n, w);
  if (v < lo || v > hi || (open_lo && v == lo)) {
    std::ostringstream os;
    os << "must lie in " << (open_lo ? "(" : "[") << lo << ", " << hi << "], got " << show(n);
    w.fail(n, os.str());
  }
  return v;
}

Vec3 vec3(const YAML::Node& n, const Ctx& w) {
  return vec<3>(n, w);
}

ShowRgb rgb(const YAML::Node& n, const Ctx& w) {
  const Vec3 v = vec3(n, w);
  for (int i = 0; i < 3; ++i)
    if (v[i] < 0 || v[i] > 1) w.index(i).fail(n[i], "colour components must lie in [0, 1]");
  return {(float)v[0], (float)v[1], (float)v[2]};
}

// A HUD line may be empty (a spacer); every other text value may not (scene_yaml::text).
std::string line_text(const YAML::Node& n, const Ctx& w) {
  if (!n.IsScalar()) w.fail(n, "expected text, got " + show(n));
  return n.Scalar();
}

const std::vector<std::pair<std::string, ShowKind>>& kinds() {
  static const std::vector<std::pair<std::string, ShowKind>> k = {
      {"axes", ShowKind::axes},
      {"angular_velocity", ShowKind::angular_velocity},
      {"angular_momentum", ShowKind::angular_momentum},
      {"velocity", ShowKind::velocity},
      {"center_of_mass", ShowKind::center_of_mass},
      {"trail", ShowKind::trail},
      {"inertia_box", ShowKind::inertia_box},
      {"inertia_ellipsoid", ShowKind::inertia_ellipsoid},
      {"cones", ShowKind::cones},
      {"poinsot", ShowKind::poinsot},
  };
  return k;
}

// The keys each kind takes.
std::vector<std::string> keys_of(ShowKind k) {
  switch (k) {
    case ShowKind::axes:
      return {"scale", "width", "opacity", "xray"};
    case ShowKind::angular_velocity:
    case ShowKind::angular_momentum:
    case ShowKind::velocity:
      return {"color", "scale", "width", "opacity", "xray"};
    case ShowKind::center_of_mass:
      return {"color", "scale", "opacity", "xray"};
    case ShowKind::trail:
      return {"point", "frame", "length", "color", "width", "opacity"};
    case ShowKind::inertia_box:
    case ShowKind::inertia_ellipsoid:
      return {"color", "opacity"};
    case ShowKind::cones:
      return {"scale", "opacity", "xray"};
    case ShowKind::poinsot:
      return {"scale", "opacity", "length", "width"};
  }
  return {};
}

ShowItem show_item(const YAML::Node& n, const Ctx& w, double duration) {
  std::vector<std::string> names;
  for (const auto& [name, kind] : kinds()) names.push_back(name);
  std::string name;
  YAML::Node opts;
  if (n.IsScalar()) {
    name = n.Scalar();
  } else if (n.IsMap() && n.size() == 1) {
    name = n.begin()->first.as<std::string>();
    opts = n.begin()->second;
  } else {
    w.fail(n, "expected an item name (axes, angular_velocity, ...) or { name: { options } }, got " + show(n));
  }
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string msg = "unknown item '" + name + "'";
    if (auto s = nearest(name, names))
      msg += "; did you mean '" + *s + "'?";
    else {
      msg += " (";
      for (size_t i = 0; i < names.size(); ++i) msg += (i ? ", " : "") + names[i];
      msg += ")";
    }
    w.fail(n, msg);
  }
  ShowItem item;
  item.kind = kinds()[(size_t)(it - names.begin())].second;
  if (item.kind == ShowKind::inertia_box || item.kind == ShowKind::inertia_ellipsoid) item.opacity = 0.35;
  if (item.kind == ShowKind::cones) item.opacity = 0.3;
  if (item.kind == ShowKind::poinsot) item.opacity = 0.3, item.length = duration, item.width = 3;
  if (item.kind == ShowKind::trail) item.width = 3;
  if (!opts || opts.IsNull()) return item;
  const Ctx c = w.child(name);
  check_keys(opts, c, keys_of(item.kind));
  if (opts["color"]) item.color = rgb(opts["color"], c.child("color"));
  if (opts["scale"]) item.scale = in_range(opts["scale"], c.child("scale"), 0, 1e9, true);
  if (opts["width"]) item.width = in_range(opts["width"], c.child("width"), 0, 100, true);
  if (opts["opacity"]) item.opacity = in_range(opts["opacity"], c.child("opacity"), 0, 1);
  if (const YAML::Node x = opts["xray"]) {
    if (x.IsScalar() && (x.Scalar() == "true" || x.Scalar() == "yes" || x.Scalar() == "on"))
      item.xray = 0.35;
    else if (x.IsScalar() && (x.Scalar() == "false" || x.Scalar() == "no" || x.Scalar() == "off"))
      item.xray = 0;
    else
      item.xray = in_range(x, c.child("xray"), 0, 1);
  }
  if (opts["point"]) item.point = vec3(opts["point"], c.child("point"));
  if (const YAML::Node f = opts["frame"]) {
    const std::string fr = text(f, c.child("frame"));
    if (fr != "body" && fr != "world")
      c.child("frame").fail(
          f, "expected body (point in the body's frame) or world (where it is at t = 0), got " + show(f));
    item.point_in_world = fr == "world";
  }
  if (opts["length"]) item.length = in_range(opts["length"], c.child("length"), 0, 1e6, true);
  return item;
}

// "[+][width][.precision][type]" to a printf conversion; empty spec: "%.6g" (an integer "%d").
bool printf_of(const std::string& spec, bool integer, std::string& out) {
  if (spec.empty()) {
    out = integer ? "%ld" : "%.6g";
    return true;
  }
  size_t i = 0;
  std::string f = "%";
  if (i < spec.size() && (spec[i] == '+' || spec[i] == ' ')) f += spec[i++];
  while (i < spec.size() && std::isdigit((unsigned char)spec[i]) && f.size() < 6) f += spec[i++];
  if (i < spec.size() && spec[i] == '.') {
    f += spec[i++];
    if (i >= spec.size() || !std::isdigit((unsigned char)spec[i])) return false;
    while (i < spec.size() && std::isdigit((unsigned char)spec[i]) && f.size() < 9) f += spec[i++];
  }
  char type = integer ? 'd' : 'g';
  if (i < spec.size()) type = spec[i++];
  if (i != spec.size() || std::string("fegd").find(type) == std::string::npos) return false;
  if (type == 'd' && !integer) return false;
  f += type == 'd' ? std::string("ld") : std::string(1, type);
  if (integer && type != 'd') return false;
  out = f;
  return true;
}

HudLine hud_line(const YAML::Node& n, const Ctx& w, const Scene& s) {
  HudLine line;
  line.source = line_text(n, w);
  const std::string& src = line.source;
  std::string lit;
  auto bad = [&](const std::string& what) { w.fail(n, "'" + src + "': " + what); };
  for (size_t i = 0; i < src.size(); ++i) {
    const char ch = src[i];
    if (ch == '}') {
      if (i + 1 < src.size() && src[i + 1] == '}') {
        lit += '}', ++i;
        continue;
      }
      bad("a lone '}' (write '}}' for the character)");
    }
    if (ch != '{') {
      lit += ch;
      continue;
    }
    if (i + 1 < src.size() && src[i + 1] == '{') {
      lit += '{', ++i;
      continue;
    }
    const size_t close = src.find('}', i);
    if (close == std::string::npos) bad("a '{' without its '}'");
    std::string field = src.substr(i + 1, close - i - 1), spec;
    if (const size_t colon = field.find(':'); colon != std::string::npos)
      spec = field.substr(colon + 1), field = field.substr(0, colon);
    HudField f;
    if (field.size() >= 2 && field.front() == '|' && field.back() == '|')
      f.norm = true, field = field.substr(1, field.size() - 2);
    // [body.]name[.x|.y|.z]
    std::vector<std::string> parts;
    for (size_t a = 0;;) {
      const size_t dot = field.find('.', a);
      parts.push_back(field.substr(a, dot == std::string::npos ? std::string::npos : dot - a));
      if (dot == std::string::npos) break;
      a = dot + 1;
    }
    if (parts.size() > 1 && (parts.back() == "x" || parts.back() == "y" || parts.back() == "z")) {
      f.component = parts.back()[0] - 'x';
      parts.pop_back();
    }
    const auto& scalars = hud_scalar_names();
    const auto& vectors = hud_body_names();
    std::vector<std::string> all = scalars;
    all.insert(all.end(), vectors.begin(), vectors.end());
    std::string body;
    if (parts.size() == 2)
      body = parts[0], f.name = parts[1];
    else if (parts.size() == 1)
      f.name = parts[0];
    else
      bad("'{" + field + "}' is not a quantity ([body.]name[.x|.y|.z])");
    const bool scalar = std::find(scalars.begin(), scalars.end(), f.name) != scalars.end();
    const bool vector = std::find(vectors.begin(), vectors.end(), f.name) != vectors.end();
    if (!scalar && !vector) {
      std::string msg = "unknown quantity '" + f.name + "'";
      if (auto sug = nearest(f.name, all)) msg += "; did you mean '" + *sug + "'?";
      msg += " (t, video_t, frame, E, E_drift, L_drift; per body omega, omega_body, L, v, position)";
      bad(msg);
    }
    if (scalar && (!body.empty() || f.component >= 0 || f.norm))
      bad("'" + f.name + "' is a number of the whole scene: no body, component or |...|");
    if (vector) {
      if (body.empty()) {
        for (size_t b = 0; b < s.bodies.size() && f.body < 0; ++b)
          if (s.bodies[b].type == BodyType::dynamic) f.body = (int)b;
        if (f.body < 0) bad("'" + f.name + "' needs a moving body, and the scene has none");
      } else {
        std::vector<std::string> names;
        for (const BodyDef& b : s.bodies) names.push_back(b.name);
        const auto it = std::find(names.begin(), names.end(), body);
        if (it == names.end()) {
          std::string msg = "no body is named '" + body + "'";
          if (auto sug = nearest(body, names)) msg += "; did you mean '" + *sug + "'?";
          bad(msg);
        }
        f.body = (int)(it - names.begin());
      }
      if (f.norm && f.component >= 0) bad("'{" + field + "}': a component or |...|, not both");
    }
    if (!printf_of(spec, f.name == "frame", f.printf))
      bad("format '" + spec + "' of {" + field + "} is not [+][width][.precision][f|e|g" +
          (f.name == "frame" ? "|d" : "") + "]");
    line.text.push_back(lit);
    lit.clear();
    line.fields.push_back(f);
    i = close;
  }
  line.text.push_back(lit);
  return line;
}

}  // namespace

const char* to_string(ShowKind k) {
  for (const auto& [name, kind] : kinds())
    if (kind == k) return name.c_str();
  return "?";
}

const std::vector<std::string>& hud_scalar_names() {
  static const std::vector<std::string> v = {"t", "video_t", "frame", "E", "E_drift", "L_drift"};
  return v;
}
const std::vector<std::string>& hud_body_names() {
  static const std::vector<std::string> v = {"omega", "omega_body", "L", "v", "position"};
  return v;
}

bool OverlaySpec::any() const {
  if (!hud.empty() || !title.empty()) return true;
  for (const auto& b : show)
    if (!b.empty()) return true;
  return false;
}

void load_overlays(const YAML::Node& root, const std::string& path, Scene& s) {
  OverlaySpec& o = s.overlays;
  o.show.assign(s.bodies.size(), {});
  const Ctx top(path, "");
  if (const YAML::Node bodies = root["bodies"]; bodies && bodies.IsSequence())
    for (size_t i = 0; i < bodies.size() && i < s.bodies.size(); ++i) {
      const YAML::Node sh = bodies[i]["show"];
      if (!sh) continue;
      const Ctx w = top.child("bodies").index(i).child("show");
      if (!sh.IsSequence())
        w.fail(sh, "expected a list of items (axes, angular_velocity, ...), got " + show(sh));
      if (s.bodies[i].type != BodyType::dynamic)
        w.fail(sh, "body '" + s.bodies[i].name + "' does not move: show items are for moving bodies");
      for (size_t k = 0; k < sh.size(); ++k) o.show[i].push_back(show_item(sh[k], w.index(k), s.duration));
    }
  const YAML::Node ov = root["overlays"];
  if (!ov) return;
  const Ctx w = top.child("overlays");
  check_keys(ov, w, {"hud", "title", "text_size"});
  if (const YAML::Node h = ov["hud"]) {
    const Ctx hw = w.child("hud");
    // A copy binds to the node (operator= would write into `h`; reset() throws on a missing key).
    const YAML::Node lines = h.IsMap() ? h["lines"] : h;
    if (h.IsMap()) {
      check_keys(h, hw, {"lines", "corner"});
      if (const YAML::Node c = h["corner"]) {
        o.hud_corner = text(c, hw.child("corner"));
        const std::vector<std::string> corners = {"top_left", "top_right", "bottom_left", "bottom_right"};
        if (std::find(corners.begin(), corners.end(), o.hud_corner) == corners.end())
          hw.child("corner").fail(
              c, "expected top_left, top_right, bottom_left or bottom_right, got " + show(c));
      }
      if (!lines) hw.fail(h, "missing key 'lines' (a list of text lines)");
    }
    const Ctx lw = h.IsMap() ? hw.child("lines") : hw;
    if (!lines.IsSequence()) lw.fail(lines, "expected a list of text lines, got " + show(lines));
    for (size_t k = 0; k < lines.size(); ++k) o.hud.push_back(hud_line(lines[k], lw.index(k), s));
  }
  if (ov["title"]) o.title = text(ov["title"], w.child("title"));
  if (ov["text_size"]) o.text_size = in_range(ov["text_size"], w.child("text_size"), 0.25, 4);
}

}  // namespace simreel
