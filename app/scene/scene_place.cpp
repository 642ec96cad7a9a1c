// `place:` on a body (scenes/README.md, "place"): where it starts, computed instead of worked out by
// hand. `on:` rests it on another body's top face (a box's face most nearly facing up, or a plane),
// touching, turned with the face; `about:` turns its whole start state about a point.
#include "app/scene/scene_place.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"

namespace simreel {

using scene_yaml::Ctx;

Vec3 collider_support(const Collider& c, const Vec3& d_B) {
  const Mat3 R = c.q_BC.toRotationMatrix();
  const Vec3 d = R.transpose() * d_B;  // collider frame
  Vec3 p = Vec3::Zero();
  switch (c.shape) {
    case ShapeKind::sphere:
      p = c.radius * d.normalized();
      break;
    case ShapeKind::box:
      for (int k = 0; k < 3; ++k) p[k] = (d[k] >= 0 ? 0.5 : -0.5) * c.size[k];
      break;
    case ShapeKind::cylinder:
    case ShapeKind::capsule: {
      const double half = c.shape == ShapeKind::cylinder ? 0.5 * c.height : 0.5 * c.height - c.radius;
      p.z() = d.z() >= 0 ? half : -half;
      if (c.shape == ShapeKind::capsule) {
        p += c.radius * d.normalized();
      } else {
        const double r = std::hypot(d.x(), d.y());
        if (r > 1e-12) p.x() = c.radius * d.x() / r, p.y() = c.radius * d.y() / r;
      }
      break;
    }
    case ShapeKind::ellipsoid: {
      const Vec3 a2d = c.radii.cwiseProduct(c.radii).cwiseProduct(d);
      p = a2d / std::max(c.radii.cwiseProduct(d).norm(), 1e-300);
      break;
    }
    default:  // a mesh: its farthest vertex
      if (c.mesh && !c.mesh->vertices.empty()) {
        p = c.mesh->vertices[0];
        for (const Vec3& v : c.mesh->vertices)
          if (v.dot(d) > p.dot(d)) p = v;
      }
      break;
  }
  return c.p_BC + R * p;
}

double collider_reach(const Collider& c, const Vec3& d_B) {
  return collider_support(c, d_B).dot(d_B);
}

namespace {

// How far the body reaches along d_B from its origin: the largest support over its colliding
// colliders (all of them if none collides).
double reach(const BodyDef& b, const Vec3& d_B) {
  bool any = false;
  for (const Collider& c : b.colliders) any = any || c.collide;
  double best = -1e300;
  for (const Collider& c : b.colliders)
    if ((c.collide || !any) && c.shape != ShapeKind::plane) best = std::max(best, collider_reach(c, d_B));
  return best;
}

// The top face of body `on`'s collider: a box's face whose outward normal points most nearly up, or a
// plane. Its centre, unit normal and, for a box, the face's half-extents along its two edges.
struct Face {
  Vec3 center, normal;
  Vec3 edge[2];    // unit directions of the face's edges
  double half[2];  // m, half-lengths along them (infinite for a plane)
  bool plane = false;
};

Face top_face(const BodyDef& on, const Collider& c, const Vec3& up) {
  const Mat3 R = on.q_WB.toRotationMatrix() * c.q_BC.toRotationMatrix();
  const Vec3 o = on.p_WB + on.q_WB * c.p_BC;
  Face f;
  if (c.shape == ShapeKind::plane) {
    f.plane = true, f.center = o, f.normal = R.col(2);
    f.edge[0] = R.col(0), f.edge[1] = R.col(1);
    f.half[0] = f.half[1] = std::numeric_limits<double>::infinity();
    return f;
  }
  int axis = 0;
  double best = -2, sign = 1;
  for (int k = 0; k < 3; ++k)
    for (double s : {1.0, -1.0})
      if (s * R.col(k).dot(up) > best + 1e-12) best = s * R.col(k).dot(up), axis = k, sign = s;
  f.normal = sign * R.col(axis);
  f.center = o + f.normal * (0.5 * c.size[axis]);
  for (int j = 0; j < 2; ++j) {
    const int k = (axis + 1 + j) % 3;
    f.edge[j] = R.col(k), f.half[j] = 0.5 * c.size[k];
  }
  return f;
}

}  // namespace

void apply_placements(const YAML::Node& bodies, const std::string& path, Scene& s, const Vec3& gravity) {
  if (!bodies || !bodies.IsSequence()) return;
  const Ctx top = Ctx(path, "").child("bodies");
  const Vec3 up = gravity.norm() > 0 ? Vec3(-gravity.normalized()) : Vec3::UnitZ();
  // A body resting on a placed body is placed after it (0: to do, 1: being placed, 2: done).
  std::vector<int> state(s.bodies.size(), 0);
  int depth = 0;  // bodies resting on placed bodies, nested (recursion: bounded)
  std::function<void(size_t)> place = [&](size_t i) {
    if (i >= bodies.size() || !bodies[i].IsMap() || !bodies[i]["place"] || state[i] == 2) return;
    const YAML::Node p = bodies[i]["place"];
    const Ctx c = top.index(i).child("place");
    if (state[i] == 1)
      c.fail(p, "bodies rest on each other in a circle: body '" + s.bodies[i].name + "' again");
    state[i] = 1;
    if (!p.IsMap())
      c.fail(p, "expected { on: BODY, at: s } or { about: [x, y, z], axis: [x, y, z], angle: deg }");
    BodyDef& b = s.bodies[i];
    if (p["about"]) {
      scene_yaml::check_keys(p, c, {"about", "axis", "angle"});
      const Vec3 O = scene_yaml::vec<3>(p["about"], c.child("about"));
      if (!p["axis"] || !p["angle"]) c.fail(p, "turning about a point needs 'axis' and 'angle' (degrees)");
      const Vec3 axis = scene_yaml::vec<3>(p["axis"], c.child("axis"));
      if (!(axis.norm() > 0)) c.child("axis").fail(p["axis"], "the axis is [0, 0, 0]");
      const double angle = scene_yaml::number(p["angle"], c.child("angle")) * std::numbers::pi / 180;
      // The whole start state turned rigidly: pose, and the velocities with it.
      const Quat q(Eigen::AngleAxisd(angle, axis.normalized()));
      b.p_WB = O + q * (b.p_WB - O);
      b.q_WB = (q * b.q_WB).normalized();
      b.v_W = q * b.v_W;
      b.w_W = q * b.w_W;
      state[i] = 2;
      return;
    }
    scene_yaml::check_keys(p, c, {"on", "at", "across", "collider"});
    if (!p["on"]) c.fail(p, "missing key 'on' (the body to rest on) or 'about' (a point to turn about)");
    const std::string name = scene_yaml::text(p["on"], c.child("on"));
    int on = -1;
    std::vector<std::string> names;
    for (size_t k = 0; k < s.bodies.size(); ++k) {
      names.push_back(s.bodies[k].name);
      if (s.bodies[k].name == name) on = (int)k;
    }
    if (on < 0) {
      std::string msg = "no body is named '" + name + "'";
      if (auto sug = nearest(name, names)) msg += "; did you mean '" + *sug + "'?";
      c.child("on").fail(p["on"], msg);
    }
    if (on == (int)i) c.child("on").fail(p["on"], "a body cannot rest on itself");
    if (++depth > 1000) c.child("on").fail(p["on"], "bodies rest on placed bodies more than 1000 deep");
    place((size_t)on);
    --depth;
    const BodyDef& base = s.bodies[on];
    int k = -1;
    if (p["collider"]) {
      const double v = scene_yaml::number(p["collider"], c.child("collider"));
      if (v != std::floor(v) || v < 0 || v >= (double)base.colliders.size())
        c.child("collider")
            .fail(p["collider"], "expected a collider index of body '" + name + "', 0 to " +
                                     std::to_string(base.colliders.size() - 1));
      k = (int)v;
    } else {
      for (size_t j = 0; j < base.colliders.size() && k < 0; ++j)
        if (base.colliders[j].shape == ShapeKind::box || base.colliders[j].shape == ShapeKind::plane)
          k = (int)j;
    }
    if (k < 0 || (base.colliders[k].shape != ShapeKind::box && base.colliders[k].shape != ShapeKind::plane))
      c.child("on").fail(p["on"], "body '" + name + "' has no box or plane collider to rest on" +
                                      (k >= 0 ? " (collider " + std::to_string(k) + " is not one)" : ""));
    const Face f = top_face(base, base.colliders[k], up);
    if (f.normal.dot(up) <= 1e-9)
      c.child("on").fail(p["on"], "body '" + name + "''s top face does not face up (its normal is " +
                                      "at or below the horizontal)");
    // Down the slope: `up`'s opposite within the face; on a level face, the face's first edge.
    Vec3 down = -up + up.dot(f.normal) * f.normal;
    const bool level = down.norm() < 1e-9;
    down = level ? f.edge[0] : Vec3(down.normalized());
    const Vec3 across_dir = f.normal.cross(down);
    Vec3 point = f.center;
    double at_along = 0, at_across = 0;
    if (const YAML::Node a = p["at"]) {
      if (a.IsSequence()) {
        const Eigen::Vector2d v = scene_yaml::vec<2>(a, c.child("at"));
        at_along = v[0], at_across = v[1];
        point += at_along * down + at_across * across_dir;  // from the face's centre
      } else {
        // From the face's uphill edge, down the slope (a box's face only).
        if (f.plane || level)
          c.child("at").fail(a, "on a level face or a plane, 'at' is [along, across] from its centre (m)");
        at_along = scene_yaml::number(a, c.child("at"));
        double to_edge = std::numeric_limits<double>::infinity();
        for (int j = 0; j < 2; ++j)
          if (std::fabs(down.dot(f.edge[j])) > 1e-12)
            to_edge = std::min(to_edge, f.half[j] / std::fabs(down.dot(f.edge[j])));
        point += (at_along - to_edge) * down;
      }
    }
    if (p["across"]) point += scene_yaml::number(p["across"], c.child("across")) * across_dir;
    // The body's frame on the face: x down the slope, z along the normal; its own orientation
    // (`orientation`, `euler`, `axis_angle`) turns it from there.
    Mat3 S;
    S.col(0) = down, S.col(1) = across_dir, S.col(2) = f.normal;
    b.q_WB = (Quat(S) * b.q_WB).normalized();
    // Touching: the body's lowest point along -normal on the face; the origin over `point`.
    const Vec3 n_B = b.q_WB.conjugate() * (-f.normal);
    b.p_WB = point + f.normal * reach(b, n_B);
    state[i] = 2;
  };
  for (size_t i = 0; i < s.bodies.size(); ++i) place(i);
}

}  // namespace simreel
