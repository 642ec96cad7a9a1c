#include "app/scene/scene_views.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/scene/frame_plan.hpp"
#include "app/scene/scene.hpp"

namespace simreel {

using namespace scene_yaml;

namespace {

constexpr size_t kMaxPanes = 16;

PaneCamera pane_camera(const YAML::Node& n, const Ctx& c, const Scene& s) {
  if (!n.IsMap()) c.fail(n, "expected a mapping (position, look_at, up, fov, follow, frame), got " + show(n));
  check_keys(n, c, {"position", "look_at", "up", "fov", "follow", "frame"});
  PaneCamera pc;
  if (n["position"]) pc.position = vec<3>(n["position"], c.child("position"));
  if (n["look_at"]) pc.look_at = vec<3>(n["look_at"], c.child("look_at"));
  if (n["up"]) pc.up = vec<3>(n["up"], c.child("up"));
  if (n["fov"]) {
    pc.fov = positive(n["fov"], c.child("fov"));
    if (*pc.fov >= 179) c.child("fov").fail(n["fov"], "must be below 179 degrees");
  }
  if (n["follow"]) {
    pc.follow = text(n["follow"], c.child("follow"));
    check_body(s, *pc.follow, n["follow"], c.child("follow"));
  }
  if (n["frame"]) {
    pc.frame_body = camera_frame_body(n["frame"], c.child("frame"));
    if (!pc.frame_body->empty()) check_body(s, *pc.frame_body, n["frame"], c.child("frame").child("body"));
  }
  if (pc.follow && pc.frame_body && !pc.frame_body->empty())
    c.child("follow").fail(n["follow"],
                           "a camera riding in a body's frame does not also follow one: give one");
  if (pc.position && pc.look_at && (*pc.position - *pc.look_at).norm() == 0)
    c.child("look_at").fail(n["look_at"], "coincides with the camera position");
  if (pc.up && pc.up->norm() == 0) c.child("up").fail(n["up"], "is zero");
  return pc;
}

int body_index(const Scene& s, const YAML::Node& n, const Ctx& c) {
  const std::string name = text(n, c);
  check_body(s, name, n, c);
  for (size_t b = 0; b < s.bodies.size(); ++b)
    if (s.bodies[b].name == name) return (int)b;
  return -1;
}

// The joints at body b (as parent or child).
std::vector<const JointDef*> joints_at(const Scene& s, int b) {
  std::vector<const JointDef*> out;
  for (const JointDef& j : s.joints)
    if (j.parent == b || j.child == b) out.push_back(&j);
  return out;
}

// `bodies: { NAME: { position, orientation | euler | axis_angle, linear_velocity, angular_velocity } }`
std::vector<VariantStart> variant_starts(const YAML::Node& n, const Ctx& c, const Scene& s) {
  if (!n.IsMap() || n.size() == 0)
    c.fail(n,
           "expected { BODY: { position, orientation, linear_velocity, angular_velocity } }, got " + show(n));
  std::vector<VariantStart> out;
  for (const auto& kv : n) {
    const Ctx bc = c.child(kv.first.as<std::string>());
    VariantStart v;
    v.body = body_index(s, kv.first, bc);
    const YAML::Node b = kv.second;
    if (!b.IsMap())
      bc.fail(b, "expected { position, orientation, linear_velocity, angular_velocity }, got " + show(b));
    check_keys(b, bc,
               {"position", "orientation", "euler", "axis_angle", "linear_velocity", "angular_velocity"});
    if (const std::vector<const JointDef*> js = joints_at(s, v.body); !js.empty())
      bc.fail(kv.first, "is held by joint '" + js[0]->name +
                            "': a jointed body's start is its mechanism's (turn a mechanism with 'turn:')");
    if (s.bodies[v.body].type != BodyType::dynamic) bc.fail(kv.first, "is not a moving body");
    if (b["position"]) v.position = vec<3>(b["position"], bc.child("position"));
    Quat q;
    if (orientation(b, bc, q)) v.orientation = q;
    if (b["linear_velocity"]) v.linear_velocity = vec<3>(b["linear_velocity"], bc.child("linear_velocity"));
    if (b["angular_velocity"])
      v.angular_velocity = vec<3>(b["angular_velocity"], bc.child("angular_velocity"));
    out.push_back(v);
  }
  return out;
}

// `turn: { bodies: [A, B], about: [x, y, z], axis: [x, y, z], angle: degrees }`
VariantTurn variant_turn(const YAML::Node& n, const Ctx& c, const Scene& s) {
  if (!n.IsMap())
    c.fail(n,
           "expected { bodies: [...], about: [x, y, z], axis: [x, y, z], angle: degrees }, got " + show(n));
  check_keys(n, c, {"bodies", "about", "axis", "angle"});
  for (const char* k : {"bodies", "about", "axis", "angle"})
    if (!n[k]) c.fail(n, std::string("needs '") + k + "' (bodies, about, axis, angle in degrees)");
  VariantTurn t;
  const YAML::Node bl = n["bodies"];
  if (!bl.IsSequence() || bl.size() == 0)
    c.child("bodies").fail(bl, "expected a list of body names, got " + show(bl));
  for (size_t k = 0; k < bl.size(); ++k) {
    const int b = body_index(s, bl[k], c.child("bodies").index(k));
    if (s.bodies[b].type != BodyType::dynamic) c.child("bodies").index(k).fail(bl[k], "is not a moving body");
    t.bodies.push_back(b);
  }
  t.about = vec<3>(n["about"], c.child("about"));
  const Vec3 axis = vec<3>(n["axis"], c.child("axis"));
  if (!(axis.norm() > 0)) c.child("axis").fail(n["axis"], "must not be zero");
  t.axis = axis.normalized();
  t.angle = number(n["angle"], c.child("angle")) * M_PI / 180;
  // A joint from a turned body to the rest must not be torn: its anchor on the line, its axis along it.
  auto turned = [&](int b) { return std::find(t.bodies.begin(), t.bodies.end(), b) != t.bodies.end(); };
  for (const JointDef& j : s.joints) {
    if (turned(j.child) == (j.parent >= 0 && turned(j.parent))) continue;  // both turned, or neither
    const Vec3 d = j.anchor_W - t.about;
    const double off = (d - d.dot(t.axis) * t.axis).norm();
    const bool has_axis = j.type == JointType::revolute || j.type == JointType::prismatic ||
                          j.type == JointType::universal || j.type == JointType::wheel;
    const bool distance = j.type == JointType::distance || j.type == JointType::pulley;
    if (off > 1e-9 * std::max(1.0, d.norm()) || distance)
      c.fail(n, "would tear joint '" + j.name +
                    "' (it holds a turned body to one that is not): turn about a line "
                    "through its anchor");
    if (has_axis && j.axis_W.normalized().cross(t.axis).norm() > 1e-9)
      c.fail(n, "would tear joint '" + j.name + "': turn about its axis");
  }
  return t;
}

std::string variant_title(const Scene& s, const VariantSpec* v) {
  const Integrator in = v && v->integrator ? *v->integrator : s.integrator;
  const double dt = v && v->timestep ? *v->timestep : s.timestep;
  char b[160];
  std::snprintf(b, sizeof b, "%s%s%s, dt = 1/%g s", v ? v->name.c_str() : "", v ? ": " : "", to_string(in),
                std::round(1 / dt * 1000) / 1000);
  return b;
}

}  // namespace

std::string camera_frame_body(const YAML::Node& n, const Ctx& c) {
  if (n.IsScalar()) {
    const std::string f = text(n, c);
    if (f == "world") return "";
    c.fail(n, "expected world or { body: NAME } (the camera rides in that body's frame), got " + show(n));
  }
  if (!n.IsMap()) c.fail(n, "expected world or { body: NAME }, got " + show(n));
  check_keys(n, c, {"body"});
  if (!n["body"]) c.fail(n, "needs 'body' (the name of the body whose frame the camera rides in)");
  return text(n["body"], c.child("body"));
}

void load_views(const YAML::Node& root, const std::string& path, Scene& s) {
  const Ctx top(path, "");
  ViewsSpec& vs = s.views;
  if (const YAML::Node v = root["variants"]) {
    const Ctx c = top.child("variants");
    if (!v.IsSequence() || v.size() == 0)
      c.fail(v, "expected a list of { name: N, integrator: I, timestep: DT }, got " + show(v));
    if (v.size() + 1 > kMaxPanes) c.fail(v, "at most " + std::to_string(kMaxPanes - 1) + " variants");
    for (size_t k = 0; k < v.size(); ++k) {
      const Ctx e = c.index(k);
      const YAML::Node n = v[k];
      if (!n.IsMap()) e.fail(n, "expected { name: N, integrator: I, timestep: DT }, got " + show(n));
      check_keys(n, e, {"name", "integrator", "timestep", "bodies", "turn", "overlay"});
      VariantSpec var;
      if (!n["name"]) e.fail(n, "needs 'name' (what a pane's 'variant:' calls it)");
      var.name = text(n["name"], e.child("name"));
      for (const VariantSpec& o : vs.variants)
        if (o.name == var.name)
          e.child("name").fail(n["name"], "another variant is named '" + var.name + "'");
      if (n["integrator"]) var.integrator = integrator(n["integrator"], e.child("integrator"));
      if (n["timestep"]) {
        var.timestep = positive(n["timestep"], e.child("timestep"));
        if (*var.timestep > s.duration)
          e.child("timestep").fail(n["timestep"], "is longer than the duration");
      }
      if (n["bodies"]) var.starts = variant_starts(n["bodies"], e.child("bodies"), s);
      if (n["turn"]) var.turn = variant_turn(n["turn"], e.child("turn"), s);
      if (const YAML::Node o = n["overlay"]) {
        const Ctx oc = e.child("overlay");
        if (o.IsMap()) {
          check_keys(o, oc, {"color", "opacity"});
          var.overlay = true;
          if (o["color"]) {
            const Vec3 c = vec<3>(o["color"], oc.child("color"));
            for (int i = 0; i < 3; ++i)
              if (c[i] < 0 || c[i] > 1)
                oc.child("color").fail(o["color"], "expected [r, g, b] in [0, 1] (linear RGB)");
            var.overlay_color = std::array<float, 3>{(float)c[0], (float)c[1], (float)c[2]};
          }
          if (o["opacity"]) {
            var.overlay_opacity = unit_interval(o["opacity"], oc.child("opacity"));
            if (!(var.overlay_opacity > 0))
              oc.child("opacity").fail(o["opacity"], "an opacity of 0 draws nothing");
          }
        } else {
          var.overlay = boolean(o, oc);
        }
      }
      if (!var.integrator && !var.timestep && var.starts.empty() && !var.turn)
        e.fail(n, "variant '" + var.name + "' changes nothing: give integrator, timestep, bodies or turn");
      vs.variants.push_back(var);
    }
  }
  if (const YAML::Node p = root["panes"]) {
    const Ctx c = top.child("panes");
    if (p.IsMap()) {
      check_keys(p, c, {"columns", "views"});
      if (!p["views"]) c.fail(p, "needs 'views' (the list of panes)");
    }
    // A copy binds to the node (operator= on a YAML::Node writes into the node it refers to).
    const YAML::Node list = p.IsMap() ? p["views"] : p;
    const Ctx lc = p.IsMap() ? c.child("views") : c;
    if (!list.IsSequence() || list.size() == 0)
      lc.fail(list, "expected a list of panes ({ title: T, camera: {...}, variant: V }), got " + show(list));
    if (list.size() > kMaxPanes) lc.fail(list, "at most " + std::to_string(kMaxPanes) + " panes");
    if (p.IsMap() && p["columns"]) {
      const YAML::Node cn = p["columns"];
      const double cols = positive(cn, c.child("columns"));
      if (cols != std::floor(cols) || cols > (double)list.size())
        c.child("columns").fail(cn, "expected a whole number from 1 to the number of panes (" +
                                        std::to_string(list.size()) + ")");
      vs.columns = (int)cols;
    }
    for (size_t k = 0; k < list.size(); ++k) {
      const Ctx e = lc.index(k);
      const YAML::Node n = list[k];
      if (!n.IsMap()) e.fail(n, "expected { title: T, camera: {...}, variant: V }, got " + show(n));
      check_keys(n, e, {"title", "camera", "variant", "show"});
      PaneSpec pane;
      if (n["title"]) pane.title = text(n["title"], e.child("title"));
      if (n["variant"]) {
        pane.variant = text(n["variant"], e.child("variant"));
        std::vector<std::string> names;
        for (const VariantSpec& o : vs.variants) names.push_back(o.name);
        if (std::find(names.begin(), names.end(), pane.variant) == names.end()) {
          std::string msg = "no variant is named '" + pane.variant + "'";
          if (names.empty())
            msg += " (the scene has no 'variants:' list)";
          else if (auto sug = nearest(pane.variant, names))
            msg += "; did you mean '" + *sug + "'?";
          e.child("variant").fail(n["variant"], msg);
        }
      }
      if (n["camera"]) pane.camera = pane_camera(n["camera"], e.child("camera"), s);
      if (const YAML::Node sh = n["show"]) {
        const Ctx sc = e.child("show");
        if (!sh.IsMap())
          sc.fail(sh,
                  "expected a mapping of body names to show lists ({ BODY: [axes, ...] }), got " + show(sh));
        for (const auto& kv : sh) {
          const std::string name = kv.first.as<std::string>();
          check_body(s, name, kv.first, sc);
          int b = 0;
          while (s.bodies[b].name != name) ++b;
          pane.show.emplace_back(b, read_show_list(kv.second, sc.child(name), s, (size_t)b));
        }
      }
      vs.panes.push_back(pane);
    }
  } else if (!vs.variants.empty()) {
    // Variants without panes: the scene and each variant side by side, the scene's camera; an
    // overlaid variant is drawn over the scene's own view instead (only overlaid ones: one view).
    bool own = false;
    for (const VariantSpec& v : vs.variants) own = own || !v.overlay;
    if (own) {
      vs.panes.push_back({variant_title(s, nullptr), "", {}, {}});
      for (const VariantSpec& v : vs.variants)
        if (!v.overlay) vs.panes.push_back({variant_title(s, &v), v.name, {}, {}});
    }
  }
}

// A body of the scene by name, or a clear error with the nearest name.
void check_body(const Scene& s, const std::string& name, const YAML::Node& n, const scene_yaml::Ctx& c) {
  std::vector<std::string> all;
  for (const BodyDef& b : s.bodies) all.push_back(b.name);
  if (std::find(all.begin(), all.end(), name) != all.end()) return;
  std::string msg = "no body is named '" + name + "'";
  if (auto sug = nearest(name, all)) msg += "; did you mean '" + *sug + "'?";
  c.fail(n, msg);
}

Scene variant_scene(const Scene& s, const VariantSpec& v) {
  Scene out = s;
  out.views = {};
  out.notes.clear();
  for (const VariantStart& st : v.starts) {
    BodyDef& b = out.bodies[st.body];
    if (st.position) b.p_WB = *st.position;
    if (st.orientation) b.q_WB = *st.orientation;
    if (st.linear_velocity) b.v_W = *st.linear_velocity;
    if (st.angular_velocity) b.w_W = *st.angular_velocity;
  }
  if (v.turn) {
    const VariantTurn& t = *v.turn;
    const Quat R(Eigen::AngleAxisd(t.angle, t.axis));
    auto point = [&](const Vec3& p) -> Vec3 {
      return t.about + R * (p - t.about);
    };  // a Vec3: not an Eigen expression of temporaries
    for (int b : t.bodies) {
      BodyDef& d = out.bodies[b];
      // The origin turns about the line; the velocities of the centre of mass and the spin turn with the
      // body.
      d.p_WB = point(d.p_WB);
      d.q_WB = (R * d.q_WB).normalized();
      d.v_W = R * d.v_W;
      d.w_W = R * d.w_W;
    }
    auto turned = [&](int b) { return std::find(t.bodies.begin(), t.bodies.end(), b) != t.bodies.end(); };
    for (JointDef& j : out.joints)
      if (turned(j.child) && j.parent >= 0 && turned(j.parent)) {  // inside the turned set: turns with it
        j.anchor_W = point(j.anchor_W);
        j.anchor2_W = point(j.anchor2_W);
        j.axis_W = R * j.axis_W;
        j.axis2_W = R * j.axis2_W;
      }
  }
  if (v.integrator) {
    out.integrator = *v.integrator;
    for (BodyDef& b : out.bodies) b.integrator.reset();
  }
  if (v.timestep) {
    out.timestep = *v.timestep;
    prepare_run(out);
    for (std::string& n : out.notes) n = "variant '" + v.name + "': " + n;
  }
  return out;
}

}  // namespace simreel
