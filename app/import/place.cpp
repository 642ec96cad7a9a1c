#include "app/import/place.hpp"
#include "app/scene/scene_place.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <set>
#include <sstream>

#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "app/scene/mesh_library.hpp"
#include "app/scene/scene.hpp"
#include "render/material.hpp"
#include "sim/geometry/convex_decomposition.hpp"

namespace simreel {

namespace {

// A body of the placed model: the link that owns it and the links welded to it.
struct PlacedBody {
  int link = -1;           // the owning link
  std::vector<int> links;  // every link in it, the owner first
  int index = -1;          // in scene.bodies
};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::string moments_str(const Vec3& m) {
  return "(" + fmt(m[0]) + ", " + fmt(m[1]) + ", " + fmt(m[2]) + ")";
}

// A shape's collider with its mass properties at unit density (a mesh: from the library; an open
// mesh weighs as its hull, with a note), placed at `pose` in the body frame.
// A static body's meshes collide as their triangles and weigh nothing (weigh_mesh false).
Collider shape_collider(const ModelShape& s, const ModelPose& pose, MeshLibrary& meshes, bool weigh,
                        bool weigh_mesh, bool decompose, std::vector<std::string>& notes) {
  Collider c;
  using K = ModelShape::Kind;
  switch (s.kind) {
    case K::box:
      c.shape = ShapeKind::box, c.size = s.size;
      break;
    case K::sphere:
      c.shape = ShapeKind::sphere, c.radius = s.radius;
      break;
    case K::cylinder:
      c.shape = ShapeKind::cylinder, c.radius = s.radius, c.height = s.length;
      break;
    case K::capsule:
      c.shape = ShapeKind::capsule, c.radius = s.radius, c.height = s.length;
      break;
    case K::ellipsoid:
      c.shape = ShapeKind::ellipsoid, c.radii = s.radii;
      break;
    case K::plane:
      c.shape = ShapeKind::plane;
      break;
    case K::mesh:
      c.shape = ShapeKind::mesh;
      break;
  }
  c.p_BC = pose.p;
  c.q_BC = pose.q;
  c.label = s.kind == K::mesh ? s.mesh_file : to_string(c.shape);
  c.props_C.mass = 0;
  c.props_C.inertia = Mat3::Zero();
  if (s.kind == K::mesh && s.inline_mesh) {
    c.mesh = s.inline_mesh;
    if (weigh) {
      MeshMassOptions opt;
      opt.density = 1.0;
      try {
        c.props_C = analyze_mesh(*s.inline_mesh, opt).props;
      } catch (const InputError& e) {  // faces that close no solid
        opt.mode = MassMode::hull;
        c.props_C = analyze_mesh(*s.inline_mesh, opt).props;
        notes.push_back(s.src.str() + ": its mesh's faces are not a closed solid (" + e.what() +
                        "); weighed as their convex hull");
      }
    }
  } else if (s.kind == K::mesh) {
    c.mesh = meshes.surface(s.mesh_file, s.scale);
    if (weigh && weigh_mesh) {
      MeshMassOptions opt;
      try {
        c.props_C = meshes.analysis(s.mesh_file, s.scale, opt).props;
      } catch (const InputError& e) {
        opt.mode = MassMode::hull;
        c.props_C = meshes.analysis(s.mesh_file, s.scale, opt).props;
        notes.push_back(s.src.str() + ": " + s.mesh_file + " is not a closed solid (" + e.what() +
                        "); weighed as its convex hull");
      }
    }
  } else if (weigh && s.kind != K::plane) {
    c.props_C = primitive_mass(c, 1.0);
  }
  // `collision: decompose`: a moving link's concave collision mesh collides as itself.
  if (decompose && s.kind == K::mesh && s.collision && weigh_mesh && !s.inline_mesh) {
    try {
      const Decomposition& d = meshes.decomposition(s.mesh_file, s.scale, 0);
      c.hulls = d.parts;
      char b[160];
      std::snprintf(b, sizeof b, ": decomposed into %zu convex parts holding %.3g%% %s volume than the mesh",
                    d.parts.size(), 100 * std::fabs(d.excess()), d.excess() >= 0 ? "more" : "less");
      notes.push_back(s.src.str() + b);
    } catch (const InputError& e) {
      notes.push_back(s.src.str() + ": " + s.mesh_file + " cannot be decomposed (" + e.what() +
                      "); it collides as its convex hull");
    }
  }
  if (s.friction) c.friction = *s.friction;
  if (s.restitution) c.restitution = *s.restitution;
  c.group = s.group;
  c.mask = s.mask;
  return c;
}

// The lowest world z of a collider of a body at (p_WB, q_WB): its reach down from the body origin.
double lowest_z(const Collider& c, const Vec3& p_WB, const Quat& q_WB) {
  if (c.shape == ShapeKind::plane) return std::numeric_limits<double>::infinity();
  return p_WB.z() - collider_reach(c, q_WB.conjugate() * Vec3(0, 0, -1));
}

}  // namespace

void apply_keyframe(Model& m, ImportSpec& spec, std::vector<std::string>& notes) {
  const std::string where = spec.src.str() + ".keyframe: ";
  const auto it = std::find_if(m.keys.begin(), m.keys.end(),
                               [&](const Model::Key& k) { return k.name == spec.keyframe; });
  if (it == m.keys.end()) {
    std::vector<std::string> names;
    for (const Model::Key& k : m.keys) names.push_back(k.name);
    std::string msg = where + m.file + " has no key named '" + spec.keyframe + "'";
    if (names.empty())
      msg += " (it has no <keyframe>)";
    else if (auto s = nearest(spec.keyframe, names))
      msg += "; did you mean '" + *s + "'?";
    throw InputError(msg);
  }
  const std::vector<double>& q = it->qpos;
  size_t need = 0;
  for (const Model::QposSlot& s : m.qpos_layout) need += (size_t)s.width;
  if (q.size() != need)
    throw InputError(where + it->src.str() + ": key '" + it->name + "' has " + std::to_string(q.size()) +
                     " qpos numbers; the file's joints take " + std::to_string(need) +
                     " (a free joint 7, a ball joint 4, a hinge or slide 1)");
  for (double x : q)
    if (!std::isfinite(x))
      throw InputError(where + it->src.str() + ": key '" + it->name + "' has a number that is not finite");
  size_t at = 0;
  for (const Model::QposSlot& s : m.qpos_layout) {
    const double* v = q.data() + at;
    at += (size_t)s.width;
    if (s.link >= 0) {  // a free body: its pose in the file's world frame
      const Quat r(v[3], v[4], v[5], v[6]);
      if (!(r.norm() > 0))
        throw InputError(where + it->src.str() + ": key '" + it->name + "': body '" + m.links[s.link].name +
                         "' has a zero quaternion");
      m.links[s.link].pose = ModelPose{Vec3(v[0], v[1], v[2]), r.normalized()};
      continue;
    }
    const ModelJoint& j = m.joints[s.joint];
    if (s.width == 4) {  // a ball joint: w x y z
      const Quat r(v[0], v[1], v[2], v[3]);
      if (!(r.norm() > 0))
        throw InputError(where + it->src.str() + ": key '" + it->name + "': ball joint '" + j.name +
                         "' has a zero quaternion");
      const Quat u = r.normalized();
      if (u.angularDistance(Quat::Identity()) == 0) continue;
      spec.ball_rotations[j.name] = u;
      // simreel measures a ball joint's range and spring from its start pose; MuJoCo from the
      // file's (qpos = 1 0 0 0).
      if (j.limits || j.stiffness > 0)
        notes.push_back(where + "key '" + it->name + "': ball joint '" + j.name +
                        "' starts turned by the key; its " + (j.limits ? "range" : "spring") +
                        " is measured from there, not from the file's pose");
      continue;
    }
    if (!spec.joint_positions.count(j.name)) spec.joint_positions[j.name] = v[0] - s.ref;
  }
}

namespace {
// The file's camera the import names (imports: camera) becomes the scene's: it looks along its
// frame's -z with +y up, at its vertical field of view. On a moving body a fixed camera rides in
// that body's frame (camera.frame); a tracking one follows the body (camera.follow: simreel aims
// it at the body, where MuJoCo keeps the file's direction); a targeting one turns to its target
// (camera.aim) from where it stands in its body. Without a name, the file's cameras
// are listed in a note.
void place_camera(const Model& m, const ImportSpec& spec, const std::vector<ModelPose>& X,
                  const std::vector<int>& body_of, const std::vector<PlacedBody>& bodies,
                  const std::vector<bool>& is_static, Scene& scene) {
  if (spec.camera.empty()) {
    if (m.cameras.empty()) return;
    std::string list;
    for (const ModelCamera& c : m.cameras) list += (list.empty() ? "'" : ", '") + c.name + "'";
    scene.notes.push_back(m.file + ": its cameras " + list +
                          " (imports: camera: NAME makes one the scene's)");
    return;
  }
  const auto it = std::find_if(m.cameras.begin(), m.cameras.end(),
                               [&](const ModelCamera& c) { return c.name == spec.camera; });
  if (it == m.cameras.end()) {
    std::vector<std::string> names;
    for (const ModelCamera& c : m.cameras) names.push_back(c.name);
    std::string msg = spec.src.str() + ".camera: " + m.file + " has no camera named '" + spec.camera + "'";
    if (names.empty())
      msg += " (it has no <camera>)";
    else if (auto s = nearest(spec.camera, names))
      msg += "; did you mean '" + *s + "'?";
    throw InputError(msg);
  }
  const ModelCamera& c = *it;
  const std::string prefix = spec.name.empty() ? "" : spec.name + "/";
  const ModelPose W = (c.link < 0 ? spec.pose : X[c.link]) * c.pose;
  const Vec3 eye = W.p, forward = W.q * Vec3(0, 0, -1), up = W.q * Vec3::UnitY();
  CameraSpec cs;
  cs.fov = c.fovy;
  cs.position = eye;
  cs.look_at = eye + forward;
  cs.up = up;
  const int b = c.link < 0 ? -1 : body_of[c.link];
  const bool moving = b >= 0 && !is_static[b];
  using M = ModelCamera::Mode;
  if (moving && c.mode == M::fixed) {
    const ModelPose& B = X[bodies[b].link];
    const Quat qi = B.q.conjugate();
    cs.frame_body = prefix + m.links[bodies[b].link].name;
    cs.position = qi * (eye - B.p);
    cs.look_at = qi * (eye + forward - B.p);
    cs.up = qi * up;
  } else if (moving && (c.mode == M::track || c.mode == M::trackcom)) {
    cs.follow = prefix + m.links[bodies[b].link].name;
    cs.look_at = X[c.link].p;
    scene.notes.push_back(
        c.src.str() + ": mode " + (c.mode == M::track ? "track" : "trackcom") +
        " follows the body aimed at it (simreel's camera.follow; MuJoCo keeps the file's direction)");
  } else if (c.mode == M::targetbody || c.mode == M::targetbodycom) {
    // MuJoCo: the position stays in the camera's body, the camera turns to the target body's
    // frame origin (targetbody) or its subtree's centre of mass (targetbodycom). simreel aims at
    // centres of mass (camera.aim): for targetbody that differs by the target's own offset from
    // its frame, which a note says.
    cs.look_at = X[c.target].p;
    if (moving) {
      const ModelPose& B = X[bodies[b].link];
      const Quat qi = B.q.conjugate();
      cs.frame_body = prefix + m.links[bodies[b].link].name;
      cs.position = qi * (eye - B.p);
      cs.look_at = qi * (cs.look_at - B.p);
      cs.up = qi * up;
    }
    std::vector<bool> in(m.links.size(), false);  // the target's subtree (targetbody: itself)
    in[c.target] = true;
    if (c.mode == M::targetbodycom)
      for (bool grew = true; grew;) {
        grew = false;
        for (const ModelJoint& j : m.joints)
          if (!j.loop && in[j.parent] && !in[j.child]) in[j.child] = grew = true;
      }
    std::vector<int> aimed;
    for (size_t l = 0; l < m.links.size(); ++l) {
      const int tb = in[l] ? body_of[l] : -1;
      if (tb >= 0 && std::find(aimed.begin(), aimed.end(), tb) == aimed.end()) aimed.push_back(tb);
    }
    for (int tb : aimed) cs.aim.push_back(prefix + m.links[bodies[tb].link].name);
    if (c.mode == M::targetbody && !aimed.empty())
      scene.notes.push_back(c.src.str() + ": turns to '" + m.links[c.target].name +
                            "''s centre of mass (camera.aim; MuJoCo aims at its frame's origin)");
  }
  if ((cs.position - cs.look_at).norm() == 0) cs.look_at = eye + forward;
  scene.camera = cs;
}
}  // namespace

void place_model(const Model& m, const ImportSpec& spec, Scene& scene, MeshLibrary& meshes) {
  const size_t n = m.links.size();
  const std::string prefix = spec.name.empty() ? "" : spec.name + "/";
  bool floor_look = false;  // the file's floor checker became the ground's
  // The tree: each link's parent joint (or -1), children in file order.
  std::vector<int> parent_joint(n, -1);
  for (size_t k = 0; k < m.joints.size(); ++k)
    if (!m.joints[k].loop) parent_joint[m.joints[k].child] = (int)k;
  // A URDF root named "world" holding nothing is the world itself (the convention of ROS arms).
  std::vector<bool> is_world(n, false);
  for (size_t i = 0; i < n; ++i)
    is_world[i] = parent_joint[i] < 0 && m.links[i].name == "world" && !m.links[i].inertial &&
                  m.links[i].shapes.empty();
  auto parent_link = [&](int l) { return parent_joint[l] < 0 ? -1 : m.joints[parent_joint[l]].parent; };

  // Start values: a coordinate whose limits leave out 0 starts at the nearer limit (simreel's joint
  // coordinates are zero at the start pose, so the limits are shifted by it).
  std::vector<double> q0(m.joints.size(), 0.0);
  for (const auto& entry : spec.joint_positions) {
    // Named, not a structured binding: clang 14 cannot capture a binding in a lambda.
    const std::string& name = entry.first;
    const double value = entry.second;
    const auto it =
        std::find_if(m.joints.begin(), m.joints.end(), [&](const ModelJoint& j) { return j.name == name; });
    if (it == m.joints.end()) {
      std::vector<std::string> names;
      for (const ModelJoint& j : m.joints) names.push_back(j.name);
      std::string msg = spec.src.str() + ".joint_positions: " + m.file + " has no joint named '" + name + "'";
      if (auto s = nearest(name, names)) msg += "; did you mean '" + *s + "'?";
      throw InputError(msg);
    }
    using K = ModelJoint::Kind;
    if (it->kind != K::revolute && it->kind != K::continuous && it->kind != K::prismatic)
      throw InputError(spec.src.str() + ".joint_positions: joint '" + name +
                       "' is not a revolute, continuous or prismatic joint (one coordinate)");
    if (it->limits && (value < (*it->limits)[0] || value > (*it->limits)[1]))
      throw InputError(spec.src.str() + ".joint_positions: " + name + " = " + fmt(value) +
                       " is outside its limits [" + fmt((*it->limits)[0]) + ", " + fmt((*it->limits)[1]) +
                       "]");
    q0[it - m.joints.begin()] = value;
  }
  for (size_t k = 0; k < m.joints.size(); ++k)
    if (const auto& L = m.joints[k].limits;
        L && !spec.joint_positions.count(m.joints[k].name) && ((*L)[0] > 0 || (*L)[1] < 0)) {
      q0[k] = std::clamp(0.0, (*L)[0], (*L)[1]);
      scene.notes.push_back(m.joints[k].src.str() + ": limits [" + fmt((*L)[0]) + ", " + fmt((*L)[1]) +
                            "] leave out 0: the joint starts at " + fmt(q0[k]));
    }
  // A mimic's leader, by name; the follower starts where the mimic puts it (its own limits and
  // joint_positions give way: the coupling decides its value).
  std::vector<int> leader_of(m.joints.size(), -1);
  for (size_t k = 0; k < m.joints.size(); ++k) {
    const ModelJoint& j = m.joints[k];
    if (j.mimic_joint.empty()) continue;
    using K = ModelJoint::Kind;
    auto one = [](K x) { return x == K::revolute || x == K::continuous || x == K::prismatic; };
    for (size_t i = 0; i < m.joints.size(); ++i)
      if (m.joints[i].name == j.mimic_joint) leader_of[k] = (int)i;
    const int l = leader_of[k];
    if (l < 0 || l == (int)k || !one(j.kind) || !one(m.joints[l].kind) || !m.joints[l].mimic_joint.empty() ||
        j.mimic_multiplier == 0) {
      scene.notes.push_back(j.src.str() + ": " +
                            (m.format == "mjcf" ? "<equality joint> to '" + j.mimic_joint + "' "
                                                : "<mimic joint=\"" + j.mimic_joint + "\"> ") +
                            (l < 0 ? "names no joint of the file"
                                   : "cannot be held (simreel couples a revolute or "
                                     "prismatic joint to another that mimics none, "
                                     "with a nonzero multiplier)") +
                            ": this joint moves on its own");
      leader_of[k] = -1;
      continue;
    }
    q0[k] = j.mimic_multiplier * q0[l] + j.mimic_offset;
  }
  // World poses of the links at the start, root first.
  std::vector<ModelPose> X(n);
  std::vector<bool> done(n, false);
  std::function<const ModelPose&(int)> pose_of = [&](int l) -> const ModelPose& {
    if (done[l]) return X[l];
    const int jk = parent_joint[l];
    ModelPose rel = m.links[l].pose;
    if (jk >= 0 && m.joints[jk].kind == ModelJoint::Kind::spherical) {
      if (const auto b = spec.ball_rotations.find(m.joints[jk].name); b != spec.ball_rotations.end()) {
        ModelPose move;  // in the child frame, about the anchor
        move.q = b->second;
        move.p = m.joints[jk].anchor - move.q * m.joints[jk].anchor;
        rel = rel * move;
      }
    } else if (jk >= 0 && q0[jk] != 0) {
      const ModelJoint& j = m.joints[jk];
      ModelPose move;  // in the child frame: about (along) the axis through the anchor
      if (j.kind == ModelJoint::Kind::prismatic) {
        move.p = q0[jk] * j.axis;
      } else {
        move.q = Quat(Eigen::AngleAxisd(q0[jk], j.axis));
        move.p = j.anchor - move.q * j.anchor;
      }
      rel = rel * move;
    }
    const int p = parent_link(l);
    X[l] = (p < 0 ? spec.pose : pose_of(p)) * rel;
    done[l] = true;
    return X[l];
  };
  for (size_t i = 0; i < n; ++i) pose_of((int)i);

  // Bodies: a link welded to its parent (fixed joint; planar, which simreel cannot make, the same
  // with a note) joins its parent's body; a floating joint frees its child.
  std::vector<int> body_of(n, -1);
  std::vector<PlacedBody> bodies;
  std::function<int(int)> assign = [&](int l) -> int {
    if (body_of[l] >= 0 || is_world[l]) return body_of[l];
    const int jk = parent_joint[l];
    const int p = parent_link(l);
    bool welded = false;
    if (jk >= 0) {
      const ModelJoint& j = m.joints[jk];
      if (j.kind == ModelJoint::Kind::planar)  // readers expand planar joints; one left is held
        scene.notes.push_back(j.src.str() + ": a planar joint is held fixed");
      welded =
          (j.kind == ModelJoint::Kind::fixed || j.kind == ModelJoint::Kind::planar) && p >= 0 && !is_world[p];
    }
    if (welded) {
      body_of[l] = assign(p);
      bodies[body_of[l]].links.push_back(l);
    } else {
      body_of[l] = (int)bodies.size();
      bodies.push_back({l, {l}, -1});
    }
    return body_of[l];
  };
  for (size_t i = 0; i < n; ++i) assign((int)i);

  // Static bodies: welded to the world, or the root with fixed_base.
  std::vector<bool> is_static(bodies.size(), false);
  for (size_t b = 0; b < bodies.size(); ++b) {
    const int l = bodies[b].link;
    const int jk = parent_joint[l];
    const int p = parent_link(l);
    if (jk < 0) {
      // A root with no mass is fixed to the world, as Bullet reads it (cartpole's slide bar, a
      // concave bin): nothing could move it.
      // (URDF: a link's mass is its <inertial>; MJCF: its geoms weigh too.)
      bool holds_mass = false;
      for (int x : bodies[b].links) {
        holds_mass = holds_mass || (m.links[x].inertial && m.links[x].inertial->mass > 0);
        if (m.format != "urdf")
          for (const ModelShape& s : m.links[x].shapes) holds_mass = holds_mass || s.weighs;
      }
      is_static[b] = spec.fixed_base || !holds_mass;
      if (is_static[b] && !spec.fixed_base)
        scene.notes.push_back(m.links[l].src.str() +
                              ": the root link has no mass: fixed to the world (as Bullet "
                              "reads it); give it an <inertial> mass to let it move");
    } else if ((p < 0 || is_world[p]) && m.joints[jk].kind == ModelJoint::Kind::fixed) {
      is_static[b] = true;  // welded to the world
    }
  }

  std::set<std::string> names;
  for (const BodyDef& b : scene.bodies) names.insert(b.name);
  const int first = (int)scene.bodies.size();
  for (size_t b = 0; b < bodies.size(); ++b) {
    PlacedBody& pb = bodies[b];
    const ModelLink& owner = m.links[pb.link];
    BodyDef def;
    def.name = prefix + owner.name;
    if (!names.insert(def.name).second)
      throw InputError(spec.src.str() + ": link '" + owner.name + "' of " + m.file + " makes a body named '" +
                       def.name + "', which the scene already has: give the import a `name`");
    def.p_WB = X[pb.link].p;
    def.q_WB = X[pb.link].q;
    def.type = is_static[b] ? BodyType::static_body : BodyType::dynamic;
    BodyLook look;
    const ModelPose to_body_inv{-(def.q_WB.conjugate() * def.p_WB), def.q_WB.conjugate()};
    // The file's mass properties (a link's stated inertial, else its shapes at their own
    // densities) and the geometry's (its shapes scaled to the stated mass, else the same).
    MassAccumulator file_mass, geom_unit;
    for (int l : pb.links) {
      const ModelLink& link = m.links[l];
      const ModelPose X_BL = to_body_inv * X[l];  // the link's frame in the body's
      const Mat3 R_BL = X_BL.q.toRotationMatrix();
      // This link's weighing shapes at unit density (to scale to a stated mass), and each at its
      // own density or mass (the link's mass when it states none).
      MassAccumulator link_geom, link_own;
      for (const ModelShape& s : link.shapes) {
        const ModelPose X_BS = X_BL * s.pose;
        // A file's own floor (MJCF's worldbody plane) where the scene already has its ground.
        if (s.kind == ModelShape::Kind::plane && scene.ground && is_static[b]) {
          const ModelPose X_WS = X[l] * s.pose;
          if ((X_WS.q * Vec3::UnitZ()).z() > 1 - 1e-12 &&
              std::fabs(X_WS.p.z() - scene.ground->height) < 1e-9) {
            scene.notes.push_back(s.src.str() + ": the file's floor plane is the scene's ground; left out");
            if (s.checker && !scene.look_given) {  // drawn in the file's checker
              const auto lin = [](const std::array<float, 3>& c) {
                return std::array<float, 3>{srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2])};
              };
              scene.render.ground_color = lin(s.checker->rgb1);
              scene.render.ground_color2 = lin(s.checker->rgb2);
              scene.render.ground_tile = s.checker->tile;
              floor_look = true;
            }
            continue;
          }
        }
        Collider c;
        try {
          c = shape_collider(s, X_BS, meshes, s.collision || s.weighs, !is_static[b], spec.decompose,
                             scene.notes);
        } catch (const InputError& e) {
          throw InputError(s.src.str() + ": " + e.what());
        }
        if (s.weighs && s.kind != ModelShape::Kind::plane && !is_static[b]) {
          MassProperties u = placed(c.props_C, c.q_BC.toRotationMatrix(), c.p_BC);
          link_geom.add(u);
          const double rho = s.mass ? *s.mass / u.mass : s.density.value_or(1000.0);
          if (rho > 0) {
            u.mass *= rho;
            u.inertia *= rho;
            link_own.add(u);
          }
        }
        c.collide = s.collision;
        if (!s.collision) {  // drawn only: weighs nothing
          c.props_C.mass = 0;
          c.props_C.inertia = Mat3::Zero();
        }
        ColliderLook cl;
        cl.drawn = spec.show_colliders ? s.collision : s.visual;
        if (spec.show_colliders) {
          cl.color = Rgb{0.90f, 0.45f, 0.10f};  // orange: what collides, for checking
        } else if (!s.texture.empty() && s.kind == ModelShape::Kind::mesh && !s.inline_mesh) {
          const auto file = meshes.file(s.mesh_file, s.scale);
          if (file->appearance && !file->appearance->corner_uv.empty()) {
            cl.appearance = image_on_uvs(*file->appearance, s.texture);
            cl.color = Rgb{1, 1, 1};
          } else {
            scene.notes.push_back(s.src.str() + ": " + s.mesh_file +
                                  " has no texture coordinates to lay its texture on; drawn in its colour");
          }
        } else if (s.kind == ModelShape::Kind::mesh && !s.inline_mesh) {
          const auto file = meshes.file(s.mesh_file, s.scale);
          if (file->appearance && file->appearance->varies) cl.appearance = file->appearance;
          if (file->color) cl.color = *file->color;
          if (!file->corner_normals.empty())
            cl.normals = std::shared_ptr<const std::vector<std::array<Eigen::Vector3f, 3>>>(
                file, &file->corner_normals);
        } else if (!s.texture.empty()) {
          scene.notes.push_back(s.src.str() + ": a " + std::string(to_string(c.shape)) +
                                " has no texture coordinates; its texture is not drawn");
        }
        // The file's colour (display values, sRGB-encoded) tints what has no texture of its own.
        if (s.color && !spec.show_colliders && !(cl.appearance && !cl.appearance->textures.empty())) {
          cl.color = Rgb{srgb_to_linear((*s.color)[0]), srgb_to_linear((*s.color)[1]),
                         srgb_to_linear((*s.color)[2])};
          cl.appearance.reset();
        }
        look.colliders.push_back(std::move(cl));
        def.append_collider(std::move(c));
      }
      // Stated and geometric mass properties of the link, in the body frame.
      const double mass = link.inertial ? link.inertial->mass : 0.0;
      if (link.inertial && mass > 0) {
        MassProperties f;
        f.mass = mass;
        f.com = link.inertial->com;
        f.inertia = link.inertial->inertia;
        file_mass.add(placed(f, R_BL, X_BL.p));
      }
      if (link_geom.count() == 0) continue;
      MassProperties g = link_geom.result();  // link geometry at unit density, body frame
      if (mass > 0) {
        const double rho = mass / g.mass;
        g.mass *= rho;
        g.inertia *= rho;
        if (spec.inertia == InertiaPolicy::check && link.inertial) {
          const Vec3 mf = principal_axes(R_BL * link.inertial->inertia * R_BL.transpose()).moments;
          const Vec3 mg = principal_axes(g.inertia).moments;
          const Vec3 cf = X_BL * link.inertial->com;
          double worst = 0;
          for (int i = 0; i < 3; ++i)
            worst = std::max(worst, std::fabs(mf[i] - mg[i]) / std::max(mf[i], mg[i]));
          const double size =
              std::sqrt(2.5 * mg.maxCoeff() / mass);  // a solid sphere's radius with that moment
          const double off = (cf - g.com).norm();
          if (worst > 0.25 || off > 0.1 * size) {
            std::ostringstream os;
            os << link.inertial->src.str()
               << ": the stated inertia disagrees with the link's collision geometry at " << fmt(mass)
               << " kg: principal moments " << moments_str(mf) << " kg m^2 stated, " << moments_str(mg)
               << " from the geometry";
            if (off > 0.1 * size) os << "; centre of mass " << fmt(1000 * off) << " mm from the geometry's";
            os << " (the file's values are used; `inertia: geometry` uses the geometry's)";
            scene.warnings.push_back(os.str());
          }
        }
        geom_unit.add(g);
      } else if (!is_static[b] && link_own.count() > 0) {
        // No stated mass: each shape at its own density (MJCF's rule; URDF has none: water's).
        const MassProperties own = link_own.result();
        geom_unit.add(own);
        file_mass.add(own);
        if (m.format == "urdf")
          scene.notes.push_back(link.src.str() +
                                ": no <inertial> mass: weighed from its collision geometry at "
                                "1000 kg/m^3 (" +
                                fmt(own.mass) + " kg)");
      }
    }
    if (!is_static[b] && owner.helper_of < 0) {
      const bool use_geometry = spec.inertia == InertiaPolicy::geometry;
      if (use_geometry && geom_unit.count() > 0) {
        def.mass_override = geom_unit.result();
      } else if (file_mass.count() > 0) {
        def.mass_override = file_mass.result();
        if (spec.inertia == InertiaPolicy::geometry)
          scene.notes.push_back(owner.src.str() +
                                ": no collision geometry to weigh: the file's inertia is used");
      } else {
        throw InputError(owner.src.str() +
                         ": has no mass (no <inertial>) and no collision geometry to weigh, "
                         "yet moves: give it an <inertial> or weld it to a link that has one");
      }
      if (const std::string bad = mass_problem(*def.mass_override, 1e-6); !bad.empty()) {
        // A stated inertia that no rigid body has: the geometry's when there is one.
        if (geom_unit.count() > 0 && !use_geometry) {
          scene.warnings.push_back(owner.src.str() + ": the stated mass properties are not physical (" + bad +
                                   "); the collision geometry's are used");
          def.mass_override = geom_unit.result();
        } else {
          throw InputError(owner.src.str() + ": mass properties are not physical: " + bad);
        }
      }
    }
    pb.index = (int)scene.bodies.size();
    scene.bodies.push_back(std::move(def));
    scene.looks.push_back(std::move(look));
  }

  // Helper links (a body's extra joints) weigh 1e-9 of the body they serve, as a small sphere at
  // their origin: enough for every simreel body to have a mass, too little to show in any result.
  int helpers = 0;
  for (size_t b = 0; b < bodies.size(); ++b)
    if (const int owner = m.links[bodies[b].link].helper_of; owner >= 0) {
      const BodyDef& served = scene.bodies[bodies[body_of[owner]].index];
      const double mass = served.mass_override ? served.mass_override->mass : 1.0;
      MassProperties h;
      h.mass = 1e-9 * mass;
      h.com = Vec3::Zero();
      h.inertia = Mat3::Identity() * (1e-9 * mass) * 1e-4;  // a 1.6 cm sphere's, scaled with the mass
      scene.bodies[bodies[b].index].mass_override = h;
      ++helpers;
    }
  if (helpers)
    scene.notes.push_back(
        m.file + ": " + std::to_string(helpers) +
        " helper bodies (named BODY#k, 1e-9 of their body's mass) carry the extra joints of bodies "
        "with more than one");

  // Joints.
  const size_t joints_before = scene.joints.size();
  std::vector<int> scene_joint(m.joints.size(), -1);  // the model's joint k as the scene's
  for (size_t k = 0; k < m.joints.size(); ++k) {
    const ModelJoint& j = m.joints[k];
    using K = ModelJoint::Kind;
    if (!j.loop && (j.kind == K::fixed || j.kind == K::planar))
      continue;  // welded into its parent's body, or static
    if (j.kind == K::floating) {
      if (j.parent >= 0 && !is_world[j.parent])
        scene.notes.push_back(j.src.str() + ": a floating joint leaves its child free (six freedoms)");
      continue;
    }
    JointDef d;
    d.name = prefix + j.name;
    int cb = body_of[j.child];
    int pb = j.parent < 0 || is_world[j.parent] ? -1 : body_of[j.parent];
    if (j.loop && is_static[cb] && pb >= 0 && !is_static[pb])
      std::swap(cb, pb);  // the moving body is the child
    if (j.loop && cb == pb) {
      scene.notes.push_back(j.src.str() + ": joins two links of one rigid body; nothing to hold");
      continue;
    }
    d.child = bodies[cb].index;
    d.parent = pb < 0 ? -1 : bodies[pb].index;
    if (is_static[cb])
      throw InputError(j.src.str() + ": moves link '" + m.links[j.child].name +
                       "', which is welded to the world");
    d.anchor_W = X[j.child] * j.anchor;
    d.axis_W = (X[j.child].q * j.axis).normalized();
    switch (j.kind) {
      case K::revolute:
      case K::continuous:
        d.type = JointType::revolute;
        break;
      case K::prismatic:
        d.type = JointType::prismatic;
        break;
      case K::spherical:
        d.type = JointType::spherical;
        break;
      case K::fixed:  // a loop's weld
        d.type = JointType::fixed;
        break;
      default:
        break;
    }
    if (j.limits && j.kind == K::spherical) {
      BallLimits B;
      B.angle = (*j.limits)[1];
      d.ball_limits = B;
    } else if (j.limits) {
      JointLimits L;
      L.lower = (*j.limits)[0] - q0[k];
      L.upper = (*j.limits)[1] - q0[k];
      d.limits = L;
    }
    if (j.damping > 0 || j.stiffness > 0) d.spring = JointSpring{j.stiffness, j.damping, j.rest - q0[k]};
    if (j.kind != K::fixed) d.friction = j.friction;  // a ball joint's: about each of its axes
    if (j.kind == K::revolute || j.kind == K::continuous || j.kind == K::prismatic) d.armature = j.armature;
    // A mimic's follower is passive: the coupling, not a motor, holds it.
    if (spec.hold && leader_of[k] < 0 &&
        (j.kind == K::revolute || j.kind == K::continuous || j.kind == K::prismatic)) {
      if (j.effort > 0) {
        JointMotor mo;
        mo.mode = JointMotor::Mode::position;
        mo.position = 0;
        mo.speed = j.velocity > 0 ? j.velocity : std::numeric_limits<double>::infinity();
        mo.max_force = j.effort;
        d.motor = mo;
      } else {
        scene.notes.push_back(j.src.str() + ": no effort limit: no motor holds it");
      }
    }
    scene_joint[k] = (int)scene.joints.size();
    scene.joints.push_back(std::move(d));
  }
  for (size_t k = 0; k < m.joints.size(); ++k)
    if (leader_of[k] >= 0 && scene_joint[k] >= 0 && scene_joint[leader_of[k]] >= 0)
      scene.joints[scene_joint[k]].mimic =
          JointMimic{scene_joint[leader_of[k]], m.joints[k].mimic_multiplier, std::nullopt};
  // Limited fixed tendons: a coupling kept within a range (a stop on the combination).
  for (size_t k = 0; k < m.joints.size(); ++k) {
    const ModelJoint& j = m.joints[k];
    if (j.coupled_joint.empty()) continue;
    auto index_of = [&](const std::string& name) {
      for (size_t i = 0; i < m.joints.size(); ++i)
        if (m.joints[i].name == name) return (int)i;
      return -1;
    };
    const int l = index_of(j.coupled_joint);
    using K = ModelJoint::Kind;
    auto one = [&](int i) {
      const K x = m.joints[i].kind;
      return (x == K::revolute || x == K::continuous || x == K::prismatic) && scene_joint[i] >= 0 &&
             !m.joints[i].loop && m.joints[i].mimic_joint.empty() && leader_of[i] < 0;
    };
    const double lo = j.coupled_range[0], hi = j.coupled_range[1];
    std::vector<std::pair<int, double>> more;
    bool more_ok = true;
    for (const auto& [name, c] : j.coupled_more) {
      const int i2 = index_of(name);
      more_ok = more_ok && i2 >= 0 && one(i2) && m.joints[i2].coupled_joint.empty();
      if (i2 >= 0) more.emplace_back(i2, c);
    }
    if (l < 0 || !one((int)k) || !one(l) || !m.joints[l].coupled_joint.empty() || !more_ok || lo > 0 ||
        hi < 0) {
      scene.notes.push_back(j.coupled_src.str() +
                            ": its joints cannot carry the limit (simreel keeps a range on revolute or "
                            "prismatic tree joints, none coupled otherwise, with the file's pose inside "
                            "it); ignored");
      continue;
    }
    JointMimic mimic{scene_joint[l], j.coupled_multiplier, std::pair{lo, hi}};
    for (const auto& [i2, c] : more) mimic.also.emplace_back(scene_joint[i2], c);
    scene.joints[scene_joint[k]].mimic = mimic;
  }
  // Ropes: distance joints between their two points, slack up to their length.
  for (const ModelRope& r : m.ropes) {
    auto end = [&](int link, const Vec3& p, int& body, Vec3& p_W) {
      const bool fixed = link < 0 || is_world[link] || body_of[link] < 0 || is_static[body_of[link]];
      body = fixed ? -1 : body_of[link];
      p_W = link < 0 ? spec.pose * p : X[link] * p;
    };
    int ba = -1, bb = -1;
    Vec3 pa, pb;
    end(r.link_a, r.point_a, ba, pa);
    end(r.link_b, r.point_b, bb, pb);
    if (ba == bb) {
      scene.notes.push_back(r.src.str() + ": both ends are on one " + (ba < 0 ? "fixed frame" : "body") +
                            "; nothing to hold");
      continue;
    }
    const double start = (pb - pa).norm();
    if ((r.max_length && start > *r.max_length * (1 + 1e-9)) ||
        (r.min_length && start < *r.min_length * (1 - 1e-9)))
      throw InputError(r.src.str() + ": its ends start " + std::to_string(start) +
                       " m apart, outside its length range");
    std::optional<JointSpring> spring = r.spring;
    if (spring && std::isnan(spring->rest)) spring->rest = start;  // the length in the file's pose
    if (!r.max_length && !r.min_length) {
      // A spring alone: the force list's spring between the two points (no bounds to hold).
      ForceDef f;
      f.kind = ForceKind::spring;
      auto point_in = [&](int b, const Vec3& p_W, int& index, Vec3& at_B) {
        const BodyDef& body = scene.bodies[bodies[b].index];
        index = bodies[b].index;
        at_B = body.q_WB.conjugate() * (p_W - body.p_WB);
      };
      if (ba < 0) std::swap(ba, bb), std::swap(pa, pb);  // the first end moves
      point_in(ba, pa, f.body, f.at_B);
      f.at_centroid = false;
      if (bb < 0) {
        f.anchor_W = pb;
      } else {
        point_in(bb, pb, f.body_b, f.at_b_B);
        f.at_b_centroid = false;
      }
      f.stiffness = spring->stiffness;
      f.damping = spring->damping;
      f.rest_length = spring->rest;
      scene.forces.push_back(f);
      continue;
    }
    JointDef d;
    d.name = prefix + r.name;
    d.type = JointType::distance;
    if (bb < 0) {  // the moving end is the child
      std::swap(ba, bb);
      std::swap(pa, pb);
    }
    d.parent = ba < 0 ? -1 : bodies[ba].index;
    d.child = bodies[bb].index;
    d.anchor_W = pa;
    d.anchor2_W = pb;
    if (r.max_length) d.max_length = std::max(*r.max_length, start);
    if (r.min_length && *r.min_length > 0) d.min_length = std::min(*r.min_length, start);
    d.spring = spring;
    scene.joints.push_back(std::move(d));
  }

  // Lifted (or lowered) so that the lowest point of what collides rests on the ground.
  if (spec.on_ground) {
    double lo = std::numeric_limits<double>::infinity();
    for (int i = first; i < (int)scene.bodies.size(); ++i)
      for (const Collider& c : scene.bodies[i].colliders)
        if (c.collide) lo = std::min(lo, lowest_z(c, scene.bodies[i].p_WB, scene.bodies[i].q_WB));
    if (std::isfinite(lo)) {
      const Vec3 up(0, 0, spec.ground_height - lo);
      for (int i = first; i < (int)scene.bodies.size(); ++i) scene.bodies[i].p_WB += up;
      for (size_t k = joints_before; k < scene.joints.size(); ++k) {
        scene.joints[k].anchor_W += up;
        scene.joints[k].anchor2_W += up;
      }
    }
  }
  // Each format's own default: a URDF model's links collide with the world, not with each other
  // (PyBullet's default: meshes of neighbouring links often overlap where they are joined); an
  // MJCF model's collide by MuJoCo's rule, every pair but those the file excludes (<contact>
  // <exclude>) and a body and its parent (the humanoid falling then gains at most 0.02 J in any
  // frame).
  const int last = (int)scene.bodies.size();
  const bool self = spec.self_collision.value_or(m.format == "mjcf");
  if (!self) {
    for (int a = first; a < last; ++a)
      for (int b = a + 1; b < last; ++b) scene.ignore_pairs.emplace_back(a, b);
  } else {
    std::set<std::pair<int, int>> pairs;  // once each, in order
    // MuJoCo never collides a body with its parent; through helper bodies (a body's extra joints)
    // the parent is the first ancestor that is not a helper.
    for (size_t l = 0; l < n; ++l) {
      if (m.links[l].helper_of >= 0 || body_of[l] < 0) continue;
      int p = parent_link((int)l);
      while (p >= 0 && m.links[p].helper_of >= 0) p = parent_link(p);
      if (p < 0 || body_of[p] < 0 || body_of[p] == body_of[l]) continue;
      const int a = bodies[body_of[l]].index, b = bodies[body_of[p]].index;
      pairs.emplace(std::min(a, b), std::max(a, b));
    }
    for (const auto& [la, lb] : m.exclude) {
      const int ba = body_of[la], bb = body_of[lb];
      if (ba < 0 || bb < 0 || ba == bb) continue;
      const int a = bodies[ba].index, b = bodies[bb].index;
      pairs.emplace(std::min(a, b), std::max(a, b));
    }
    scene.ignore_pairs.insert(scene.ignore_pairs.end(), pairs.begin(), pairs.end());
  }
  // The file's sky (MJCF's gradient skybox: its top colour straight up, the mean of its two at the
  // horizon, where the gradient is half way), unless the scene gives its own.
  if (m.sky && !scene.look_given) {
    for (int k = 0; k < 3; ++k) {
      scene.render.background[k] = srgb_to_linear(m.sky->top[k]);
      scene.render.horizon[k] = srgb_to_linear(0.5f * (m.sky->top[k] + m.sky->bottom[k]));
    }
    scene.render.sky_gradient = true;
  }
  if (m.sky || floor_look) scene.look_given = true;  // the first file's look holds
  // The file's gravity is the scene's unless the scene gives its own (or an earlier file did).
  auto fmt_vec = [](const Vec3& v) {
    char b[96];
    std::snprintf(b, sizeof b, "[%g, %g, %g]", v.x(), v.y(), v.z());
    return std::string(b);
  };
  if (m.gravity && *m.gravity != scene.gravity) {
    if (scene.gravity_given)
      scene.notes.push_back(m.file + ": its gravity (" + fmt_vec(*m.gravity) +
                            " m/s^2) is not the scene's (" + fmt_vec(scene.gravity) + "); the scene's acts");
    else
      scene.gravity = *m.gravity;
  }
  if (m.gravity) scene.gravity_given = true;
  place_camera(m, spec, X, body_of, bodies, is_static, scene);
  for (const std::string& note : m.notes) scene.notes.push_back(note);
  // What the scene now depends on (its goldens notice when one changes).
  scene.inputs.insert(scene.inputs.end(), m.files.begin(), m.files.end());
  for (const ModelLink& l : m.links)
    for (const ModelShape& s : l.shapes)
      if (!s.texture.empty()) scene.inputs.push_back(s.texture);
}

}  // namespace simreel
