// `place:` on a body: start poses computed from other bodies instead of by hand (a ball on a ramp at
// 1.2 m from its top edge, a pendulum bob let go at 30 degrees).
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

#include <simreel/math.hpp>

namespace simreel {

struct Scene;
struct Collider;

// The farthest point of collider c (sphere, box, cylinder, capsule, ellipsoid, or a mesh's farthest
// vertex; not a plane) along the direction d_B, in the body frame B (its offset p_BC included), and
// how far that is along d_B (d_B a unit vector).
Vec3 collider_support(const Collider& c, const Vec3& d_B);
double collider_reach(const Collider& c, const Vec3& d_B);

// For each body of the scene's `bodies:` list (`bodies`, parallel to s.bodies) with a `place:`:
//   { on: BODY, at: s | [along, across], across: m, collider: k }: rests it on BODY's top face (the
//     face of its box collider whose outward normal points most nearly against `gravity`, or its
//     plane), touching, its frame turned onto the face (x down the slope, z along the face's normal;
//     the body's own orientation then turns it from there), its origin at `at` m down the slope from
//     the face's uphill edge (or [along, across] from the face's centre) and `across` m across it;
//   { about: [x, y, z], axis: [x, y, z], angle: deg }: turns its whole start state (pose and
//     velocities) rigidly about the point.
// A body resting on a placed body is placed after it. Throws InputError "FILE:LINE:COL: KEY: what".
void apply_placements(const YAML::Node& bodies, const std::string& path, Scene& s, const Vec3& gravity);

}  // namespace simreel
