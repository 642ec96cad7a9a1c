// Shared by the narrow-phase tests (collide_test.cpp, trimesh_test.cpp, ccd_mesh_test.cpp): the
// CollideShape of each kind, sized as the tests state them (radius, half-length, half-extents).
#pragma once
#include <algorithm>
#include <cmath>
#include <deque>

#include "sim/collision/narrow/geometry.hpp"
#include "sim/geometry/polyhedron.hpp"
#include "sim/geometry/trimesh.hpp"

namespace simreel::collide_shapes {

// Polyhedra built for the tests live here (a CollideShape points at its hull).
inline std::deque<ConvexPolyhedron>& store() {
  static std::deque<ConvexPolyhedron> s;
  return s;
}
inline CollideShape plane() {
  CollideShape s;
  s.kind = CollideKind::plane;
  return s;
}
inline CollideShape sphere(double r) {
  CollideShape s;
  s.kind = CollideKind::sphere;
  s.radius = r;
  s.bounding_radius = r;
  return s;
}
inline CollideShape capsule(double r, double hl) {
  CollideShape s;
  s.kind = CollideKind::capsule;
  s.radius = r;
  s.half_length = hl;
  s.bounding_radius = r + hl;
  return s;
}
inline CollideShape cylinder(double r, double hl) {
  CollideShape s;
  s.kind = CollideKind::cylinder;
  s.radius = r;
  s.half_length = hl;
  s.bounding_radius = std::hypot(r, hl);
  return s;
}
inline CollideShape ellipsoid(const Vec3& radii) {
  CollideShape s;
  s.kind = CollideKind::ellipsoid;
  s.radii = radii;
  s.bounding_radius = radii.maxCoeff();
  return s;
}
inline CollideShape box(const Vec3& h) {
  CollideShape s;
  s.kind = CollideKind::box;
  s.half_extents = h;
  store().push_back(make_box_polyhedron(h));
  s.hull = &store().back();
  s.bounding_radius = h.norm();
  return s;
}
inline CollideShape hull(const ConvexPolyhedron& p) {
  CollideShape s;
  s.kind = CollideKind::hull;
  store().push_back(p);
  s.hull = &store().back();
  for (const Vec3& v : p.vertices) s.bounding_radius = std::max(s.bounding_radius, v.norm());
  return s;
}
// A static triangle mesh (the shape refers to `tm`, which must outlive it).
inline CollideShape mesh(const TriMeshShape& tm) {
  CollideShape s;
  s.kind = CollideKind::mesh;
  s.mesh = &tm;
  return s;
}

}  // namespace simreel::collide_shapes
