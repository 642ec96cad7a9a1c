#include "app/scene/ghost.hpp"

#include <algorithm>

#include "app/scene/scene.hpp"
#include <simreel/error.hpp>

namespace simreel {

using namespace scene_yaml;

GhostSpec parse_ghost(const YAML::Node& n, const Ctx& c) {
  GhostSpec g;
  if (n.IsScalar()) {
    g.on = boolean(n, c);
    return g;
  }
  if (!n.IsMap()) c.fail(n, "expected true, false or { color, opacity, offset }, got " + show(n));
  check_keys(n, c, {"color", "opacity", "offset"});
  g.on = true;
  if (n["color"]) {
    const Vec3 v = vec<3>(n["color"], c.child("color"));
    for (int i = 0; i < 3; ++i)
      if (v[i] < 0 || v[i] > 1)
        c.child("color").index(i).fail(n["color"][i], "colour components must lie in [0, 1]");
    g.color = std::array<float, 3>{(float)v[0], (float)v[1], (float)v[2]};
  }
  if (n["opacity"]) {
    g.opacity = unit_interval(n["opacity"], c.child("opacity"));
    if (g.opacity <= 0) c.child("opacity").fail(n["opacity"], "must be above 0 (0 draws nothing)");
  }
  if (n["offset"]) g.offset = vec<3>(n["offset"], c.child("offset"));
  return g;
}

namespace {

// Whether any collider of body a may touch any of body b by their filters (sim/collision/shape_table.hpp).
bool may_touch(const BodyDef& a, const BodyDef& b) {
  for (const Collider& x : a.colliders)
    for (const Collider& y : b.colliders)
      if (x.collide && y.collide && (x.group & y.mask) && (y.group & x.mask)) return true;
  return false;
}

}  // namespace

void check_ghosts(const YAML::Node& root, const std::string& path, const Scene& s) {
  const YAML::Node bodies = root["bodies"];
  for (size_t i = 0; i < s.looks.size() && i < s.bodies.size(); ++i) {
    if (!s.looks[i].ghost.on) continue;
    const Ctx c = Ctx(path, "").child("bodies").index(i).child("ghost");
    const YAML::Node n =
        bodies && bodies.IsSequence() && i < bodies.size() ? bodies[i]["ghost"] : YAML::Node();
    const BodyDef& b = s.bodies[i];
    const std::string who = "body '" + b.name + "' has no closed-form motion to draw as a ghost: ";
    if (b.type != BodyType::dynamic)
      c.fail(n, who + "it is " + std::string(to_string(b.type)) + ", not dynamic");
    for (size_t k = 0; k < s.forces.size(); ++k) {
      const ForceDef& f = s.forces[k];
      if (f.body == (int)i || f.body_b == (int)i)
        c.fail(n, who + "forces[" + std::to_string(k) +
                      "] acts on it (a closed form needs a free body: no "
                      "force but uniform gravity)");
    }
    for (size_t j = 0; j < s.bodies.size(); ++j) {
      if (j == i || !may_touch(b, s.bodies[j])) continue;
      const std::pair<int, int> p((int)std::min(i, j), (int)std::max(i, j));
      if (std::find(s.ignore_pairs.begin(), s.ignore_pairs.end(), p) != s.ignore_pairs.end()) continue;
      c.fail(n, who + "contacts with body '" + s.bodies[j].name +
                    "' could act on it (if they never meet, say so: simulation.ignore_pairs: [[" + b.name +
                    ", " + s.bodies[j].name + "]])");
    }
  }
}

FreeMotion ghost_motion(const World& w, int i) {
  return FreeMotion(w.principal_moments(i), w.principal_orientation(i), w.angular_velocity_principal(i),
                    w.centroid(i), w.linear_velocity(i), w.config().gravity);
}

}  // namespace simreel
