#include "app/scene/scene_joints.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <tuple>
#include <utility>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"

namespace simreel {

namespace {

using namespace scene_yaml;

constexpr const char* kKeys[] = {"name",        "type",           "bodies",     "anchor",
                                 "axis",        "axis2",          "spring",     "collide_connected",
                                 "limits",      "motor",          "motor2",     "friction",
                                 "steering",    "anchors",        "min_length", "max_length",
                                 "restitution", "pulley_anchors", "ratio",      "wheel",
                                 "mimic",       "armature"};

std::string metres(double x) {
  std::ostringstream os;
  os << std::setprecision(10) << x << " m";
  return os.str();
}

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
  if (type == JointType::fixed) c.fail(l, "a fixed joint has no coordinate for limits");
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

// A ball joint's `limits: { cone, twist: [lower, upper], angle, restitution }` (rad).
BallLimits load_ball_limits(const YAML::Node& l, const Ctx& c) {
  constexpr double kPi = std::numbers::pi;
  if (!l.IsMap())
    c.fail(l,
           "a spherical joint's limits are { cone: rad, twist: [lower, upper], angle: rad, restitution } "
           "(stops about its axis, or on its whole turn), got " +
               show(l));
  check_keys(l, c, {"cone", "twist", "angle", "restitution"});
  if (!l["cone"] && !l["twist"] && !l["angle"])
    c.fail(l,
           "a spherical joint's limits need 'cone' (rad: how far the child's axis may tilt), 'twist' "
           "([lower, upper] rad: how far it may turn about its axis) or 'angle' (rad: how far it may "
           "turn from the start pose, about any axis)");
  BallLimits out;
  if (const YAML::Node k = l["angle"]) {
    out.angle = positive(k, c.child("angle"));
    if (out.angle >= kPi) c.child("angle").fail(k, "a rotation's angle is under pi rad");
  }
  if (const YAML::Node k = l["cone"]) {
    out.cone = positive(k, c.child("cone"));
    if (out.cone >= kPi) c.child("cone").fail(k, "the cone's half angle must be under pi rad");
  }
  if (const YAML::Node t = l["twist"]) {
    const Ctx tc = c.child("twist");
    if (!t.IsSequence() || t.size() != 2) tc.fail(t, "expected [lower, upper] (rad), got " + show(t));
    out.twist_lower = number(t[0], tc.index(0));
    out.twist_upper = number(t[1], tc.index(1));
    std::ostringstream range;
    range << "[" << out.twist_lower << ", " << out.twist_upper << "]";
    if (!(out.twist_lower < out.twist_upper))
      tc.fail(t, "twist limits out of order: lower must be below upper, got " + range.str());
    if (out.twist_lower > 0 || out.twist_upper < 0)
      tc.fail(t, "the twist is 0 in the start pose, so its limits must contain 0, got " + range.str());
    if (out.twist_lower < -kPi || out.twist_upper > kPi)
      tc.fail(t, "a twist is an angle in [-pi, pi], got " + range.str());
  }
  if (l["restitution"]) out.restitution = unit_interval(l["restitution"], c.child("restitution"));
  return out;
}

// `motor: { speed, max_torque }` or `{ position, max_torque, speed, time_constant }` (max_force on
// a slider). On a ball joint the targets are vectors: `speed: [wx, wy, wz]` (rad/s, the child's
// axes) or `position: [rx, ry, rz]` (a rotation vector, rad), and `speed` with a position caps the
// approach rate's length.
JointMotor load_motor(const YAML::Node& m, const Ctx& c, JointType type) {
  if (type == JointType::fixed) c.fail(m, "a fixed joint has no coordinate for a motor");
  const bool slider = type == JointType::prismatic;  // a wheel's motor drives its axle: N m
  const bool ball = type == JointType::spherical;
  const char* max_key = slider ? "max_force" : "max_torque";
  const char* wrong_key = slider ? "max_torque" : "max_force";
  const std::string force_unit = slider ? "N" : ball ? "N m, about each axis" : "N m";
  const std::string rate = ball ? "[wx, wy, wz]" : "RATE", target = ball ? "[rx, ry, rz]" : "TARGET";
  if (!m.IsMap())
    c.fail(m, "expected { speed: " + rate + ", " + max_key + ": MAX } or { position: " + target + ", " +
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
    const Ctx pc = c.child("position");
    if (ball) {
      if (!m["position"].IsSequence())
        pc.fail(m["position"],
                "a ball joint's target is a rotation vector [rx, ry, rz] (rad: axis times angle), got " +
                    show(m["position"]));
      out.rotation = vec<3>(m["position"], pc);
      if (!(out.rotation.norm() < std::numbers::pi))
        pc.fail(m["position"], "a rotation vector's length is its angle, under pi rad");
    } else {
      out.position = number(m["position"], pc);
    }
    out.speed = m["speed"] ? positive(m["speed"], c.child("speed")) : std::numeric_limits<double>::infinity();
    if (m["time_constant"]) out.time_constant = positive(m["time_constant"], c.child("time_constant"));
  } else if (m["speed"]) {
    out.mode = JointMotor::Mode::speed;
    const Ctx sc = c.child("speed");
    if (ball) {
      if (!m["speed"].IsSequence())
        sc.fail(m["speed"], "a ball joint's target speed is an angular velocity [wx, wy, wz] (rad/s), got " +
                                show(m["speed"]));
      out.angular_velocity = vec<3>(m["speed"], sc);
    } else {
      out.speed = number(m["speed"], sc);
    }
    if (m["time_constant"])
      c.child("time_constant")
          .fail(m["time_constant"],
                "is for a position motor (with 'position'); a speed motor holds its speed");
  } else {
    c.fail(m, ball ? std::string("a motor needs 'speed' (an angular velocity [wx, wy, wz], rad/s) or "
                                 "'position' (a rotation vector [rx, ry, rz], rad)")
                   : "a motor needs 'speed' (a target rate, " + std::string(slider ? "m/s" : "rad/s") +
                         ") or 'position' (a target, " + (slider ? "m" : "rad") + ")");
  }
  return out;
}

// Two world points at t = 0: `anchors` (the parent's, the child's) or `pulley_anchors`.
std::pair<Vec3, Vec3> two_points(const YAML::Node& n, const Ctx& c, const char* what) {
  if (!n.IsSequence() || n.size() != 2)
    c.fail(n, std::string("expected [[x, y, z], [x, y, z]] (") + what + "), got " +
                  (n.IsSequence() ? "a list of " + std::to_string(n.size()) : show(n)));
  return {vec<3>(n[0], c.index(0)), vec<3>(n[1], c.index(1))};
}

// The keys a joint's type does not take, each refused with what to write instead: a distance or
// pulley joint has two anchors and no axis, limits, motor or friction; their own keys belong to them.
void refuse_foreign_keys(const YAML::Node& n, const Ctx& c, JointType type) {
  const bool distance = type == JointType::distance, pulley = type == JointType::pulley;
  const std::string a = std::string("a ") + to_string(type) + " joint ";
  auto refuse = [&](const char* key, const std::string& why) {
    if (n[key]) c.child(key).fail(n[key], why);
  };
  if (distance || pulley) {
    refuse("anchor", distance ? "a distance joint takes 'anchors: [[parent point], [child point]]'"
                              : "a pulley joint takes 'anchors: [[a point], [b point]]' (where the rope is "
                                "tied to each of its bodies)");
    refuse("axis", a + "has no axis: its rope runs between its anchors");
    refuse("axis2", "only a universal or wheel joint has axis2");
    refuse("steering", "only a wheel joint steers");
    refuse("motor", a + "takes no motor");
    refuse("friction", a + "has no friction");
  } else {
    refuse("anchors", "only a distance or pulley joint takes 'anchors'; " + a + "takes 'anchor: [x, y, z]'");
  }
  if (distance) {
    refuse("limits", "a distance joint's limits are min_length/max_length (m): a rope slack between them");
  } else if (pulley) {
    refuse("limits",
           "a pulley joint has no limits: its rope keeps L0 + ratio L1 at most its start value (a "
           "distance joint's bounds are min_length/max_length)");
    refuse("spring", "a pulley joint takes no spring (a spring along a rope is a distance joint's)");
    for (const char* k : {"min_length", "max_length"})
      refuse(k, std::string("a pulley's rope keeps its start length: ") + k + " is for a distance joint");
  } else {
    for (const char* k : {"min_length", "max_length"})
      refuse(k, std::string("only a distance joint has ") + k + " (a rope between two points)");
    refuse("restitution",
           "only a rope (a distance joint with min_length or max_length) or a pulley has restitution; a "
           "joint's stops take limits: { lower, upper, restitution }");
  }
  if (!pulley)
    for (const char* k : {"pulley_anchors", "ratio", "wheel"})
      refuse(k, std::string("only a pulley joint has ") + k);
}

// A distance joint's `min_length`, `max_length` and `restitution` around the anchors' start
// distance d0 (> 0): a rope's bounds must hold it, in order.
void load_rope(const YAML::Node& n, const Ctx& c, JointDef& j, double d0) {
  const YAML::Node lo = n["min_length"], hi = n["max_length"];
  if (lo) j.min_length = non_negative(lo, c.child("min_length"));
  if (hi) j.max_length = positive(hi, c.child("max_length"));
  if (lo && hi && *j.min_length >= *j.max_length)
    c.child("min_length")
        .fail(lo,
              "min_length must be below max_length, got " + metres(*j.min_length) + " and " +
                  metres(*j.max_length) +
                  (*j.min_length == *j.max_length ? " (equal bounds are a rigid rod: leave both out)" : ""));
  // Within 1e-9 m of the start distance a bound is taken as it (the rope starts taut).
  if (hi) {
    if (*j.max_length < d0 - 1e-9)
      c.child("max_length")
          .fail(hi, "max_length " + metres(*j.max_length) + " is shorter than the anchors' start distance " +
                        metres(d0) + ": it must be at least that (the rope starts within its bounds)");
    j.max_length = std::max(*j.max_length, d0);
  }
  if (lo) {
    if (*j.min_length > d0 + 1e-9)
      c.child("min_length")
          .fail(lo, "min_length " + metres(*j.min_length) + " is longer than the anchors' start distance " +
                        metres(d0) + ": it must be at most that (the rope starts within its bounds)");
    j.min_length = std::min(*j.min_length, d0);
  }
  if (const YAML::Node r = n["restitution"]) {
    if (!lo && !hi)
      c.child("restitution")
          .fail(r,
                "a rigid rod (no min_length or max_length) never goes slack, so it has no restitution; give "
                "max_length (or min_length) for a rope");
    j.restitution = unit_interval(r, c.child("restitution"));
  }
}

// A pulley's `pulley_anchors`, `ratio`, `wheel` and `restitution`.
void load_pulley(const YAML::Node& n, const Ctx& c, JointDef& j, const std::vector<BodyDef>& bodies) {
  if (!n["pulley_anchors"])
    c.fail(n,
           "a pulley joint needs 'pulley_anchors: [[x, y, z], [x, y, z]]' (m, fixed world points: where the "
           "rope from each body's anchor meets the pulley)");
  const Ctx pc = c.child("pulley_anchors");
  std::tie(j.pulley_anchor_W[0], j.pulley_anchor_W[1]) =
      two_points(n["pulley_anchors"], pc, "the points over the parent's and the child's side");
  const Vec3 ends[2] = {j.anchor_W, j.anchor2_W};
  for (int s : {0, 1})
    if ((j.pulley_anchor_W[s] - ends[s]).norm() < 1e-9)
      pc.index(s).fail(n["pulley_anchors"][s], std::string("the rope's ") + (s == 0 ? "parent" : "child") +
                                                   " side starts with no length: pulley_anchors[" +
                                                   std::to_string(s) + "] must differ from anchors[" +
                                                   std::to_string(s) + "]");
  if (n["ratio"]) j.ratio = positive(n["ratio"], c.child("ratio"));
  if (const YAML::Node w = n["wheel"]) {
    const Ctx wc = c.child("wheel");
    j.wheel = body_index(w, wc, bodies);
    if (j.wheel < 0) wc.fail(w, "the wheel must be a body that turns on a revolute joint, not the world");
    const BodyDef& b = bodies[j.wheel];
    if (b.type != BodyType::dynamic)
      wc.fail(w, "the wheel '" + b.name + "' is " + to_string(b.type) +
                     ": it must be a dynamic body on a revolute joint");
    if (j.wheel == j.parent || j.wheel == j.child)
      wc.fail(w,
              "the wheel '" + b.name +
                  "' is one of the rope's bodies: the wheel is a third body, on a revolute joint, that the "
                  "rope turns");
    if (j.ratio != 1)
      c.child("ratio").fail(n["ratio"],
                            "a rope over a wheel has ratio 1 (another ratio is a block and tackle: leave out "
                            "'wheel' for a massless pulley)");
  }
  if (n["restitution"]) j.restitution = unit_interval(n["restitution"], c.child("restitution"));
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
        for (const char* s :
             {"revolute", "prismatic", "spherical", "fixed", "universal", "wheel", "distance", "pulley"})
          names.push_back(s);
        std::string msg = "unknown joint type '" + t + "' (" + joint_type_names() + ")";
        if (auto s = nearest(t, names)) msg += "; did you mean '" + *s + "'?";
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
    refuse_foreign_keys(n, c, j.type);
    const bool rope = j.type == JointType::distance || j.type == JointType::pulley;
    double start_length = 0;  // distance: |anchor2 - anchor| at t = 0
    if (rope) {
      if (!n["anchors"])
        c.fail(n, std::string("a ") + to_string(j.type) +
                      " joint needs 'anchors: [[parent point], [child point]]' (m, world points at t = 0)");
      std::tie(j.anchor_W, j.anchor2_W) =
          two_points(n["anchors"], c.child("anchors"), "the parent's point, the child's point");
      start_length = (j.anchor2_W - j.anchor_W).norm();
      if (j.type == JointType::distance) {
        if (start_length < 1e-9)
          c.child("anchors").fail(n["anchors"],
                                  "the anchors coincide; a distance joint needs two distinct points (use "
                                  "spherical for a ball joint)");
        load_rope(n, c, j, start_length);
      } else {
        load_pulley(n, c, j, bodies);
      }
    } else {
      if (!n["anchor"]) c.fail(n, "missing key 'anchor' ([x, y, z] in m, a world point at t = 0)");
      j.anchor_W = vec<3>(n["anchor"], c.child("anchor"));
    }
    const bool axial = j.type == JointType::revolute || j.type == JointType::prismatic ||
                       j.type == JointType::universal || j.type == JointType::wheel;
    if (n["axis"]) {
      if (!axial && j.type != JointType::spherical)
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
      if (j.type == JointType::fixed) sc.fail(s, "a fixed joint has no coordinate for a spring");
      if (j.type == JointType::spherical && s["rest"])
        sc.child("rest").fail(s["rest"],
                              "a spherical joint's spring rests at the start pose: it pulls the child's "
                              "rotation vector back to 0 (leave out 'rest')");
      JointSpring sp;
      if (s["stiffness"]) sp.stiffness = non_negative(s["stiffness"], sc.child("stiffness"));
      if (s["damping"]) sp.damping = non_negative(s["damping"], sc.child("damping"));
      if (j.type == JointType::distance)  // along a length: the rest length, the start distance unless given
        sp.rest = s["rest"] ? non_negative(s["rest"], sc.child("rest")) : start_length;
      else if (s["rest"])
        sp.rest = number(s["rest"], sc.child("rest"));
      j.spring = sp;
    }
    if (const YAML::Node l = n["limits"]) {
      if (j.type == JointType::spherical) {
        j.ball_limits = load_ball_limits(l, c.child("limits"));
        if (!n["axis"] && (l["cone"] || l["twist"]))
          c.fail(
              n,
              "a spherical joint with a cone or twist needs 'axis' ([x, y, z], a world direction at t = 0: "
              "the child's axis that the cone holds and the twist turns about)");
      } else {
        j.limits = load_limits(l, c.child("limits"), j.type);
      }
    }
    if (const YAML::Node m = n["motor"]) j.motor = load_motor(m, c.child("motor"), j.type);
    if (const YAML::Node m = n["motor2"]) {
      if (j.type != JointType::universal)
        c.child("motor2").fail(m, "only a universal joint has motor2 (the motor on its angle about axis2)");
      j.motor2 = load_motor(m, c.child("motor2"), j.type);
    }
    if (const YAML::Node m = n["steering"]) {
      const Ctx sc = c.child("steering");
      if (j.type != JointType::wheel) sc.fail(m, "only a wheel joint steers");
      j.steering = load_motor(m, sc, JointType::revolute);
      if (j.steering->mode != JointMotor::Mode::position)
        sc.fail(m, "steering turns the wheel to an angle: { position: rad, max_torque: N m }");
    }
    if (const YAML::Node f = n["friction"]) {
      const Ctx fc = c.child("friction");
      if (j.type == JointType::fixed) fc.fail(f, "a fixed joint has no coordinate for friction");
      j.friction = non_negative(f, fc);
    }
    if (const YAML::Node a = n["armature"]) {
      const Ctx ac = c.child("armature");
      if (j.type != JointType::revolute && j.type != JointType::prismatic && j.type != JointType::universal)
        ac.fail(a,
                std::string("a ") + to_string(j.type) +
                    " joint has no armature: it is a rotor's inertia on a revolute, prismatic or universal "
                    "joint's coordinate");
      j.armature = positive(a, ac);
    }
    if (n["collide_connected"])
      j.collide_connected = boolean(n["collide_connected"], c.child("collide_connected"));
    // An anchor far from both bodies is legal (a long massless arm) but usually a typo: a note. A
    // rope's anchors are each on one body: each is measured from its own.
    if (rope) {
      const int side[2] = {j.parent, j.child};
      const Vec3 at[2] = {j.anchor_W, j.anchor2_W};
      for (int s : {0, 1}) {
        if (side[s] < 0) continue;
        const double d = (bodies[side[s]].p_WB - at[s]).norm();
        if (d <= 10) continue;
        std::ostringstream os;
        os << where(n["anchors"][s], c.child("anchors").index(s)) << ": the anchor is " << d
           << " m from the origin of its body '" << bodies[side[s]].name << "'; is it where you meant?";
        notes.push_back(os.str());
      }
    } else {
      double nearest_d = 1e300;
      for (int i : {j.parent, j.child})
        if (i >= 0) nearest_d = std::min(nearest_d, (bodies[i].p_WB - j.anchor_W).norm());
      if (nearest_d > 10 && nearest_d < 1e300) {
        std::ostringstream os;
        os << where(n["anchor"], c.child("anchor")) << ": the anchor is " << nearest_d
           << " m from the nearer of its bodies' origins; is it where you meant?";
        notes.push_back(os.str());
      }
    }
    out.push_back(std::move(j));
  }
  // A mimic names its leader, which may come later in the list.
  for (size_t k = 0; k < out.size(); ++k) {
    const YAML::Node mm = list[k]["mimic"];
    if (!mm) continue;
    const Ctx mc = top.index((int)k).child("mimic");
    if (out[k].type != JointType::revolute && out[k].type != JointType::prismatic)
      mc.fail(mm, std::string("only a revolute or prismatic joint can mimic another (this is ") +
                      to_string(out[k].type) + ")");
    if (!mm.IsMap())
      mc.fail(mm, "expected { joint: NAME, multiplier: m, range: [lower, upper] }, got " + show(mm));
    check_keys(mm, mc, {"joint", "multiplier", "range", "also"});
    if (!mm["joint"]) mc.fail(mm, "missing key 'joint' (the joint whose coordinate this one follows)");
    // A leader by name: a revolute or prismatic joint of the list other than this one.
    auto leader_index = [&](const YAML::Node& n, const Ctx& c) {
      const std::string leader = text(n, c);
      std::vector<std::string> names;
      int found = -1;
      for (size_t i = 0; i < out.size(); ++i) {
        if (i != k) names.push_back(out[i].name);
        if (out[i].name == leader) found = (int)i;
      }
      if (found < 0) {
        std::string msg = "no joint is named '" + leader + "'";
        if (auto nm = nearest(leader, names)) msg += "; did you mean '" + *nm + "'?";
        c.fail(n, msg);
      }
      if (found == (int)k) c.fail(n, "a joint cannot mimic itself");
      if (out[found].type != JointType::revolute && out[found].type != JointType::prismatic)
        c.fail(n, "'" + leader + "' is a " + to_string(out[found].type) +
                      " joint: a mimic follows a revolute or prismatic joint's coordinate");
      return found;
    };
    JointMimic m;
    m.leader = leader_index(mm["joint"], mc.child("joint"));
    if (mm["multiplier"]) {
      m.multiplier = number(mm["multiplier"], mc.child("multiplier"));
      if (m.multiplier == 0)
        mc.child("multiplier")
            .fail(mm["multiplier"], "must not be 0 (a coordinate held at 0 is a fixed joint)");
    }
    if (const YAML::Node r = mm["range"]) {  // q - multiplier q_leader kept within it, not at 0
      const Ctx rc = mc.child("range");
      if (!r.IsSequence() || r.size() != 2) rc.fail(r, "expected [lower, upper] (rad or m), got " + show(r));
      const double lo = number(r[0], rc.index(0)), hi = number(r[1], rc.index(1));
      if (!(lo < hi) || lo > 0 || hi < 0)
        rc.fail(r, "expected lower < upper with 0 (the start pose) between them, got " + show(r));
      m.range = std::pair{lo, hi};
    }
    // More leaders: { NAME: multiplier, ... }, q - multiplier q_leader - sum m_k q_k the combination.
    if (const YAML::Node a = mm["also"]) {
      const Ctx ac = mc.child("also");
      if (!a.IsMap() || a.size() == 0) ac.fail(a, "expected { JOINT: multiplier, ... }, got " + show(a));
      for (const auto& kv : a) {
        const Ctx ec = ac.child(kv.first.as<std::string>());
        const int idx = leader_index(kv.first, ec);
        const double mult = number(kv.second, ec);
        if (mult == 0) ec.fail(kv.second, "must not be 0");
        for (const auto& [other, c] : m.also)
          if (other == idx) ec.fail(kv.first, "names a joint twice");
        if (idx == m.leader) ec.fail(kv.first, "is the mimic's joint already");
        m.also.emplace_back(idx, mult);
      }
    }
    out[k].mimic = m;
  }
  // A pulley's wheel turns on a revolute joint (one of its two bodies), which may come later in the list.
  for (size_t k = 0; k < out.size(); ++k) {
    const JointDef& p = out[k];
    if (p.type != JointType::pulley || p.wheel < 0) continue;
    const bool hinged = std::any_of(out.begin(), out.end(), [&](const JointDef& o) {
      return o.type == JointType::revolute && (o.child == p.wheel || o.parent == p.wheel);
    });
    if (!hinged)
      top.index((int)k).child("wheel").fail(list[k]["wheel"], "the wheel '" + bodies[p.wheel].name +
                                                                  "' turns on no revolute joint: give it one "
                                                                  "about its axle (type: revolute)");
  }
  return out;
}

}  // namespace simreel
