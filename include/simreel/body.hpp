// What a body is made of, before simulation: colliders placed in the body frame, composed into
// the body's mass properties (the article's Collider and RigidBody::AddCollider).
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <optional>

#include <simreel/mass_properties.hpp>
#include <simreel/math.hpp>
#include <simreel/mesh.hpp>
#include <simreel/settings.hpp>

namespace simreel {

struct ConvexPolyhedron;  // a collision hull (built by mesh_collider; the engine's own type)

enum class ShapeKind { box, sphere, cylinder, capsule, mesh, plane, ellipsoid };
const char* to_string(ShapeKind s);

// static: never moves (zero velocity whatever is set). kinematic: moves with its given velocity,
// infinite mass, pushes dynamic bodies and is never pushed (a conveyor, a paddle). dynamic: moved
// by forces, gravity and contacts.
enum class BodyType { static_body, kinematic, dynamic };
const char* to_string(BodyType t);

// How a mesh collider on a dynamic body collides: as the convex hull of its vertices (default),
// or one convex hull per object of the file (`mode: parts`).
enum class MeshCollision { hull, parts };

struct Collider {
  ShapeKind shape = ShapeKind::box;
  Vec3 size = Vec3::Ones();   ///< m, box full extents
  double radius = 0.5;        ///< m, sphere, cylinder, capsule
  double height = 1.0;        ///< m, cylinder, capsule (tip to tip); axis along the collider's z
  Vec3 radii = Vec3::Ones();  ///< m, ellipsoid semi-axes along the collider's x, y, z
  std::shared_ptr<const TriangleMesh> mesh;  ///< mesh shapes: the surface as weighed (mesh axes)
  MassProperties props_C;                    ///< in the collider frame C (mesh: mesh axes)
  Vec3 p_BC = Vec3::Zero();                  ///< m, collider frame origin in the body frame
  Quat q_BC = Quat::Identity();
  std::string label;  ///< for messages: "collider 2 (mesh assets/t.obj)"
  // ---- Contact (docs/contacts.md). A pair uses sqrt(f_a f_b) and max(e_a, e_b).
  double friction = 0.6;     ///< Coulomb coefficient, >= 0
  double restitution = 0.0;  ///< in [0, 1]: normal speed kept after an impact above the threshold
  bool collide = true;       ///< false: mass only, never touches anything
  uint32_t group = 1;        ///< bits this collider belongs to
  uint32_t mask =
      0xFFFFFFFFu;  ///< bits it collides with: a and b touch if (a.group & b.mask) && (b.group & a.mask)
  /// Collision hulls of a mesh collider (one, or one per object with MeshCollision::parts), in the
  /// collider frame; empty for primitives (built by the World when absent).
  std::vector<std::shared_ptr<const ConvexPolyhedron>> hulls;
};

// Colliders of uniform density (kg/m^3), their mass properties from the shape: closed forms for
// the primitives, exact from the triangles for a mesh. Each sits at the body origin (set p_BC and
// q_BC to place it) with the default material (friction 0.6, restitution 0).
Collider box_collider(const Vec3& size, double density);                   ///< size: full extents, m
Collider sphere_collider(double radius, double density);                   ///< m
Collider cylinder_collider(double radius, double height, double density);  ///< m; axis along z
Collider capsule_collider(double radius, double height, double density);   ///< m, tip to tip; axis z
Collider ellipsoid_collider(const Vec3& radii, double density);            ///< m, semi-axes
/// The plane z = 0 of the collider frame, solid below: static bodies only, massless.
Collider plane_collider();
/// A mesh of uniform density: mass, centroid and inertia exactly from the mesh (after welding and
/// orientation repairs, which `report` describes when given), colliding as its convex hull, or as
/// one hull per connected part with `parts`; on a static body it collides as its triangles.
/// Collider frame = mesh axes. hull_vertices >= 4: each collision hull simplified to at most that
/// many of its vertices (an inner hull: a little smaller; the mass properties stay the mesh's).
/// Throws InputError for a mesh with no volume.
Collider mesh_collider(std::shared_ptr<const TriangleMesh> mesh, double density, bool parts = false,
                       MeshReport* report = nullptr, int hull_vertices = 0);

// Collider mass properties for a primitive shape from its size and density (kg/m^3).
MassProperties primitive_mass(const Collider& c, double density);

struct BodyDef {
  std::string name;
  Vec3 p_WB = Vec3::Zero();      ///< m, body origin in the world (the article's m_position)
  Quat q_WB = Quat::Identity();  ///< body to world
  Vec3 v_W = Vec3::Zero();       ///< m/s, centre-of-mass velocity, world frame
  Vec3 w_W = Vec3::Zero();       ///< rad/s, angular velocity, world frame
  BodyType type = BodyType::dynamic;
  std::optional<Integrator> integrator;  ///< overrides the world's for this body (side-by-side demos)
  /// Swept for time of impact every step it moves, however slowly (docs/continuous-collision.md;
  /// other bodies only when they move more than half their smallest width in a step).
  bool bullet = false;
  std::vector<Collider> colliders;
  /// Mass properties stated rather than drawn (scene key `mass_properties`): mass, centre of mass
  /// and inertia about it in the body frame B. When set, mass_B() and the World use it instead of
  /// the colliders' composition (the colliders then only collide). Checked by mass_problem().
  std::optional<MassProperties> mass_override;

  // The article's AddCollider: appends and returns the updated composite mass properties.
  const MassProperties& add_collider(Collider c);
  // Appends without composing: composition waits until mass_B() is asked for, so a body built
  // from n colliders costs O(n), not O(n^2) (16,000 colliders took 20 s when each addition
  // re-summed all earlier ones).
  void append_collider(Collider c);
  // Composite mass, centroid (the article's m_localCentroid) and inertia about it, body frame; the
  // override when one is set.
  const MassProperties& mass_B() const;

 private:
  mutable MassProperties mass_B_;
  mutable size_t composed_ = 0;  ///< colliders mass_B_ was composed from
};

// The composition of a list of colliders (body frame): total mass, mass-weighted centroid,
// inertia about it by the parallel axis theorem, each collider first rotated (R I R^T).
MassProperties compose(const std::vector<Collider>& colliders);

// Why stated mass properties are not physical: mass not positive and finite, centre not finite,
// inertia not symmetric, not positive definite or breaking the triangle inequality of its principal
// moments (inertia_problem with relative slack `rel_tol`). Empty when valid.
std::string mass_problem(const MassProperties& mp, double rel_tol = 1e-9);

}  // namespace simreel
