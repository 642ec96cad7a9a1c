#include "app/scene/scene_joints.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"

namespace simreel {

namespace {

using namespace scene_yaml;

constexpr const char* kKeys[] = {"name",   "type",  "bodies",   "anchor",
                                 "axis",   "axis2", "spring",   "collide_connected",
                                 "limits", "motor", "friction", "steering"};

// A body name (or `world`) -> body index, -1 for the world; a did-you-mean for a typo.
int body_index(const YAML::Node& n, const Ctx& c, const std::vector<BodyDef>& bodies) {
  const std::string name = text(n, c);
  std::vector<std::string> names;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name) return (int)i;
    names.push_back(bodies[i].name);
  }
  if (name == "world" || name == "ground") return -1;
  names.push_back("world");
  std::string msg = "no body is named '" + name + "'";
  if (auto s = nearest(name, names)) msg += "; did you mean '" + *s + "'?";
  c.fail(n, msg);
  return -1;
}

// `limits: [lower, upper]` or `{ lower, upper, restitution }` (rad, or m for a slider).
JointLimits load_limits(const YAML::Node& l, const Ctx& c, JointType type) {
  if (type == JointType::spherical || type == JointType::fixed)
    c.fail(l, std::string("a ") + to_string(type) + " joint has no coordinate for limits");
  JointLimits out;
  if (l.IsSequence()) {
    if (l.size() != 2)
      c.fail(l, "expected [lower, upper] or { lower, upper, restitution }, got a list of " +
                    std::to_string(l.size()));
    out.lower = number(l[0], c.index(0));
    out.upper = number(l[1], c.index(1));
  } else if (l.IsMap()) {
    check_keys(l, c, {"lower", "upper", "restitution"});
    for (const char* k : {"lower", "upper"})
      if (!l[k]) c.fail(l, std::string("missing key '") + k + "' (limits: { lower, upper, restitution })");
    out.lower = number(l["lower"], c.child("lower"));
    out.upper = number(l["upper"], c.child("upper"));
    if (l["restitution"]) out.restitution = unit_interval(l["restitution"], c.child("restitution"));
  } else {
    c.fail(l, "expected [lower, upper] or { lower, upper, restitution }, got " + show(l));
  }
  std::ostringstream range;
  range << "[" << out.lower << ", " << out.upper << "]";
  if (out.lower > out.upper) c.fail(l, "limits out of order: lower must be below upper, got " + range.str());
  if (out.lower == out.upper)
    c.fail(l, "lower equals upper, got " + range.str() +
                  ": the joint could not move (a joint that cannot move is `type: fixed`)");
  if (out.lower > 0 || out.upper < 0)
    c.fail(l, "joint coordinates are 0 in the start pose, so the limits must contain 0, got " + range.str());
  return out;
}

// `motor: { speed, max_torque }` or `{ position, max_torque, speed, time_constant }` (max_force on
// a slider).
JointMotor load_motor(const YAML::Node& m, const Ctx& c, JointType type) {
  if (type == JointType::spherical || type == JointType::fixed)
    c.fail(m, std::string("a ") + to_string(type) + " joint has no coordinate for a motor");
  if (type == JointType::universal)
    c.fail(m,
           "a motor drives one coordinate: revolute and prismatic joints only (a universal joint has two)");
  const bool slider = type == JointType::prismatic;  // a wheel's motor drives its axle: N m
  const char* max_key = slider ? "max_force" : "max_torque";
  const char* wrong_key = slider ? "max_torque" : "max_force";
  const std::string force_unit = slider ? "N" : "N m";
  const std::string rate_unit = slider ? "m/s" : "rad/s";
  const std::string pos_unit = slider ? "m" : "rad";
  if (!m.IsMap())
    c.fail(m, std::string("expected { speed: RATE, ") + max_key + ": MAX } or { position: TARGET, " +
                  max_key + ": MAX }, got " + show(m));
  check_keys(m, c, {"speed", "position", "time_constant", "max_torque", "max_force"});
  if (m[wrong_key])
    c.child(wrong_key).fail(m[wrong_key], std::string("a ") + to_string(type) + " joint's motor takes '" +
                                              max_key + "' (" + force_unit + "), not '" + wrong_key + "' (" +
                                              (slider ? "N m" : "N") + ")");
  if (!m[max_key])
    c.fail(m, std::string("a motor needs '") + max_key + "' (" + force_unit +
                  ", > 0): the most it may push with");
  JointMotor out;
  out.max_force = positive(m[max_key], c.child(max_key));
  if (m["position"]) {
    out.mode = JointMotor::Mode::position;
    out.position = number(m["position"], c.child("position"));
    out.speed = m["speed"] ? positive(m["speed"], c.child("speed")) : std::numeric_limits<double>::infinity();
    if (m["time_constant"]) out.time_constant = positive(m["time_constant"], c.child("time_constant"));
  } else if (m["speed"]) {
    out.mode = JointMotor::Mode::speed;
    out.speed = number(m["speed"], c.child("speed"));
    if (m["time_constant"])
      c.child("time_constant")
          .fail(m["time_constant"],
                "is for a position motor (with 'position'); a speed motor holds its speed");
  } else {
    c.fail(m, "a motor needs 'speed' (a target rate, " + rate_unit + ") or 'position' (a target, " +
                  pos_unit + ")");
  }
  return out;
}

}  // namespace

std::vector<JointDef> load_joints(const YAML::Node& list, const std::string& file,
                                  const std::vector<BodyDef>& bodies, std::vector<std::string>& notes) {
  const Ctx top(file, "joints");
  if (!list.IsSequence()) top.fail(list, "expected a list of joints, got " + show(list));
  std::vector<JointDef> out;
  const std::vector<std::string> keys(std::begin(kKeys), std::end(kKeys));
  for (size_t k = 0; k < list.size(); ++k) {
    const YAML::Node n = list[k];
    const Ctx c = top.index((int)k);
    if (!n.IsMap())
      c.fail(n,
             "expected a mapping like { type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, "
             "1, 0] }, "
             "got " +
                 show(n));
    check_keys(n, c, keys);
    JointDef j;
    j.name = n["name"] ? text(n["name"], c.child("name")) : "joint" + std::to_string(k);
    for (const JointDef& o : out)
      if (o.name == j.name)
        c.child("name").fail(n["name"], "the name '" + j.name + "' is used by an earlier joint");
    if (!n["type"]) c.fail(n, std::string("missing key 'type' (") + joint_type_names() + ")");
    {
      const Ctx tc = c.child("type");
      const std::string t = text(n["type"], tc);
      const auto jt = joint_type_from_name(t);
      if (!jt) {
        std::vector<std::string> names;
        for (const char* s : {"revolute", "prismatic", "spherical", "fixed", "universal", "wheel"})
          names.push_back(s);
        std::string msg = "unknown joint type '" + t + "' (" + joint_type_names() + ")";
        if (t == "distance")
          msg = "joint type '" + t + "' is not supported yet (" + std::string(joint_type_names()) + ")";
        else if (auto s = nearest(t, names))
          msg += "; did you mean '" + *s + "'?";
        tc.fail(n["type"], msg);
      }
      j.type = *jt;
    }
    if (!n["bodies"]) c.fail(n, "missing key 'bodies' ([parent, child]; 'world' is the fixed frame)");
    {
      const YAML::Node b = n["bodies"];
      const Ctx bc = c.child("bodies");
      if (!b.IsSequence() || b.size() != 2) bc.fail(b, "expected [parent, child], got " + show(b));
      j.parent = body_index(b[0], bc.index(0), bodies);
      j.child = body_index(b[1], bc.index(1), bodies);
      if (j.parent == j.child)
        bc.fail(b, j.parent < 0 ? "joins the world to itself"
                                : "joins body '" + bodies[j.child].name + "' to itself");
      auto fixed = [&](int i) { return i < 0 || bodies[i].type == BodyType::static_body; };
      if (fixed(j.parent) && fixed(j.child))
        bc.fail(b, "joins two bodies that cannot move (static or world)");
      for (int i : {j.parent, j.child})
        if (i >= 0 && bodies[i].type == BodyType::kinematic)
          bc.fail(b, "body '" + bodies[i].name +
                         "' is kinematic: jointing kinematic bodies is not supported yet");
    }
    if (!n["anchor"]) c.fail(n, "missing key 'anchor' ([x, y, z] in m, a world point at t = 0)");
    j.anchor_W = vec<3>(n["anchor"], c.child("anchor"));
    const bool axial = j.type == JointType::revolute || j.type == JointType::prismatic ||
                       j.type == JointType::universal || j.type == JointType::wheel;
    if (n["axis"]) {
      if (!axial)
        c.child("axis").fail(n["axis"], std::string("a ") + to_string(j.type) + " joint has no axis");
      j.axis_W = vec<3>(n["axis"], c.child("axis"));
      if (j.axis_W.norm() < 1e-12) c.child("axis").fail(n["axis"], "the axis must not be zero");
    } else if (axial) {
      c.fail(n, std::string("a ") + to_string(j.type) +
                    " joint needs 'axis' ([x, y, z], a world direction at t = 0)");
    }
    if (n["axis2"]) {
      if (j.type != JointType::universal && j.type != JointType::wheel)
        c.child("axis2").fail(n["axis2"], "only a universal or wheel joint has axis2");
      j.axis2_W = vec<3>(n["axis2"], c.child("axis2"));
      if (j.axis2_W.norm() < 1e-12) c.child("axis2").fail(n["axis2"], "axis2 must not be zero");
      if (std::abs(j.axis_W.normalized().dot(j.axis2_W.normalized())) > 1e-6)
        c.child("axis2").fail(n["axis2"], "axis2 must be perpendicular to axis");
    } else if (j.type == JointType::universal) {
      c.fail(n, "a universal joint needs 'axis2' (the child's axis, perpendicular to 'axis')");
    } else if (j.type == JointType::wheel) {
      c.fail(n, "a wheel joint needs 'axis2' (the wheel's axle, perpendicular to the suspension 'axis')");
    }
    if (const YAML::Node s = n["spring"]) {
      const Ctx sc = c.child("spring");
      if (!s.IsMap()) sc.fail(s, "expected { stiffness: k, damping: c, rest: q0 }, got " + show(s));
      check_keys(s, sc, {"stiffness", "damping", "rest"});
      if (j.type == JointType::spherical || j.type == JointType::fixed)
        sc.fail(s, std::string("a ") + to_string(j.type) + " joint has no coordinate for a spring");
      JointSpring sp;
      if (s["stiffness"]) sp.stiffness = non_negative(s["stiffness"], sc.child("stiffness"));
      if (s["damping"]) sp.damping = non_negative(s["damping"], sc.child("damping"));
      if (s["rest"]) sp.rest = number(s["rest"], sc.child("rest"));
      j.spring = sp;
    }
    if (const YAML::Node l = n["limits"]) j.limits = load_limits(l, c.child("limits"), j.type);
    if (const YAML::Node m = n["motor"]) j.motor = load_motor(m, c.child("motor"), j.type);
    if (const YAML::Node m = n["steering"]) {
      const Ctx sc = c.child("steering");
      if (j.type != JointType::wheel) sc.fail(m, "only a wheel joint steers");
      j.steering = load_motor(m, sc, JointType::revolute);
      if (j.steering->mode != JointMotor::Mode::position)
        sc.fail(m, "steering turns the wheel to an angle: { position: rad, max_torque: N m }");
    }
    if (const YAML::Node f = n["friction"]) {
      const Ctx fc = c.child("friction");
      if (j.type == JointType::spherical || j.type == JointType::fixed)
        fc.fail(f, std::string("a ") + to_string(j.type) + " joint has no coordinate for friction");
      j.friction = non_negative(f, fc);
    }
    if (n["collide_connected"])
      j.collide_connected = boolean(n["collide_connected"], c.child("collide_connected"));
    // An anchor far from both bodies is legal (a long massless arm) but usually a typo: a note.
    double nearest_d = 1e300;
    for (int i : {j.parent, j.child})
      if (i >= 0) nearest_d = std::min(nearest_d, (bodies[i].p_WB - j.anchor_W).norm());
    if (nearest_d > 10 && nearest_d < 1e300) {
      std::ostringstream os;
      os << where(n["anchor"], c.child("anchor")) << ": the anchor is " << nearest_d
         << " m from the nearer of its bodies' origins; is it where you meant?";
      notes.push_back(os.str());
    }
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace simreel
