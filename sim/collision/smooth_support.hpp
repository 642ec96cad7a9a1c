// The support point of a smooth shape and how it moves: what a contact on a flat surface follows
// as the shape turns (the solver's tracked contacts, sim/collision/tracked_contacts.hpp, and the
// rolling contact, sim/solver/rolling_contact.hpp).
#pragma once
#include "sim/collision/narrow/geometry.hpp"

namespace simreel {

// Below this sine between a surface's normal and a cylinder's axis the cylinder stands on its end
// face (the narrow phase's cap test, collide/internal.hpp kSinTol): no single rim point.
constexpr double kRimMinSine = 0.04471;
// A capsule whose axis is within this sine of the surface lies on its side (two points).
constexpr double kCapsuleMinSine = 1e-6;

// Whether a shape has a smooth surface where it can touch a flat one at a single point.
inline bool smooth_kind(CollideKind k) {
  return k == CollideKind::sphere || k == CollideKind::ellipsoid || k == CollideKind::capsule ||
         k == CollideKind::cylinder;
}

// The support point p of shape g along the unit direction d, both in the shape frame C, and its
// derivative J = dp/dd (the surface's radii of curvature at p, as a map of the direction's change
// to the point's). p(d) is homogeneous of degree 0 in d, so J d = 0 and J acts in the tangent plane.
//   sphere (radius rho):  p = rho d,  J = rho (1 - d d^T);
//   capsule:              the end sphere's: p = sign(d_z) L z + rho d, J as the sphere's;
//   ellipsoid A = diag(a^2, b^2, c^2) (x^T A^-1 x = 1): p = A d / s with s = sqrt(d^T A d), so
//                         J = A / s - (A d)(A d)^T / s^3;
//   cylinder rim:         p = sign(d_z) L z + rho e, e = d_xy / |d_xy| the rim's unit radius
//                         towards d, so J = rho (1 - e e^T - z z^T) / |d_xy| = rho t t^T / |d_xy|,
//                         t = z x e the rim's tangent (only the rim angle moves).
// `end` (capsule and cylinder): 0 takes the end d points to; +1 or -1 only that end (false when d
// points to the other). False where p is not unique (a cylinder on its end face, a capsule on its
// side) or the shape is not smooth.
bool smooth_support(const CollideShape& g, const Vec3& d, int end, Vec3& p, Mat3& J);

}  // namespace simreel
