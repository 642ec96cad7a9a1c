#include "app/scene/scene_overlays.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {

// The readers every part of the scene format shares (app/scene/scene_yaml.hpp): values are read, and
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

constexpr EnumNames<ShowKind, 17> kShowKinds{
    {"axes", "angular_velocity", "angular_momentum", "velocity", "center_of_mass", "trail", "inertia_box",
     "inertia_ellipsoid", "cones", "poinsot", "forces", "contacts", "joints", "joint_forces", "momentum",
     "angular_momentum_about", "snapshot"}};
static_assert(kShowKinds.complete());

// The keys each kind takes.
std::vector<std::string> keys_of(ShowKind k) {
  switch (k) {
    case ShowKind::axes:
      return {"scale", "width", "opacity", "xray"};
    case ShowKind::angular_velocity:
    case ShowKind::angular_momentum:
    case ShowKind::velocity:
    case ShowKind::momentum:
      return {"color", "scale", "width", "opacity", "xray"};
    case ShowKind::angular_momentum_about:
      return {"color", "scale", "width", "opacity", "xray", "point"};
    case ShowKind::snapshot:
      return {"at", "color", "opacity"};
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
    case ShowKind::forces:
      return {"color", "scale",   "torque_scale", "width",  "opacity",
              "xray",  "gravity", "anchor",       "arrows", "springs"};
    case ShowKind::contacts:
      return {"color", "scale", "width", "opacity", "xray", "points", "normals", "arrows"};
    case ShowKind::joints:
      return {"color", "scale", "width", "opacity", "xray"};
    case ShowKind::joint_forces:
      return {"color", "scale", "torque_scale", "width", "opacity", "xray"};
  }
  return {};
}

ShowItem show_item(const YAML::Node& n, const Ctx& w, double duration) {
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
  const std::optional<ShowKind> kind = kShowKinds.parse(name);
  if (!kind) {
    const std::vector<std::string> names(kShowKinds.names.begin(), kShowKinds.names.end());
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
  item.kind = *kind;
  if (item.kind == ShowKind::inertia_box || item.kind == ShowKind::inertia_ellipsoid) item.opacity = 0.35;
  if (item.kind == ShowKind::cones) item.opacity = 0.3;
  if (item.kind == ShowKind::poinsot) item.opacity = 0.3, item.length = duration, item.width = 3;
  if (item.kind == ShowKind::trail) item.width = 3;
  if (item.kind == ShowKind::contacts) item.xray = 0.6;  // contact forces lie inside the bodies
  if (item.kind == ShowKind::forces) item.xray = 0.35;
  if (item.kind == ShowKind::joints) item.xray = 0.5;         // a pivot sits half inside its body
  if (item.kind == ShowKind::joint_forces) item.xray = 0.35;  // as `forces`: arrows start at the pivot
  if (item.kind == ShowKind::snapshot) {
    item.opacity = 0.35;
    if (!opts || opts.IsNull() || !opts["at"])
      w.fail(n,
             "snapshot: missing key 'at' (the time of the copy, s, or a list of times): "
             "{ snapshot: { at: [0.5, 1.5] } }");
  }
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
  if (const YAML::Node a = opts["at"]) {
    const Ctx ac = c.child("at");
    if (a.IsSequence()) {
      if (a.size() == 0) ac.fail(a, "expected a time (s) or a list of times, got an empty list");
      for (size_t k = 0; k < a.size(); ++k) item.at.push_back(in_range(a[k], ac.index(k), 0, duration));
    } else {
      item.at.push_back(in_range(a, ac, 0, duration));
    }
    std::sort(item.at.begin(), item.at.end());
  }
  if (const YAML::Node f = opts["frame"]) {
    const std::string fr = text(f, c.child("frame"));
    if (fr != "body" && fr != "world")
      c.child("frame").fail(
          f, "expected body (point in the body's frame) or world (where it is at t = 0), got " + show(f));
    item.point_in_world = fr == "world";
  }
  if (opts["length"]) item.length = in_range(opts["length"], c.child("length"), 0, 1e6, true);
  if (opts["torque_scale"])
    item.torque_scale = in_range(opts["torque_scale"], c.child("torque_scale"), 0, 1e9, true);
  if (opts["gravity"]) item.gravity = boolean(opts["gravity"], c.child("gravity"));
  if (const YAML::Node a = opts["anchor"]) {
    const std::string v = text(a, c.child("anchor"));
    if (v != "tail" && v != "tip")
      c.child("anchor").fail(
          a,
          "expected tail (the arrow starts at the point of action) or tip (it ends there), got " + show(a));
    item.at_tip = v == "tip";
  }
  if (opts["points"]) item.points = boolean(opts["points"], c.child("points"));
  if (opts["normals"]) item.normals = boolean(opts["normals"], c.child("normals"));
  if (opts["arrows"]) item.arrows = boolean(opts["arrows"], c.child("arrows"));
  if (const YAML::Node sp = opts["springs"]) {
    // `line`: straight, for springs standing in for strings (a Newton's cradle); else a bool.
    item.spring_lines = sp.IsScalar() && sp.Scalar() == "line";
    if (!item.spring_lines) {
      if (sp.IsScalar() && sp.Scalar() != "true" && sp.Scalar() != "false" && sp.Scalar() != "yes" &&
          sp.Scalar() != "no" && sp.Scalar() != "on" && sp.Scalar() != "off")
        c.child("springs").fail(sp, "expected true, false or line (straight lines), got " + show(sp));
      item.springs = boolean(sp, c.child("springs"));
    }
  }
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

// A '{' at src[i] that opens a TeX group: right after '_' or '^', or after a TeX command such as
// \vec or \dot (a backslash and letters).
bool tex_group_opens(const std::string& src, size_t i) {
  if (i == 0) return false;
  if (src[i - 1] == '_' || src[i - 1] == '^') return true;
  size_t k = i;
  while (k > 0 && std::isalpha((unsigned char)src[k - 1])) --k;
  return k < i && k > 0 && src[k - 1] == '\\';
}

HudLine hud_line(const YAML::Node& n, const Ctx& w, const Scene& s) {
  HudLine line;
  line.source = line_text(n, w);
  const std::string& src = line.source;
  std::string lit;
  const std::function<void(const std::string&)> bad = [&](const std::string& what) {
    w.fail(n, "'" + src + "': " + what);
  };
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
    if (tex_group_opens(src, i)) {  // x_{ij}, \vec{L}: a TeX group (render/tex.hpp), not a field
      const size_t close = src.find('}', i);
      if (close == std::string::npos) bad("a TeX group '{' without its '}'");
      lit += src.substr(i, close - i + 1);
      i = close;
      continue;
    }
    const size_t close = src.find('}', i);
    if (close == std::string::npos) bad("a '{' without its '}'");
    std::string field = src.substr(i + 1, close - i - 1), spec;
    if (const size_t colon = field.find(':'); colon != std::string::npos)
      spec = field.substr(colon + 1), field = field.substr(0, colon);
    HudField f = parse_field(field, s, -1, bad);
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

// A quantity's name in the TeX subset: omega_body.y -> \omega_2, |L| -> |L|, v.x -> v_x.
std::string default_plot_label(const HudField& f, const Scene& s) {
  if (f.is_expr() || f.is_meter()) {  // as written, its TeX characters escaped
    std::string out;
    for (char c : f.source) {
      if (c == '_' || c == '^' || c == '{' || c == '}' || c == '\\') out += '\\';
      out += c;
    }
    return out;
  }
  std::string base = f.name;
  bool body_axes = false;
  if (f.name == "omega") base = "\\omega";
  if (f.name == "omega_body") base = "\\omega", body_axes = true;
  if (f.name == "position") base = "x";
  if (f.name == "E_drift") return "E/E_0 - 1";
  if (f.name == "tilt") return "\\theta";
  if (f.name == "precession") return "\\Omega";
  if (f.name == "L_drift") return "|L - L_0|/|L_0|";
  if (f.name == "joint_gap") return "gap (m)";
  if (f.joint >= 0) {
    const bool slider = s.joints[f.joint].type == JointType::prismatic;
    std::string q = slider ? "x" : "\\theta";
    if (f.name.starts_with("speed")) q = slider ? "\\dot x" : "\\dot\\theta";
    if (f.name.starts_with("period")) q = "T";
    if (f.coord == 1) q += "_2";
    if (s.joints.size() > 1) q += " (" + s.joints[f.joint].name + ")";
    return q;
  }
  if (f.norm) return "|" + base + "|";
  if (f.component >= 0) {
    if (f.name == "position") return std::string(1, (char)('x' + f.component));
    return base + "_" +
           (body_axes ? std::string(1, (char)('1' + f.component))
                      : std::string(1, (char)('x' + f.component)));
  }
  return base;
}

int body_index(const YAML::Node& n, const Ctx& c, const Scene& s) {
  const std::string name = text(n, c);
  std::vector<std::string> names;
  for (const BodyDef& b : s.bodies) names.push_back(b.name);
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string msg = "no body is named '" + name + "'";
    if (auto sug = nearest(name, names)) msg += "; did you mean '" + *sug + "'?";
    c.fail(n, msg);
  }
  return (int)(it - names.begin());
}

const YAML::Node& list_of(const YAML::Node& n, const Ctx& c, const char* what) {
  if (!n.IsSequence()) c.fail(n, std::string("expected a list of ") + what + ", got " + show(n));
  return n;
}

void load_captions(const YAML::Node& n, const Ctx& w, Scene& s) {
  list_of(n, w, "captions ({ text, from, to })");
  for (size_t k = 0; k < n.size(); ++k) {
    const Ctx c = w.index(k);
    const YAML::Node e = n[k];
    if (!e.IsMap()) c.fail(e, "expected { text: ..., from: s, to: s }, got " + show(e));
    check_keys(e, c, {"text", "from", "to", "fade", "position"});
    Caption cap;
    if (!e["text"]) c.fail(e, "missing key 'text'");
    cap.text = text(e["text"], c.child("text"));
    cap.from = e["from"] ? in_range(e["from"], c.child("from"), 0, 1e9) : 0.0;
    cap.to = e["to"] ? in_range(e["to"], c.child("to"), 0, 1e9) : s.duration + 1;
    if (cap.to <= cap.from) {
      if (!e["to"])
        c.child("from").fail(e["from"], "comes after the end of the run: the caption would never show");
      c.child("to").fail(e["to"], "must come after 'from'");
    }
    if (e["fade"]) cap.fade = in_range(e["fade"], c.child("fade"), 0, 1e6);
    if (const YAML::Node p = e["position"]) {
      cap.position = text(p, c.child("position"));
      if (cap.position != "bottom" && cap.position != "top" && cap.position != "center")
        c.child("position").fail(p, "expected bottom, top or center, got " + show(p));
    }
    s.overlays.captions.push_back(cap);
  }
}

void load_labels(const YAML::Node& n, const Ctx& w, Scene& s) {
  list_of(n, w, "labels ({ body, text })");
  for (size_t k = 0; k < n.size(); ++k) {
    const Ctx c = w.index(k);
    const YAML::Node e = n[k];
    if (!e.IsMap()) c.fail(e, "expected { body: NAME, text: ... }, got " + show(e));
    check_keys(e, c, {"body", "text", "offset", "color"});
    BodyLabel l;
    if (!e["body"]) c.fail(e, "missing key 'body'");
    if (!e["text"]) c.fail(e, "missing key 'text'");
    l.body = body_index(e["body"], c.child("body"), s);
    l.text = text(e["text"], c.child("text"));
    if (e["offset"]) {
      const Eigen::Vector2d v = vec<2>(e["offset"], c.child("offset"));
      if (std::fabs(v.x()) > 1e4 || std::fabs(v.y()) > 1e4)
        c.child("offset").fail(e["offset"], "must lie within 10000 px");
      l.has_offset = true, l.dx = v.x(), l.dy = v.y();
    }
    if (e["color"]) l.color = rgb(e["color"], c.child("color"));
    s.overlays.labels.push_back(l);
  }
}

const std::vector<std::string>& corners() {
  static const std::vector<std::string> c = {"top_left", "top_right", "bottom_left", "bottom_right"};
  return c;
}

std::string corner(const YAML::Node& n, const Ctx& c) {
  const std::string v = text(n, c);
  if (std::find(corners().begin(), corners().end(), v) == corners().end())
    c.fail(n, "expected top_left, top_right, bottom_left or bottom_right, got " + show(n));
  return v;
}

void load_legend(const YAML::Node& n, const Ctx& w, Scene& s) {
  Legend& L = s.overlays.legend;
  if (n.IsScalar()) {
    L.shown = boolean(n, w);
    return;
  }
  if (!n.IsMap()) w.fail(n, "expected true, or { corner: C, items: [{ text, color }] }, got " + show(n));
  check_keys(n, w, {"corner", "items"});
  L.shown = true;
  if (n["corner"]) L.corner = corner(n["corner"], w.child("corner"));
  if (const YAML::Node items = n["items"]) {
    const Ctx iw = w.child("items");
    list_of(items, iw, "legend entries ({ text, color })");
    for (size_t k = 0; k < items.size(); ++k) {
      const Ctx c = iw.index(k);
      const YAML::Node e = items[k];
      if (!e.IsMap()) c.fail(e, "expected { text: ..., color: [r, g, b] }, got " + show(e));
      check_keys(e, c, {"text", "color"});
      if (!e["text"]) c.fail(e, "missing key 'text'");
      if (!e["color"]) c.fail(e, "missing key 'color'");
      L.items.push_back({text(e["text"], c.child("text")), rgb(e["color"], c.child("color"))});
    }
  }
}

void load_plots(const YAML::Node& n, const Ctx& w, Scene& s) {
  list_of(n, w, "plots ({ quantities: [...] })");
  for (size_t k = 0; k < n.size(); ++k) {
    const Ctx c = w.index(k);
    const YAML::Node e = n[k];
    if (!e.IsMap())
      c.fail(e, "expected { quantities: [omega_body.x, ...], rect: [x, y, w, h] }, got " + show(e));
    check_keys(e, c, {"quantities", "body", "rect", "y_range", "labels", "colors", "title"});
    PlotSpec p;
    const int body = e["body"] ? body_index(e["body"], c.child("body"), s) : -1;
    if (body >= 0 && s.bodies[body].type != BodyType::dynamic)
      c.child("body").fail(e["body"], "body '" + s.bodies[body].name + "' does not move");
    if (!e["quantities"]) c.fail(e, "missing key 'quantities' (a list such as [omega_body.x, omega_body.y])");
    const Ctx qw = c.child("quantities");
    const YAML::Node q = list_of(e["quantities"], qw, "quantities");
    if (q.size() == 0 || q.size() > 8) qw.fail(q, "expected 1 to 8 quantities");
    for (size_t j = 0; j < q.size(); ++j) {
      const Ctx qc = qw.index(j);
      const std::string name = text(q[j], qc);
      const std::function<void(const std::string&)> bad = [&](const std::string& m) {
        qc.fail(q[j], "'" + name + "': " + m);
      };
      HudField f = parse_field(name, s, body, bad);
      if (f.name == "t" || f.name == "video_t" || f.name == "frame")
        bad("plots are against time already: plot another quantity");
      if (f.uses("frame") || f.uses("video_t"))
        bad("a plot is sampled at physics steps, where there is no video frame: use t");
      if (!f.scalar()) bad("a vector: plot a component (" + name + ".x) or its magnitude (|" + name + "|)");
      f.printf = "%.6g";
      p.quantities.push_back(f);
      p.labels.push_back(default_plot_label(f, s));
    }
    if (const YAML::Node l = e["labels"]) {
      const Ctx lc = c.child("labels");
      list_of(l, lc, "labels");
      if (l.size() != q.size())
        lc.fail(l, "expected one label per quantity (" + std::to_string(q.size()) + ")");
      for (size_t j = 0; j < l.size(); ++j) p.labels[j] = text(l[j], lc.index(j));
    }
    p.colors.assign(q.size(), std::nullopt);
    if (const YAML::Node l = e["colors"]) {
      const Ctx lc = c.child("colors");
      list_of(l, lc, "colours");
      if (l.size() != q.size())
        lc.fail(l, "expected one colour per quantity (" + std::to_string(q.size()) + ")");
      for (size_t j = 0; j < l.size(); ++j) p.colors[j] = rgb(l[j], lc.index(j));
    }
    if (const YAML::Node r = e["rect"]) {
      const Ctx rc = c.child("rect");
      const Eigen::Vector4d v = vec<4>(r, rc);
      if (v[0] < 0 || v[1] < 0 || v[2] < 0.05 || v[3] < 0.05 || v[0] + v[2] > 1 + 1e-9 ||
          v[1] + v[3] > 1 + 1e-9)
        rc.fail(r,
                "[x, y, w, h] as fractions of the frame from its top left: w and h at least 0.05, inside the "
                "frame");
      for (int j = 0; j < 4; ++j) p.rect[j] = v[j];
    }
    if (const YAML::Node y = e["y_range"]) {
      const Ctx yc = c.child("y_range");
      if (!(y.IsScalar() && y.Scalar() == "auto")) {
        const Eigen::Vector2d v = vec<2>(y, yc);
        if (!(v[1] > v[0])) yc.fail(y, "expected auto or [min, max] with min < max, got " + show(y));
        p.auto_range = false, p.y_min = v[0], p.y_max = v[1];
      }
    }
    if (e["title"]) p.title = text(e["title"], c.child("title"));
    s.overlays.plots.push_back(p);
  }
}

// `system:` (one mapping or a list): { bodies: [a, b] (default: every moving body), show: [momentum,
// velocity, angular_momentum, center_of_mass], name: "system" }.
void load_systems(const YAML::Node& n, const Ctx& w, Scene& s) {
  auto one = [&](const YAML::Node& e, const Ctx& c) {
    if (!e.IsMap())
      c.fail(e, "expected { bodies: [a, b], show: [momentum, center_of_mass, angular_momentum] }, got " +
                    show(e));
    check_keys(e, c, {"bodies", "show", "name"});
    SystemSpec y;
    if (const YAML::Node b = e["bodies"]) {
      const Ctx bc = c.child("bodies");
      const YAML::Node l = list_of(b, bc, "bodies");
      for (size_t k = 0; k < l.size(); ++k) {
        const int i = body_index(l[k], bc.index(k), s);
        if (s.bodies[i].type != BodyType::dynamic)
          bc.index(k).fail(l[k],
                           "body '" + s.bodies[i].name + "' does not move: a system is of moving bodies");
        if (std::find(y.bodies.begin(), y.bodies.end(), i) != y.bodies.end())
          bc.index(k).fail(l[k], "body '" + s.bodies[i].name + "' is listed twice");
        y.bodies.push_back(i);
      }
    } else {
      for (size_t i = 0; i < s.bodies.size(); ++i)
        if (s.bodies[i].type == BodyType::dynamic) y.bodies.push_back((int)i);
    }
    if (y.bodies.empty()) c.fail(e, "a system needs at least one moving body");
    if (!e["show"]) c.fail(e, "missing key 'show' (momentum, velocity, angular_momentum, center_of_mass)");
    const Ctx sc = c.child("show");
    const YAML::Node l = list_of(e["show"], sc, "show");
    for (size_t k = 0; k < l.size(); ++k) {
      ShowItem item = show_item(l[k], sc.index(k), s.duration);
      if (item.kind != ShowKind::momentum && item.kind != ShowKind::velocity &&
          item.kind != ShowKind::angular_momentum && item.kind != ShowKind::center_of_mass)
        sc.index(k).fail(l[k], std::string("a system shows momentum, velocity, angular_momentum or "
                                           "center_of_mass (of its bodies taken together), not ") +
                                   to_string(item.kind));
      y.show.push_back(item);
    }
    if (e["name"]) y.name = text(e["name"], c.child("name"));
    s.overlays.systems.push_back(std::move(y));
  };
  if (n.IsSequence())
    for (size_t k = 0; k < n.size(); ++k) one(n[k], w.index(k));
  else
    one(n, w);
}

}  // namespace

namespace {

// A joint quantity's joint and coordinate (f.name one of hud_joint_names(); `prefix` the text
// before the dot, empty for none).
void resolve_joint(HudField& f, const std::string& prefix, const Scene& s,
                   const std::function<void(const std::string&)>& bad) {
  const std::string list = "angle, speed, period, angle2, speed2, period2";
  if (f.component >= 0 || f.norm) bad("'" + f.name + "' is a number of a joint: no component or |...|");
  f.coord = f.name.back() == '2' ? 1 : 0;
  if (prefix.empty()) {
    for (size_t j = 0; j < s.joints.size() && f.joint < 0; ++j)
      if (s.joints[j].type != JointType::fixed) f.joint = (int)j;
    if (f.joint < 0)
      bad("'" + f.name + "' is a joint's coordinate (" + list + "), and the scene has no joint with one");
  } else {
    std::vector<std::string> names;
    for (const JointDef& j : s.joints) names.push_back(j.name);
    const auto it = std::find(names.begin(), names.end(), prefix);
    if (it == names.end()) {
      std::string msg = "no joint is named '" + prefix + "'";
      if (auto sug = nearest(prefix, names)) msg += "; did you mean '" + *sug + "'?";
      for (const BodyDef& b : s.bodies)
        if (b.name == prefix) {
          msg += " ('" + prefix + "' is a body; " + list + " are a joint's)";
          break;
        }
      if (names.empty()) msg += " (the scene has no joints)";
      bad(msg);
    }
    f.joint = (int)(it - names.begin());
  }
  const JointDef& j = s.joints[f.joint];
  const std::string what = "joint '" + j.name + "' is " + to_string(j.type);
  if (j.type == JointType::fixed) bad(what + ": it has no coordinate");
  if (f.coord == 1 && j.type != JointType::universal)
    bad(what + ": '" + f.name + "' is a universal joint's second coordinate");
  if (f.name.starts_with("period") && j.type == JointType::spherical)
    bad(what + ": its angle never changes sign, so it has no period to measure");
}

}  // namespace

HudField parse_quantity(const std::string& field_in, const Scene& s, int default_body,
                        const std::function<void(const std::string&)>& bad) {
  std::string field = field_in;
  HudField f;
  if (field.size() >= 2 && field.front() == '|' && field.back() == '|')
    f.norm = true, field = field.substr(1, field.size() - 2);
  // [body.]name[.x|.y|.z] or [joint.]name
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
  const auto& angles = hud_body_scalar_names();
  const auto& per_joint = hud_joint_names();
  std::vector<std::string> all = scalars;
  all.insert(all.end(), vectors.begin(), vectors.end());
  all.insert(all.end(), angles.begin(), angles.end());
  all.insert(all.end(), per_joint.begin(), per_joint.end());
  std::string body;
  if (parts.size() == 2)
    body = parts[0], f.name = parts[1];
  else if (parts.size() == 1)
    f.name = parts[0];
  else
    bad("'{" + field + "}' is not a quantity ([body.]name[.x|.y|.z] or [joint.]name)");
  const bool scalar = std::find(scalars.begin(), scalars.end(), f.name) != scalars.end();
  const bool body_scalar = std::find(angles.begin(), angles.end(), f.name) != angles.end();
  const bool vector = body_scalar || std::find(vectors.begin(), vectors.end(), f.name) != vectors.end();
  const bool joint = std::find(per_joint.begin(), per_joint.end(), f.name) != per_joint.end();
  if (!scalar && !vector && !joint) {
    std::string msg = "unknown quantity '" + f.name + "'";
    if (auto sug = nearest(f.name, all)) msg += "; did you mean '" + *sug + "'?";
    msg +=
        " (t, video_t, frame, E, E_drift, L_drift, P; per body omega, omega_body, L, v, p, position, tilt, "
        "precession, m, KE; per joint angle, speed, period, angle2, speed2, period2)";
    bad(msg);
  }
  if (joint) {
    resolve_joint(f, body, s, bad);
    return f;
  }
  if (scalar && (!body.empty() || f.component >= 0 || f.norm))
    bad("'" + f.name + "' is a number of the whole scene: no body, component or |...|");
  if (body_scalar && (f.component >= 0 || f.norm)) bad("'" + f.name + "' is a number: no component or |...|");
  if (vector && f.name == "P") {  // the whole scene's total momentum: a vector of no one body
    if (!body.empty()) bad("'P' is the total momentum of all moving bodies: no body (a body's own is p)");
    f.body = -1;
  } else if (vector) {
    if (body.empty()) {
      f.body = default_body;
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
        for (const JointDef& j : s.joints)
          if (j.name == body) {
            msg += " ('" + body +
                   "' is a joint: its quantities are angle, speed, period, angle2, speed2, period2)";
            break;
          }
        bad(msg);
      }
      f.body = (int)(it - names.begin());
    }
    if (f.norm && f.component >= 0) bad("'{" + field + "}': a component or |...|, not both");
  }
  return f;
}

const char* to_string(ShowKind k) {
  return kShowKinds(k);
}

const std::vector<std::string>& hud_scalar_names() {
  static const std::vector<std::string> v = {"t", "video_t", "frame", "E", "E_drift", "L_drift", "joint_gap"};
  return v;
}
const std::vector<std::string>& hud_body_names() {
  static const std::vector<std::string> v = {"omega", "omega_body", "L", "v", "p", "position", "P"};
  return v;
}
const std::vector<std::string>& hud_body_scalar_names() {
  static const std::vector<std::string> v = {"tilt", "precession", "m", "KE"};
  return v;
}
const std::vector<std::string>& hud_joint_names() {
  static const std::vector<std::string> v = {"angle", "speed", "period", "angle2", "speed2", "period2"};
  return v;
}

// A distance or pulley joint: never a tree edge (docs/joints.md), a rope between two bodies' points.
static bool is_rope(const JointDef& j) {
  return j.type == JointType::distance || j.type == JointType::pulley;
}

bool joint_sides(const JointDef& j, const std::vector<BodyDef>& bodies, int& parent, int& child) {
  auto fixed = [&](int b) {
    return b < 0 || b >= (int)bodies.size() || bodies[b].type == BodyType::static_body;
  };
  parent = j.parent, child = j.child;
  if (fixed(child)) std::swap(parent, child);
  return !fixed(child);
}

bool OverlaySpec::any() const {
  if (!hud.empty() || !title.empty() || !captions.empty() || !labels.empty() || legend.shown ||
      !plots.empty() || !systems.empty())
    return true;
  for (const auto& b : show)
    if (!b.empty()) return true;
  return false;
}

std::vector<ShowItem> read_show_list(const YAML::Node& sh, const scene_yaml::Ctx& w, const Scene& s,
                                     size_t body) {
  if (!sh.IsSequence()) w.fail(sh, "expected a list of items (axes, angular_velocity, ...), got " + show(sh));
  if (s.bodies[body].type != BodyType::dynamic && sh.size() > 0)
    w.fail(sh, "body '" + s.bodies[body].name + "' does not move: show items are for moving bodies");
  std::vector<ShowItem> items;
  for (size_t k = 0; k < sh.size(); ++k) {
    items.push_back(show_item(sh[k], w.index(k), s.duration));
    const ShowKind kind = items.back().kind;
    if (kind != ShowKind::joints && kind != ShowKind::joint_forces) continue;
    // A tree joint (not a rope) holding the body to its parent, or a rope (a distance or pulley
    // joint) with the body at either end: `joints` draws the rope, `joint_forces` does not (yet).
    bool held = false;
    const JointDef* rope = nullptr;
    for (const JointDef& j : s.joints) {
      if (is_rope(j)) {
        if (!rope && (j.parent == (int)body || j.child == (int)body)) rope = &j;
        continue;
      }
      int parent, child;
      held = held || (joint_sides(j, s.bodies, parent, child) && child == (int)body);
    }
    if (!held && rope && kind == ShowKind::joint_forces)
      w.index(k).fail(sh[k], "body '" + s.bodies[body].name + "' hangs on " + to_string(rope->type) +
                                 " joint '" + rope->name +
                                 "', and `joint_forces` does not draw a rope's force yet (it draws the "
                                 "force and torque through the joint that holds a body to its parent); "
                                 "`joints` draws the rope");
    if (!held && !rope)
      w.index(k).fail(sh[k], "body '" + s.bodies[body].name + "' is no joint's child: " +
                                 (kind == ShowKind::joints
                                      ? "`joints` draws the joint that holds a body to its parent, or a "
                                        "rope (distance or pulley joint) at either of its ends"
                                      : "`joint_forces` draws the force and torque through the joint that "
                                        "holds a body to its parent"));
  }
  return items;
}

void load_overlays(const YAML::Node& root, const std::string& path, Scene& s) {
  OverlaySpec& o = s.overlays;
  o.show.assign(s.bodies.size(), {});
  const Ctx top(path, "");
  if (const YAML::Node bodies = root["bodies"]; bodies && bodies.IsSequence())
    for (size_t i = 0; i < bodies.size() && i < s.bodies.size(); ++i) {
      const YAML::Node sh = bodies[i].IsMap() ? bodies[i]["show"] : YAML::Node();
      if (!sh) continue;
      o.show[i] = read_show_list(sh, top.child("bodies").index(i).child("show"), s, i);
    }
  const YAML::Node ov = root["overlays"];
  if (!ov) return;
  const Ctx w = top.child("overlays");
  check_keys(ov, w, {"hud", "title", "text_size", "captions", "labels", "legend", "plots", "system"});
  if (const YAML::Node h = ov["hud"]) {
    const Ctx hw = w.child("hud");
    // A copy binds to the node (operator= would write into `h`; reset() throws on a missing key).
    const YAML::Node lines = h.IsMap() ? h["lines"] : h;
    if (h.IsMap()) {
      check_keys(h, hw, {"lines", "corner"});
      if (const YAML::Node c = h["corner"])
        o.hud_corner = c.IsScalar() && c.Scalar() == "auto" ? "auto" : corner(c, hw.child("corner"));
      if (!lines) hw.fail(h, "missing key 'lines' (a list of text lines)");
    }
    const Ctx lw = h.IsMap() ? hw.child("lines") : hw;
    if (!lines.IsSequence()) lw.fail(lines, "expected a list of text lines, got " + show(lines));
    for (size_t k = 0; k < lines.size(); ++k) o.hud.push_back(hud_line(lines[k], lw.index(k), s));
  }
  if (ov["title"]) o.title = text(ov["title"], w.child("title"));
  if (ov["text_size"]) o.text_size = in_range(ov["text_size"], w.child("text_size"), 0.25, 4);
  if (const YAML::Node c = ov["captions"]) load_captions(c, w.child("captions"), s);
  if (const YAML::Node l = ov["labels"]) load_labels(l, w.child("labels"), s);
  if (const YAML::Node l = ov["legend"]) load_legend(l, w.child("legend"), s);
  if (const YAML::Node p = ov["plots"]) load_plots(p, w.child("plots"), s);
  if (const YAML::Node y = ov["system"]) load_systems(y, w.child("system"), s);
}

}  // namespace simreel
