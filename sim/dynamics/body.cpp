#include <simreel/body.hpp>

#include <cmath>

#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "sim/mass/primitives.hpp"
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {
constexpr EnumNames<ShapeKind, 7> kShapeKinds{{"box", "sphere", "cylinder", "capsule", "mesh", "plane", "ellipsoid"}};
static_assert(kShapeKinds.complete());
constexpr EnumNames<BodyType, 3> kBodyTypes{{"static", "kinematic", "dynamic"}};
static_assert(kBodyTypes.complete());
}  // namespace

const char* to_string(ShapeKind s) {
  return kShapeKinds(s);
}

const char* to_string(BodyType t) {
  return kBodyTypes(t);
}

MassProperties primitive_mass(const Collider& c, double rho) {
  switch (c.shape) {
    case ShapeKind::box:
      return box_mass(c.size, rho);
    case ShapeKind::sphere:
      return sphere_mass(c.radius, rho);
    case ShapeKind::cylinder:
      return cylinder_mass(c.radius, c.height, rho);
    case ShapeKind::capsule:
      return capsule_mass(c.radius, c.height, rho);
    case ShapeKind::ellipsoid:
      return ellipsoid_mass(c.radii, rho);
    case ShapeKind::plane:
      throw InputError("a plane has no mass: it may only be a collider of a static body");
    case ShapeKind::mesh:
      break;
  }
  throw InputError("primitive_mass called for a mesh collider");
}

Collider box_collider(const Vec3& size, double density) {
  Collider c;
  c.shape = ShapeKind::box;
  c.size = size;
  c.props_C = box_mass(size, density);
  return c;
}

Collider sphere_collider(double radius, double density) {
  Collider c;
  c.shape = ShapeKind::sphere;
  c.radius = radius;
  c.props_C = sphere_mass(radius, density);
  return c;
}

Collider cylinder_collider(double radius, double height, double density) {
  Collider c;
  c.shape = ShapeKind::cylinder;
  c.radius = radius;
  c.height = height;
  c.props_C = cylinder_mass(radius, height, density);
  return c;
}

Collider capsule_collider(double radius, double height, double density) {
  Collider c;
  c.shape = ShapeKind::capsule;
  c.radius = radius;
  c.height = height;
  c.props_C = capsule_mass(radius, height, density);
  return c;
}

Collider ellipsoid_collider(const Vec3& radii, double density) {
  Collider c;
  c.shape = ShapeKind::ellipsoid;
  c.radii = radii;
  c.props_C = ellipsoid_mass(radii, density);
  return c;
}

Collider plane_collider() {
  Collider c;
  c.shape = ShapeKind::plane;
  return c;
}

MassProperties compose(const std::vector<Collider>& colliders) {
  MassAccumulator acc;
  for (const Collider& c : colliders) acc.add(placed(c.props_C, c.q_BC.toRotationMatrix(), c.p_BC));
  return acc.result();
}

std::string mass_problem(const MassProperties& mp, double rel_tol) {
  if (!std::isfinite(mp.mass) || !(mp.mass > 0)) return "mass must be positive and finite";
  if (!mp.com.allFinite()) return "centre of mass is not finite";
  return inertia_problem(mp.inertia, rel_tol);
}

const MassProperties& BodyDef::add_collider(Collider c) {
  colliders.push_back(std::move(c));
  return mass_B();
}

void BodyDef::append_collider(Collider c) {
  colliders.push_back(std::move(c));
}

const MassProperties& BodyDef::mass_B() const {
  if (mass_override) return *mass_override;
  if (composed_ != colliders.size()) {
    mass_B_ = compose(colliders);
    composed_ = colliders.size();
  }
  return mass_B_;
}

}  // namespace simreel
