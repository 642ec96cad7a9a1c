// The flat shape table (Box2D's b2Shape array, MuJoCo's geom arrays): one record per colliding
// piece of every collider, built once from the bodies' colliders, in body order. A record holds
// the narrow phase's geometry (sim/collision/narrow/geometry.hpp), its pose in the owning body's principal
// frame P (the frame the state integrates: origin at the centre of mass), the contact material
// and the collision filter. Mass-only colliders (`collide: false`) have no record.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <simreel/body.hpp>
#include "sim/collision/narrow/geometry.hpp"
#include "sim/dynamics/state.hpp"

namespace simreel {

struct ShapeRecord {
  int body = -1;      ///< owning body index
  int collider = -1;  ///< index in the body's colliders
  CollideShape geom;
  Mat3 R_PC = Mat3::Identity();  ///< shape frame C in the body's principal frame P
  Vec3 p_PC = Vec3::Zero();      ///< m
  double friction = 0.6;         ///< Coulomb coefficient
  double restitution = 0;        ///< [0, 1]
  uint32_t group = 1, mask = ~0u;
  // R_PC as a signed permutation (most shapes: a box's or a primitive's principal axes are its own,
  // up to order and sign): perm[j] = +-(1 + i) when column j of R_PC is +-e_i, else all 0; and
  // whether p_PC is zero. world_pose then picks columns instead of multiplying, with the same
  // values (each product term but one is an exact zero): the 3x3 product was 9% of a step among
  // 100,000 falling boxes. Set by classify() after R_PC and p_PC.
  int8_t perm[3] = {0, 0, 0};
  bool centred = false;
  void classify();
};

// World-frame axis-aligned box.
struct Aabb {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< m
  bool overlaps(const Aabb& o) const {
    return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y() &&
           lo.z() <= o.hi.z() && o.lo.z() <= hi.z();
  }
};

class ShapeTable {
 public:
  // Builds the records of every colliding collider. `models` gives each body's principal frame.
  // A static body's mesh colliders collide as their triangles (CollideKind::mesh, sim/geometry/trimesh.hpp,
  // built once per mesh); other mesh colliders as their convex hulls (Collider::hulls, or the hull
  // of the mesh's vertices). Throws InputError for a plane on a body that is not static, or a
  // static mesh with no triangle of any area.
  ShapeTable(const std::vector<BodyDef>& defs, const std::vector<BodyModel>& models,
             std::vector<std::string>& notes);

  const std::vector<ShapeRecord>& shapes() const { return shapes_; }
  int size() const { return (int)shapes_.size(); }
  const ShapeRecord& operator[](int i) const { return shapes_[i]; }

  // World pose of shape i for its body's state.
  static Pose world_pose(const ShapeRecord& s, const MotionState& st) {
    Pose x;
    const Mat3 R_WP = st.q_WP.toRotationMatrix();
    if (s.perm[0] != 0) {
      for (int j = 0; j < 3; ++j)
        x.R.col(j) = s.perm[j] > 0 ? Vec3(R_WP.col(s.perm[j] - 1)) : Vec3(-R_WP.col(-s.perm[j] - 1));
    } else {
      x.R = R_WP * s.R_PC;
    }
    x.p = s.centred ? st.x_W : Vec3(st.x_W + R_WP * s.p_PC);
    return x;
  }
  // Tight world box of a (non-plane) shape at pose x.
  static Aabb bounds(const CollideShape& g, const Pose& x);

 private:
  std::vector<ShapeRecord> shapes_;
  std::vector<std::shared_ptr<const ConvexPolyhedron>> owned_;     ///< box and mesh hulls
  std::vector<std::shared_ptr<const TriMeshShape>> owned_meshes_;  ///< static meshes' triangles
};

// m, the radius of curvature the shape's surface has wherever it touches (sphere, capsule and
// cylinder: the radius; ellipsoid: its smallest semi-axis, a lower bound; flat-faced shapes 0).
// The contact solver follows a rolling surface's gap through its centre of curvature.
double rounding_radius(const CollideShape& g);

// Whether two shapes may touch by their filters: (a.group & b.mask) && (b.group & a.mask).
inline bool filters_allow(const ShapeRecord& a, const ShapeRecord& b) {
  return (a.group & b.mask) != 0 && (b.group & a.mask) != 0;
}

}  // namespace simreel
