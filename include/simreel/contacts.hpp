// Contacts as a program reads them (Box2D's b2ContactData): each pair of colliders that touched in
// the last step, its points and normal, and the forces the contact solver applied, in newtons.
//
// Forces are the last substep's impulses divided by the substep (dt / World::substeps()): what
// held the bodies at the end of the step. A box resting on the ground carries its weight m g
// spread over its points; during an impact the force is that substep's, which can be far larger
// than the weight. A pair's friction acts at the manifold's centre; each point is given a share of
// it in proportion to its normal force (an equal share when no point presses).
#pragma once
#include <simreel/math.hpp>

namespace simreel {

struct ContactData {
  struct Point {
    Vec3 p_W = Vec3::Zero();               ///< m, world, where the point was when the pair collided
    double separation = 0;                 ///< m, negative: overlap
    double normal_force = 0;               ///< N, >= 0, pushing body b away from a along normal_W
    Vec3 friction_force_W = Vec3::Zero();  ///< N, on body b, this point's share of the pair's friction
    Vec3 force_W = Vec3::Zero();           ///< N, on body b: normal_force normal_W + friction_force_W
  };
  int body_a = -1, body_b = -1;          ///< body indices; a body's own read-out puts it on side b
  int collider_a = -1, collider_b = -1;  ///< indices in each body's BodyDef::colliders
  Vec3 normal_W = Vec3::UnitZ();         ///< unit, world, from a into b
  int count = 0;                         ///< points in use, 1 to 4
  Point points[4];
  double friction = 0;     ///< the pair's Coulomb coefficient, sqrt(f_a f_b)
  double restitution = 0;  ///< the pair's, max(e_a, e_b)

  /// N, the total force on body b (on a: its negative).
  Vec3 force_W() const {
    Vec3 f = Vec3::Zero();
    for (int j = 0; j < count; ++j) f += points[j].force_W;
    return f;
  }
};

}  // namespace simreel
